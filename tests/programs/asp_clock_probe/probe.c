/*
 * Uses time as RasPike-ART's asp does (target/raspi_gcc: main.c's sleep(1) before the kernel starts,
 * target_timer.c's one-shot ITIMER_REAL re-armed from the SIGALRM handler and stopped with the old value read
 * back, clock_gettime(CLOCK_MONOTONIC) as the high-resolution timer, target_kernel_impl.c's sigsuspend idle
 * with SIGALRM blocked outside it), then a periodic timer firing during a nanosleep, then libraspike-art's
 * wait for an acknowledgement its receiving thread hands over (raspike_protocol.c 359-384). Built for aarch64 and run
 * under qemu-user with asp's clock library preloaded (tests/athrill/test_asp_clock.py); prints each time it
 * reads, in microseconds.
 */
#define _GNU_SOURCE
#include <errno.h>
#include <pthread.h>
#include <signal.h>
#include <stdio.h>
#include <sys/time.h>
#include <time.h>
#include <unistd.h>

static volatile int ticks;
static volatile int rearm = 1;
static long long at[16];

static pthread_mutex_t ack_mutex = PTHREAD_MUTEX_INITIALIZER;
static pthread_cond_t ack_cond = PTHREAD_COND_INITIALIZER;
static int ack;

static void *receiver(void *arg)
{
    (void)arg;
    pthread_mutex_lock(&ack_mutex);
    ack = 1;
    pthread_cond_signal(&ack_cond);
    pthread_mutex_unlock(&ack_mutex);
    return NULL;
}

/* raspike_timedwait_ack's wait: a deadline of time(0) + `waitsec`; the receiver (if any) started with the
 * mutex held, so that it answers only once the wait has begun. */
static int wait_ack(int waitsec, pthread_t *thread)
{
    int result = 0;
    pthread_mutex_lock(&ack_mutex);
    if (thread != NULL)
        pthread_create(thread, NULL, receiver, NULL);
    while (!ack && result == 0) {
        struct timespec deadline = {time(0) + waitsec, 0};
        result = pthread_cond_timedwait(&ack_cond, &ack_mutex, &deadline);
    }
    pthread_mutex_unlock(&ack_mutex);
    return result;
}

static long long now_us(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (long long)ts.tv_sec * 1000000 + ts.tv_nsec / 1000;
}

static void arm(long us, long interval_us)
{
    struct itimerval val = {{0, interval_us}, {0, us}};
    setitimer(ITIMER_REAL, &val, NULL);
}

static void on_alarm(int sig)
{
    (void)sig;
    at[ticks++ % 16] = now_us();
    if (rearm)
        arm(10000, 0);
}

int main(void)
{
    printf("start %lld\n", now_us());
    sleep(1);
    printf("slept %lld\n", now_us());

    struct sigaction sa = {0};
    sa.sa_handler = on_alarm;
    sigaction(SIGALRM, &sa, NULL);
    sigset_t alarm_only, none;
    sigemptyset(&alarm_only);
    sigaddset(&alarm_only, SIGALRM);
    sigemptyset(&none);
    sigprocmask(SIG_BLOCK, &alarm_only, NULL);
    arm(10000, 0);
    while (ticks < 5)
        sigsuspend(&none);
    for (int i = 0; i < 5; i++)
        printf("tick %lld\n", at[i]);

    struct itimerval stop = {{0, 0}, {0, 0}}, old;
    rearm = 0;
    setitimer(ITIMER_REAL, &stop, &old);
    printf("left %ld\n", (long)old.it_value.tv_usec);

    ticks = 0;
    arm(3000, 3000);
    sigprocmask(SIG_UNBLOCK, &alarm_only, NULL);
    struct timespec ten_ms = {0, 10000000};
    nanosleep(&ten_ms, NULL);
    setitimer(ITIMER_REAL, &stop, NULL);
    for (int i = 0; i < ticks; i++)
        printf("during %lld\n", at[i]);
    printf("woke %lld\n", now_us());

    printf("unanswered %s\n", wait_ack(0, NULL) == ETIMEDOUT ? "ETIMEDOUT" : "?");
    pthread_t thread;
    printf("answered %d\n", wait_ack(1, &thread));
    pthread_join(thread, NULL);
    printf("acked %lld\n", now_us());
    return 0;
}
