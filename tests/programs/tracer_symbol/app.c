/* The Fig. 7 tracer with its gains as globals, tuned with symbol parameters. */
#include "tracer.h"

float g_kp = 1.0f;
float g_ki = 0.5f;
float g_kd = 0.5f;
float g_power = 15.0f;

void main_task(intptr_t unused)
{
    trace(g_kp, g_ki, g_kd, g_power);
}
