/* ET Robocon's start: wait for the touch sensor, trace the line for 8 s, then tell the simulator the run is
 * complete, as a competition program does at its end. */
#include "app.h"
#include "etroboc_ext.h"
#include "tracer.h"

#define TOUCH EV3_PORT_1
#define RUN_US (8 * 1000 * 1000)

void main_task(intptr_t unused)
{
    ev3_sensor_config(TOUCH, TOUCH_SENSOR);
    tracer_init();
    while (!ev3_touch_sensor_is_pressed(TOUCH)) {
        tslp_tsk(10 * 1000);
    }
    SYSTIM start;
    get_tim(&start);
    sta_cyc(CYC_TRACER);
    tslp_tsk(RUN_US);
    stp_cyc(CYC_TRACER);
    ev3_motor_stop(EV3_PORT_C, true);
    ev3_motor_stop(EV3_PORT_B, true);
    ETRoboc_notifyCompletedToSimulator();
    ext_tsk();
}

void tracer_task(intptr_t unused)
{
    tracer_run();
    ext_tsk();
}
