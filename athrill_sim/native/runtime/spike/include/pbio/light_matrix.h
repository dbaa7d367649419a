/* pbio's light matrix types (pbio/light_matrix.h): the sides hub_display_orientation takes. */
#ifndef _PBIO_LIGHT_MATRIX_H_
#define _PBIO_LIGHT_MATRIX_H_
#ifdef __cplusplus
extern "C" {
#endif
#include <stdint.h>
#include <pbio/error.h>

typedef struct _pbio_light_matrix_t pbio_light_matrix_t;

typedef enum {
    PBIO_SIDE_TOP,
    PBIO_SIDE_LEFT,
    PBIO_SIDE_BOTTOM,
    PBIO_SIDE_RIGHT,
    PBIO_SIDE_FRONT,
    PBIO_SIDE_BACK,
} pbio_side_t;

/* Not provided: pbio's own matrix driver (RasPike-ART's header makes each a stub answering
 * PBIO_ERROR_NOT_SUPPORTED; here each is a link error naming it). Use hub_display_*. */
uint8_t pbio_light_matrix_get_size(pbio_light_matrix_t *light_matrix);
void pbio_light_matrix_set_orientation(pbio_light_matrix_t *light_matrix, pbio_side_t up_side);
pbio_error_t pbio_light_matrix_clear(pbio_light_matrix_t *light_matrix);
pbio_error_t pbio_light_matrix_set_rows(pbio_light_matrix_t *light_matrix, const uint8_t *rows);
pbio_error_t pbio_light_matrix_set_pixel(pbio_light_matrix_t *light_matrix, uint8_t row, uint8_t col,
                                         uint8_t brightness);
pbio_error_t pbio_light_matrix_set_image(pbio_light_matrix_t *light_matrix, const uint8_t *image);
void pbio_light_matrix_start_animation(pbio_light_matrix_t *light_matrix, const uint8_t *cells, uint8_t num_cells,
                                       uint16_t interval);
void pbio_light_matrix_stop_animation(pbio_light_matrix_t *light_matrix);

#ifdef __cplusplus
}
#endif
#endif /* _PBIO_LIGHT_MATRIX_H_ */
