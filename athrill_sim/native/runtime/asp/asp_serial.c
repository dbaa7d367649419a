/*
 * asp's serial port in the lockstep: the hub (the physics side, hakoniwa/physics/raspike_hub.py) answers only
 * between steps, and asp takes in a step's bytes before any task runs at that step.
 *
 * libraspike-art's receiving thread polls the port in wall time (VMIN = 0, raspike_com.c 190-194), beside the
 * thread the tasks run in, so without this the step a status or an acknowledgement is taken in was the wall's
 * race. Each side counts what it sent in a small file of the run (HAKO_RASPIKE_SERIAL: the hub's bytes, then
 * asp's), not what a FIONREAD finds, since a pty's bytes reach the other end through the tty layer's flip
 * buffer, pushed by a kernel work item, and an empty queue does not mean that nothing more is coming:
 * - write: counted after the real write, so that the count asp publishes with its answer (the physics side
 *   reads it after the answer) covers every byte it sent;
 * - read, in the receiving thread: blocks (wall time) until the hub has sent more than was read, and says,
 *   while it waits with everything read, that the thread is idle, which hako_serial_drain waits for;
 * - read, in the main thread (the handshake, raspike_protocol.c 136-160, before the kernel starts): when all
 *   the hub sent is read, the bench moves a step, as the hub answers only between steps.
 * The receiving thread reads only what a drain released: a step the bench moved through a clock read's cost
 * (asp_time.c) is drained at the next idle point, not where the read was, since the main thread may hold
 * libraspike-art's port mutex there (raspike_timedwait_ack reads time(0) under dev->mutex), which the
 * receiving thread needs to take the bytes in. Held back, they are taken at the same point in every run.
 * The port is the one RasPike-ART opens (vdev_com_usb.c 27); it is found by its path at open.
 */
#define _GNU_SOURCE
#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <stdarg.h>
#include <stdatomic.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <unistd.h>

#include "asp.h"
#include "hako_timing.h"
#include "real.h"
#include "runtime.h"

#define SERIAL_PATH "/dev/USB_SPIKE"
/* How long a side may take to see bytes the other counted as sent, in wall time, before it is a fault of the
 * bench: generous, since qemu and a busy machine stand between them [s]. */
#define DELIVERY_LIMIT_S 20.0
#define READ_NAP_MS 1
#define WAKE_CHECK_S 0.01 /* a futex wait's longest sleep before it looks again, a wake-up missed or not */
#define DRAIN_SPINS 20000 /* looks at the receiving thread before a drain sleeps: some tens of us under qemu */
/* Bytes held back from the receiving thread past which a move drains even from a clock read: a program that
 * polls a clock for long must not fill the pty (about 4 KiB), whose writes would then block the hub. */
#define BACKLOG_MAX 2048

static int serial_fd = -1;
static volatile uint64_t *counts; /* the run's HAKO_RASPIKE_SERIAL, mapped */
static _Atomic uint64_t received; /* bytes of the hub read so far */
static _Atomic uint64_t released; /* bytes of the hub the receiving thread may read: as of the last drain */
static atomic_bool reader_idle; /* the receiving thread waits in read with everything read */
/* Futex words, each bumped before its wake: a drain that releases bytes wakes the receiving thread, and the
 * receiving thread, idle again, wakes the drain waiting for it. */
static _Atomic uint32_t releases;
static _Atomic uint32_t idles;
static uint64_t sent_at_publish; /* asp's count as of the bench's last move */

/* A word of the run's HAKO_RASPIKE_SERIAL, at its byte offset. */
static uint64_t shared_word(size_t offset)
{
    return __atomic_load_n(&counts[offset / sizeof(uint64_t)], __ATOMIC_ACQUIRE);
}

static uint64_t hub_sent(void) { return shared_word(HAKO_RASPIKE_HUB_SENT); }

