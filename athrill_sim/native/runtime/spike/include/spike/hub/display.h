/* SPIKE-RT's hub display API (spike/hub/display.h): each call a line in the log, taking the time SPIKE-RT's
 * takes (docs/NATIVE.md, "SPIKE"). */
#ifndef _HUB_DISPLAY_H_
#define _HUB_DISPLAY_H_
#ifdef __cplusplus
extern "C" {
#endif
#include <stdint.h>
#include <pbio/error.h>
#include <pbio/light_matrix.h>

pbio_error_t hub_display_orientation(uint8_t up);
pbio_error_t hub_display_off(void);
pbio_error_t hub_display_pixel(uint8_t row, uint8_t column, uint8_t brightness);
pbio_error_t hub_display_image(uint8_t *image);
pbio_error_t hub_display_number(const int8_t num);
pbio_error_t hub_display_char(const char c);
pbio_error_t hub_display_text(const char *text, uint32_t on, uint32_t off);
pbio_error_t hub_display_text_scroll(const char *text, uint32_t delay);

#ifdef __cplusplus
}
#endif
#endif /* _HUB_DISPLAY_H_ */
