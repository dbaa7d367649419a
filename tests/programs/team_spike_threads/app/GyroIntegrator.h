// The heading, integrated from the hub's gyro every 5 ms in a thread of its own, read under a mutex.
#ifndef GYRO_INTEGRATOR_H
#define GYRO_INTEGRATOR_H

#include <atomic>
#include <mutex>
#include <thread>

#include "IMU.h"

class GyroIntegrator {
public:
    void start();
    void stop();
    float heading() const;

private:
    void run();

    spikeapi::IMU mImu;
    mutable std::mutex mMutex;
    float mHeading = 0.0f;
    std::atomic<bool> mRunning{false};
    std::thread mThread;
};

#endif