static void map_counts(void)
{
    const char *run_dir = getenv("HAKO_RUN_DIR"); /* asp_time.c's constructor has checked it */
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", run_dir, HAKO_RASPIKE_SERIAL);
    int fd = hako_real()->open(path, O_RDWR);
    if (fd < 0)
        hako_bench_fault("cannot open %s: %s", path, strerror(errno));
    void *map = mmap(NULL, HAKO_RASPIKE_SERIAL_SIZE, PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
    close(fd);
    if (map == MAP_FAILED)
        hako_bench_fault("cannot map %s: %s", path, strerror(errno));
    counts = map;
}

int open(const char *path, int flags, ...)
{
    va_list args;
    va_start(args, flags);
    mode_t mode = (flags & O_CREAT) || (flags & O_TMPFILE) == O_TMPFILE ? va_arg(args, mode_t) : 0;
    va_end(args);
    int fd = hako_real()->open(path, flags, mode);
    if (fd >= 0 && strcmp(path, SERIAL_PATH) == 0) {
        if (counts == NULL)
            map_counts();
        serial_fd = fd;
    }
    return fd;
}

ssize_t write(int fd, const void *buf, size_t size)
{
    ssize_t done = hako_real()->write(fd, buf, size);
    if (fd == serial_fd && done > 0)
        __atomic_fetch_add(&counts[HAKO_RASPIKE_PROGRAM_SENT / sizeof(uint64_t)], (uint64_t)done, __ATOMIC_RELEASE);
    return done;
}

/* Wait (wall time) until the port has bytes to read: they are counted as sent, so they are on their way. */
static void await_bytes(int fd)
{
    double limit = hako_wall_s() + DELIVERY_LIMIT_S;
    struct pollfd p = {fd, POLLIN, 0};
    while (hako_real()->poll(&p, 1, READ_NAP_MS) == 0)
        if (hako_wall_s() > limit)
            hako_bench_fault("the hub's bytes did not reach asp's serial port in %.0f s", DELIVERY_LIMIT_S);
}

ssize_t read(int fd, void *buf, size_t size)
{
    if (fd != serial_fd || size == 0)
        return hako_real()->read(fd, buf, size);
    bool main_thread = hako_asp_is_main();
    for (;;) {
        /* Main may have read past `released` a moment before raising it (the handshake, with the receiving
         * thread already started): nothing is owed then, never a wrapped-around difference. */
        uint64_t avail = main_thread ? hub_sent() : released, done = received;
        uint64_t owed = avail > done ? avail - done : 0;
        if (owed > 0) {
            await_bytes(fd);
            ssize_t got = hako_real()->read(fd, buf, size < owed ? size : owed);
            if (got > 0)
                received += (uint64_t)got;
            if (main_thread && received > released)
                released = received;
            return got;
        }
        if (main_thread) {
            hako_asp_step_undrained();
            continue;
        }
        reader_idle = true;
        atomic_fetch_add(&idles, 1);
        hako_wall_wake((uint32_t *)&idles);
        for (;;) { /* asleep until a drain releases more: the pty's unreleased bytes would make a poll spin */
            uint32_t seen = atomic_load(&releases);
            if (released > received)
                break;
            hako_wall_wait((uint32_t *)&releases, seen, WAKE_CHECK_S);
        }
        reader_idle = false;
    }
}

static uint64_t program_sent(void) { return shared_word(HAKO_RASPIKE_PROGRAM_SENT); }

void hako_serial_published(void)
{
    if (counts != NULL)
        sent_at_publish = program_sent();
}

bool hako_serial_sent(void) { return counts != NULL && program_sent() != sent_at_publish; }

/* When the hub sends its next status, as it publishes it (HAKO_NEVER_WAKES before the handshake). */
static int64_t next_status(void) { return (int64_t)shared_word(HAKO_RASPIKE_HUB_NEXT_STATUS); }

int64_t hako_serial_hub_sends(void)
{
    int64_t step = hako_tick() + HAKO_PHYSICS_STEP_US;
    if (counts == NULL || hako_serial_sent())
        return step;
    return next_status() > step ? next_status() : step;
}

bool hako_serial_hub_quiet(int64_t step)
{
    return counts != NULL && next_status() != HAKO_NEVER_WAKES && step < next_status();
}

bool hako_serial_backlog(void) { return counts != NULL && hub_sent() - released > BACKLOG_MAX; }

/* Whether the receiving thread goes idle again within a short spin: it takes a status in within tens of
 * microseconds, less than the futex sleep and wake it would otherwise cost (a lap of team_spike_threads took
 * 15% less wall time so). Never longer: another bench may need the core. */
static bool reader_came_back(uint32_t seen)
{
    for (int i = 0; i < DRAIN_SPINS; i++)
        if (atomic_load(&idles) != seen)
            return true;
    return false;
}

void hako_serial_release(void)
{
    if (counts == NULL)
        return;
    uint64_t sent = hub_sent();
    if (sent != released) {
        released = sent;
        atomic_fetch_add(&releases, 1);
        hako_wall_wake((uint32_t *)&releases);
    }
}

void hako_serial_drain(void)
{
    if (counts == NULL)
        return;
    hako_serial_release();
    double limit = hako_wall_s() + DELIVERY_LIMIT_S;
    for (;;) {
        uint32_t seen = atomic_load(&idles);
        if (reader_idle && received == released)
            return;
        if (hako_wall_s() > limit)
            hako_bench_fault("asp's receiving thread did not take in the hub's bytes in %.0f s", DELIVERY_LIMIT_S);
        if (!reader_came_back(seen))
            hako_wall_wait((uint32_t *)&idles, seen, WAKE_CHECK_S);
    }
}
