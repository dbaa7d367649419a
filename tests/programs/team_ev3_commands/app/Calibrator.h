// Course selection and the colour sensor's calibration, with the brick's buttons as the person uses them.
#ifndef CALIBRATOR_H
#define CALIBRATOR_H

#include "ColorSensor.h"

class Calibrator {
public:
    explicit Calibrator(const ev3api::ColorSensor& color) : mColor(color) {}
    bool selectCourse();  // true for the L course
    void calibrate();
    int black() const { return mBlack; }
    int white() const { return mWhite; }
    int threshold(int percent) const { return mBlack + (mWhite - mBlack) * percent / 100; }

private:
    static void waitClick(button_t button);

    const ev3api::ColorSensor& mColor;
    int mBlack = 0;
    int mWhite = 100;
};

#endif
