/* The Fig. 7 tracer with its gains as constants in pid.h, tuned with source parameters. */
#include "tracer.h"
#include "pid.h"

void main_task(intptr_t unused)
{
    trace(KP_GAIN, KI_GAIN, KD_GAIN, BASE_POWER);
}
