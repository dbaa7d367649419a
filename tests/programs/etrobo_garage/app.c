/* ET Robocon's run on the bench's etrobocon-l course, on HackEV: trace the line's right edge (steering as
 * ET Robocon's HackEV sample does, calibrated white 23 / black 0) until the second blue section, the landmark
 * before the garage; follow it a little further to where the line ends, drive straight into the garage by the
 * wheel counts, and stop there. Under --objective etrobocon the run ends as FINISH once the robot has stood
 * still in the garage for 3 s, scored by its LAP time, gates and finish. */
#include "ev3api.h"
#include "app.h"
#include "hackev.h"
#include "gains.h"

#define PERIOD_US (4 * 1000)
#define BLUE_READINGS 3     /* consecutive blue readings that make a blue section */
#define SECTION_GAP_MM 400  /* blue seen again within this much driving is the same section */
#define GARAGE_BLUE 2       /* the garage's landmark: the second blue section of the run */
#define FOLLOW_MM 300       /* from the landmark's start, along the line to its end */
#define INTO_GARAGE_MM 300  /* then straight into the garage */

void main_task(intptr_t unused)
{
    ev3_sensor_config(color, COLOR_SENSOR);
    ev3_motor_config(left, LARGE_MOTOR);
    ev3_motor_config(right, LARGE_MOTOR);
    ev3_motor_reset_counts(left);
    ev3_motor_reset_counts(right);
    int blue = 0, sections = 0, last_blue_mm = -SECTION_GAP_MM;
    while (sections < GARAGE_BLUE) {
        trace_edge(POWER, TURN);
        if (ev3_color_sensor_get_color(color) != COLOR_BLUE) {
            blue = 0;
        } else if (++blue >= BLUE_READINGS) {
            if (driven_mm() - last_blue_mm >= SECTION_GAP_MM) {
                sections++;
                syslog(LOG_NOTICE, "blue section %d at %d mm", sections, driven_mm());
            }
            last_blue_mm = driven_mm();
        }
        tslp_tsk(PERIOD_US);
    }
    int landmark = driven_mm();
    while (driven_mm() - landmark < FOLLOW_MM) {
        trace_edge(POWER, TURN);
        tslp_tsk(PERIOD_US);
    }
    int straight = driven_mm();
    ev3_motor_set_power(left, POWER);
    ev3_motor_set_power(right, POWER);
    while (driven_mm() - straight < INTO_GARAGE_MM)
        tslp_tsk(PERIOD_US);
    stop_wheels();
    syslog(LOG_NOTICE, "stopped in the garage at %d mm", driven_mm());
    ext_tsk();
}
