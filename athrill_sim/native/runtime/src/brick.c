/*
 * The brick's other devices: button click handlers, the speaker (each call a line in the log; there is no
 * sound) and the battery (its RX slots, as uart_dri_get_data_battery reads them), and Athrill's stopwatch. A
 * click is EV3RT's (brick_dri.c, brick_button_cyc): a button that was down and is now up; its handler runs,
 * like a cyclic handler, before any task, at the first snapshot that shows the button up again. EV3RT polls
 * the buttons every 10 ms whatever the tasks do, so while a click handler is set the kernel wakes at least
 * that often (hako_buttons_watched): a press shorter than the program's sleep, or one that a task waits for
 * in slp_tsk, is seen as on EV3RT.
 */
#include "athrill_syscall.h"
#include "devices.h"
#include "ev3api.h"
#include "runtime.h"
#include "scheduler.h"

static ISR click_handlers[TNUM_BUTTON];
static intptr_t click_exinfs[TNUM_BUTTON];
static uint32_t buttons_before;

ER ev3_button_set_on_clicked(button_t button, ISR handler, intptr_t exinf)
{
    if ((int)button < LEFT_BUTTON || (int)button > BACK_BUTTON)
        return E_ID;
    click_handlers[button] = handler;
    click_exinfs[button] = exinf;
    return E_OK;
}

static bool buttons_watched(void)
{
    for (int b = LEFT_BUTTON; b <= BACK_BUTTON; b++)
        if (click_handlers[b] != NULL)
            return true;
    return false;
}

/* At every snapshot: the click handlers of the buttons just released. */
static void poll_buttons(void)
{
    uint32_t now = *(volatile const uint32_t *)((uintptr_t)HAKO_RX_GUEST_BASE + HAKO_RX_BUTTONS);
    uint32_t released = buttons_before & ~now;
    buttons_before = now;
    for (int b = LEFT_BUTTON; b <= BACK_BUTTON; b++)
        if ((released >> b & 1) && click_handlers[b] != NULL)
            click_handlers[b](click_exinfs[b]);
}

/* While a click handler is set, the kernel wakes every HAKO_BUTTON_POLL_US, as EV3RT's button cyclic runs. */
static int64_t next_poll(int64_t tick)
{
    return buttons_watched() ? (tick / HAKO_BUTTON_POLL_US + 1) * HAKO_BUTTON_POLL_US : HAKO_FOREVER;
}

HAKO_DEVICE(buttons_device) = {.serve = poll_buttons, .next_due = next_poll};

ER ev3_speaker_set_volume(uint8_t volume)
{
    hako_log("speaker: volume %u", (unsigned)volume);
    return E_OK;
}

ER ev3_speaker_play_tone(uint16_t frequency, int32_t duration)
{
    hako_log("speaker: tone %u Hz for %d ms", (unsigned)frequency, (int)duration);
    return E_OK;
}

ER ev3_speaker_play_file(const memfile_t *p_memfile, int32_t duration)
{
    if (p_memfile == NULL || p_memfile->buffer == NULL)
        return E_PAR;
    hako_log("speaker: %u-byte file for %d ms", (unsigned)p_memfile->filesz, (int)duration);
    return E_OK;
}

ER ev3_speaker_stop(void)
{
    hako_log("speaker: stop");
    return E_OK;
}

int ev3_battery_current_mA(void)
{
    hako_spend_call(); /* a device read takes time (sim_time.h) */
    return *(volatile const int32_t *)((uintptr_t)HAKO_RX_GUEST_BASE + HAKO_RX_BATTERY_CURRENT);
}

int ev3_battery_voltage_mV(void)
{
    hako_spend_call(); /* a device read takes time (sim_time.h) */
    return *(volatile const int32_t *)((uintptr_t)HAKO_RX_GUEST_BASE + HAKO_RX_BATTERY_VOLTAGE);
}

static int64_t stopwatch_us;

void athrill_reset_time(void) { stopwatch_us = hako_now(); }

void athrill_show_time(void) { hako_log("athrill time: %lld us", (long long)(hako_now() - stopwatch_us)); }
