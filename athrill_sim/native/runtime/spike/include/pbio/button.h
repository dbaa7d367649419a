/* pbio's button bits (pbio/button.h); SPIKE-RT's hub/button.h names the hub's four of them. */
#ifndef _PBIO_BUTTON_H_
#define _PBIO_BUTTON_H_
#ifdef __cplusplus
extern "C" {
#endif
#include <pbio/error.h>
#include <pbio/port.h>

#define PBIO_BUTTON_NUM_BUTTONS 9

typedef enum _pbio_button_flags_t {
    PBIO_BUTTON_LEFT_DOWN = 1 << 1,
    PBIO_BUTTON_DOWN = 1 << 2,
    PBIO_BUTTON_RIGHT_DOWN = 1 << 3,
    PBIO_BUTTON_LEFT = 1 << 4,
    PBIO_BUTTON_CENTER = 1 << 5,
    PBIO_BUTTON_RIGHT = 1 << 6,
    PBIO_BUTTON_LEFT_UP = 1 << 7,
    PBIO_BUTTON_UP = 1 << 8,
    PBIO_BUTTON_RIGHT_UP = 1 << 9,
} pbio_button_flags_t;

typedef pbio_error_t (*pbio_button_is_pressed_func_t)(pbio_button_flags_t *pressed);

/* As pbio's header: the driver's function, which neither the SDK nor this runtime provides (a link error). */
#define pbio_button_is_pressed pbdrv_button_is_pressed
pbio_error_t pbdrv_button_is_pressed(pbio_button_flags_t *pressed);

#ifdef __cplusplus
}
#endif
#endif /* _PBIO_BUTTON_H_ */
