/* HackEV's wiring: touch 1, colour 2, wheels C (left) and B (right). */
#include "tracer.h"

#define LEFT EV3_PORT_C
#define RIGHT EV3_PORT_B
#define COLOR EV3_PORT_2
#define TARGET 75
#define POWER 30

static int last_error;

void tracer_init(void)
{
    ev3_sensor_config(COLOR, COLOR_SENSOR);
    ev3_motor_config(LEFT, LARGE_MOTOR);
    ev3_motor_config(RIGHT, LARGE_MOTOR);
}

void tracer_run(void)
{
    int error = TARGET - ev3_color_sensor_get_reflect(COLOR);
    int turn = (6 * error + 20 * (error - last_error)) / 10;
    last_error = error;
    ev3_motor_set_power(LEFT, POWER + turn);
    ev3_motor_set_power(RIGHT, POWER - turn);
}
