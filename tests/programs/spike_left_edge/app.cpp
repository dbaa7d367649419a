// A team's left-edge tracer for HackSPi, written as teams write it for RasPike-ART: a LineTracer class that
// keeps its colour sensor on the LEFT edge of the line (black on its right, white on its left), a
// proportional steer every 10 ms paced by sleep_until on steady_clock, started by the force sensor. Set down
// on the line's right edge it steers the wrong way at once: a team puts it down on the left edge
// (`[[place]] over = "start"`, `edge = "left"`).
#include "app.h"

#include <chrono>
#include <cstdio>
#include <thread>

#include "spike/pup/colorsensor.h"
#include "spike/pup/forcesensor.h"
#include "spike/pup/motor.h"

namespace {
constexpr int WHITE = 40, BLACK = 10;  // the SPIKE sensor on ET Robocon's mat
constexpr auto PERIOD = std::chrono::milliseconds(10);

enum class Edge { Left = 1, Right = -1 };  // which side of the line the sensor keeps to

class LineTracer {
public:
    // HackSPi's wheels: the left motor on port B, mounted mirror-wise, the right on A; the colour sensor on E.
    explicit LineTracer(Edge edge)
        : left_(pup_motor_get_device(PBIO_PORT_ID_B)), right_(pup_motor_get_device(PBIO_PORT_ID_A)),
          color_(pup_color_sensor_get_device(PBIO_PORT_ID_E)), edge_(edge)
    {
        pup_motor_setup(left_, PUP_DIRECTION_COUNTERCLOCKWISE, true);
        pup_motor_setup(right_, PUP_DIRECTION_CLOCKWISE, true);
    }

    // More white than the target means the sensor has drifted off the edge, away from the line: on the left
    // edge the line is to the right, so the robot turns right (left wheel faster).
    void step()
    {
        int error = pup_color_sensor_reflection(color_) - (WHITE + BLACK) / 2;
        int steer = static_cast<int>(kKp * static_cast<float>(error)) * static_cast<int>(edge_);
        pup_motor_set_power(left_, kPower + steer);
        pup_motor_set_power(right_, kPower - steer);
    }

private:
    static constexpr float kKp = 1.5f;
    static constexpr int kPower = 40;
    pup_motor_t* left_;
    pup_motor_t* right_;
    pup_device_t* color_;
    Edge edge_;
};
}  // namespace

void main_task(intptr_t unused)
{
    LineTracer tracer(Edge::Left);
    pup_device_t* force = pup_force_sensor_get_device(PBIO_PORT_ID_D);
    while (!pup_force_sensor_touched(force)) {
        std::this_thread::sleep_for(PERIOD);
    }
    std::printf("left edge tracer: go\n");
    for (auto next = std::chrono::steady_clock::now();; std::this_thread::sleep_until(next)) {
        tracer.step();
        next += PERIOD;
    }
}
