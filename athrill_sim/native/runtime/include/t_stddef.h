/*
 * TOPPERS basic types and constants, as EV3RT programs (ASP3) and RasPike-ART programs (HRP3) on Athrill
 * expect them: every type of the SDKs' t_stddef.h and tool_stddef.h (float32_t included). Times are
 * microseconds (ASP3's RELTIM, TMO and SYSTIM). Under TOPPERS_MACRO_ONLY (how app.cfg is preprocessed) only
 * macros are defined.
 */
#ifndef HAKO_T_STDDEF_H
#define HAKO_T_STDDEF_H

#ifndef TOPPERS_MACRO_ONLY
#include <limits.h>
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
typedef uint32_t PRCTIM;
typedef uint32_t HRTCNT;
typedef uintptr_t MB_T;
struct TOPPERS_dummy_t {
    int TOPPERS_dummy_field;
};
typedef void (*FP)(struct TOPPERS_dummy_t);
/* HRP3's access control (RasPike's kernel is HRP3): accepted, never checked here. */
typedef uint32_t ACPTN;
typedef struct acvct {
    ACPTN acptn1;
    ACPTN acptn2;
    ACPTN acptn3;
    ACPTN acptn4;
} ACVCT;
/* tool_stddef.h's IEEE 754 types (TOPPERS_STDFLOAT_TYPE1). */
typedef float float32_t;
typedef double double64_t;
#endif /* TOPPERS_MACRO_ONLY */

#define FLOAT32_MIN 1.17549435e-38F
#define FLOAT32_MAX 3.40282347e+38F
#define DOUBLE64_MIN 2.2250738585072014e-308
#define DOUBLE64_MAX 1.7976931348623157e+308
#define Inline static inline
#define NoReturn __attribute__((__noreturn__))

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
#define E_RASTER (-53)
#define E_WBLK (-57)
#define E_BOVR (-58)
#define E_COMM (-65)

/* Error codes with a sub-code (t_stddef.h's ERCD / MERCD / SERCD). */
#define ERCD(mercd, sercd) ((ER)((((uint_t)(sercd)) << 8) | (((uint_t)(mercd)) & 0xffU)))
#define MERCD(ercd) ((ER)((int8_t)(ercd)))
#define SERCD(ercd) ((ER)((ercd) >> 8))

#define TA_NULL 0U
#define TMO_POL 0
#define TMO_FEVR (-1)
#define TMO_NBLK (-2) /* ASP3's UINT32_MAX - 1 as a TMO; the mock's tslp_tsk takes it as polling */
#define TMAX_RELTIM 4000000000U

#define TACP_KERNEL 0U
#define TACP_SHARED (~0U)
#define TACP(domid) (1U << ((domid) - 1))

#define ALIGN_TYPE(addr, type) ((((uintptr_t)(addr)) & (__alignof__(type) - 1)) == 0U)

#endif /* HAKO_T_STDDEF_H */
