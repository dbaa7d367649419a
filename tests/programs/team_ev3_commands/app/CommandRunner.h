// The command file's rows, run one after the other: "LineTracer distance_mm timeout_s power target_percent
// edge kp ki kd end_color", fields separated by spaces.
#ifndef COMMAND_RUNNER_H
#define COMMAND_RUNNER_H

#include <string>
#include <vector>

#include "Calibrator.h"
#include "ColorSensor.h"
#include "Motor.h"

struct Command {
    std::string name;
    int distanceMm;
    int timeoutS;
    int power;
    int targetPercent;
    bool leftEdge;
    float kp, ki, kd;
    std::string endColor;
};

class CommandRunner {
public:
    CommandRunner(ev3api::Motor& left, ev3api::Motor& right, const ev3api::ColorSensor& color,
                  const Calibrator& calibrator, bool leftCourse);
    bool load(const std::string& path);
    void run();

private:
    void lineTrace(const Command& c);
    double travelledMm() const;

    ev3api::Motor& mLeft;
    ev3api::Motor& mRight;
    const ev3api::ColorSensor& mColor;
    const Calibrator& mCalibrator;
    bool mLeftCourse;
    std::vector<Command> mCommands;
};

#endif
