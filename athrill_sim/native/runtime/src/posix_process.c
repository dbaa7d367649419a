/*
 * The program as a process of the robot's Linux: the commands it starts, and the interrupt that ends it.
 *
 * system() and popen() run /bin/sh in the program's working folder (its workspace) while simulated time stands
 * still, each bounded in wall time (HAKO_CHILD_BOUND_S, from the environment, else 5 s: the physics process
 * takes a program that is silent for its --athrill-timeout as stalled) and stopped with its whole process group
 * past it. Their output goes to the program's log, except what popen() hands the program: a popen for reading
 * runs the command to its end and gives the program what it wrote, one for writing runs it at pclose with what
 * the program wrote. Every command is a line in the log. A fork()ed child is detached from the lockstep at once.
 *
 * SIGINT and SIGTERM handlers are the program's own, and run when the test ends (the physics process sends
 * SIGINT, as Ctrl-C on the robot): the lockstep is then detached (lockstep.c) before the handler runs, so that a
 * handler that only raises a flag lets the program see it, end its loops and write its logs.
 */
#define _GNU_SOURCE
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include "posix.h"
#include "real.h"

#define DEFAULT_CHILD_BOUND_S 5.0
#define MAX_POPEN 16

static double child_bound_s(void)
{
    static double bound = -1;
    if (bound < 0) {
        const char *given = getenv("HAKO_CHILD_BOUND_S");
        char *end;
        bound = given != NULL ? strtod(given, &end) : DEFAULT_CHILD_BOUND_S;
        if (given != NULL && (*end != '\0' || bound <= 0))
            bound = DEFAULT_CHILD_BOUND_S;
    }
    return bound;
}

/* /bin/sh -c `command`, its standard input and output where given (else the program's), to its end or the
 * bound; its wait status. */
static int run_shell(const char *call, const char *command, int in_fd, int out_fd)
{
    fflush(stdout);
    hako_log("%s: sh -c \"%s\"", call, command);
    pid_t pid = hako_real()->fork();
    if (pid < 0)
        return -1;
    if (pid == 0) {
        prctl(PR_SET_PDEATHSIG, SIGKILL);
        setpgid(0, 0);
        if (in_fd >= 0)
            dup2(in_fd, STDIN_FILENO);
        if (out_fd >= 0)
            dup2(out_fd, STDOUT_FILENO);
        execl("/bin/sh", "sh", "-c", command, (char *)NULL);
        _exit(127);
    }
    double deadline = hako_wall_s() + child_bound_s();
    int status = 0;
    for (;;) {
        pid_t done = waitpid(pid, &status, WNOHANG);
        if (done == pid || (done < 0 && errno != EINTR))
            break;
        if (hako_wall_s() > deadline) {
            kill(-pid, SIGKILL);
            kill(pid, SIGKILL);
            waitpid(pid, &status, 0);
            hako_log("%s: \"%s\" ran past %g s of wall time, the bench's bound: stopped", call, command,
                     child_bound_s());
            break;
        }
        hako_wall_nap(0.002);
    }
    return status;
}

int system(const char *command)
{
    if (command == NULL)
        return 1; /* a shell is there */
    return run_shell(__func__, command, -1, -1);
}

static struct {
    FILE *file;
    int status;
    char *command; /* a popen for writing: run at pclose */
} opened[MAX_POPEN];

FILE *popen(const char *command, const char *mode)
{
    bool reading = mode[0] == 'r';
    if ((mode[0] != 'r' && mode[0] != 'w') || command == NULL) {
        errno = EINVAL;
        return NULL;
    }
    int slot = 0;
    while (slot < MAX_POPEN && opened[slot].file != NULL)
        slot++;
    int fd = slot < MAX_POPEN ? memfd_create("popen", MFD_CLOEXEC) : -1;
    if (fd < 0) {
        errno = EMFILE;
        return NULL;
    }
    int status = 0;
    if (reading) {
        status = run_shell(__func__, command, -1, fd);
        lseek(fd, 0, SEEK_SET);
    }
    FILE *file = fdopen(fd, reading ? "r" : "w+");
    if (file == NULL) {
        close(fd);
        return NULL;
    }
    opened[slot].file = file;
    opened[slot].status = status;
    opened[slot].command = reading ? NULL : strdup(command);
    return file;
}

int pclose(FILE *file)
{
    for (int slot = 0; slot < MAX_POPEN; slot++) {
        if (opened[slot].file != file || file == NULL)
            continue;
        int status = opened[slot].status;
        if (opened[slot].command != NULL) {
            fflush(file);
            lseek(fileno(file), 0, SEEK_SET);
            status = run_shell("popen", opened[slot].command, fileno(file), -1);
            free(opened[slot].command);
        }
        fclose(file);
        opened[slot].file = NULL;
        return status;
    }
    return hako_real()->pclose(file);
}

/* A child runs as on Linux, its forking thread alone, detached from the lockstep from its first instruction:
 * it never reaches the bench's files, so a library that forks a helper and execs it (GStreamer's plugin
 * scanner) works, and a child that goes on in the program's code runs in simulated time of its own. */
pid_t fork(void)
{
    fflush(NULL);
    pid_t pid = hako_real()->fork();
    if (pid == 0) {
        hako_lockstep_detach();
        hako_kernel_forked();
    }
    return pid;
}

/* -- the interrupt at the test's end ------------------------------------------------------------------------- */

static struct sigaction programs[2]; /* the program's own for SIGINT and SIGTERM */

static int interrupt_index(int sig) { return sig == SIGINT ? 0 : sig == SIGTERM ? 1 : -1; }

static void on_interrupt(int sig, siginfo_t *info, void *context)
{
    struct sigaction *own = &programs[interrupt_index(sig)];
    hako_lockstep_detach();
    if (own->sa_flags & SA_SIGINFO)
        own->sa_sigaction(sig, info, context);
    else
        own->sa_handler(sig);
}

int sigaction(int sig, const struct sigaction *restrict act, struct sigaction *restrict old)
{
    int i = interrupt_index(sig);
    if (i < 0)
        return hako_real()->sigaction(sig, act, old);
    struct sigaction before = programs[i];
    if (act != NULL) {
        struct sigaction installed = *act;
        if (act->sa_handler != SIG_DFL && act->sa_handler != SIG_IGN) {
            installed.sa_sigaction = on_interrupt;
            installed.sa_flags = (act->sa_flags | SA_SIGINFO) & ~SA_RESTART; /* out of the lockstep's wait at once */
        }
        if (hako_real()->sigaction(sig, &installed, NULL) != 0)
            return -1;
        programs[i] = *act;
    }
    if (old != NULL) {
        *old = before;
        if (before.sa_handler == NULL && !(before.sa_flags & SA_SIGINFO))
            old->sa_handler = SIG_DFL;
    }
    return 0;
}
int hako_sigaction(int sig, const struct sigaction *restrict act, struct sigaction *restrict old)
    __attribute__((alias("sigaction")));

sighandler_t signal(int sig, sighandler_t handler)
{
    struct sigaction act = {.sa_handler = handler, .sa_flags = SA_RESTART}, old;
    sigemptyset(&act.sa_mask);
    if (hako_sigaction(sig, &act, &old) != 0)
        return SIG_ERR;
    return old.sa_handler;
}
