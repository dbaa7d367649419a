// The tutorial's app.cpp: the tracer and the clock are globals beside main_task, named as the tutorial names
// them; `clock` is the program's own, as on the robot, where it wins over the C library's clock().
#include "app.h"
#include "Tracer.h"
#include "Clock.h"

using namespace ev3api;

Tracer tracer;
Clock clock;

void tracer_task(intptr_t exinf)
{
    tracer.run();
    ext_tsk();
}

void main_task(intptr_t unused)
{
    const uint32_t duration = 100 * 1000;

    tracer.init();
    sta_cyc(TRACER_CYC);
    for (int i = 0; i < 5; i++) { // the tutorial waits for a button here; five periods do for the tests
        clock.sleep(duration);
    }
    stp_cyc(TRACER_CYC);
    tracer.terminate();
    syslog(LOG_NOTICE, "main_task ends at %u us", static_cast<unsigned>(clock.now()));
    ext_tsk();
}
