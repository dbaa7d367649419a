#include "Tracer.h"

Tracer::Tracer() : leftWheel(PORT_C), rightWheel(PORT_B), colorSensor(PORT_2) {}

void Tracer::init() { syslog(LOG_NOTICE, "Tracer"); }

void Tracer::terminate()
{
    syslog(LOG_NOTICE, "Stopped after %d steps.", mSteps);
    leftWheel.stop();
    rightWheel.stop();
}

// On the line (dark) turn one way, off it the other: the tutorial's first tracer, before its PID.
void Tracer::run()
{
    if (colorSensor.getBrightness() >= mThreshold) {
        leftWheel.setPWM(0);
        rightWheel.setPWM(pwm);
    } else {
        leftWheel.setPWM(pwm);
        rightWheel.setPWM(0);
    }
    mSteps++;
}
