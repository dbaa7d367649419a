/* Pybricks' pbio error codes, as SPIKE-RT returns them (libpybricks lib/pbio/include/pbio/error.h). */
#ifndef _PBIO_ERROR_H_
#define _PBIO_ERROR_H_
#ifdef __cplusplus
extern "C" {
#endif

typedef enum {
    PBIO_SUCCESS,
    PBIO_ERROR_FAILED,
    PBIO_ERROR_INVALID_ARG,
    PBIO_ERROR_IO,
    PBIO_ERROR_BUSY,
    PBIO_ERROR_NO_DEV,
    PBIO_ERROR_NOT_IMPLEMENTED,
    PBIO_ERROR_NOT_SUPPORTED,
    PBIO_ERROR_AGAIN,
    PBIO_ERROR_INVALID_OP,
    PBIO_ERROR_TIMEDOUT,
    PBIO_ERROR_CANCELED
} pbio_error_t;

/* Not provided (as in ET Robocon's SDK, which ships pbio's headers without its sources): a link error. */
const char *pbio_error_str(pbio_error_t err);

#ifdef __cplusplus
}
#endif
#endif /* _PBIO_ERROR_H_ */
