#include "Tracer.h"

#include <numeric>

Tracer::Tracer(ev3api::Motor& left, ev3api::Motor& right, ev3api::ColorSensor& color)
    : mLeft(left), mRight(right), mColor(color), mPid(), mName("cpp-tracer")
{
}

void Tracer::start()
{
    mName += " (running)";
    mRecent.clear();
}

void Tracer::run()
{
    mRecent.push_back(mColor.getBrightness());
    if (mRecent.size() > SMOOTHING) {
        mRecent.erase(mRecent.begin());
    }
    int sum = std::accumulate(mRecent.begin(), mRecent.end(), 0);
    float brightness = static_cast<float>(sum) / static_cast<float>(mRecent.size());
    int turn = static_cast<int>(mPid.control(TARGET - brightness));
    mLeft.setPWM(POWER + turn);
    mRight.setPWM(POWER - turn);
}
