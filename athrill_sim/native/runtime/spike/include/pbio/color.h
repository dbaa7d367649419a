/* pbio's colours (pbio/color.h): the named colours (hue, saturation and value squeezed into 8 bits, as
 * PBIO_COLOR_ENCODE does), the hues, and RGB / HSV. */
#ifndef _PBIO_COLOR_H_
#define _PBIO_COLOR_H_
#ifdef __cplusplus
extern "C" {
#endif
#include <stdint.h>

#define PBIO_COLOR_ENCODE(h, s, v) ((((h) / 30) << 3) | (((s) / 51) << 2) | ((v) / 34))
typedef enum {
    PBIO_COLOR_NONE = PBIO_COLOR_ENCODE(180, 0, 0),
    PBIO_COLOR_BLACK = PBIO_COLOR_ENCODE(0, 0, 0),
    PBIO_COLOR_GRAY = PBIO_COLOR_ENCODE(0, 0, 50),
    PBIO_COLOR_WHITE = PBIO_COLOR_ENCODE(0, 0, 100),
    PBIO_COLOR_RED = PBIO_COLOR_ENCODE(0, 100, 100),
    PBIO_COLOR_BROWN = PBIO_COLOR_ENCODE(30, 100, 50),
    PBIO_COLOR_ORANGE = PBIO_COLOR_ENCODE(30, 100, 100),
    PBIO_COLOR_YELLOW = PBIO_COLOR_ENCODE(60, 100, 100),
    PBIO_COLOR_GREEN = PBIO_COLOR_ENCODE(120, 100, 100),
    PBIO_COLOR_SPRING_GREEN = PBIO_COLOR_ENCODE(150, 100, 100),
    PBIO_COLOR_CYAN = PBIO_COLOR_ENCODE(180, 100, 100),
    PBIO_COLOR_BLUE = PBIO_COLOR_ENCODE(240, 100, 100),
    PBIO_COLOR_VIOLET = PBIO_COLOR_ENCODE(270, 100, 100),
    PBIO_COLOR_MAGENTA = PBIO_COLOR_ENCODE(300, 100, 100),
} pbio_color_t;
#undef PBIO_COLOR_ENCODE

typedef enum {
    PBIO_COLOR_HUE_RED = 0,
    PBIO_COLOR_HUE_ORANGE = 30,
    PBIO_COLOR_HUE_YELLOW = 60,
    PBIO_COLOR_HUE_GREEN = 120,
    PBIO_COLOR_HUE_SPRING_GREEN = 150,
    PBIO_COLOR_HUE_CYAN = 180,
    PBIO_COLOR_HUE_BLUE = 240,
    PBIO_COLOR_HUE_VIOLET = 270,
    PBIO_COLOR_HUE_MAGENTA = 300,
} pbio_color_hue_t;

#define PBIO_COLOR_HUE_MODULO 360

typedef struct {
    uint8_t r;
    uint8_t g;
    uint8_t b;
} pbio_color_rgb_t;

typedef struct {
    uint16_t h; /* 0..359 degrees */
    uint8_t s; /* 0..100 % */
    uint8_t v; /* 0..100 % */
} pbio_color_hsv_t;

typedef struct __attribute__((__packed__)) {
    uint16_t h : 9;
    uint8_t s : 7;
    uint8_t v;
} pbio_color_compressed_hsv_t;

/* Not provided (pbio's sources are not in ET Robocon's SDK either): each is a link error naming it. */
void pbio_color_rgb_to_hsv(const pbio_color_rgb_t *rgb, pbio_color_hsv_t *hsv);
void pbio_color_hsv_to_rgb(const pbio_color_hsv_t *hsv, pbio_color_rgb_t *rgb);
void pbio_color_to_hsv(pbio_color_t color, pbio_color_hsv_t *hsv);
void pbio_color_to_rgb(pbio_color_t color, pbio_color_rgb_t *rgb);
void pbio_color_hsv_compress(const pbio_color_hsv_t *hsv, pbio_color_compressed_hsv_t *compressed);
void pbio_color_hsv_expand(const pbio_color_compressed_hsv_t *compressed, pbio_color_hsv_t *hsv);

#ifdef __cplusplus
}
#endif
#endif /* _PBIO_COLOR_H_ */
