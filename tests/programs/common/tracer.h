/*
 * The line tracer of the paper's Fig. 7, as athrill_sim/apps/line_trace.c computes it, with its gains and
 * motor power given: the programs beside it keep them as teams keep theirs (a macro, a global, a data file,
 * a constant in a header). Their Makefile.inc puts this folder on the include path.
 */
#ifndef TRACER_H
#define TRACER_H
#include "ev3api.h"

#define WHITE 100
#define BLACK 50

static const motor_port_t left_motor = EV3_PORT_A;
static const motor_port_t right_motor = EV3_PORT_B;
static const sensor_port_t color_sensor = EV3_PORT_1;

static void trace(float kp, float ki, float kd, float power)
{
    ev3_sensor_config(color_sensor, COLOR_SENSOR);
    ev3_motor_config(left_motor, LARGE_MOTOR);
    ev3_motor_config(right_motor, LARGE_MOTOR);

    float lasterror = 0, integral = 0;
    float mid = (WHITE - BLACK) / 2 + BLACK;
    while (1) {
        float error = mid - ev3_color_sensor_get_reflect(color_sensor);
        integral = error + integral * 0.01;
        float steer = kp * error + ki * integral + kd * (error - lasterror);
        int turn = steer > 100 ? 100 : steer < -100 ? -100 : (int)steer;
        ev3_motor_steer(left_motor, right_motor, (int)power, turn);
        lasterror = error;
        tslp_tsk(100000); /* 100 ms */
    }
}
#endif
