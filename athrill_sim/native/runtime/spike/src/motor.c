/*
 * SPIKE-RT's motors as a HackSPi program sees them through RasPike-ART (libraspike-art's raspike_motor.c and
 * the hub's raspike.c), on the EV3 motor slots: port index i (A = 0) has its power at TX MOTOR_POWER + 4 i,
 * its brake flag at TX MOTOR_BRAKE + 4 i, its encoder reset at TX MOTOR_RESET_ANGLE + 4 i and its count at RX
 * MOTOR_ANGLE + 4 i (the bench has encoders on A..D only; the SDK's E and F land on the next slots, and so do
 * ours). pup_motor_setup hands the direction to the hub (TX SPIKE_DIRECTION + 4 i), and the physics process,
 * as the hub's pbio, applies it to the power written and to the count it reports: the power goes out in the
 * program's direction, the count comes back in it (hakoniwa/physics/spike_hub.py).
 *
 * What a program reads is the hub's status (status.c): count, speed, power and stall as of the last 10 ms.
 * get_power is libraspike-art's: the power last set while the last command was set_power (stop, brake and
 * hold do not change that), otherwise the hub's report (RX SPIKE_MOTOR_POWER + 4 i).
 *
 * What the hub's pbio does, on the bench's snapshots:
 * - the counts are sampled when the program gets a motor and at each snapshot after; the speed is the count's
 *   change, in degrees per second, since the newest sample at least SPEED_WINDOW_US (Pybricks' differentiator
 *   window) older, or the oldest one kept;
 * - set_speed and hold are regulated, and while a motor is the kernel wakes every CONTROL_PERIOD_US
 *   (Pybricks' control loop): the angle follows a reference that moves at the speed asked (hold: stands
 *   still), power = POSITION_GAIN per degree behind it, within the duty limit; while the power is at the
 *   limit the reference waits for the motor, as Pybricks' trajectory does when it stalls;
 * - stalled: driven (a power set, or a regulated motor at its limit) for STALL_TIME_US and slower than
 *   STALL_SPEED_DPS over them (Pybricks' stall tolerances), from the newest sample at least that old;
 * - set_duty_limit caps the power written (a percentage; SPIKE-RT returns a voltage, an opaque value that
 *   restore_duty_limit takes back, as here).
 */
#include <stddef.h>
#include <stdlib.h>

#include "../../src/devices.h"
#include "spike.h"
#include "spike/pup/motor.h"

#define CONTROL_PERIOD_US 5000 /* PBIO_CONFIG_CONTROL_LOOP_TIME_MS */
#define SPEED_WINDOW_US 100000 /* PBIO_CONFIG_DIFFERENTIATOR_WINDOW_MS */
#define HISTORY 256 /* samples kept: the window's worth at a snapshot per physics step, and more */
#define STALL_SPEED_DPS 20 /* Pybricks' stall_speed_limit */
#define STALL_TIME_US 200000 /* Pybricks' stall_time */
#define POSITION_GAIN 2.0 /* power per degree behind the reference (ours: the bench's wheels settle in 0.1 s) */
#define FULL_DUTY 100

typedef struct {
    bool taken;
    bool power_mode; /* libraspike-art's pdev->cmd == RP_CMD_ID_MOT_POW: the last of set_power and set_speed */
    bool regulated; /* set_speed or hold */
    int32_t speed; /* deg/s in the program's direction, while regulated */
    double ref_angle; /* the reference, in the program's direction, at ref_time */
    int64_t ref_time;
    int duty_limit;
    int applied; /* the power last written, in the program's direction */
    int64_t driven_since; /* a power set (not 0), or a regulated motor at its limit, since then; -1: not */
} motor_state;

static motor_state states[SPIKE_PORTS];
static bool any_motor;
static int32_t counts[HISTORY][SPIKE_PORTS]; /* ring of samples, one per snapshot */
static int64_t sampled_at[HISTORY];
static int samples, newest;

static void sample(int64_t now);

static pup_device_t *device(pup_motor_t *motor, const char *caller)
{
    if (motor == NULL) { /* the SDK dereferences it: a crash there too */
        hako_log("%s(): the motor is NULL (pup_motor_get_device found no free port)", caller);
        abort();
    }
    return (pup_device_t *)motor;
}

static motor_state *state(const pup_device_t *pdev) { return &states[pdev->port_id]; }
/* The count as the hub reports it at this snapshot: in the program's direction. */
static int32_t count_now(int index) { return (int32_t)spike_read_u32(HAKO_RX_MOTOR_ANGLE + 4 * index); }
static double angle(const pup_device_t *pdev) { return (double)count_now(pdev->port_id); }

static int limited(const motor_state *s, int power)
{
    return power > s->duty_limit ? s->duty_limit : power < -s->duty_limit ? -s->duty_limit : power;
}

/* The power write, in the program's direction (the hub applies the direction), and the brake flag raised on
 * a 0 (never lowered again), as the SDK's. A duty limit below 100 caps it; without one the power goes out as
 * set. */
