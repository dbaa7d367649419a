// A PD line tracer over ET Robocon's libcpp-spike classes.
#ifndef TRACER_H
#define TRACER_H

#include <string>
#include <vector>

#include "ColorSensor.h"
#include "Motor.h"
#include "Pd.h"

class Tracer {
public:
    Tracer(spikeapi::Motor& left, spikeapi::Motor& right, spikeapi::ColorSensor& color);
    void run();
    const std::string& name() const { return mName; }

private:
    static constexpr int POWER = 50;
    static constexpr int TARGET = 25;  // between the SPIKE sensor's white (40) and black (10), as sample_c5_spike

    spikeapi::Motor& mLeft;
    spikeapi::Motor& mRight;
    spikeapi::ColorSensor& mColor;
    Pd mPd;
    std::vector<int> mReadings;
    std::string mName;
};

#endif
