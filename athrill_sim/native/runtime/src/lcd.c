/*
 * The EV3's 178x128 LCD. EV3RT on Athrill draws nothing (its calls return E_OK); here every drawing call is
 * kept, in order, as a line of the run directory's lcd.txt, stamped with the simulated time, and the physics
 * process draws the screen from it as lcd.png at the end of the test (hakoniwa/physics/lcd.py). Argument
 * checks are EV3RT's (ev3api_lcd.c): an unknown font is E_ID; the image calls check nothing.
 */
#include <stdio.h>
#include <string.h>

#include "ev3api.h"
#include "real.h"
#include "runtime.h"

static lcdfont_t font = EV3_FONT_SMALL;
static FILE *lcd_log;

static const int32_t font_size[2][2] = {{6, 8}, {10, 16}}; /* EV3RT's font_w6h8 and font_w10h16 */

static void draw(const char *format, ...) __attribute__((format(printf, 1, 2)));
static void draw(const char *format, ...)
{
    if (lcd_log == NULL) {
        char path[4096];
        snprintf(path, sizeof path, "%s/%s", hako_run_dir(), HAKO_LCD_LOG);
        lcd_log = hako_real()->fopen(path, "w");
        if (lcd_log == NULL)
            return;
    }
    va_list args;
    va_start(args, format);
    fprintf(lcd_log, "%lld ", (long long)hako_now());
    vfprintf(lcd_log, format, args);
    fputc('\n', lcd_log);
    fflush(lcd_log);
    va_end(args);
}

ER ev3_lcd_set_font(lcdfont_t f)
{
    if (f != EV3_FONT_SMALL && f != EV3_FONT_MEDIUM)
        return E_ID;
    font = f;
    return E_OK;
}

ER ev3_font_get_size(lcdfont_t f, int32_t *p_width, int32_t *p_height)
{
    if (f != EV3_FONT_SMALL && f != EV3_FONT_MEDIUM)
        return E_ID;
    if (p_width != NULL)
        *p_width = font_size[f][0];
    if (p_height != NULL)
        *p_height = font_size[f][1];
    return E_OK;
}

ER ev3_lcd_draw_string(const char *str, int32_t x, int32_t y)
{
    char text[EV3_LCD_WIDTH + 1]; /* more characters than that cannot show */
    size_t n = 0;
    for (; str != NULL && str[n] != '\0' && n < sizeof text - 1; n++)
        text[n] = str[n] == '\n' || str[n] == '\r' ? ' ' : str[n];
    text[n] = '\0';
    draw("string %d %d %d %s", (int)font, (int)x, (int)y, text);
    return E_OK;
}

ER ev3_lcd_draw_line(int32_t x0, int32_t y0, int32_t x1, int32_t y1)
{
    draw("line %d %d %d %d", (int)x0, (int)y0, (int)x1, (int)y1);
    return E_OK;
}

ER ev3_lcd_fill_rect(int32_t x, int32_t y, int32_t w, int32_t h, lcdcolor_t color)
{
    draw("fill %d %d %d %d %d", (int)x, (int)y, (int)w, (int)h, color == EV3_LCD_BLACK ? 1 : 0);
    return E_OK;
}

/* EV3RT on Athrill returns E_OK before its argument checks and loads, frees and draws nothing (ev3api_lcd.c);
 * a drawn image is still kept in lcd.txt, as its frame. */
ER ev3_image_load(const memfile_t *p_memfile, image_t *p_image)
{
    (void)p_memfile, (void)p_image;
    return E_OK;
}

ER ev3_image_free(image_t *p_image)
{
    (void)p_image;
    return E_OK;
}

ER ev3_lcd_draw_image(const image_t *p_image, int32_t x, int32_t y)
{
    if (p_image != NULL)
        draw("image %d %d %d %d", (int)x, (int)y, (int)p_image->width, (int)p_image->height);
    return E_OK;
}
