/* The Fig. 7 tracer with its gains as macros (gains.h), tuned with define parameters. */
#include "tracer.h"
#include "gains.h"

void main_task(intptr_t unused)
{
    trace(KP, KI, KD, MOTOR_POWER);
}
