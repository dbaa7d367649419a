/*
 * Waiting for files, and the devices and peers the bench does not have.
 *
 * poll, ppoll, select, pselect and epoll_wait wait in simulated time: the descriptors are looked at once a step
 * (without waiting in the operating system) until one is ready or the timeout, counted as a sleep is, has
 * passed; with no descriptors at all they are plain sleeps.
 *
 * A camera (/dev/video*) and network peers are what a robot may lack: opening a camera fails with ENOENT, and
 * connecting to anything but this machine fails with ENETUNREACH (looking up a name other than localhost with
 * EAI_AGAIN), at once, with a line in the log naming the call, so that a program that uses them behaves as on
 * a robot without them and never waits on a peer that will not answer.
 */
#undef _FORTIFY_SOURCE /* the runtime defines open() itself; a program's COPTS may ask for fortified headers */
#define _GNU_SOURCE
#include <arpa/inet.h>
#include <errno.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <stdarg.h>
#include <string.h>
#include <sys/stat.h>

#include "posix.h"
#include "real.h"

/* -- waiting for descriptors ---------------------------------------------------------------------------- */

static const char polling; /* what a poll waits on between two looks */

/* Look with `look` (which must not wait) once a step until it finds something or `timeout_us` (-1: none)
 * has passed; its last answer. */
static int look_until(int (*look)(void *), void *arg, int64_t timeout_us, const char *call)
{
    int64_t due = timeout_us < 0 ? HAKO_FOREVER : hako_tick() + hako_whole_steps(timeout_us);
    for (;;) {
        int found = look(arg);
        if (found != 0 || timeout_us == 0 || hako_now() >= due)
            return found;
        int64_t next = hako_tick() + HAKO_PHYSICS_STEP_US;
        if (hako_block_on(&polling, next < due ? next : due) == EDEADLK) {
            hako_uncovered(call, "it would wait where no task runs, and looks once");
            return found;
        }
    }
}

struct poll_args {
    struct pollfd *fds;
    nfds_t n;
};

static int look_poll(void *arg)
{
    struct poll_args *p = arg;
    return hako_real()->poll(p->fds, p->n, 0);
}

static int poll_us(struct pollfd *fds, nfds_t n, int64_t timeout_us, const char *call)
{
    if (n == 0) {
        if (timeout_us < 0 ? hako_sleep_until(HAKO_FOREVER) == EDEADLK : hako_sleep_for(timeout_us) == EDEADLK)
            hako_uncovered(call, "it would wait where no task runs, and returns at once");
        return 0;
    }
    struct poll_args args = {fds, n};
    return look_until(look_poll, &args, timeout_us, call);
}

int poll(struct pollfd *fds, nfds_t n, int timeout_ms)
{
    return poll_us(fds, n, timeout_ms < 0 ? -1 : (int64_t)timeout_ms * 1000, __func__);
}

int ppoll(struct pollfd *fds, nfds_t n, const struct timespec *timeout, const sigset_t *mask)
{
    (void)mask;
    int64_t us = timeout != NULL ? hako_duration_us(timeout) : -1;
    if (timeout != NULL && us < 0) {
        errno = EINVAL;
        return -1;
    }
    return poll_us(fds, n, us == HAKO_FOREVER ? -1 : us, __func__);
}

struct select_args {
    int n;
    fd_set *sets[3];
    fd_set given[3]; /* select rewrites the sets it is given: each look starts from the program's */
};

static int look_select(void *arg)
{
    struct select_args *s = arg;
    for (int i = 0; i < 3; i++)
        if (s->sets[i] != NULL)
            *s->sets[i] = s->given[i];
    struct timeval none = {0, 0};
    return hako_real()->select(s->n, s->sets[0], s->sets[1], s->sets[2], &none);
}

static int select_us(int n, fd_set *r, fd_set *w, fd_set *e, int64_t timeout_us, const char *call)
{
    struct select_args args = {n, {r, w, e}, {{{0}}}};
    bool any = false;
    for (int i = 0; i < 3; i++) {
        if (args.sets[i] != NULL) {
            args.given[i] = *args.sets[i];
            for (int fd = 0; fd < n && !any; fd++)
                any = FD_ISSET(fd, args.sets[i]);
        }
    }
    if (!any)
        return poll_us(NULL, 0, timeout_us, call); /* select(0, NULL, NULL, NULL, &t): a sleep */
    return look_until(look_select, &args, timeout_us, call);
}

int select(int n, fd_set *restrict r, fd_set *restrict w, fd_set *restrict e, struct timeval *restrict timeout)
{
    if (timeout != NULL && (timeout->tv_sec < 0 || timeout->tv_usec < 0 || timeout->tv_usec >= 1000000)) {
        errno = EINVAL;
        return -1;
    }
    int64_t us = timeout != NULL ? (int64_t)timeout->tv_sec * 1000000 + timeout->tv_usec : -1;
    int found = select_us(n, r, w, e, us, __func__);
    if (timeout != NULL)
        *timeout = (struct timeval){0, 0};
    return found;
}

