/*
 * syslog: one line on stderr (the run's athrill.log), stamped with the simulated time in the mock's format
 * ("[    12.300 s] message"). A line is written with a single write(), so the lines of the running and the
 * pre-launched process never interleave. Every priority is written until the program sets a log mask
 * (syslog_msk_log): then a line is written if its priority is in either mask, the buffer's or the low-level
 * output's, as ASP3's tSysLog would either log it or print it.
 */
#include <stdarg.h>
#include <stdio.h>
#include <unistd.h>

#include "runtime.h"
#include "syssvc/syslog.h"
#include "t_syslog.h"

static uint_t log_mask = LOG_UPTO(LOG_DEBUG);

void hako_vline(const char *prefix, const char *format, va_list args)
{
    char line[1024];
    int n = snprintf(line, sizeof line, "%s", prefix);
    n += vsnprintf(line + n, sizeof line - (size_t)n, format, args);
    if (n > (int)sizeof line - 2)
        n = (int)sizeof line - 2;
    line[n++] = '\n';
    (void)!write(STDERR_FILENO, line, (size_t)n);
}

static void vlog(const char *format, va_list args)
{
    char stamp[32];
    snprintf(stamp, sizeof stamp, "[%10.3f s] ", (double)hako_now() / 1e6);
    hako_vline(stamp, format, args);
}

void hako_log(const char *format, ...)
{
    va_list args;
    va_start(args, format);
    vlog(format, args);
    va_end(args);
}

ER syslog_msk_log(uint_t logmask, uint_t lowmask)
{
    log_mask = logmask | lowmask;
    return E_OK;
}

void syslog(uint_t prio, const char *format, ...)
{
    if ((log_mask & LOG_MASK(prio)) == 0U)
        return;
    va_list args;
    va_start(args, format);
    vlog(format, args);
    va_end(args);
}
