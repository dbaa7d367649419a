/* SPIKE-RT's hub status light API (spike/hub/light.h): the EV3 LED byte, as ET Robocon's SDK writes it. */
#ifndef _HUB_LIGHT_H_
#define _HUB_LIGHT_H_
#ifdef __cplusplus
extern "C" {
#endif
#include <stdint.h>
#include <pbio/color.h>
#include <pbio/error.h>

pbio_error_t hub_light_on_hsv(const pbio_color_hsv_t *hsv);
pbio_error_t hub_light_on_color(pbio_color_t color);
pbio_error_t hub_light_off(void);

#ifdef __cplusplus
}
#endif
#endif /* _HUB_LIGHT_H_ */
