/*
 * HackSPi's line tracer as a RasPike-ART team writes one in C, for the bench's tests: a cyclic task traces the
 * left edge every 10 ms by the colour sensor's reflection, and names blue by a rule on the hub's HSV, as teams
 * tune it on the mat (a hue of 200..280 with some saturation). Each period it reads both, so the sensor's mode
 * switches twice a period; on the robot each switch waits for the hub's status that carries the new mode
 * (libraspike-art's raspike_port_com_change_if_needed). It prints how long its first reads took, and the
 * blue sections it meets with the distance by both wheel counts.
 */
#include "app.h"

#include <math.h>
#include <stdio.h>
#include <time.h>

#include "spike/pup/colorsensor.h"
#include "spike/pup/forcesensor.h"
#include "spike/pup/motor.h"

#define TARGET 25 /* between HackSPi's white (40) and black (10), as sample_c5_spike calibrates */
#define POWER 40
#define KP 1.2
#define KD 2.0
#define WHEEL_MM_PER_DEG (56.0 * M_PI / 360.0)
#define TIMED_PERIODS 3

static pup_motor_t *left_motor, *right_motor;
static pup_device_t *color_sensor;
static int last_error;
static int in_blue;
static int periods;

static long long now_us(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (long long)ts.tv_sec * 1000000 + ts.tv_nsec / 1000;
}

static int driven_mm(void)
{
    double counts = (pup_motor_get_count(left_motor) + pup_motor_get_count(right_motor)) / 2.0;
    return (int)(counts * WHEEL_MM_PER_DEG);
}

void main_task(intptr_t unused)
{
    pup_device_t *force = pup_force_sensor_get_device(PBIO_PORT_ID_D);
    color_sensor = pup_color_sensor_get_device(PBIO_PORT_ID_E);
    left_motor = pup_motor_get_device(PBIO_PORT_ID_B);
    right_motor = pup_motor_get_device(PBIO_PORT_ID_A);
    pup_motor_setup(left_motor, PUP_DIRECTION_COUNTERCLOCKWISE, true);
    pup_motor_setup(right_motor, PUP_DIRECTION_CLOCKWISE, true);
    printf("press the force sensor to start\n");
    while (!pup_force_sensor_touched(force)) {
        dly_tsk(10 * 1000);
    }
    sta_cyc(TRACER_CYC);
    ext_tsk();
}

void tracer_task(intptr_t unused)
{
    long long start = now_us();
    int error = TARGET - pup_color_sensor_reflection(color_sensor);
    long long reflected = now_us();
    pup_color_hsv_t hsv = pup_color_sensor_hsv(color_sensor, true);
    if (periods++ < TIMED_PERIODS) {
        printf("reflection %lld us, hsv %lld us\n", reflected - start, now_us() - reflected);
    }
    int steer = (int)(KP * error + KD * (error - last_error));
    last_error = error;
    pup_motor_set_power(left_motor, POWER + steer);
    pup_motor_set_power(right_motor, POWER - steer);

    int blue = hsv.h >= 200 && hsv.h <= 280 && hsv.s >= 20;
    if (blue && !in_blue) {
        printf("blue at %d mm\n", driven_mm());
    }
    in_blue = blue;
    ext_tsk();
}
