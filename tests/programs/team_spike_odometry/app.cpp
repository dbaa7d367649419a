// A HackSPi run as teams write it: the distance is the mean of both wheel counts (the left motor is mounted
// mirror-wise, so it is set up counter-clockwise and counts up going forward, as on the hub), each wheel is
// held at its target speed by a PI loop on its measured speed (get_speed, deg/s), and the line's edge steers
// the targets apart. It stops after DISTANCE_MM and says the run is over.
#include "spike_drive_task.h"

#include <cstdio>

#include "ColorSensor.h"
#include "ForceSensor.h"
#include "Motor.h"
#include "etroboc_ext.h"

using namespace spikeapi;

static constexpr float WHEEL_MM_PER_DEG = 56.0f * 3.14159265f / 360.0f;  // SPIKE's 56 mm wheel
static constexpr int DISTANCE_MM = 3000;
static constexpr int BASE_DPS = 400;     // both wheels' target on a straight, deg/s
static constexpr int TARGET = 25;        // between the sensor's white (40) and black (10)
static constexpr float STEER_DPS = 8.0f; // deg/s of difference per unit of reflection off the edge
static constexpr float FEED = 0.1f;      // power per deg/s: about 1000 deg/s at full power
static constexpr float KP = 0.05f;
static constexpr float KI = 0.5f;        // per second

static Motor gLeft(EPort::PORT_B, Motor::EDirection::COUNTERCLOCKWISE);
static Motor gRight(EPort::PORT_A, Motor::EDirection::CLOCKWISE);
static ColorSensor gColor(EPort::PORT_E);
static ForceSensor gForce(EPort::PORT_D);

struct SpeedLoop {
    const Motor& motor;
    float integral = 0;

    int power(int target_dps) {
        float error = static_cast<float>(target_dps - motor.getSpeed());
        integral += error * DRIVE_PERIOD_US / 1e6f;
        return static_cast<int>(FEED * target_dps + KP * error + KI * integral);
    }
};

static SpeedLoop gLeftLoop{gLeft}, gRightLoop{gRight};
static int gTicks;

static int drivenMm()
{
    return static_cast<int>((gLeft.getCount() + gRight.getCount()) / 2.0f * WHEEL_MM_PER_DEG);
}

void main_task(intptr_t unused)
{
    while (!gForce.isTouched())
        dly_tsk(10 * 1000);
    gLeft.resetCount();
    gRight.resetCount();
    std::printf("go\n");
    sta_cyc(DRIVE_CYC);
    ext_tsk();
}

void drive_task(intptr_t unused)
{
    int driven = drivenMm();
    if (driven >= DISTANCE_MM) {
        stp_cyc(DRIVE_CYC);
        gLeft.brake();
        gRight.brake();
        std::printf("stopped at %d mm (counts %d %d)\n", driven, static_cast<int>(gLeft.getCount()),
                    static_cast<int>(gRight.getCount()));
        ETRoboc_notifyCompletedToSimulator();
        ext_tsk();
    }
    int steer = static_cast<int>(STEER_DPS * (TARGET - gColor.getReflection()));
    gLeft.setPower(gLeftLoop.power(BASE_DPS + steer));
    gRight.setPower(gRightLoop.power(BASE_DPS - steer));
    if (++gTicks % 50 == 0)
        std::printf("speed %d %d at %d mm\n", static_cast<int>(gLeft.getSpeed()), static_cast<int>(gRight.getSpeed()),
                    driven);
    ext_tsk();
}
