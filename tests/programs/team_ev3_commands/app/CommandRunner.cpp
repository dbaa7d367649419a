#include "CommandRunner.h"

#include <chrono>
#include <cstdio>
#include <fstream>
#include <sstream>

namespace {
constexpr double WHEEL_MM_PER_DEG = 3.14159265 * 100.0 / 360.0;  // HackEV's 100 mm wheels
constexpr auto PERIOD = std::chrono::milliseconds(10);
}  // namespace

CommandRunner::CommandRunner(ev3api::Motor& left, ev3api::Motor& right, const ev3api::ColorSensor& color,
                             const Calibrator& calibrator, bool leftCourse)
    : mLeft(left), mRight(right), mColor(color), mCalibrator(calibrator), mLeftCourse(leftCourse)
{
}

bool CommandRunner::load(const std::string& path)
{
    std::ifstream in(path);
    std::string line;
    while (std::getline(in, line)) {
        std::istringstream row(line);
        Command c;
        std::string edge;
        if (line.empty() || line[0] == '#' || !(row >> c.name)) {
            continue;
        }
        if (c.name == "LineTracer" && row >> c.distanceMm >> c.timeoutS >> c.power >> c.targetPercent >> edge >> c.kp >>
                                              c.ki >> c.kd >> c.endColor) {
            c.leftEdge = edge == "LEFT_EDGE";
            mCommands.push_back(c);
        }
    }
    std::printf("%zu commands from %s\n", mCommands.size(), path.c_str());
    return !mCommands.empty();
}

double CommandRunner::travelledMm() const
{
    return (mLeft.getCount() + mRight.getCount()) / 2.0 * WHEEL_MM_PER_DEG;
}

void CommandRunner::run()
{
    for (const Command& c : mCommands) {
        if (c.name == "LineTracer") {
            lineTrace(c);
        }
    }
    mLeft.stop();
    mRight.stop();
}

// A PID trace on one edge of the line, every 10 ms: the loop waits for its period by polling steady_clock.
void CommandRunner::lineTrace(const Command& c)
{
    using clock = std::chrono::steady_clock;
    const int target = mCalibrator.threshold(c.targetPercent);
    const double start = travelledMm();
    const auto deadline = clock::now() + std::chrono::seconds(c.timeoutS);
    const int side = c.leftEdge == mLeftCourse ? 1 : -1;
    float integral = 0.0f, last = 0.0f;
    auto next = clock::now();
    while (travelledMm() - start < c.distanceMm && clock::now() < deadline) {
        float error = static_cast<float>(mColor.getBrightness() - target);
        integral += error * 0.01f;
        float turn = side * (c.kp * error + c.ki * integral + c.kd * (error - last));
        last = error;
        mLeft.setPWM(c.power - static_cast<int>(turn));
        mRight.setPWM(c.power + static_cast<int>(turn));
        next += PERIOD;
        while (clock::now() < next) {  // busy-waits, never sleeps
        }
    }
}
