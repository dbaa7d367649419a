/*
 * syslog: one line on stderr (the run's athrill.log), stamped as lines.c stamps the runtime's own. Every
 * priority is written until the program sets a log mask (syslog_msk_log): then a line is written if its
 * priority is in either mask, the buffer's or the low-level output's, as ASP3's tSysLog would either log it
 * or print it.
 */
#include <stdarg.h>

#include "runtime.h"
#include "syssvc/syslog.h"
#include "t_syslog.h"

static uint_t log_mask = LOG_UPTO(LOG_DEBUG);

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
    hako_vlog(format, args);
    va_end(args);
}
