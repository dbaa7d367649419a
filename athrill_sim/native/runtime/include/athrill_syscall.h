/*
 * Athrill's system-call header (athrill/apl/include/athrill_syscall.h), the part EV3RT's samples use: the
 * emulator's stopwatch. Here it measures simulated time and says it in the log. Athrill's socket and file
 * calls are not provided.
 */
#ifndef _ATHRILL_SYSCALL_H_
#define _ATHRILL_SYSCALL_H_
#ifdef __cplusplus
extern "C" {
#endif
void athrill_reset_time(void);
void athrill_show_time(void);
#ifdef __cplusplus
}
#endif
#endif /* _ATHRILL_SYSCALL_H_ */
