#include "Tracer.h"

Tracer::Tracer(spikeapi::Motor& left, spikeapi::Motor& right, spikeapi::ColorSensor& color)
    : mLeft(left), mRight(right), mColor(color), mPd(), mName("spike-cpp-tracer")
{
}

void Tracer::run()
{
    int reflection = mColor.getReflection();
    mReadings.push_back(reflection);
    int turn = static_cast<int>(mPd.control(static_cast<float>(TARGET - reflection)));
    mLeft.setPower(POWER + turn);
    mRight.setPower(POWER - turn);
}
