/*
 * ET Robocon's simulator extension (ETrobocon/etrobo, dist/etroboc_common/etroboc_ext.h), with its names:
 * the completion notice (TX body 480 = 1, which ends the test as COMPLETED) and the course information the
 * physics side writes from the course (RX body 480 card number, 484 block number, 488.. block positions, one
 * byte each). The bench is the simulator, so ETROBOC_SIM is defined. The offsets are hako_layout.h's.
 */
#ifndef _ETROBOC_EXT_H
#define _ETROBOC_EXT_H
#include <stdint.h>
#include "sil.h"
#include "hako_layout.h"
#ifdef __cplusplus
extern "C" {
#endif
#define ETROBOC_SIM 1

enum ETROBOC_COURSE_INFO_ID {
    ETROBOC_COURSE_INFO_CARD_NUMBER,
    ETROBOC_COURSE_INFO_BLOCK_NUMBER,
    ETROBOC_COURSE_INFO_BLOCK_POS_START,
    ETROBOC_COURSE_INFO_BLOCK_POS_BLACK1 = ETROBOC_COURSE_INFO_BLOCK_POS_START,
    ETROBOC_COURSE_INFO_BLOCK_POS_BLACK2,
    ETROBOC_COURSE_INFO_BLOCK_POS_RED1,
    ETROBOC_COURSE_INFO_BLOCK_POS_RED2,
    ETROBOC_COURSE_INFO_BLOCK_POS_YELLOW1,
    ETROBOC_COURSE_INFO_BLOCK_POS_YELLOW2,
    ETROBOC_COURSE_INFO_BLOCK_POS_BLUE1,
    ETROBOC_COURSE_INFO_BLOCK_POS_BLUE2,
    ETROBOC_COURSE_INFO_BLOCK_POS_GREEN1,
    ETROBOC_COURSE_INFO_BLOCK_POS_GREEN2,
    ETROBOC_COURSE_INFO_BLOCK_POS_END = ETROBOC_COURSE_INFO_BLOCK_POS_GREEN2,
    ETROBOC_COURSE_INFO_MAX = ETROBOC_COURSE_INFO_BLOCK_POS_END
};

inline static void ETRoboc_notifyCompletedToSimulator(void)
{
    sil_wrw_mem((volatile uint32_t *)(uintptr_t)(HAKO_TX_GUEST_BASE + HAKO_TX_COMPLETED), 1);
}

/* ET Robocon's spelling; -1 for an unknown id, as theirs. */
inline static int ETRoboc_getCourceInfo(enum ETROBOC_COURSE_INFO_ID info)
{
    uintptr_t rx = HAKO_RX_GUEST_BASE;
    if (info == ETROBOC_COURSE_INFO_CARD_NUMBER)
        return (int)sil_rew_mem((volatile uint32_t *)(rx + HAKO_RX_COURSE_CARD_NUMBER));
    if (info == ETROBOC_COURSE_INFO_BLOCK_NUMBER)
        return (int)sil_rew_mem((volatile uint32_t *)(rx + HAKO_RX_COURSE_BLOCK_NUMBER));
    if (info >= ETROBOC_COURSE_INFO_BLOCK_POS_START && info <= ETROBOC_COURSE_INFO_BLOCK_POS_END)
        return (int)sil_reb_mem((volatile uint8_t *)(rx + HAKO_RX_COURSE_BLOCK_POS + (info - ETROBOC_COURSE_INFO_BLOCK_POS_START)));
    return -1;
}

#ifdef __cplusplus
}
#endif
#endif /* _ETROBOC_EXT_H */
