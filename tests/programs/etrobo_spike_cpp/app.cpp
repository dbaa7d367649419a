// HackSPi's line tracer on libcpp-spike: wait for the force sensor, then trace every 10 ms.
#include "app.h"

#include <cstdio>

#include "Clock.h"
#include "ForceSensor.h"
#include "IMU.h"
#include "Tracer.h"

using namespace spikeapi;

// HackSPi's wiring (RasPike-ART's sample_c5_spike): its left motor is mounted mirror-wise.
static Motor gLeftWheel(EPort::PORT_B, Motor::EDirection::COUNTERCLOCKWISE);
static Motor gRightWheel(EPort::PORT_A, Motor::EDirection::CLOCKWISE);
static ColorSensor gColorSensor(EPort::PORT_E);
static ForceSensor gForceSensor(EPort::PORT_D);
static IMU gImu;
static Clock gClock;
static Tracer gTracer(gLeftWheel, gRightWheel, gColorSensor);

void main_task(intptr_t unused)
{
    while (!gForceSensor.isTouched()) {
        gClock.sleep(10 * 1000);
    }
    IMU::AngularVelocity rate;
    gImu.getAngularVelocity(rate);
    printf("%s started at %u ms, turning at %d deg/s\n", gTracer.name().c_str(),
           static_cast<unsigned>(gClock.now() / 1000), static_cast<int>(rate.z));
    sta_cyc(TRACER_CYC);
    ext_tsk();
}

void tracer_task(intptr_t unused)
{
    gTracer.run();
    ext_tsk();
}
