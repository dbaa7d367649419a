// The benchmark's HackSPi tracer (scripts/bench_sim.py): the control of ET Robocon's sample_c5_spike, a
// proportional steer every 100 ms, written as teams write it for RasPike-ART: the loop is a std::thread paced
// by sleep_until on steady_clock, started by the main task through a condition variable once the force sensor
// is pressed. Its rate against the sample's is what the threads and clocks cost.
#include "app.h"

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <thread>

#include "spike/pup/colorsensor.h"
#include "spike/pup/forcesensor.h"
#include "spike/pup/motor.h"

namespace {
constexpr int WHITE = 40, BLACK = 10;  // the SPIKE sensor on ET Robocon's mat
constexpr float GAIN = 0.8f;
constexpr int POWER = 50;
constexpr auto PERIOD = std::chrono::milliseconds(100);

std::mutex gLock;
std::condition_variable gGo;
bool gStarted = false;

void trace(pup_motor_t* left, pup_motor_t* right, pup_device_t* color)
{
    {
        std::unique_lock<std::mutex> lock(gLock);
        gGo.wait(lock, [] { return gStarted; });
    }
    auto next = std::chrono::steady_clock::now();
    for (;;) {
        int steer = static_cast<int>(GAIN * static_cast<float>((WHITE + BLACK) / 2 - pup_color_sensor_reflection(color)));
        pup_motor_set_power(left, POWER + steer);
        pup_motor_set_power(right, POWER - steer);
        next += PERIOD;
        std::this_thread::sleep_until(next);
    }
}
}  // namespace

void main_task(intptr_t unused)
{
    pup_motor_t* left = pup_motor_get_device(PBIO_PORT_ID_B);
    pup_motor_t* right = pup_motor_get_device(PBIO_PORT_ID_A);
    pup_motor_setup(left, PUP_DIRECTION_COUNTERCLOCKWISE, true);
    pup_motor_setup(right, PUP_DIRECTION_CLOCKWISE, true);
    pup_device_t* color = pup_color_sensor_get_device(PBIO_PORT_ID_E);
    pup_device_t* force = pup_force_sensor_get_device(PBIO_PORT_ID_D);
    std::thread tracer(trace, left, right, color);
    while (!pup_force_sensor_touched(force)) {
        std::this_thread::sleep_for(PERIOD);
    }
    {
        std::lock_guard<std::mutex> lock(gLock);
        gStarted = true;
    }
    gGo.notify_one();
    tracer.join();
}
