#include "Pid.h"

float Pid::control(float error)
{
    mIntegral += error * 0.01f;
    float derivative = error - mLastError;
    mLastError = error;
    return KP * error + KI * mIntegral + KD * derivative;
}
