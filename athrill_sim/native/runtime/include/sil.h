/* TOPPERS' system interface layer: memory access by address, as sil.h gives it (little-endian, like the guest). */
#ifndef HAKO_SIL_H
#define HAKO_SIL_H
#include "t_stddef.h"
#ifndef TOPPERS_MACRO_ONLY
static inline uint8_t sil_reb_mem(const volatile uint8_t *mem) { return *mem; }
static inline void sil_wrb_mem(volatile uint8_t *mem, uint8_t data) { *mem = data; }
static inline uint16_t sil_reh_mem(const volatile uint16_t *mem) { return *mem; }
static inline void sil_wrh_mem(volatile uint16_t *mem, uint16_t data) { *mem = data; }
static inline uint32_t sil_rew_mem(const volatile uint32_t *mem) { return *mem; }
static inline void sil_wrw_mem(volatile uint32_t *mem, uint32_t data) { *mem = data; }
static inline void sil_dly_nse(ulong_t dlytim) { (void)dlytim; } /* computation takes no simulated time */
#define SIL_PRE_LOC
#define SIL_LOC_INT() ((void)0)
#define SIL_UNL_INT() ((void)0)
#endif
#endif /* HAKO_SIL_H */
