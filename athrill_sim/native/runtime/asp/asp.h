/*
 * What asp's clock (asp_time.c) and its serial port (asp_serial.c) ask of each other.
 */
#ifndef HAKO_ASP_H
#define HAKO_ASP_H

#include <stdbool.h>
#include <stdint.h>

/* Whether the calling thread is asp's main thread, the one its kernel and every task run in, which alone reads
 * the hub's port itself (the handshake). */
bool hako_asp_is_main(void);

/* The bench one step on, with no drain of the serial port: for the main thread reading the port itself (the
 * handshake, before the receiving thread starts). */
void hako_asp_step_undrained(void);

/* Wait (wall time) until asp's receiving thread has read every byte the hub sent and is back in read, so that
 * what a step's bytes do (a status copied, an acknowledgement signalled, the buffered commands sent) is done
 * before any task runs at that step. Nothing to wait for before asp opens the port. */
void hako_serial_drain(void);

/* What the hub has sent, released to the receiving thread without waiting for it to take it in: for a spinning
 * player, which makes no call where a drain could wait. */
void hako_serial_release(void);

/* The bench moves on: what asp has sent so far goes with its answer, and the hub answers it at the next step. */
void hako_serial_published(void);

/* The earliest the hub may send asp something: the next step if asp has sent it bytes since the bench last
 * moved (it answers them then), otherwise its next status, which it publishes (HAKO_RASPIKE_HUB_NEXT_STATUS);
 * the next step before asp opens the port. */
int64_t hako_serial_hub_sends(void);

/* Whether asp has sent the hub bytes since its last answer. */
bool hako_serial_sent(void);

/* Whether the hub sends asp nothing of its own before `step`: it has shaken hands, and its next status, which it
 * publishes, is after `step`. Nothing asp reads changes before then: it reads the world only through the hub. */
bool hako_serial_hub_quiet(int64_t step);

/* Whether so many of the hub's bytes are held back from the receiving thread (not yet drained) that the pty
 * could fill: a move drains then even where it would otherwise owe the drain to the next idle point. */
bool hako_serial_backlog(void);

/* -- asp_time.c, for the baton: the caller holds the baton's lock -------------------------------------- */

/* Move the bench to the step `until` falls in and the clock within it to `until`, the serial port drained if
 * `drained`: true when the kernel's timer fell due on the way (its SIGALRM is then owed). */
bool hako_asp_move(int64_t until, bool drained);

/* Wait until the physics side has taken in asp's last told answer (one asp moved on from without waiting), if
 * that is still out: before the next answer, and before the hub's bytes are released out of a drain, whose
 * reading may make libraspike-art send more, which the physics side would count with the told answer. */
void hako_asp_told_taken(void);

/* When the kernel's timer falls due next [simulated us], HAKO_FOREVER when stopped. */
int64_t hako_asp_timer_due(void);

/* -- asp_threads.c: the baton ----------------------------------------------------------------------------- */

/* What a player waits for. */
enum hako_wait_kind {
    HAKO_WAIT_TIME, /* simulated time `due` */
    HAKO_WAIT_SIGNAL, /* a signal of the condition `object` (its count was `signals`), or `due` */
    HAKO_WAIT_TICK, /* the kernel's tick (asp's idle loop) */
    HAKO_WAIT_MUTEX, /* the mutex `object` let go */
    HAKO_WAIT_JOIN, /* the end of the player numbered `object` */
};

struct hako_wait {
    enum hako_wait_kind kind;
    int64_t due;
    const void *object;
    uint64_t signals;
};

/* The lock of the baton and of the clock's moves (asp's threads all read clocks). */
void hako_asp_lock(void);
void hako_asp_unlock(void);

/* The calling thread, asp's main one, is the first player (asp_time.c's constructor); and asp's kernel has set
 * its timer, after which a thread a player starts is a player too. */
void hako_asp_players_start(void);
void hako_asp_kernel_started(void);

/* Whether the calling thread is one of asp's players, which alone move the bench. */
bool hako_asp_player(void);

/* Whether a waiting player may wait for what the hub sends: a signal of a condition that not only players have
 * signalled (the receiving thread signals what the hub brings), or a mutex (the receiving thread's, maybe). */
bool hako_asp_awaits_hub(void);

/* How many times the condition `cond` was signalled. */
uint64_t hako_asp_signals(const void *cond);

/* The calling player waits for `w`, the baton handed on (the bench moved until a player may run); it returns
 * with the baton, after the kernel's tick in the main thread if it fell due meanwhile, which ends every wait of
 * the main thread (the caller looks whether its own has ended). */
void hako_asp_wait(const struct hako_wait *w);

/* The calling player has spent a whole step, whose move `fired` the kernel's timer or not: the baton goes on to
 * the next player that may run, the caller after them. */
void hako_asp_spent_step(bool fired);

/* In a signal handler, in a thread that is not a player: the baton's holder has computed a slice without a call.
 * If it is not waiting and the baton's lock is free, the bench moves by up to `spin_us` (no further than a
 * waiting player's or the kernel's timer's next time), the hub's bytes are released to the receiving thread,
 * and the kernel's tick, if it fell due, goes to the main thread if it holds the baton. Whether it moved. */
bool hako_asp_spun(int64_t spin_us);

/* -- asp_spin.c: the CPU clock that moves the bench for a spinning player -------------------------------- */

/* Asp's kernel has started: from now on a player computing for a slice without a call moves the bench (it keeps
 * the baton). */
void hako_asp_spin_clock_start(void);

/* The calling player has taken the baton: its slice of CPU time starts now. */
void hako_asp_slice_start(void);

#endif /* HAKO_ASP_H */
