/*
 * The guest addresses of EV3RT on Athrill: RX at 0x090F0000 and TX at 0x090F1000, each a 4 KiB window onto
 * its file's body (file offset HAKO_HEADER_SIZE). A program reads its gains with
 * `*(volatile float *)(0x090F0000 + 540)`, unmodified.
 *
 * mmap cannot put file offset 32 at a page-aligned address, so the windows are a private anonymous mapping
 * at the fixed guest address that shadows the two bodies:
 * - load (after each handshake, before the program runs): copy both bodies in, and remember them as `seen`;
 * - flush (each time the kernel gets control back: a task blocks, ends or yields, a handler returns, and
 *   before publishing a wake-up): write to the files only the bytes the program changed since `seen`.
 * Bytes the program left alone are never written, so a reset flag the physics process cleared, or the
 * controller's start and end flags, are never overwritten with stale copies. Nothing else is mapped next to
 * the windows, so a wild pointer just outside them faults (SIGSEGV) instead of reading something.
 */
#include <string.h>
#include <sys/mman.h>

#include "runtime.h"

#define WINDOWS 2
#define WINDOW_BYTES (WINDOWS * HAKO_WINDOW_SIZE)

_Static_assert(HAKO_TX_GUEST_BASE == HAKO_RX_GUEST_BASE + HAKO_WINDOW_SIZE, "TX follows RX in guest memory");
_Static_assert(HAKO_HEADER_SIZE + HAKO_WINDOW_SIZE <= HAKO_FILE_SIZE, "a window lies within its file");

static uint8_t *const window = (uint8_t *)(uintptr_t)HAKO_RX_GUEST_BASE;
static uint8_t seen[WINDOW_BYTES]; /* what the files held when last loaded or flushed */

static uint8_t *body(int i) { return i == 0 ? hako_rx_body() : hako_tx_body(); }

void hako_window_map(void)
{
    void *want = window;
    void *got =
        mmap(want, WINDOW_BYTES, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS | MAP_FIXED_NOREPLACE, -1, 0);
    if (got != want) {
        if (got != MAP_FAILED)
            munmap(got, WINDOW_BYTES); /* a kernel without MAP_FIXED_NOREPLACE took it as a hint */
        hako_bench_fault("cannot map the guest windows at 0x%08X: the address is taken", HAKO_RX_GUEST_BASE);
    }
}

void hako_window_load(void)
{
    if (hako_lockstep_detached())
        return; /* the test is over: the program goes on with its last snapshot */
    for (int i = 0; i < WINDOWS; i++)
        memcpy(window + i * HAKO_WINDOW_SIZE, body(i), HAKO_WINDOW_SIZE);
    memcpy(seen, window, WINDOW_BYTES);
}

void hako_window_flush(void)
{
    if (hako_lockstep_detached())
        return; /* the test is over: the files are the next test's */
    const uint64_t *now = (const uint64_t *)window;
    const uint64_t *before = (const uint64_t *)seen;
    for (size_t w = 0; w < WINDOW_BYTES / sizeof(uint64_t); w++) {
        if (now[w] == before[w])
            continue;
        for (size_t at = w * sizeof(uint64_t); at < (w + 1) * sizeof(uint64_t); at++) {
            if (window[at] != seen[at]) {
                body((int)(at / HAKO_WINDOW_SIZE))[at % HAKO_WINDOW_SIZE] = window[at];
                seen[at] = window[at];
            }
        }
    }
}
