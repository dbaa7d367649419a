/*
 * ASP3's syssvc/syslog.h, which SPIKE-RT's programs include for syslog() (and RasPike-ART's and EV3RT's may):
 * the priorities and syslog() of t_syslog.h, and the log mask. syslog_fls_log is declared with ASP3's
 * signature but not provided (every line is written at once, there is no buffer to flush): a call is a link
 * error that names it.
 */
#ifndef HAKO_SYSSVC_SYSLOG_H
#define HAKO_SYSSVC_SYSLOG_H

#include "t_stddef.h"
#include "t_syslog.h"

#ifndef TOPPERS_MACRO_ONLY
#ifdef __cplusplus
extern "C" {
#endif
ER syslog_msk_log(uint_t logmask, uint_t lowmask);
/* Not provided. */
ER syslog_fls_log(void);
#ifdef __cplusplus
}
#endif
#endif

#endif /* HAKO_SYSSVC_SYSLOG_H */
