/*
 * The runtime's lines on stderr (the run's athrill.log), stamped with the simulated time in the mock's format
 * ("[    12.300 s] message"). A line is written with a single write(), so the lines of the running and the
 * pre-launched process never interleave. Apart from syslog.c so that asp's clock library (../asp), whose
 * program has a syslog of its own, logs as the runtime does.
 */
#include <stdarg.h>
#include <stdio.h>
#include <unistd.h>

#include "runtime.h"

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

void hako_vlog(const char *format, va_list args)
{
    char stamp[32];
    snprintf(stamp, sizeof stamp, "[%10.3f s] ", (double)hako_now() / 1e6);
    hako_vline(stamp, format, args);
}

void hako_log(const char *format, ...)
{
    va_list args;
    va_start(args, format);
    hako_vlog(format, args);
    va_end(args);
}
