/*
 * HackSPi's line tracer as a RasPike-ART team writes one in C, for the bench's tests: its gains are a row of a
 * command file read relative to the workspace (`make start` runs asp from there) and its edge's brightness a
 * #define (TARGET) behind #ifndef, a cyclic task traces the
 * left edge every 10 ms with a PD on the brightness, the distance is the mean of both wheel counts (the left
 * motor is mirrored, so it is set up counter-clockwise), and the colour is read in one mode only, RGB, as
 * teams do who know that each switch of the sensor's mode waits for the hub (libraspike-art's
 * raspike_port_com_change_if_needed): the brightness is the hub's reflection formula over the 10-bit RGB, and
 * blue is a blue channel above the red and the green. It prints the blue sections it meets, with their distance.
 */
#include "app.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "spike/pup/colorsensor.h"
#include "spike/pup/forcesensor.h"
#include "spike/pup/motor.h"

#define COMMAND_FILE "./raspike_command_tracer/gains.csv"
#define WHITE 40 /* HackSPi's sensor: ET Robocon's sample_c5_spike calibration */
#define BLACK 10
#ifndef TARGET
#define TARGET ((WHITE + BLACK) / 2) /* the brightness of the edge it traces */
#endif
#define WHEEL_MM_PER_DEG (56.0 * M_PI / 360.0)

static pup_motor_t *left_motor, *right_motor;
static pup_device_t *color_sensor;
static int power = 50;
static double kp = 1.0, kd = 2.0;
static int last_error;
static int in_blue;

/* The hub's reflection from its RGB (SPIKE-RT's colorsensor.c: (r + g + b) * 100 / 3072). */
static int brightness(pup_color_rgb_t rgb) { return (rgb.r + rgb.g + rgb.b) * 100 / 3072; }

static void read_gains(void)
{
    FILE *f = fopen(COMMAND_FILE, "r");
    char line[128];
    if (f == NULL) {
        printf("no %s: default gains\n", COMMAND_FILE);
        return;
    }
    while (fgets(line, sizeof line, f) != NULL) {
        if (strncmp(line, "LineTrace,", 10) == 0) {
            sscanf(line + 10, "%d,%lf,%lf", &power, &kp, &kd);
        }
    }
    fclose(f);
    printf("gains power=%d kp=%g kd=%g\n", power, kp, kd);
}

static int driven_mm(void)
{
    double counts = (pup_motor_get_count(left_motor) + pup_motor_get_count(right_motor)) / 2.0;
    return (int)(counts * WHEEL_MM_PER_DEG);
}

void main_task(intptr_t unused)
{
    read_gains();
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
    pup_color_rgb_t rgb = pup_color_sensor_rgb(color_sensor);
    int error = TARGET - brightness(rgb);
    int steer = (int)(kp * error + kd * (error - last_error));
    last_error = error;
    pup_motor_set_power(left_motor, power + steer);
    pup_motor_set_power(right_motor, power - steer);

    int blue = rgb.b > rgb.r + 40 && rgb.b > rgb.g;
    if (blue && !in_blue) {
        printf("blue at %d mm\n", driven_mm());
    }
    in_blue = blue;
    ext_tsk();
}
