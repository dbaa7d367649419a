/*
 * A RasPike-ART program that computes without a call, as beginners' programs do: it waits for the force sensor
 * in a busy loop (libraspike-art's reading is a load of the last status, no call the bench sees), drives, and
 * ends in `while (1) {}`. On the robot the loops take the Pi's time; on the bench's clock they must too, or the
 * press never comes and the test never reaches its time limit.
 */
#include "app.h"

#include <stdio.h>
#include <time.h>

#include "spike/pup/forcesensor.h"
#include "spike/pup/motor.h"

static volatile unsigned long spins;

static long long now_us(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (long long)ts.tv_sec * 1000000 + ts.tv_nsec / 1000;
}

void main_task(intptr_t unused)
{
    pup_device_t *force = pup_force_sensor_get_device(PBIO_PORT_ID_D);
    pup_motor_t *left = pup_motor_get_device(PBIO_PORT_ID_B);
    pup_motor_t *right = pup_motor_get_device(PBIO_PORT_ID_A);
    pup_motor_setup(left, PUP_DIRECTION_COUNTERCLOCKWISE, true);
    pup_motor_setup(right, PUP_DIRECTION_CLOCKWISE, true);
    long long start = now_us();
    while (!pup_force_sensor_touched(force)) {
        spins++;
    }
    printf("pressed after %lld ms of spinning\n", (now_us() - start) / 1000);
    pup_motor_set_power(left, 20);
    pup_motor_set_power(right, 20);
    while (1) {
        spins++;
    }
}
