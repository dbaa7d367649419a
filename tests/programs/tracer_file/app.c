/* The Fig. 7 tracer with its gains in a data file on the SD card (gains.csv: a header line, then kp, ki,
 * kd and the motor power), read at start as a team reads its command files; tuned with file parameters. */
#include <stdio.h>
#include "tracer.h"

void main_task(intptr_t unused)
{
    float kp = 1.0f, ki = 0.5f, kd = 0.5f, power = 15.0f;
    FILE *f = fopen("gains.csv", "r");
    if (f == NULL || fscanf(f, "%*[^\n]\n%f,%f,%f,%f", &kp, &ki, &kd, &power) != 4)
        syslog(LOG_ERROR, "gains.csv: cannot read the gains; running with the defaults");
    if (f != NULL)
        fclose(f);
    trace(kp, ki, kd, power);
}
