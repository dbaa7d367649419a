/*
 * The C library's own functions where the runtime defines one of the same name (posix_*.c): the runtime's
 * own waiting and timing is in wall time, and a call the runtime passes on goes to the real one. Found with
 * dlsym(RTLD_NEXT), once, before the first use; a function the runtime needs is one line of HAKO_REAL_CALLS.
 */
#ifndef HAKO_REAL_H
#define HAKO_REAL_H

#include <netdb.h>
#include <poll.h>
#include <pthread.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <sys/epoll.h>
#include <sys/select.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <sys/types.h>
#include <time.h>

/* Each real function as X(return type, name, parameter list): the one list, from which both the struct and
 * its resolution are made. */
#define HAKO_REAL_CALLS(X)                                                                                             \
    X(int, clock_gettime, (clockid_t, struct timespec *))                                                              \
    X(int, nanosleep, (const struct timespec *, struct timespec *))                                                    \
    X(long, syscall, (long, ...))                                                                                      \
    X(int, sigaction, (int, const struct sigaction *, struct sigaction *))                                             \
    X(int, setitimer, (int, const struct itimerval *, struct itimerval *))                                             \
    X(int, sigsuspend, (const sigset_t *))                                                                             \
    X(int, pthread_cond_timedwait, (pthread_cond_t *, pthread_mutex_t *, const struct timespec *))                     \
    X(int, pthread_cond_wait, (pthread_cond_t *, pthread_mutex_t *))                                                   \
    X(int, pthread_cond_signal, (pthread_cond_t *))                                                                    \
    X(int, pthread_cond_broadcast, (pthread_cond_t *))                                                                 \
    X(int, pthread_mutex_lock, (pthread_mutex_t *))                                                                    \
    X(int, pthread_create, (pthread_t *, const pthread_attr_t *, void *(*)(void *), void *))                           \
    X(int, pthread_join, (pthread_t, void **))                                                                         \
    X(int, open, (const char *, int, ...))                                                                             \
    X(int, openat, (int, const char *, int, ...))                                                                      \
    X(ssize_t, read, (int, void *, size_t))                                                                            \
    X(ssize_t, write, (int, const void *, size_t))                                                                     \
    X(FILE *, fopen, (const char *, const char *))                                                                     \
    X(int, connect, (int, const struct sockaddr *, socklen_t))                                                         \
    X(int, getaddrinfo, (const char *, const char *, const struct addrinfo *, struct addrinfo **))                     \
    X(int, poll, (struct pollfd *, nfds_t, int))                                                                       \
    X(int, select, (int, fd_set *, fd_set *, fd_set *, struct timeval *))                                              \
    X(int, epoll_wait, (int, struct epoll_event *, int, int))                                                          \
    X(int, pclose, (FILE *))                                                                                           \
    X(pid_t, fork, (void))

#define HAKO_REAL_FIELD(ret, name, params) ret(*name) params;
struct hako_real {
    HAKO_REAL_CALLS(HAKO_REAL_FIELD)
};
#undef HAKO_REAL_FIELD

/* The real functions; resolved at the first call. */
const struct hako_real *hako_real(void);

/* Wall time, for the runtime's own waits [s]. */
double hako_wall_s(void);
void hako_wall_nap(double seconds);
/* A futex: sleep while *word still holds `expected`, at most `seconds` (the kernel compares before it sleeps);
 * and wake every sleeper on `word`, once it has changed. It works across processes on a shared file mapping. */
void hako_wall_wait(uint32_t *word, uint32_t expected, double seconds);
void hako_wall_wake(uint32_t *word);

#endif /* HAKO_REAL_H */