int pselect(int n, fd_set *restrict r, fd_set *restrict w, fd_set *restrict e, const struct timespec *restrict timeout,
            const sigset_t *restrict mask)
{
    (void)mask;
    int64_t us = timeout != NULL ? hako_duration_us(timeout) : -1;
    if (timeout != NULL && us < 0) {
        errno = EINVAL;
        return -1;
    }
    return select_us(n, r, w, e, us == HAKO_FOREVER ? -1 : us, __func__);
}

struct epoll_args {
    int epfd;
    struct epoll_event *events;
    int max;
};

static int look_epoll(void *arg)
{
    struct epoll_args *e = arg;
    return hako_real()->epoll_wait(e->epfd, e->events, e->max, 0);
}

int epoll_wait(int epfd, struct epoll_event *events, int max, int timeout_ms)
{
    struct epoll_args args = {epfd, events, max};
    return look_until(look_epoll, &args, timeout_ms < 0 ? -1 : (int64_t)timeout_ms * 1000, __func__);
}

int epoll_pwait(int epfd, struct epoll_event *events, int max, int timeout_ms, const sigset_t *mask)
{
    (void)mask;
    return epoll_wait(epfd, events, max, timeout_ms);
}

/* -- a camera ------------------------------------------------------------------------------------------- */

static bool is_camera(const char *path) { return path != NULL && strncmp(path, "/dev/video", 10) == 0; }

static int no_camera(const char *call, const char *path)
{
    hako_log("%s(\"%s\"): the bench has no camera: it fails with ENOENT", call, path);
    errno = ENOENT;
    return -1;
}

static mode_t mode_arg(int flags, va_list args)
{
    return (flags & O_CREAT) || (flags & O_TMPFILE) == O_TMPFILE ? (mode_t)va_arg(args, int) : 0;
}

int open(const char *path, int flags, ...)
{
    va_list args;
    va_start(args, flags);
    mode_t mode = mode_arg(flags, args);
    va_end(args);
    return is_camera(path) ? no_camera(__func__, path) : hako_real()->open(path, flags, mode);
}

int open64(const char *path, int flags, ...) __attribute__((alias("open")));

int openat(int dir, const char *path, int flags, ...)
{
    va_list args;
    va_start(args, flags);
    mode_t mode = mode_arg(flags, args);
    va_end(args);
    return is_camera(path) ? no_camera(__func__, path) : hako_real()->openat(dir, path, flags, mode);
}

int openat64(int dir, const char *path, int flags, ...) __attribute__((alias("openat")));

FILE *fopen(const char *restrict path, const char *restrict mode)
{
    if (is_camera(path)) {
        no_camera(__func__, path);
        return NULL;
    }
    return hako_real()->fopen(path, mode);
}

FILE *fopen64(const char *restrict path, const char *restrict mode) __attribute__((alias("fopen")));

/* -- network peers -------------------------------------------------------------------------------------- */

static bool on_this_machine(const struct sockaddr *addr)
{
    if (addr->sa_family == AF_INET)
        return ntohl(((const struct sockaddr_in *)addr)->sin_addr.s_addr) >> 24 == 127;
    if (addr->sa_family == AF_INET6) {
        const struct in6_addr *a = &((const struct sockaddr_in6 *)addr)->sin6_addr;
        return IN6_IS_ADDR_LOOPBACK(a) || (IN6_IS_ADDR_V4MAPPED(a) && a->s6_addr[12] == 127);
    }
    return true; /* a Unix socket, or another family the program means for this machine */
}

int connect(int fd, const struct sockaddr *addr, socklen_t len)
{
    if (addr != NULL && !on_this_machine(addr)) {
        char host[INET6_ADDRSTRLEN] = "?";
        int port = 0;
        if (addr->sa_family == AF_INET) {
            inet_ntop(AF_INET, &((const struct sockaddr_in *)addr)->sin_addr, host, sizeof host);
            port = ntohs(((const struct sockaddr_in *)addr)->sin_port);
        } else {
            inet_ntop(AF_INET6, &((const struct sockaddr_in6 *)addr)->sin6_addr, host, sizeof host);
            port = ntohs(((const struct sockaddr_in6 *)addr)->sin6_port);
        }
        hako_log("connect(%s port %d): the bench has no network: it fails with ENETUNREACH", host, port);
        errno = ENETUNREACH;
        return -1;
    }
    return hako_real()->connect(fd, addr, len);
}

int getaddrinfo(const char *restrict node, const char *restrict service, const struct addrinfo *restrict hints,
                struct addrinfo **restrict found)
{
    struct in6_addr numeric;
    bool local = node == NULL || strcmp(node, "localhost") == 0 || inet_pton(AF_INET, node, &numeric) == 1 ||
                 inet_pton(AF_INET6, node, &numeric) == 1;
    if (!local) {
        hako_log("getaddrinfo(\"%s\"): the bench has no network: it fails with EAI_AGAIN", node);
        return EAI_AGAIN;
    }
    return hako_real()->getaddrinfo(node, service, hints, found);
}
