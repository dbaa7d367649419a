/* pbio's motor direction (pbio/dcmotor.h); RasPike-ART's copy has no dcmotor functions (PBIO_CONFIG_DCMOTOR off). */
#ifndef _PBIO_DCMOTOR_H_
#define _PBIO_DCMOTOR_H_
#ifdef __cplusplus
extern "C" {
#endif
#include <stdint.h>

typedef enum {
    PBIO_DIRECTION_CLOCKWISE,
    PBIO_DIRECTION_COUNTERCLOCKWISE,
} pbio_direction_t;

#ifdef __cplusplus
}
#endif
#endif /* _PBIO_DCMOTOR_H_ */
