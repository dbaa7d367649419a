/*
 * The lockstep with the physics process, exactly as athrill_sim/kernel.py speaks it (hakoniwa/sync.py is
 * the other side):
 * - a pre-launched process waits, napping, until RX TEST_SEQ names its test;
 * - to sleep until `wake`, publish NEXT_WAKE, the TX header times (Athrill's clock and the echo of the unity
 *   time), then bump ANSWER_SEQ last; then wait until the RX header's unity time reaches `wake`.
 * Waiting naps through most of a control period and spins only around the moment the snapshot is due, with
 * the mock's own constants (hako_timing.h is generated from it). The process leaves (status 0) when the
 * physics process is gone.
 */
#include <signal.h>
#include <errno.h>
#include <string.h>
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

static void relax(void)
{
#if defined(__x86_64__) || defined(__i386__)
    __builtin_ia32_pause();
#endif
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
}

void hako_wait_snapshot(int64_t wake_us)
{
    static double last_wait_s;
    double start = wall_s();
    double spin_from = HAKO_SNAPSHOT_SPIN_FROM * last_wait_s;
    double next_check = start + HAKO_CHECK_EVERY_S;
    unsigned polls = 0;
    while ((int64_t)hako_rx_unity_time() < wake_us) {
        if (++polls & 255) {
            relax();
            continue;
        }
        double now = wall_s(), waited = now - start;
        if (!(spin_from <= waited && waited <= spin_from + HAKO_SNAPSHOT_SPIN_S))
            nap(HAKO_NAP_S);
        if (now > next_check) {
            next_check = now + HAKO_CHECK_EVERY_S;
            check_physics();
        }
    }
    last_wait_s = wall_s() - start;
}
