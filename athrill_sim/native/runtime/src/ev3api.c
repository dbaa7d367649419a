/*
 * EV3RT's sensor, motor, LED and button API over guest memory, mirroring athrill_sim/mock/ev3api.py call for
 * call: the same reads (the low byte of the colour slots, 16 bits of the gyro, ultrasonic and touch slots,
 * ultrasonic millimetres returned as centimetres), the same error codes, the same flags. Every access goes
 * through the guest windows, exactly as a program's own pointer would, so the API and raw addresses always
 * agree.
 */
#include "ev3api.h"
#include "runtime.h"
#include "scheduler.h"

#define RX(offset) ((uintptr_t)HAKO_RX_GUEST_BASE + (offset))
#define TX(offset) ((uintptr_t)HAKO_TX_GUEST_BASE + (offset))

static sensor_type_t sensors[TNUM_SENSOR_PORT];
static motor_type_t motors[TNUM_MOTOR_PORT];
static int motor_power[TNUM_MOTOR_PORT]; /* ev3api_motor.c's: the power last set, which get_power answers */

static uint8_t read_u8(uintptr_t addr) { return *(volatile const uint8_t *)addr; }
static uint16_t read_u16(uintptr_t addr) { return *(volatile const uint16_t *)addr; }
static int16_t read_i16(uintptr_t addr) { return *(volatile const int16_t *)addr; }
static int32_t read_i32(uintptr_t addr) { return *(volatile const int32_t *)addr; }
static uint32_t read_u32(uintptr_t addr) { return *(volatile const uint32_t *)addr; }
static void write_i32(uintptr_t addr, int32_t value) { *(volatile int32_t *)addr = value; }

/* motor_brake (motor_dri.c) of opOUTPUT_STOP: the power slot 0, and the brake as the command's char carries it. */
static void motor_brake(motor_port_t port, char brake)
{
    write_i32(TX(HAKO_TX_MOTOR_POWER + 4 * port), 0);
    write_i32(TX(HAKO_TX_MOTOR_BRAKE + 4 * port), brake);
}

static bool sensor_port_ok(sensor_port_t port) { return (int)port >= 0 && (int)port < TNUM_SENSOR_PORT; }
static bool motor_port_ok(motor_port_t port) { return (int)port >= 0 && (int)port < TNUM_MOTOR_PORT; }

/* -- configuration ------------------------------------------------------------------------------------ */

ER ev3_sensor_config(sensor_port_t port, sensor_type_t type)
{
    if (!sensor_port_ok(port))
        return E_ID;
    sensors[port] = type;
    return E_OK;
}

ER_UINT ev3_sensor_get_type(sensor_port_t port) { return sensor_port_ok(port) ? (ER_UINT)sensors[port] : E_ID; }

ER ev3_motor_config(motor_port_t port, motor_type_t type)
{
    if (!motor_port_ok(port))
        return E_ID;
    if ((int)type < NONE_MOTOR || (int)type > UNREGULATED_MOTOR)
        return E_PAR;
    motors[port] = type;
    motor_brake(port, 0); /* opOUTPUT_STOP, brake 0: configured idle, as EV3RT does */
    return E_OK;
}

ER_UINT ev3_motor_get_type(motor_port_t port) { return motor_port_ok(port) ? (ER_UINT)motors[port] : E_ID; }

/* -- sensors ------------------------------------------------------------------------------------------ */

/* Whether `port` has a sensor of `kind` (EV3RT's CHECK_PORT and CHECK_COND(type == kind, E_OBJ)); if not,
 * EV3RT's warning in the log. */
static ER sensor_error(sensor_port_t port, sensor_type_t kind, const char *name)
{
    ER ercd = !sensor_port_ok(port) ? E_ID : sensors[port] != kind ? E_OBJ : E_OK;
    if (ercd != E_OK)
        hako_log("%s(): ercd %d", name, ercd);
    return ercd;
}

static bool sensor_ready(sensor_port_t port, sensor_type_t kind, const char *name)
{
    return sensor_error(port, kind, name) == E_OK;
}

/* get_sensor_index (ev3api_sensor.c): how many earlier ports have a sensor of the same kind. */
static int sensor_index(sensor_port_t port, sensor_type_t kind)
{
    int index = 0;
    for (int p = 0; p < (int)port; p++)
        index += sensors[p] == kind;
    return index;
}

