#include "ev3api.h"

void tracer_init(void);
void tracer_run(void);
