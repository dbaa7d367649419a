/*
 * The lockstep with the physics process, exactly as athrill_sim/mock/kernel.py speaks it (hakoniwa/sync.py is
 * the other side):
 * - a pre-launched process waits, napping, until RX TEST_SEQ names its test;
 * - to sleep until `wake`, publish NEXT_WAKE, the TX header times (Athrill's clock and the echo of the unity
 *   time), then bump ANSWER_SEQ last and wake the physics process sleeping on it; then sleep on the low word of
 *   the RX header's unity time until it reaches `wake` (the physics process wakes us when it writes it).
 * The sleeps are futexes on the shared file mapping, as in hakoniwa/waiting.py, with a timeout to check every
 * HAKO_CHECK_EVERY_S that the physics process lives; the process leaves (status 0) when it is gone.
 *
 * Once the test is over and the program was interrupted (SIGINT, as Ctrl-C ends a program on the robot, and the
 * program has a handler that returned: posix_process.c), the lockstep is *detached*: the program goes on in
 * simulated time with the last snapshot and without waiting, and nothing reaches the files any more, so that
 * a handler that only raises a flag lets the program's loops see it, end and write their logs, while the
 * next test already runs. Past HAKO_AFTER_INTERRUPT_US of simulated time it leaves.
 */
#include <errno.h>
#include <signal.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "real.h"
#include "runtime.h"

#define HAKO_AFTER_INTERRUPT_US (10 * 1000000LL) /* how long a detached program may go on */

static uint32_t physics_pid;
static volatile sig_atomic_t detached;
static int64_t detached_until = -1; /* the simulated time it leaves at, set at its first wait detached */

void hako_lockstep_detach(void) { detached = 1; }

bool hako_lockstep_detached(void) { return detached != 0; }

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
        hako_wall_nap(HAKO_TEST_WAIT_NAP_S);
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
    if (detached)
        return;
    uint8_t *tx = hako_tx_file();
    uint64_t athrill_time = (uint64_t)now_us, unity_time = hako_rx_unity_time();
    memcpy(tx + HAKO_HEADER_SIZE + HAKO_TX_NEXT_WAKE, &wake_us, sizeof wake_us);
    memcpy(tx + HAKO_HDR_ATHRILL_TIME, &athrill_time, sizeof athrill_time);
    memcpy(tx + HAKO_HDR_UNITY_TIME, &unity_time, sizeof unity_time);
    uint32_t *answer = (uint32_t *)(tx + HAKO_HEADER_SIZE + HAKO_TX_ANSWER_SEQ);
    __atomic_store_n(answer, *answer + 1, __ATOMIC_RELEASE); /* last: the physics process acts on it */
    hako_wall_wake(answer);
}

static void go_on_detached(int64_t wake_us)
{
    if (detached_until < 0)
        detached_until = wake_us + HAKO_AFTER_INTERRUPT_US;
    else if (wake_us > detached_until)
        hako_leave("the program was interrupted and did not end within %lld s of simulated time",
                   (long long)(HAKO_AFTER_INTERRUPT_US / 1000000));
}

void hako_wait_snapshot(int64_t wake_us)
{
    uint32_t *low_word = (uint32_t *)(hako_rx_file() + HAKO_HDR_UNITY_TIME); /* little-endian: the low half */
    double next_check = hako_wall_s() + HAKO_CHECK_EVERY_S;
    while (!detached && (int64_t)hako_rx_unity_time() < wake_us) {
        uint32_t expected = __atomic_load_n(low_word, __ATOMIC_ACQUIRE);
        if ((int64_t)hako_rx_unity_time() >= wake_us)
            break;
        hako_wall_wait(low_word, expected, HAKO_CHECK_EVERY_S);
        double now = hako_wall_s();
        if (now > next_check) {
            next_check = now + HAKO_CHECK_EVERY_S;
            check_physics();
        }
    }
    if (detached)
        go_on_detached(wake_us);
}