/* EV3_SENSOR_ADDR_* (ev3_vdev.h): the second colour sensor (index 1) reads the COLOR1 slots, any other COLOR0's. */
static uintptr_t color_slot(sensor_port_t port, uint32_t slot0)
{
    return RX(slot0 + (sensor_index(port, COLOR_SENSOR) == 1 ? HAKO_RX_COLOR1_AMBIENT - HAKO_RX_COLOR0_AMBIENT : 0));
}

uint8_t ev3_color_sensor_get_reflect(sensor_port_t port)
{
    hako_spend_call(); /* a device read takes time (sim_time.h) */
    return sensor_ready(port, COLOR_SENSOR, __func__) ? read_u8(color_slot(port, HAKO_RX_COLOR0_REFLECT)) : 0;
}

uint8_t ev3_color_sensor_get_ambient(sensor_port_t port)
{
    hako_spend_call(); /* a device read takes time (sim_time.h) */
    return sensor_ready(port, COLOR_SENSOR, __func__) ? read_u8(color_slot(port, HAKO_RX_COLOR0_AMBIENT)) : 0;
}

colorid_t ev3_color_sensor_get_color(sensor_port_t port)
{
    hako_spend_call(); /* a device read takes time (sim_time.h) */
    return sensor_ready(port, COLOR_SENSOR, __func__) ? (colorid_t)read_u8(color_slot(port, HAKO_RX_COLOR0_COLOR))
                                                      : COLOR_NONE;
}

/* On an error *val is left alone, as EV3RT leaves it. */
void ev3_color_sensor_get_rgb_raw(sensor_port_t port, rgb_raw_t *val)
{
    hako_spend_call(); /* a device read takes time (sim_time.h) */
    if (!sensor_ready(port, COLOR_SENSOR, __func__))
        return;
    val->r = read_u16(color_slot(port, HAKO_RX_COLOR0_RGB + 0));
    val->g = read_u16(color_slot(port, HAKO_RX_COLOR0_RGB + 4));
    val->b = read_u16(color_slot(port, HAKO_RX_COLOR0_RGB + 8));
}

int16_t ev3_gyro_sensor_get_angle(sensor_port_t port)
{
    hako_spend_call(); /* a device read takes time (sim_time.h) */
    return sensor_ready(port, GYRO_SENSOR, __func__) ? read_i16(RX(HAKO_RX_GYRO_ANGLE)) : 0;
}

int16_t ev3_gyro_sensor_get_rate(sensor_port_t port)
{
    hako_spend_call(); /* a device read takes time (sim_time.h) */
    return sensor_ready(port, GYRO_SENSOR, __func__) ? read_i16(RX(HAKO_RX_GYRO_RATE)) : 0;
}

/* uart_dri_get_data_gyro's GYRO_CAL: the TX flag (the physics process clears it once it has zeroed its angle),
 * and the RX angle and rate zeroed at once, so that a read before the next snapshot is 0. */
ER ev3_gyro_sensor_reset(sensor_port_t port)
{
    ER ercd = sensor_error(port, GYRO_SENSOR, __func__);
    if (ercd != E_OK)
        return ercd;
    write_i32(TX(HAKO_TX_GYRO_RESET), 1);
    write_i32(RX(HAKO_RX_GYRO_ANGLE), 0);
    write_i32(RX(HAKO_RX_GYRO_RATE), 0);
    return E_OK;
}

int16_t ev3_ultrasonic_sensor_get_distance(sensor_port_t port)
{
    hako_spend_call(); /* a device read takes time (sim_time.h) */
    return sensor_ready(port, ULTRASONIC_SENSOR, __func__) ? (int16_t)(read_i16(RX(HAKO_RX_ULTRASONIC_MM)) / 10) : 0;
}

bool_t ev3_ultrasonic_sensor_listen(sensor_port_t port)
{
    hako_spend_call(); /* a device read takes time (sim_time.h) */
    return sensor_ready(port, ULTRASONIC_SENSOR, __func__) && read_u32(RX(HAKO_RX_ULTRASONIC_LISTEN)) != 0;
}

bool_t ev3_touch_sensor_is_pressed(sensor_port_t port)
{
    hako_spend_call(); /* a device read takes time (sim_time.h) */
    return sensor_ready(port, TOUCH_SENSOR, __func__) &&
           read_i16(RX(sensor_index(port, TOUCH_SENSOR) == 0 ? HAKO_RX_TOUCH0 : HAKO_RX_TOUCH1)) > ADC_RES / 2;
}

