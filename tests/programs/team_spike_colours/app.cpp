// A HackSPi run as teams write it: trace the line's right edge by the reflection (as ET Robocon's
// sample_c5_spike does), and name every reading by the rules teams tune on the real mat: on the hub's HSV, a
// hue of 200..280 with some saturation is blue, else v below 32 is black and s below 40 white; on its 10-bit
// RGB, blue is b well above r and above g. A few blue readings in a row by a rule are a blue section; the lane
// has two (after the first curve, and before the garage), and past the second the run is over.
#include "spike_drive_task.h"

#include <cstdio>

#include "ColorSensor.h"
#include "ForceSensor.h"
#include "Motor.h"
#include "etroboc_ext.h"

using namespace spikeapi;

static constexpr float WHEEL_MM_PER_DEG = 56.0f * 3.14159265f / 360.0f;
static constexpr int POWER = 30;
static constexpr int TARGET = 25;  // between the sensor's white (40) and black (10)
static constexpr float KP = 1.5f;  // sample_c5_spike's
static constexpr int IN_A_ROW = 3;  // blue readings in a row that make a blue section
static constexpr int PAST_MM = 100;  // driven without a blue reading: the section is behind
static constexpr int SECTIONS = 2;  // the lane's blue sections

enum class Named { BLACK, WHITE, BLUE, OTHER };

static Motor gLeft(EPort::PORT_B, Motor::EDirection::COUNTERCLOCKWISE);
static Motor gRight(EPort::PORT_A, Motor::EDirection::CLOCKWISE);
static ColorSensor gColor(EPort::PORT_E);
static ForceSensor gForce(EPort::PORT_D);

static Named byHsv(const ColorSensor::HSV& hsv)
{
    if (hsv.h >= 200 && hsv.h <= 280 && hsv.s >= 20)
        return Named::BLUE;
    if (hsv.v < 32)
        return Named::BLACK;
    if (hsv.s < 40)
        return Named::WHITE;
    return Named::OTHER;
}

static bool blueByRgb(const ColorSensor::RGB& rgb) { return rgb.b > rgb.r + 60 && rgb.b > rgb.g; }

struct Detector {
    const char* rule;
    int inARow = 0;
    int found = 0;  // sections seen
    bool inside = false;  // on a section now
    int lastMm = 0;  // the last blue reading

    void see(bool blue, int mm, const ColorSensor::HSV& hsv, const ColorSensor::RGB& rgb) {
        inARow = blue ? inARow + 1 : 0;
        if (inside && mm - lastMm > PAST_MM)
            inside = false;
        if (inARow >= IN_A_ROW && !inside) {
            inside = true;
            found++;
            std::printf("%s: blue section %d at %d mm (hsv %d %d %d, rgb %d %d %d)\n", rule, found, mm, hsv.h, hsv.s,
                        hsv.v, rgb.r, rgb.g, rgb.b);
        }
        if (blue)
            lastMm = mm;
    }

    bool done() const { return found >= SECTIONS && !inside; }
};

static Detector gHsvRule{"hsv"}, gRgbRule{"rgb"};
static int gSeen[4];

static int drivenMm()
{
    return static_cast<int>((gLeft.getCount() + gRight.getCount()) / 2.0f * WHEEL_MM_PER_DEG);
}

void main_task(intptr_t unused)
{
    while (!gForce.isTouched())
        dly_tsk(10 * 1000);
    sta_cyc(DRIVE_CYC);
    ext_tsk();
}

void drive_task(intptr_t unused)
{
    int mm = drivenMm();
    ColorSensor::HSV hsv;
    ColorSensor::RGB rgb;
    gColor.getHSV(hsv);
    gColor.getRGB(rgb);
    Named named = byHsv(hsv);
    gSeen[static_cast<int>(named)]++;
    gHsvRule.see(named == Named::BLUE, mm, hsv, rgb);
    gRgbRule.see(blueByRgb(rgb), mm, hsv, rgb);
    if (gHsvRule.done() && gRgbRule.done()) {
        stp_cyc(DRIVE_CYC);
        gLeft.brake();
        gRight.brake();
        std::printf("past the last blue section at %d mm: black %d, white %d, blue %d, other %d readings\n", mm,
                    gSeen[0], gSeen[1], gSeen[2], gSeen[3]);
        ETRoboc_notifyCompletedToSimulator();
        ext_tsk();
    }
    int steer = static_cast<int>(KP * (TARGET - gColor.getReflection()));
    gLeft.setPower(POWER + steer);
    gRight.setPower(POWER - steer);
    ext_tsk();
}
