/* TOPPERS syslog: a line on stderr (the run's athrill.log), stamped with the simulated time. */
#ifndef HAKO_T_SYSLOG_H
#define HAKO_T_SYSLOG_H

#include "t_stddef.h"

#define LOG_EMERG 0U
#define LOG_ALERT 1U
#define LOG_CRIT 2U
#define LOG_ERROR 3U
#define LOG_WARNING 4U
#define LOG_NOTICE 5U
#define LOG_INFO 6U
#define LOG_DEBUG 7U

#define LOG_MASK(prio) (1U << (prio))
#define LOG_UPTO(prio) ((1U << ((prio) + 1)) - 1)

#ifndef TOPPERS_MACRO_ONLY
#ifdef __cplusplus
extern "C" {
#endif
void syslog(uint_t prio, const char *format, ...) __attribute__((format(printf, 2, 3)));
#ifdef __cplusplus
}
#endif
#endif

#endif /* HAKO_T_SYSLOG_H */
