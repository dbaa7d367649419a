/* SPIKE-RT's hub speaker API (spike/hub/speaker.h): each call a line in the log, a tone taking its duration
 * as SPIKE-RT's does. The notes are EV3RT's (hako_notes.h), with the same values. */
#ifndef _HUB_SPEAKER_H_
#define _HUB_SPEAKER_H_
#ifdef __cplusplus
extern "C" {
#endif
#include <stdint.h>
#include "hako_notes.h"

void hub_speaker_set_volume(uint8_t volume);
void hub_speaker_play_tone(uint16_t frequency, int32_t duration);
void hub_speaker_stop(void);

#ifdef __cplusplus
}
#endif
#endif /* _HUB_SPEAKER_H_ */
