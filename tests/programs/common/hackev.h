/*
 * HackEV's wiring and the pieces the ET Robocon-course programs beside it share (etrobo_garage, etrobo_sumo):
 * a step along the line's right edge, calibrated to ET Robocon's simulator (white 23, black 0), and the
 * distance driven from the wheel counts. Their Makefile.inc puts this folder on the include path.
 */
#ifndef HACKEV_H
#define HACKEV_H
#include "ev3api.h"

#define LIGHT_TARGET ((23 + 0) / 2)
#define WHEEL_MM 314 /* the EV3 robot's 100 mm wheels, once round */

static const sensor_port_t color = EV3_PORT_2, sonar = EV3_PORT_3, gyro = EV3_PORT_4;
static const motor_port_t left = EV3_PORT_C, right = EV3_PORT_B;

static int driven_mm(void)
{
    int deg = (ev3_motor_get_counts(left) + ev3_motor_get_counts(right)) / 2;
    return deg * WHEEL_MM / 360;
}

/* One step of the tracer, as ET Robocon's HackEV sample steers: hard left on white, hard right on black (by
 * `turn`, -100..100 of ev3_motor_steer), so that it runs along the line's right edge. */
static void trace_edge(int power, int turn)
{
    int white = ev3_color_sensor_get_reflect(color) >= LIGHT_TARGET;
    ev3_motor_steer(left, right, power, white ? -turn : turn);
}

static void stop_wheels(void)
{
    ev3_motor_stop(left, true);
    ev3_motor_stop(right, true);
}
#endif
