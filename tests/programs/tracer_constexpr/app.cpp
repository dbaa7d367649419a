// The Fig. 7 tracer in C++, with its gains as constexpr constants of gains.h, tuned with source parameters.
#include "tracer.h"
#include "gains.h"

extern "C" void main_task(intptr_t unused)
{
    trace(gains::KP, gains::KI, gains::KD, gains::POWER);
}
