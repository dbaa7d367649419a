// HackSPi's line tracer as teams write it since RasPike-ART: the hub's devices through libcpp-spike, and the
// rest as a Linux program does it. The control loop is a std::thread paced by sleep_until on steady_clock; a
// second thread integrates the gyro under a mutex; a logger thread, fed through a condition variable, writes a
// CSV beside the program; the gains are a row of datafiles/LineTraceLeft.csv, read relative to the workspace.
#include "app.h"

#include <chrono>
#include <cstdio>
#include <thread>

#include "CommandFile.h"
#include "CsvLogger.h"
#include "ForceSensor.h"
#include "Port.h"
#include "GyroIntegrator.h"
#include "LineTracer.h"

using namespace std::chrono;

static spikeapi::Motor gLeftWheel(EPort::PORT_B, spikeapi::Motor::EDirection::COUNTERCLOCKWISE);
static spikeapi::Motor gRightWheel(EPort::PORT_A, spikeapi::Motor::EDirection::CLOCKWISE);
static spikeapi::ColorSensor gColorSensor(EPort::PORT_E);
static spikeapi::ForceSensor gForceSensor(EPort::PORT_D);

void main_task(intptr_t unused)
{
    // The workspace is the working directory, as when `make app=team_spike_threads start` runs it.
    CommandFile commands("./team_spike_threads/datafiles/LineTraceLeft.csv");
    TraceParams params;
    if (!commands.find("LineTrace", params)) {
        printf("no LineTrace row in %s: default gains\n", commands.path().c_str());
    }
    printf("gains kp=%g ki=%g kd=%g power=%d\n", params.kp, params.ki, params.kd, params.power);

    printf("Push the force sensor to start\n");
    while (!gForceSensor.isTouched()) {
        std::this_thread::sleep_for(milliseconds(10));
    }

    CsvLogger logger("./team_spike_threads/run_log.csv");
    GyroIntegrator gyro;
    LineTracer tracer(gLeftWheel, gRightWheel, gColorSensor, params, gyro, logger);
    gyro.start();
    tracer.start();
    tracer.join();  // the tracer runs until the test ends
    gyro.stop();
    logger.stop();
}
