/*
 * The hub's speaker, which the bench has not: each call a line in the log, as the EV3 speaker's. A tone takes
 * its duration (SPIKE-RT's hub_speaker_play_tone waits it out, then stops), unless it is SOUND_MANUAL_STOP;
 * its frequency is SPIKE-RT's 64..24000 Hz. ET Robocon's SDK does nothing and returns at once.
 */
#include "spike/hub/speaker.h"
#include "kernel.h"
#include "spike.h"

#define MIN_HZ 64
#define MAX_HZ 24000

void hub_speaker_set_volume(uint8_t volume) { hako_log("speaker: volume %u", (unsigned)volume); }

void hub_speaker_play_tone(uint16_t frequency, int32_t duration)
{
    unsigned hz = frequency < MIN_HZ ? MIN_HZ : frequency > MAX_HZ ? MAX_HZ : frequency;
    hako_log("speaker: tone %u Hz for %d ms", hz, (int)duration);
    if (duration < 0)
        return;
    dly_tsk((RELTIM)duration * 1000);
    hub_speaker_stop();
}

void hub_speaker_stop(void) { hako_log("speaker: stop"); }
