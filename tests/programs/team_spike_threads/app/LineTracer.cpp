#include "LineTracer.h"

#include <chrono>
#include <csignal>
#include <cstdio>
#include <string>

namespace {
std::atomic<bool> gInterrupted{false};

void onInterrupt(int) { gInterrupted = true; }
}  // namespace

LineTracer::LineTracer(spikeapi::Motor& left, spikeapi::Motor& right, spikeapi::ColorSensor& color,
                       const TraceParams& params, const GyroIntegrator& gyro, CsvLogger& logger)
    : mLeft(left), mRight(right), mColor(color), mParams(params), mGyro(gyro), mLogger(logger)
{
    std::signal(SIGINT, onInterrupt);  // Ctrl-C: stop the motors and close the log
}

void LineTracer::start() { mThread = std::thread(&LineTracer::run, this); }

void LineTracer::join() { mThread.join(); }

void LineTracer::run()
{
    using namespace std::chrono;
    auto start = steady_clock::now();
    auto next = start;
    float integral = 0.0f;
    float last = 0.0f;
    int tick = 0;
    while (!gInterrupted) {
        int reflection = mColor.getReflection();
        float error = static_cast<float>(TARGET - reflection);
        integral += error * PERIOD_MS / 1000.0f;
        float turn = mParams.kp * error + mParams.ki * integral + mParams.kd * (error - last);
        last = error;
        mLeft.setPower(mParams.power + static_cast<int>(turn));
        mRight.setPower(mParams.power - static_cast<int>(turn));
        if (++tick % 10 == 0) {
            auto ms = duration_cast<milliseconds>(steady_clock::now() - start).count();
            mLogger.log(std::to_string(ms) + "," + std::to_string(reflection) + "," +
                        std::to_string(static_cast<int>(turn)) + "," + std::to_string(mGyro.heading()));
        }
        next += milliseconds(PERIOD_MS);
        std::this_thread::sleep_until(next);
    }
    mLeft.stop();
    mRight.stop();
    std::printf("interrupted after %d periods\n", tick);
}
