/*
 * A start as ET Robocon teams program it, for HackEV (--robot hackev: colour 2, ultrasonic 3, wheels C left and
 * B right). A person puts the robot on the line's black and presses ENTER, on the white floor and presses ENTER
 * again, picks the course with LEFT or RIGHT (which edge of the line to trace), puts it on the start and holds a
 * hand in front of the ultrasonic sensor to start it. It then traces that edge with the threshold half way
 * between the black and the white it read. Black and white closer than MIN_CONTRAST mean it was never moved
 * between the two presses: the run is refused, as a team's program beeps and stays put.
 * docs/examples/calibrate-then-start.toml is that person's part.
 */
#include "ev3api.h"

#define COLOR EV3_PORT_2
#define SONAR EV3_PORT_3
#define LEFT_MOTOR EV3_PORT_C
#define RIGHT_MOTOR EV3_PORT_B
#define PERIOD_US (10 * 1000)
#define SAMPLES 8 /* readings averaged for black and for white */
#define MIN_CONTRAST 20
#define START_CM 10 /* a hand nearer than this starts the run */
#define POWER 35
#define KP 2.5f
#define KD 6.0f

static void wait_click(button_t button)
{
    while (!ev3_button_is_pressed(button)) {
        tslp_tsk(PERIOD_US);
    }
    while (ev3_button_is_pressed(button)) {
        tslp_tsk(PERIOD_US);
    }
}

static int average_reflect(void)
{
    int sum = 0;
    for (int i = 0; i < SAMPLES; i++) {
        sum += ev3_color_sensor_get_reflect(COLOR);
        tslp_tsk(PERIOD_US);
    }
    return sum / SAMPLES;
}

/* +1: the line's right edge (the R course), -1: its left edge (the L course). */
static int pick_edge(void)
{
    for (;;) {
        if (ev3_button_is_pressed(LEFT_BUTTON)) {
            wait_click(LEFT_BUTTON);
            return -1;
        }
        if (ev3_button_is_pressed(RIGHT_BUTTON)) {
            wait_click(RIGHT_BUTTON);
            return 1;
        }
        tslp_tsk(PERIOD_US);
    }
}

void main_task(intptr_t unused)
{
    ev3_sensor_config(COLOR, COLOR_SENSOR);
    ev3_sensor_config(SONAR, ULTRASONIC_SENSOR);
    ev3_motor_config(LEFT_MOTOR, LARGE_MOTOR);
    ev3_motor_config(RIGHT_MOTOR, LARGE_MOTOR);

    syslog(LOG_NOTICE, "Put me on black, press ENTER");
    wait_click(ENTER_BUTTON);
    int black = average_reflect();
    syslog(LOG_NOTICE, "black %d. Put me on white, press ENTER", black);
    wait_click(ENTER_BUTTON);
    int white = average_reflect();
    if (white - black < MIN_CONTRAST) {
        syslog(LOG_NOTICE, "calibration failed: black %d, white %d", black, white);
        ext_tsk();
    }
    syslog(LOG_NOTICE, "white %d. LEFT or RIGHT course?", white);
    int edge = pick_edge();
    syslog(LOG_NOTICE, "%s course. Hand in front of the sensor to start", edge > 0 ? "R" : "L");
    while (ev3_ultrasonic_sensor_get_distance(SONAR) >= START_CM) {
        tslp_tsk(PERIOD_US);
    }
    syslog(LOG_NOTICE, "start");

    float threshold = (black + white) / 2.0f, last = 0;
    for (;;) {
        float error = ev3_color_sensor_get_reflect(COLOR) - threshold; /* > 0: on white */
        float steer = -edge * (KP * error + KD * (error - last));
        last = error;
        int turn = steer > 100 ? 100 : steer < -100 ? -100 : (int)steer;
        ev3_motor_steer(LEFT_MOTOR, RIGHT_MOTOR, POWER, turn);
        tslp_tsk(PERIOD_US);
    }
}
