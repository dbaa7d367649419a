/* The hub's I/O ports, A to F, as RasPike-ART's pbio/port.h numbers them (by their letters). */
#ifndef _PBIO_PORT_H_
#define _PBIO_PORT_H_
#ifdef __cplusplus
extern "C" {
#endif
#include <stdbool.h>
#include <stdint.h>

#define PBDRV_CONFIG_HAS_PORT_A 1
#define PBDRV_CONFIG_HAS_PORT_B 1
#define PBDRV_CONFIG_HAS_PORT_C 1
#define PBDRV_CONFIG_HAS_PORT_D 1
#define PBDRV_CONFIG_HAS_PORT_E 1
#define PBDRV_CONFIG_HAS_PORT_F 1

typedef enum {
    PBIO_PORT_ID_A = 'A',
    PBIO_PORT_ID_B = 'B',
    PBIO_PORT_ID_C = 'C',
    PBIO_PORT_ID_D = 'D',
    PBIO_PORT_ID_E = 'E',
    PBIO_PORT_ID_F = 'F',
} pbio_port_id_t;

#ifdef __cplusplus
}
#endif
#endif /* _PBIO_PORT_H_ */
