/*
 * The lockstep with the physics process, exactly as athrill_sim/kernel.py speaks it (hakoniwa/sync.py is
 * the other side):
 * - a pre-launched process waits, napping, until RX TEST_SEQ names its test;
 * - to sleep until `wake`, publish NEXT_WAKE, the TX header times (Athrill's clock and the echo of the unity
 *   time), then bump ANSWER_SEQ last and wake the physics process sleeping on it; then sleep on the low word of
 *   the RX header's unity time until it reaches `wake` (the physics process wakes us when it writes it).
 * The sleeps are futexes on the shared file mapping, as in hakoniwa/waiting.py, with a timeout to check every
 * HAKO_CHECK_EVERY_S that the physics process lives; the process leaves (status 0) when it is gone.
 */
#include <signal.h>
#include <errno.h>
#include <limits.h>
#include <linux/futex.h>
#include <string.h>
#include <sys/syscall.h>
#include <time.h>
#include <unistd.h>

#include "runtime.h"

static uint32_t physics_pid;

static double wall_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

static void nap(double seconds)
{
    struct timespec ts = {(time_t)seconds, (long)((seconds - (double)(time_t)seconds) * 1e9)};
    nanosleep(&ts, NULL);
}

static void futex_wake(uint32_t *word)
{
    syscall(SYS_futex, word, FUTEX_WAKE, INT_MAX, NULL, NULL, 0);
}

/* Sleep while *word still holds `expected`, at most `seconds` (the kernel compares before it sleeps). */
static void futex_wait(uint32_t *word, uint32_t expected, double seconds)
{
    struct timespec ts = {(time_t)seconds, (long)((seconds - (double)(time_t)seconds) * 1e9)};
    syscall(SYS_futex, word, FUTEX_WAIT, expected, &ts, NULL, 0);
}

static void check_physics(void)
{
    if (kill((pid_t)physics_pid, 0) != 0 && errno == ESRCH)
        hako_leave("physics process %u is gone", physics_pid);
}

void hako_wait_for_test(uint32_t test)
{
    physics_pid = hako_rx_u32(HAKO_RX_PHYSICS_PID);
    for (;;) {
        uint32_t current = hako_rx_u32(HAKO_RX_TEST_SEQ);
        if (current == test)
            return;
        check_physics();
        if (current > test)
            hako_leave("test %u will not run (physics is at test %u)", test, current);
        nap(HAKO_TEST_WAIT_NAP_S);
    }
}

void hako_announce(void)
{
    physics_pid = hako_rx_u32(HAKO_RX_PHYSICS_PID);
    uint32_t pid = (uint32_t)getpid();
    memcpy(hako_tx_body() + HAKO_TX_ATHRILL_PID, &pid, sizeof pid);
}

void hako_publish(int64_t now_us, int64_t wake_us)
{
    uint8_t *tx = hako_tx_file();
    uint64_t athrill_time = (uint64_t)now_us, unity_time = hako_rx_unity_time();
    memcpy(tx + HAKO_HEADER_SIZE + HAKO_TX_NEXT_WAKE, &wake_us, sizeof wake_us);
    memcpy(tx + HAKO_HDR_ATHRILL_TIME, &athrill_time, sizeof athrill_time);
    memcpy(tx + HAKO_HDR_UNITY_TIME, &unity_time, sizeof unity_time);
    uint32_t *answer = (uint32_t *)(tx + HAKO_HEADER_SIZE + HAKO_TX_ANSWER_SEQ);
    __atomic_store_n(answer, *answer + 1, __ATOMIC_RELEASE); /* last: the physics process acts on it */
    futex_wake(answer);
}

void hako_wait_snapshot(int64_t wake_us)
{
    uint32_t *low_word = (uint32_t *)(hako_rx_file() + HAKO_HDR_UNITY_TIME); /* little-endian: the low half */
    double next_check = wall_s() + HAKO_CHECK_EVERY_S;
    while ((int64_t)hako_rx_unity_time() < wake_us) {
        uint32_t expected = __atomic_load_n(low_word, __ATOMIC_ACQUIRE);
        if ((int64_t)hako_rx_unity_time() >= wake_us)
            break;
        futex_wait(low_word, expected, HAKO_CHECK_EVERY_S);
        double now = wall_s();
        if (now > next_check) {
            next_check = now + HAKO_CHECK_EVERY_S;
            check_physics();
        }
    }
}