static void write_power(pup_device_t *pdev, int power)
{
    motor_state *s = state(pdev);
    if (s->duty_limit < FULL_DUTY)
        power = limited(s, power);
    s->applied = power;
    if (!s->regulated)
        s->driven_since = power == 0 ? -1 : s->driven_since >= 0 ? s->driven_since : hako_tick();
    spike_write_u32(HAKO_TX_MOTOR_POWER + 4 * pdev->port_id, (uint32_t)power);
    if (power == 0)
        spike_write_u32(HAKO_TX_MOTOR_BRAKE + 4 * pdev->port_id, 1);
}

pup_motor_t *pup_motor_get_device(pbio_port_id_t port)
{
    pup_device_t *pdev = spike_take_port(port, DEVICE_MOTOR, __func__);
    if (pdev != NULL) {
        *state(pdev) = (motor_state){.taken = true, .duty_limit = FULL_DUTY, .driven_since = -1};
        any_motor = true;
        sample(hako_tick()); /* the speed's first reference */
    }
    return (pup_motor_t *)pdev;
}

pbio_error_t pup_motor_setup(pup_motor_t *motor, pup_direction_t positive_direction, bool reset_count)
{
    pup_device_t *pdev = device(motor, __func__);
    pdev->direction = (unsigned char)positive_direction;
    if (pdev->port_id < HAKO_MOTOR_PORTS) /* the hub's motors with an encoder on the bench */
        spike_write_u32(HAKO_TX_SPIKE_DIRECTION + 4 * pdev->port_id, positive_direction);
    return reset_count ? pup_motor_reset_count(motor) : PBIO_SUCCESS;
}

/* The SDK's: power 0 (which stops a regulated motor too) and the reset flag; the physics process zeroes the
 * encoder and clears the flag. The samples are moved along, so that the speed does not see the jump, and the
 * status's count is 0 until the next status, as libraspike-art clears it (raspike_motor.c 42-46). */
pbio_error_t pup_motor_reset_count(pup_motor_t *motor)
{
    pup_device_t *pdev = device(motor, __func__);
    int index = pdev->port_id;
    int32_t before = count_now(index);
    for (int k = 0; k < HISTORY; k++)
        counts[k][index] -= before;
    spike_status_count_reset(index);
    state(pdev)->regulated = false;
    state(pdev)->applied = 0;
    state(pdev)->driven_since = -1;
    spike_write_u32(HAKO_TX_MOTOR_POWER + 4 * index, 0);
    spike_write_u32(HAKO_TX_MOTOR_RESET_ANGLE + 4 * index, 1);
    return PBIO_SUCCESS;
}

int32_t pup_motor_get_count(pup_motor_t *motor)
{
    hako_spend_call(); /* a device read takes time (sim_time.h) */
    return spike_status()->motors[device(motor, __func__)->port_id].count;
}

/* The count's change per second since the newest sample at least `window_us` before the newest, or the
 * oldest kept; how long before is left in *span_us (0, with a speed of 0, before two samples). */
static int32_t speed_over(int index, int64_t window_us, int64_t *span_us)
{
    int then = newest;
    for (int k = 1; k < samples; k++) {
        then = (newest - k + HISTORY) % HISTORY;
        if (sampled_at[newest] - sampled_at[then] >= window_us)
            break;
    }
    *span_us = sampled_at[newest] - sampled_at[then];
    return *span_us == 0 ? 0 : (int32_t)((int64_t)(counts[newest][index] - counts[then][index]) * 1000000 / *span_us);
}

int32_t pup_motor_get_speed(pup_motor_t *motor)
{
    hako_spend_call(); /* a device read takes time (sim_time.h) */
    return spike_status()->motors[device(motor, __func__)->port_id].speed;
}

int32_t pup_motor_get_power(pup_motor_t *motor)
{
    hako_spend_call(); /* a device read takes time (sim_time.h) */
    pup_device_t *pdev = device(motor, __func__);
    return state(pdev)->power_mode ? pdev->power : spike_status()->motors[pdev->port_id].power;
}

pbio_error_t pup_motor_set_power(pup_motor_t *motor, int power)
{
    pup_device_t *pdev = device(motor, __func__);
    state(pdev)->regulated = false;
    state(pdev)->power_mode = true;
    pdev->power = power;
    write_power(pdev, power);
    return PBIO_SUCCESS;
}

/* The reference keeps moving on through a change of speed, so a program that sets the same speed every
 * period is regulated as one that set it once. */
static void regulate(pup_device_t *pdev, int32_t speed, bool from_here)
{
    motor_state *s = state(pdev);
    int64_t now = hako_tick();
    if (from_here || !s->regulated)
        s->ref_angle = angle(pdev);
    else
        s->ref_angle += (double)s->speed * (double)(now - s->ref_time) / 1e6;
    s->ref_time = now;
    s->speed = speed;
    s->regulated = true;
}

pbio_error_t pup_motor_set_speed(pup_motor_t *motor, int speed)
{
    pup_device_t *pdev = device(motor, __func__);
    state(pdev)->power_mode = false;
    if (!state(pdev)->regulated || state(pdev)->speed != speed)
        regulate(pdev, speed, false);
    return PBIO_SUCCESS;
}

