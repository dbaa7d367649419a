// The C++ a team's program relies on: static objects constructed before the first task (configuring a motor
// there), the standard library, new/delete, virtual calls, templates, stdio and iostream. It prints rather
// than calls syslog: EV3RT's C++ build sends syslog to its log task, not to the emulator's output.
#include "app.h"

#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

#include "Clock.h"
#include "Motor.h"
#include "Shapes.h"

// ET Robocon's samples define this for EV3RT, which links without the C runtime's start files.
void *__dso_handle = 0;

struct Announcer {
    explicit Announcer(const char *what) : what(what)
    {
        printf("constructed %s\n", what);
    }
    const char *what;
};

static ev3api::Motor gLeft(PORT_A);
static ev3api::Clock gClock;
static Announcer gFirst("the first global");
static std::string gName = "features";
static std::vector<int> gSquares = {1, 4, 9};

void main_task(intptr_t unused)
{
    printf("main_task: %s, %d squares\n", gName.c_str(), static_cast<int>(gSquares.size()));
    std::vector<std::unique_ptr<Shape>> shapes = make_shapes();
    std::vector<int> areas;
    for (const auto& s : shapes)
        areas.push_back(s->area());
    printf("%s and %s: total area %d\n", shapes[0]->name().c_str(), shapes[1]->name().c_str(),
           total(areas));
    int *block = new int[1000];
    block[999] = 7;
    printf("new int[1000]: %d\n", block[999]);
    delete[] block;
    std::cout << "iostream works" << std::endl;
    gLeft.setPWM(40);
    gClock.sleep(20 * 1000);
    printf("clock: %u ms\n", static_cast<unsigned>(gClock.now() / 1000));
    ext_tsk();
}
