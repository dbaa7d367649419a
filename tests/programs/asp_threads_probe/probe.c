/*
 * Threads as a team's program starts them from a task under RasPike-ART's asp, for the baton of asp's clock
 * library (athrill_sim/native/runtime/asp/asp_threads.c): once the kernel's timer is set (asp's kernel
 * starts), the main thread starts three: A sleeps 3 ms seven times, B 7 ms three times and signals C after
 * each, C waits on a condition variable for B's third; each notes which it is and the simulated time, floored
 * to the step, under a mutex; then the main thread joins them and prints the notes in their order, and
 * sleeps until the test ends. Built for aarch64 and run under qemu-user (tests/athrill/test_asp_clock.py).
 */
#define _GNU_SOURCE
#include <pthread.h>
#include <stdio.h>
#include <sys/time.h>
#include <time.h>
#include <unistd.h>

#define STEP_US 1000

static pthread_mutex_t mutex = PTHREAD_MUTEX_INITIALIZER;
static pthread_cond_t cond = PTHREAD_COND_INITIALIZER;
static int b_count;
static char notes[32][32];
static int note_count;

static long long step_us(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    long long us = (long long)ts.tv_sec * 1000000 + ts.tv_nsec / 1000;
    return us / STEP_US * STEP_US;
}

static void note(const char *who) { snprintf(notes[note_count++], sizeof notes[0], "%s %lld", who, step_us()); }

static void *a(void *arg)
{
    (void)arg;
    for (int i = 0; i < 7; i++) {
        usleep(3000);
        pthread_mutex_lock(&mutex);
        note("A");
        pthread_mutex_unlock(&mutex);
    }
    return NULL;
}

static void *b(void *arg)
{
    (void)arg;
    for (int i = 0; i < 3; i++) {
        usleep(7000);
        pthread_mutex_lock(&mutex);
        note("B");
        b_count++;
        pthread_cond_signal(&cond);
        pthread_mutex_unlock(&mutex);
    }
    return NULL;
}

static void *c(void *arg)
{
    (void)arg;
    pthread_mutex_lock(&mutex);
    while (b_count < 3)
        pthread_cond_wait(&cond, &mutex);
    note("C");
    pthread_mutex_unlock(&mutex);
    return NULL;
}

int main(void)
{
    struct itimerval stopped = {{0, 0}, {0, 0}};
    setitimer(ITIMER_REAL, &stopped, NULL); /* asp's kernel starts: its tasks' threads are players */
    pthread_t threads[3];
    void *(*entries[3])(void *) = {a, b, c};
    for (int i = 0; i < 3; i++)
        pthread_create(&threads[i], NULL, entries[i], NULL);
    for (int i = 0; i < 3; i++)
        pthread_join(threads[i], NULL);
    for (int i = 0; i < note_count; i++)
        printf("%s\n", notes[i]);
    printf("joined %lld\n", step_us());
    sleep(1000);
    return 0;
}
