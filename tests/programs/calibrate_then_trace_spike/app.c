/*
 * calibrate_then_trace for HackSPi (--robot hackspi: left wheel B mounted mirror-wise, right A, force D, colour E,
 * ultrasonic F), on SPIKE-RT's API: the hub's CENTER button after black and after white, LEFT or RIGHT for the
 * course, and the force sensor to start. docs/examples/calibrate-then-start-spike.toml is the person's part.
 */
#include "spikeapi.h"
#include "spike/hub/button.h"
#include "spike/pup/colorsensor.h"
#include "spike/pup/forcesensor.h"
#include "spike/pup/motor.h"

#define PERIOD_US (10 * 1000)
#define SAMPLES 8
#define MIN_CONTRAST 12 /* the SPIKE sensor reads ET Robocon's course 10 on black, 40 on white */
#define POWER 50
#define KP 3.0f
#define KD 8.0f

static hub_button_t pressed(void)
{
    hub_button_t buttons;
    hub_button_is_pressed(&buttons);
    return buttons;
}

/* Waits for a click of any of `buttons` (pressed, then released); returns which were pressed. */
static hub_button_t wait_click(hub_button_t buttons)
{
    hub_button_t got;
    while (!((got = pressed()) & buttons)) {
        dly_tsk(PERIOD_US);
    }
    while (pressed() & buttons) {
        dly_tsk(PERIOD_US);
    }
    return got & buttons;
}

static int average_reflection(pup_device_t *color)
{
    int sum = 0;
    for (int i = 0; i < SAMPLES; i++) {
        sum += pup_color_sensor_reflection(color);
        dly_tsk(PERIOD_US);
    }
    return sum / SAMPLES;
}

void main_task(intptr_t unused)
{
    pup_device_t *color = pup_color_sensor_get_device(PBIO_PORT_ID_E);
    pup_device_t *force = pup_force_sensor_get_device(PBIO_PORT_ID_D);
    pup_motor_t *left = pup_motor_get_device(PBIO_PORT_ID_B);
    pup_motor_t *right = pup_motor_get_device(PBIO_PORT_ID_A);
    pup_motor_setup(left, PUP_DIRECTION_COUNTERCLOCKWISE, true);
    pup_motor_setup(right, PUP_DIRECTION_CLOCKWISE, true);

    printf("Put me on black, press CENTER\n");
    wait_click(HUB_BUTTON_CENTER);
    int black = average_reflection(color);
    printf("black %d. Put me on white, press CENTER\n", black);
    wait_click(HUB_BUTTON_CENTER);
    int white = average_reflection(color);
    if (white - black < MIN_CONTRAST) {
        printf("calibration failed: black %d, white %d\n", black, white);
        ext_tsk();
    }
    printf("white %d. LEFT or RIGHT course?\n", white);
    int edge = wait_click(HUB_BUTTON_LEFT | HUB_BUTTON_RIGHT) & HUB_BUTTON_RIGHT ? 1 : -1;
    printf("%s course. Press the force sensor to start\n", edge > 0 ? "R" : "L");
    while (!pup_force_sensor_touched(force)) {
        dly_tsk(PERIOD_US);
    }
    printf("start\n");

    float threshold = (black + white) / 2.0f, last = 0;
    for (;;) {
        float error = pup_color_sensor_reflection(color) - threshold; /* > 0: on white */
        float steer = -edge * (KP * error + KD * (error - last));
        last = error;
        pup_motor_set_power(left, POWER + (int)steer);
        pup_motor_set_power(right, POWER - (int)steer);
        dly_tsk(PERIOD_US);
    }
}
