/*
 * The line tracer of the paper's Fig. 7, in C, for the native mock (`--app line_trace_c`).
 *
 * The gains and the motor power are read through their guest addresses on every loop, as the paper's code
 * dereferences its pointers; the test controller writes them into unity_mmap.bin before the start.
 * athrill_sim/apps/line_trace.py computes the same float32 arithmetic step for step; built with
 * -ffp-contract=off (no fused multiply-add), the two steer the robot bit for bit alike.
 */
#include "ev3api.h"

#define WHITE 100
#define BLACK 50

#define Kp (*(volatile float *)(0x090F0000 + 540))
#define Ki (*(volatile float *)(0x090F0000 + 544))
#define Kd (*(volatile float *)(0x090F0000 + 548))
#define MOTOR_POWER (*(volatile float *)(0x090F0000 + 552))

static const motor_port_t left_motor = EV3_PORT_A;
static const motor_port_t right_motor = EV3_PORT_B;
static const sensor_port_t color_sensor = EV3_PORT_1;

/* EV3RT caps |turn| at 100 itself; clamping first keeps a float beyond int's range out of C's undefined
 * float-to-int conversion. Both arguments are converted to int, truncating. */
static void motor_steer(motor_port_t left, motor_port_t right, float power, float steer)
{
    int turn = steer > 100 ? 100 : steer < -100 ? -100 : (int)steer;
    ev3_motor_steer(left, right, (int)power, turn);
}

void main_task(intptr_t unused)
{
    ev3_sensor_config(color_sensor, COLOR_SENSOR);
    ev3_motor_config(left_motor, LARGE_MOTOR);
    ev3_motor_config(right_motor, LARGE_MOTOR);

    float lasterror = 0, integral = 0;
    float mid = (WHITE - BLACK) / 2 + BLACK;
    while (1) {
        float error = mid - ev3_color_sensor_get_reflect(color_sensor);
        integral = error + integral * 0.01;
        float steer = Kp * error + Ki * integral + Kd * (error - lasterror);
        motor_steer(left_motor, right_motor, MOTOR_POWER, steer);
        lasterror = error;
        tslp_tsk(100000); /* 100 ms */
    }
}
