// HackEV's competition program as teams wrote it for RasPike (2023): the brick's API through libcpp-ev3, run as
// a Linux process. The course is picked with the brick's buttons, the colour sensor is calibrated by hand on
// black and white, a script prepares the run, a hand in front of the sonar starts it, and the course is driven
// from the rows of a command file. Its loops never sleep: they poll, and pace themselves on steady_clock.
#include "app.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>

#include "Calibrator.h"
#include "CommandRunner.h"
#include "SonarSensor.h"

using namespace ev3api;

static Motor gLeftWheel(PORT_C);
static Motor gRightWheel(PORT_B);
static ColorSensor gColorSensor(PORT_2);
static SonarSensor gSonar(PORT_3);

static void waitForHand()
{
    std::printf("Hold a hand in front of the sonar to start\n");
    while (gSonar.getDistance() > 10) {  // polls without sleeping, as the team's loop did
    }
    while (gSonar.getDistance() <= 10) {
    }
}

void main_task(intptr_t unused)
{
    Calibrator calibrator(gColorSensor);
    bool leftCourse = calibrator.selectCourse();
    std::printf("%s course\n", leftCourse ? "L" : "R");
    calibrator.calibrate();
    std::printf("black %d white %d\n", calibrator.black(), calibrator.white());

    int status = std::system("bash ./team_ev3_commands/scripts/init.sh");
    std::printf("init.sh exited with %d\n", WEXITSTATUS(status));

    CommandRunner runner(gLeftWheel, gRightWheel, gColorSensor, calibrator, leftCourse);
    if (!runner.load("./team_ev3_commands/datafiles/commands.txt")) {
        std::printf("no commands: stop\n");
        return;
    }
    waitForHand();
    std::time_t started = std::time(nullptr);
    char stamp[32];
    std::strftime(stamp, sizeof stamp, "%H:%M:%S", std::localtime(&started));
    std::printf("start at %s\n", stamp);
    runner.run();
}
