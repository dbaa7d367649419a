/* ET Robocon's sumo on the bench's etrobocon-l course, on HackEV: trace the line's right edge past the LAP
 * gate to the sumo ring (its yellow outline, which the line crosses), drive on to level with the bottle, turn
 * left on the spot until the ultrasonic sensor has swept across the bottle, face its middle, push it straight
 * out of the ring and stop inside, then tell the simulator the run is over. Under --objective etrobocon the
 * score counts the LAP, the gates and the bottle: out of the ring, standing, and the robot not out with it. */
#include "ev3api.h"
#include "app.h"
#include "hackev.h"
#include "etroboc_ext.h"

#define POWER 30
#define TURN 80
#define PERIOD_US (4 * 1000)
#define SONAR_US (40 * 1000)  /* the ultrasonic sensor's pace */
#define YELLOW_READINGS 2
#define TO_BOTTLE_MM 260      /* from where the sensor meets the ring to the axle level with the bottle */
#define SEES_CM 45            /* nearer than this, the ultrasonic sensor sees the bottle */
#define OUT_MM 550            /* past the ring: its radius, the bottle's, and what the wheels slip while pushing */
#define SONAR_TO_FRONT_MM 15  /* the ultrasonic sensor sits this far ahead of the robot's front */
#define SLOW 15

/* Straight ahead for `mm`, holding the gyro's heading `heading`. */
static void straight(int mm, int heading)
{
    int from = driven_mm();
    while (driven_mm() - from < mm) {
        int turn = heading - ev3_gyro_sensor_get_angle(gyro);
        ev3_motor_set_power(left, SLOW + turn);
        ev3_motor_set_power(right, SLOW - turn);
        tslp_tsk(PERIOD_US);
    }
    stop_wheels();
}

/* Turn on the spot (left: `sign` -1, the gyro counting down) until `done` says so, looking every 40 ms. */
static int sweep(int sign, int (*done)(int cm, int angle))
{
    for (;;) {
        ev3_motor_set_power(left, sign * SLOW / 2);
        ev3_motor_set_power(right, -sign * SLOW / 2);
        tslp_tsk(SONAR_US);
        int cm = ev3_ultrasonic_sensor_get_distance(sonar), angle = ev3_gyro_sensor_get_angle(gyro);
        if (done(cm, angle)) {
            stop_wheels();
            return angle;
        }
    }
}

static int nearest_cm = 255;
static int sees(int cm, int angle) { (void)angle; if (cm < nearest_cm) nearest_cm = cm; return cm < SEES_CM; }
static int lost(int cm, int angle) { (void)angle; if (cm < nearest_cm) nearest_cm = cm; return cm >= SEES_CM; }
static int middle;
static int faces(int cm, int angle) { (void)cm; return angle >= middle; }

void main_task(intptr_t unused)
{
    ev3_sensor_config(color, COLOR_SENSOR);
    ev3_sensor_config(sonar, ULTRASONIC_SENSOR);
    ev3_sensor_config(gyro, GYRO_SENSOR);
    ev3_motor_config(left, LARGE_MOTOR);
    ev3_motor_config(right, LARGE_MOTOR);
    ev3_motor_reset_counts(left);
    ev3_motor_reset_counts(right);
    int yellow = 0;
    while (yellow < YELLOW_READINGS) {
        trace_edge(POWER, TURN);
        colorid_t seen = ev3_color_sensor_get_color(color);
        /* On the line's edge the outline is half black: a dark yellow, which the sensor may call brown. */
        yellow = seen == COLOR_YELLOW || seen == COLOR_BROWN ? yellow + 1 : 0;
        tslp_tsk(PERIOD_US);
    }
    syslog(LOG_NOTICE, "the ring at %d mm", driven_mm());
    ev3_gyro_sensor_reset(gyro);
    straight(TO_BOTTLE_MM, 0);
    int first = sweep(-1, sees), last = sweep(-1, lost);
    middle = (first + last) / 2;
    sweep(1, faces);
    syslog(LOG_NOTICE, "the bottle %d cm away, between %d and %d deg", nearest_cm, first, last);
    straight(nearest_cm * 10 + SONAR_TO_FRONT_MM + OUT_MM, middle);
    syslog(LOG_NOTICE, "pushed at %d mm", driven_mm());
    tslp_tsk(1000 * 1000);
    ETRoboc_notifyCompletedToSimulator();
    ext_tsk();
}
