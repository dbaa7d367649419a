#include "GyroIntegrator.h"

#include <chrono>

void GyroIntegrator::start()
{
    mRunning = true;
    mThread = std::thread(&GyroIntegrator::run, this);
}

void GyroIntegrator::stop()
{
    mRunning = false;
    if (mThread.joinable()) {
        mThread.join();
    }
}

float GyroIntegrator::heading() const
{
    std::lock_guard<std::mutex> lock(mMutex);
    return mHeading;
}

void GyroIntegrator::run()
{
    using clock = std::chrono::steady_clock;
    auto last = clock::now();
    while (mRunning) {
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
        spikeapi::IMU::AngularVelocity rate;
        mImu.getAngularVelocity(rate);
        auto now = clock::now();
        float dt = std::chrono::duration<float>(now - last).count();
        last = now;
        std::lock_guard<std::mutex> lock(mMutex);
        mHeading += rate.z * dt;
    }
}
