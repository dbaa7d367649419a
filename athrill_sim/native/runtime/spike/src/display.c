/*
 * The hub's 5x5 display, which the bench has not: each call is a line in the log, and takes the time
 * SPIKE-RT's takes (drivers/spike/hub/display.c: text shows each character for `on` ms, then `off` ms dark;
 * a scroll moves one column every `delay` ms), with SPIKE-RT's errors for a pixel off the matrix or a
 * character it has no glyph for. ET Robocon's SDK does nothing and returns at once.
 */
#include <stdio.h>
#include <string.h>

#include "kernel.h"
#include "spike.h"
#include "spike/hub/display.h"

#define SIZE 5 /* pixels a side */
#define FIRST_GLYPH 32 /* the characters SPIKE-RT's 5x5 font has: ' ' .. '~' */
#define LAST_GLYPH 126

static bool has_glyph(char c) { return c >= FIRST_GLYPH && c <= LAST_GLYPH; }

static bool all_glyphs(const char *text)
{
    for (const char *p = text; *p; p++)
        if (!has_glyph(*p))
            return false;
    return true;
}

pbio_error_t hub_display_orientation(uint8_t up)
{
    hako_log("display: orientation %u", (unsigned)up);
    return PBIO_SUCCESS;
}

pbio_error_t hub_display_off(void)
{
    hako_log("display: off");
    return PBIO_SUCCESS;
}

pbio_error_t hub_display_pixel(uint8_t row, uint8_t column, uint8_t brightness)
{
    if (row >= SIZE || column >= SIZE)
        return PBIO_ERROR_INVALID_ARG;
    hako_log("display: pixel row %u column %u at %u%%", (unsigned)row, (unsigned)column, (unsigned)brightness);
    return PBIO_SUCCESS;
}

pbio_error_t hub_display_image(uint8_t *image)
{
    char rows[SIZE * SIZE * 4 + SIZE + 1] = "";
    for (int i = 0; i < SIZE * SIZE; i++)
        snprintf(rows + strlen(rows), sizeof rows - strlen(rows), "%s%u",
                 i == 0     ? ""
                 : i % SIZE ? " "
                            : " / ",
                 (unsigned)image[i]);
    hako_log("display: image %s", rows);
    return PBIO_SUCCESS;
}

pbio_error_t hub_display_number(const int8_t num)
{
    hako_log("display: number %d", (int)num);
    return PBIO_SUCCESS;
}

pbio_error_t hub_display_char(const char c)
{
    if (!has_glyph(c))
        return PBIO_ERROR_INVALID_ARG;
    hako_log("display: char '%c'", c);
    return PBIO_SUCCESS;
}

pbio_error_t hub_display_text(const char *text, uint32_t on, uint32_t off)
{
    if (!all_glyphs(text))
        return PBIO_ERROR_INVALID_ARG;
    hako_log("display: text \"%s\" (%u ms each, %u ms dark between)", text, (unsigned)on, (unsigned)off);
    for (size_t i = 0, n = strlen(text); i < n; i++) {
        dly_tsk(on * 1000);
        if (off > 0 || i == n - 1)
            dly_tsk(off * 1000);
    }
    return PBIO_SUCCESS;
}

pbio_error_t hub_display_text_scroll(const char *text, uint32_t delay)
{
    if (!all_glyphs(text))
        return PBIO_ERROR_INVALID_ARG;
    hako_log("display: scroll \"%s\" (%u ms a column)", text, (unsigned)delay);
    for (size_t frame = 0, n = (strlen(text) + 1) * (SIZE + 1); frame < n; frame++) /* a column between glyphs */
        dly_tsk(delay * 1000);
    return PBIO_SUCCESS;
}
