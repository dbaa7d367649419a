// The tracer's start: wait for the touch sensor, then trace the line every 10 ms.
#include "app.h"
#include "Tracer.h"
#include "TouchSensor.h"
#include "Clock.h"

using namespace ev3api;

// Objects with static storage, as teams write them: constructed before the first task runs.
static Motor gLeftWheel(PORT_A);
static Motor gRightWheel(PORT_B);
static ColorSensor gColorSensor(PORT_1);
static TouchSensor gBumper(PORT_3);
static TouchSensor gStartButton(PORT_4);
static Clock gClock;
static Tracer gTracer(gLeftWheel, gRightWheel, gColorSensor);

void main_task(intptr_t unused)
{
    while (!gStartButton.isPressed()) {
        gClock.sleep(10 * 1000);
    }
    gTracer.start();
    syslog(LOG_NOTICE, "%s started at %u us", gTracer.name().c_str(), static_cast<unsigned>(gClock.now()));
    sta_cyc(TRACER_CYC);
    ext_tsk();
}

void tracer_task(intptr_t unused)
{
    gTracer.run();
    ext_tsk();
}