bool_t ev3_button_is_pressed(button_t button)
{
    hako_spend_call(); /* a device read takes time (sim_time.h) */
    if ((int)button < LEFT_BUTTON || (int)button > BACK_BUTTON)
        return false;
    return (read_u32(RX(HAKO_RX_BUTTONS)) >> button) & 1;
}

/* -- motors ------------------------------------------------------------------------------------------- */

static ER motor_error(motor_port_t port)
{
    if (!motor_port_ok(port))
        return E_ID;
    return motors[port] == NONE_MOTOR ? E_OBJ : E_OK;
}

int32_t ev3_motor_get_counts(motor_port_t port)
{
    hako_spend_call(); /* a device read takes time (sim_time.h) */
    ER ercd = motor_error(port);
    if (ercd == E_OK)
        return read_i32(RX(HAKO_RX_MOTOR_ANGLE + 4 * port));
    hako_log("%s(): Failed to get motor counts, ercd: %d", __func__, ercd);
    return 0;
}

ER ev3_motor_reset_counts(motor_port_t port)
{
    ER ercd = motor_error(port);
    if (ercd != E_OK)
        return ercd;
    write_i32(TX(HAKO_TX_MOTOR_RESET_ANGLE + 4 * port), 1); /* motor_clr_angle, port D's too; physics clears it */
    return E_OK;
}

ER ev3_motor_set_power(motor_port_t port, int power)
{
    ER ercd = motor_error(port);
    if (ercd != E_OK)
        return ercd;
    if (power < -100 || power > 100) {
        int used = power > 0 ? 100 : -100;
        hako_log("%s(): power %d is out-of-range, %d is used instead.", __func__, power, used);
        power = used;
    }
    write_i32(TX(HAKO_TX_MOTOR_POWER + 4 * port), power);
    motor_power[port] = power;
    return E_OK;
}

int ev3_motor_get_power(motor_port_t port)
{
    hako_spend_call(); /* a device read takes time (sim_time.h) */
    ER ercd = motor_error(port);
    if (ercd == E_OK)
        return motor_power[port];
    hako_log("%s(): Failed to get motor power, ercd: %d", __func__, ercd);
    return 0;
}

/* EV3RT for Athrill does not support it: E_OK, and the motor is left alone (ev3api_motor.c). */
ER ev3_motor_rotate(motor_port_t port, int degrees, uint32_t speed_abs, bool_t blocking)
{
    (void)port, (void)degrees, (void)speed_abs, (void)blocking;
    return E_OK;
}

ER ev3_motor_stop(motor_port_t port, bool_t brake)
{
    ER ercd = motor_error(port);
    if (ercd != E_OK)
        return ercd;
    ev3_motor_set_power(port, 0);
    motor_brake(port, (char)brake);
    return E_OK;
}

/* EV3RT's steer (ev3api_motor.c): |turn| and |power| capped at 100, the inner wheel slowed to
 * |p|*(100-|t|)/100, so it stops at +-100 and never runs backwards; a positive turn slows the right wheel. */
ER ev3_motor_steer(motor_port_t left_motor, motor_port_t right_motor, int power, int turn_ratio)
{
    ER ercd = motor_error(left_motor);
    if (ercd == E_OK)
        ercd = motor_error(right_motor);
    if (ercd != E_OK)
        return ercd;
    int abs_turn = turn_ratio < 0 ? -turn_ratio : turn_ratio;
    int abs_power = power < 0 ? -power : power;
    if (abs_turn > 100)
        abs_turn = 100;
    if (abs_power > 100)
        abs_power = 100;
    int inner = abs_power * (100 - abs_turn) / 100;
    int left = turn_ratio > 0 ? abs_power : inner, right = turn_ratio > 0 ? inner : abs_power;
    if (power < 0) {
        left = -left;
        right = -right;
    }
    ev3_motor_set_power(left_motor, left);
    ev3_motor_set_power(right_motor, right);
    return E_OK;
}

/* -- LED ---------------------------------------------------------------------------------------------- */

/* EV3RT keeps only the RED and GREEN bits of `color` (ev3api_brick.c), so it never fails; gpio_set_value
 * (gpio_dri.c) sets or clears each in the LED byte and leaves its other bits alone. */
ER ev3_led_set_color(ledcolor_t color)
{
    volatile uint8_t *led = (volatile uint8_t *)TX(HAKO_TX_LED);
    uint8_t value = *led;
    value = color & LED_RED ? value | LED_RED : value & ~LED_RED;
    value = color & LED_GREEN ? value | LED_GREEN : value & ~LED_GREEN;
    *led = value;
    return E_OK;
}
