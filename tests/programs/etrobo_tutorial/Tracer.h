// A line tracer in the tutorial's shape: two wheels and a colour sensor, one step of steering per call.
#include "Motor.h"
#include "ColorSensor.h"
#include "app.h"

using namespace ev3api;

class Tracer {
public:
    Tracer();
    void run();
    void init();
    void terminate();
    int steps() const { return mSteps; }

private:
    Motor leftWheel;
    Motor rightWheel;
    ColorSensor colorSensor;
    const int8_t mThreshold = 20;
    const int8_t pwm = (Motor::PWM_MAX) / 6;
    int mSteps = 0;
};
