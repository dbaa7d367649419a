/*
 * The C library's own functions where the runtime defines one of the same name (posix_*.c): the runtime's
 * own waiting and timing is in wall time, and a call the runtime passes on goes to the real one. Found with
 * dlsym(RTLD_NEXT), once, before the first use.
 */
#ifndef HAKO_REAL_H
#define HAKO_REAL_H

#include <netdb.h>
#include <poll.h>
#include <pthread.h>
#include <signal.h>
#include <stdio.h>
#include <sys/epoll.h>
#include <sys/select.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <time.h>

struct hako_real {
    int (*clock_gettime)(clockid_t, struct timespec *);
    int (*nanosleep)(const struct timespec *, struct timespec *);
    long (*syscall)(long, ...);
    int (*sigaction)(int, const struct sigaction *, struct sigaction *);
    int (*setitimer)(int, const struct itimerval *, struct itimerval *);
    int (*sigsuspend)(const sigset_t *);
    int (*pthread_cond_timedwait)(pthread_cond_t *, pthread_mutex_t *, const struct timespec *);
    int (*open)(const char *, int, ...);
    int (*openat)(int, const char *, int, ...);
    FILE *(*fopen)(const char *, const char *);
    int (*connect)(int, const struct sockaddr *, socklen_t);
    int (*getaddrinfo)(const char *, const char *, const struct addrinfo *, struct addrinfo **);
    int (*poll)(struct pollfd *, nfds_t, int);
    int (*select)(int, fd_set *, fd_set *, fd_set *, struct timeval *);
    int (*epoll_wait)(int, struct epoll_event *, int, int);
    int (*pclose)(FILE *);
};

/* The real functions; resolved at the first call. */
const struct hako_real *hako_real(void);

/* Wall time, for the runtime's own waits [s]. */
double hako_wall_s(void);
void hako_wall_nap(double seconds);

#endif /* HAKO_REAL_H */
