/* TOPPERS t_stdlib.h: the C library parts TOPPERS code expects, and assert (ASP3's comes with it). */
#ifndef HAKO_T_STDLIB_H
#define HAKO_T_STDLIB_H
#include "t_stddef.h"
#ifndef TOPPERS_MACRO_ONLY
#include <assert.h>
#include <stdlib.h>
#include <string.h>
#endif
#endif /* HAKO_T_STDLIB_H */
