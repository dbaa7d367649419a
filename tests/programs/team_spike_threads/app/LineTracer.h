// The PID line tracer: a std::thread that runs every 10 ms, paced by sleep_until on steady_clock.
#ifndef LINE_TRACER_H
#define LINE_TRACER_H

#include <atomic>
#include <thread>

#include "ColorSensor.h"
#include "CommandFile.h"
#include "CsvLogger.h"
#include "GyroIntegrator.h"
#include "Motor.h"

class LineTracer {
public:
    LineTracer(spikeapi::Motor& left, spikeapi::Motor& right, spikeapi::ColorSensor& color, const TraceParams& params,
               const GyroIntegrator& gyro, CsvLogger& logger);
    void start();
    void join();

private:
    void run();

    static constexpr int TARGET = 25;  // between the SPIKE sensor's white (40) and black (10)
    static constexpr int PERIOD_MS = 10;

    spikeapi::Motor& mLeft;
    spikeapi::Motor& mRight;
    spikeapi::ColorSensor& mColor;
    TraceParams mParams;
    const GyroIntegrator& mGyro;
    CsvLogger& mLogger;
    std::thread mThread;
};

#endif
