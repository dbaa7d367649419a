// A PID line tracer over EV3RT's C++ classes.
#ifndef TRACER_H
#define TRACER_H

#include <string>
#include <vector>

#include "ColorSensor.h"
#include "Motor.h"
#include "Pid.h"

class Tracer {
public:
    Tracer(ev3api::Motor& left, ev3api::Motor& right, ev3api::ColorSensor& color);
    void start();
    void run();
    const std::string& name() const { return mName; }

private:
    static constexpr int POWER = 30;
    static constexpr int TARGET = 75;  // between the oval's white (100) and black (50)
    static constexpr std::size_t SMOOTHING = 2;

    ev3api::Motor& mLeft;
    ev3api::Motor& mRight;
    ev3api::ColorSensor& mColor;
    Pid mPid;
    std::vector<int> mRecent;
    std::string mName;
};

#endif
