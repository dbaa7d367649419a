/*
 * TOPPERS basic types and constants, as EV3RT programs for the ASP3 kernel on Athrill expect them.
 * Times are microseconds (ASP3's RELTIM, TMO and SYSTIM). Under TOPPERS_MACRO_ONLY (how app.cfg is
 * preprocessed) only macros are defined.
 */
#ifndef HAKO_T_STDDEF_H
#define HAKO_T_STDDEF_H

#ifndef TOPPERS_MACRO_ONLY
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

typedef int int_t;
typedef unsigned int uint_t;
typedef long long_t;
typedef unsigned long ulong_t;
typedef int bool_t;
typedef int_t FN;
typedef int_t ER;
typedef int_t ID;
typedef uint_t ATR;
typedef uint_t STAT;
typedef uint_t MODE;
typedef int_t PRI;
typedef uint32_t RELTIM;
typedef int32_t TMO;
typedef uint64_t SYSTIM;
typedef int_t ER_BOOL;
typedef int_t ER_ID;
typedef int_t ER_UINT;
typedef uint_t FLGPTN;
#endif /* TOPPERS_MACRO_ONLY */

#define INT_C(val) (val)
#define UINT_C(val) (val##U)
#define LONG_C(val) (val##L)
#define ULONG_C(val) (val##UL)

/* Main error codes. */
#define E_OK 0
#define E_SYS (-5)
#define E_NOSPT (-9)
#define E_RSFN (-10)
#define E_RSATR (-11)
#define E_PAR (-17)
#define E_ID (-18)
#define E_CTX (-25)
#define E_MACV (-26)
#define E_OACV (-27)
#define E_ILUSE (-28)
#define E_NOMEM (-33)
#define E_NOID (-34)
#define E_NORES (-35)
#define E_OBJ (-41)
#define E_NOEXS (-42)
#define E_QOVR (-43)
#define E_RLWAI (-49)
#define E_TMOUT (-50)
#define E_DLT (-51)
#define E_CLS (-52)
#define E_WBLK (-57)
#define E_BOVR (-58)

#define TA_NULL 0U
#define TMO_POL 0
#define TMO_FEVR (-1)

#endif /* HAKO_T_STDDEF_H */
