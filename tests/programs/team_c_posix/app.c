/*
 * HackSPi's line tracer in C, written as a Linux program: the control loop is a POSIX thread woken at absolute
 * times (clock_nanosleep on CLOCK_MONOTONIC); the main task starts it once the force sensor is pressed, hands
 * it the go through a condition variable it waits on with a timeout, and then watches it, printing its
 * progress every second (poll() as a sleep). The gains are in tracer.ini, found from getcwd().
 */
#include <errno.h>
#include <poll.h>
#include <pthread.h>
#include <stdbool.h>
#include <stdio.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "app.h"
#include "ini.h"
#include "spike/pup/colorsensor.h"
#include "spike/pup/forcesensor.h"
#include "spike/pup/motor.h"

#define TARGET 25 /* between the SPIKE sensor's white (40) and black (10) */

static struct {
    double kp, ki, kd;
    int power;
    long period_ns;
} gains;

static pup_motor_t *left, *right;
static pup_device_t *color;
static pthread_mutex_t lock = PTHREAD_MUTEX_INITIALIZER;
static pthread_cond_t go = PTHREAD_COND_INITIALIZER;
static bool started;
static long periods;

static void add_ns(struct timespec *t, long ns)
{
    t->tv_nsec += ns;
    while (t->tv_nsec >= 1000000000L) {
        t->tv_nsec -= 1000000000L;
        t->tv_sec++;
    }
}

static void *control(void *unused)
{
    (void)unused;
    pthread_mutex_lock(&lock);
    while (!started) {
        struct timespec until;
        clock_gettime(CLOCK_REALTIME, &until);
        add_ns(&until, 50 * 1000000L);
        pthread_cond_timedwait(&go, &lock, &until);
    }
    pthread_mutex_unlock(&lock);
    struct timespec next;
    clock_gettime(CLOCK_MONOTONIC, &next);
    double integral = 0, last = 0;
    for (;;) {
        double error = TARGET - pup_color_sensor_reflection(color);
        integral += error * gains.period_ns / 1e9;
        double turn = gains.kp * error + gains.ki * integral + gains.kd * (error - last);
        last = error;
        pup_motor_set_power(left, gains.power + (int)turn);
        pup_motor_set_power(right, gains.power - (int)turn);
        pthread_mutex_lock(&lock);
        periods++;
        pthread_mutex_unlock(&lock);
        add_ns(&next, gains.period_ns);
        while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &next, NULL) == EINTR) {
        }
    }
    return NULL;
}

void main_task(intptr_t unused)
{
    char path[512];
    if (getcwd(path, sizeof path - 32) == NULL)
        path[0] = '\0';
    strcat(path, "/team_c_posix/tracer.ini");
    gains.kp = ini_number(path, "pid", "kp", 1.0);
    gains.ki = ini_number(path, "pid", "ki", 0.0);
    gains.kd = ini_number(path, "pid", "kd", 0.0);
    gains.power = (int)ini_number(path, "drive", "power", 40);
    gains.period_ns = (long)ini_number(path, "drive", "period_ms", 10) * 1000000L;
    printf("kp %g ki %g kd %g power %d\n", gains.kp, gains.ki, gains.kd, gains.power);

    left = pup_motor_get_device(PBIO_PORT_ID_B);
    right = pup_motor_get_device(PBIO_PORT_ID_A);
    pup_motor_setup(left, PUP_DIRECTION_COUNTERCLOCKWISE, true);
    pup_motor_setup(right, PUP_DIRECTION_CLOCKWISE, true);
    color = pup_color_sensor_get_device(PBIO_PORT_ID_E);
    pup_device_t *force = pup_force_sensor_get_device(PBIO_PORT_ID_D);

    pthread_t thread;
    pthread_create(&thread, NULL, control, NULL);
    while (!pup_force_sensor_touched(force))
        usleep(10 * 1000);
    pthread_mutex_lock(&lock);
    started = true;
    pthread_cond_signal(&go);
    pthread_mutex_unlock(&lock);

    for (;;) {
        poll(NULL, 0, 1000);
        pthread_mutex_lock(&lock);
        long n = periods;
        pthread_mutex_unlock(&lock);
        struct timespec now;
        clock_gettime(CLOCK_MONOTONIC, &now);
        printf("%ld.%03ld s: %ld periods\n", (long)now.tv_sec, now.tv_nsec / 1000000L, n);
    }
}
