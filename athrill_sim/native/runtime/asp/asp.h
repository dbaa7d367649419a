/*
 * What asp's clock (asp_time.c) and its serial port (asp_serial.c) ask of each other.
 */
#ifndef HAKO_ASP_H
#define HAKO_ASP_H

#include <stdbool.h>

/* Whether the calling thread is asp's main thread, the one its kernel and every task run in: the only thread
 * that moves the bench, so that asp's receiving thread, which runs in wall time, cannot make a run differ. */
bool hako_asp_is_main(void);

/* The bench one step on, with no drain of the serial port: for the main thread reading the port itself (the
 * handshake, before the receiving thread starts). */
void hako_asp_step_undrained(void);

/* Wait (wall time) until asp's receiving thread has read every byte the hub sent and is back in read, so that
 * what a step's bytes do (a status copied, an acknowledgement signalled, the buffered commands sent) is done
 * before any task runs at that step. Nothing to wait for before asp opens the port. */
void hako_serial_drain(void);

/* Whether so many of the hub's bytes are held back from the receiving thread (not yet drained) that the pty
 * could fill: a move drains then even where it would otherwise owe the drain to the next idle point. */
bool hako_serial_backlog(void);

#endif /* HAKO_ASP_H */
