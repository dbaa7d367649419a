/*
 * The POSIX timers and alarms (alarm, setitimer, timer_create, timerfd_create) are not covered by the native
 * runtime: no program this bench was built for uses them. Each says so in one line and fails with ENOSYS,
 * rather than never firing in silence. (RasPike-ART's asp, whose kernel tick is setitimer, has its timer on
 * simulated time in athrill_sim/native/runtime/asp, which does not link this file.)
 */
#define _GNU_SOURCE
#include <errno.h>
#include <sys/time.h>
#include <sys/timerfd.h>
#include <unistd.h>

#include "posix.h"

unsigned int alarm(unsigned int seconds)
{
    (void)seconds;
    hako_uncovered(__func__, "the alarm never fires");
    return 0;
}

int setitimer(__itimer_which_t which, const struct itimerval *restrict value, struct itimerval *restrict old)
{
    (void)which, (void)value, (void)old;
    hako_uncovered(__func__, "it fails with ENOSYS");
    errno = ENOSYS;
    return -1;
}

int timer_create(clockid_t clock, struct sigevent *restrict event, timer_t *restrict timer)
{
    (void)clock, (void)event, (void)timer;
    hako_uncovered(__func__, "it fails with ENOSYS");
    errno = ENOSYS;
    return -1;
}

int timerfd_create(int clock, int flags)
{
    (void)clock, (void)flags;
    hako_uncovered(__func__, "it fails with ENOSYS");
    errno = ENOSYS;
    return -1;
}
