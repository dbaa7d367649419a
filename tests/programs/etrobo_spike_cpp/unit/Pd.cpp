#include "Pd.h"

float Pd::control(float error)
{
    float derivative = error - mLastError;
    mLastError = error;
    return KP * error + KD * derivative;
}