/* The SDK's stop: power 0 and the brake flag. The bench's motors are speed servos, so a power of 0 holds the
 * wheel still, as SPIKE-RT's brake does; SPIKE-RT's stop lets it coast. The power set is kept for get_power,
 * as libraspike-art keeps it (its stop sends a command and changes neither pdev->cmd nor pdev->power). */
pbio_error_t pup_motor_stop(pup_motor_t *motor)
{
    pup_device_t *pdev = device(motor, __func__);
    state(pdev)->regulated = false;
    write_power(pdev, 0);
    return PBIO_SUCCESS;
}

pbio_error_t pup_motor_brake(pup_motor_t *motor) { return pup_motor_stop(motor); }

pbio_error_t pup_motor_hold(pup_motor_t *motor)
{
    regulate(device(motor, __func__), 0, true);
    return PBIO_SUCCESS;
}

bool pup_motor_is_stalled(pup_motor_t *motor)
{
    hako_spend_call(); /* a device read takes time (sim_time.h) */
    return spike_status()->motors[device(motor, __func__)->port_id].stalled;
}

/* pbio's stall detection at this snapshot. */
static bool stalled(int index, int64_t now)
{
    const motor_state *s = &states[index];
    if (s->driven_since < 0 || now - s->driven_since < STALL_TIME_US)
        return false;
    int64_t span;
    int32_t speed = speed_over(index, STALL_TIME_US, &span);
    return span >= STALL_TIME_US && speed < STALL_SPEED_DPS && speed > -STALL_SPEED_DPS;
}

void spike_motor_status(int index, int64_t now, spike_motor_reading *out)
{
    int64_t span;
    out->count = count_now(index);
    out->speed = speed_over(index, SPEED_WINDOW_US, &span);
    out->power = (int32_t)spike_read_u32(HAKO_RX_SPIKE_MOTOR_POWER + 4 * index);
    out->stalled = states[index].taken && stalled(index, now);
}

int32_t pup_motor_set_duty_limit(pup_motor_t *motor, int duty_limit)
{
    motor_state *s = state(device(motor, __func__));
    int32_t old = s->duty_limit;
    s->duty_limit = duty_limit < 0 ? 0 : duty_limit > FULL_DUTY ? FULL_DUTY : duty_limit;
    return old;
}

void pup_motor_restore_duty_limit(pup_motor_t *motor, int old_value) { pup_motor_set_duty_limit(motor, old_value); }

void spike_motors_off(void)
{
    for (int i = 0; i < SPIKE_PORTS; i++)
        if (states[i].taken) {
            states[i].regulated = false;
            spike_write_u32(HAKO_TX_MOTOR_POWER + 4 * i, 0);
        }
}

/* -- the control period: sampling, regulation, stall detection ---------------------------------------- */

static void regulate_step(pup_device_t *pdev, int64_t now)
{
    motor_state *s = state(pdev);
    double target = s->ref_angle + (double)s->speed * (double)(now - s->ref_time) / 1e6;
    double behind = target - angle(pdev);
    double reach = s->duty_limit / POSITION_GAIN;
    bool at_limit = behind >= reach || behind <= -reach;
    s->driven_since = !at_limit ? -1 : s->driven_since >= 0 ? s->driven_since : now;
    if (at_limit) { /* the reference waits where the motor can follow it */
        s->ref_angle = angle(pdev) + (behind > 0 ? reach : -reach);
        s->ref_time = now;
        behind = behind > 0 ? reach : -reach;
    }
    pdev->power = (int32_t)(behind * POSITION_GAIN);
    write_power(pdev, pdev->power);
}

/* The counts at this instant (a second look at one instant replaces the first). */
static void sample(int64_t now)
{
    if (samples == 0 || sampled_at[newest] != now) {
        newest = (newest + 1) % HISTORY;
        if (samples < HISTORY)
            samples++;
    }
    sampled_at[newest] = now;
    for (int i = 0; i < SPIKE_PORTS; i++)
        counts[newest][i] = count_now(i);
}

void spike_motors_serve(int64_t now)
{
    if (!any_motor)
        return;
    sample(now);
    for (int i = 0; i < SPIKE_PORTS; i++) {
        motor_state *s = &states[i];
        if (!s->taken)
            continue;
        pup_device_t *pdev = spike_port(i);
        if (s->regulated)
            regulate_step(pdev, now);
    }
}

/* When the kernel must wake next for the motors: every control period while one is regulated (status.c
 * serves them, before it takes a status). */
static int64_t motors_next_due(int64_t now_us)
{
    for (int i = 0; i < SPIKE_PORTS; i++)
        if (states[i].taken && states[i].regulated)
            return (now_us / CONTROL_PERIOD_US + 1) * CONTROL_PERIOD_US;
    return HAKO_NEVER_WAKES;
}

HAKO_DEVICE(motors_device) = {.next_due = motors_next_due};
