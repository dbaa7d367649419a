#include "Calibrator.h"

#include <chrono>
#include <cstdio>
#include <thread>

void Calibrator::waitClick(button_t button)
{
    while (!ev3_button_is_pressed(button)) {
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    while (ev3_button_is_pressed(button)) {
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
}

bool Calibrator::selectCourse()
{
    std::printf("Select the course: LEFT button for L, RIGHT button for R\n");
    for (;;) {
        if (ev3_button_is_pressed(LEFT_BUTTON)) {
            waitClick(LEFT_BUTTON);
            return true;
        }
        if (ev3_button_is_pressed(RIGHT_BUTTON)) {
            waitClick(RIGHT_BUTTON);
            return false;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
}

void Calibrator::calibrate()
{
    std::printf("Press the Left Button on the Black\n");
    waitClick(LEFT_BUTTON);
    mBlack = mColor.getBrightness();
    std::printf("Press the Left Button on the White\n");
    waitClick(LEFT_BUTTON);
    mWhite = mColor.getBrightness();
}
