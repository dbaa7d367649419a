/*
 * What the parts of the native runtime tell one another. The runtime is the Athrill process for a user's
 * EV3RT program: it maps the two bench files itself and keeps the deterministic lockstep with the physics
 * process (docs/NATIVE.md), with no Python in the loop.
 */
#ifndef HAKO_RUNTIME_H
#define HAKO_RUNTIME_H

#include <stdarg.h>
#include <stdbool.h>
#include <stdint.h>

#include "hako_layout.h"
#include "hako_timing.h"
#include "sim_time.h"

_Static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "the bench files are little-endian, as is the guest");

/* The simulated time a preempted spin (a task or thread computing without a call) is taken to have used, at
 * most: the native kernel's (kernel.c) and asp's (asp_spin.c). */
#define HAKO_SPIN_TIME_US 10000

/* mapped_files.c: the two files, checked and mapped; leaving the process. */
void hako_files_open(const char *run_dir);
uint8_t *hako_rx_body(void);
uint8_t *hako_tx_body(void);
uint8_t *hako_tx_file(void); /* with its header, which lockstep.c writes */
uint8_t *hako_rx_file(void); /* with its header, whose unity time lockstep.c sleeps on */
uint64_t hako_rx_unity_time(void);
uint32_t hako_rx_u32(unsigned offset);
void hako_bench_fault(const char *format, ...) __attribute__((noreturn, format(printf, 1, 2)));
void hako_leave(const char *format, ...) __attribute__((noreturn, format(printf, 1, 2)));

/* guest_window.c: the guest addresses 0x090F0000.. as a shadow of the two file bodies. */
void hako_window_map(void);
void hako_window_load(void);
void hako_window_flush(void);

/* lockstep.c: the time protocol with the physics process. */
void hako_wait_for_test(uint32_t test);
void hako_announce(void);
void hako_publish(int64_t now_us, int64_t wake_us);
void hako_wait_snapshot(int64_t wake_us);
void hako_lockstep_detach(void); /* async-signal-safe: the test is over, go on without the files */
bool hako_lockstep_detached(void);

/* kernel.c: the tasks and cyclic handlers of app.cfg in simulated time; leaving it as when every task has
 * ended (the outputs flushed, NEVER_WAKES published). */
void hako_kernel_start(int64_t start_us); /* the tables, TA_ACT tasks and TA_STA handlers; the devices' start */
void hako_kernel_run(void) __attribute__((noreturn));
void hako_kernel_exit(void) __attribute__((noreturn));

/* main.c: the run directory (absolute: the program's working directory is its own, the bench's copy of its
 * workspace). */
const char *hako_run_dir(void);

/* lines.c: lines on stderr, each written at once; hako_vlog and hako_log stamp them with the simulated time. */
void hako_vline(const char *prefix, const char *format, va_list args);
void hako_vlog(const char *format, va_list args);
void hako_log(const char *format, ...) __attribute__((format(printf, 1, 2)));

#endif /* HAKO_RUNTIME_H */
