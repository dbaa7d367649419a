/*
 * SPIKE-RT's libcpp/libcpp.h: libcpp_is_ready() says whether the C++ global objects are built. On the hub an
 * init task builds them (drivers/libcpp/app_init.c) while the program's tasks wait for it (libcpp_sync());
 * natively the C++ runtime builds them before the first task, so they always are.
 */
#include <stdbool.h>

bool libcpp_is_ready(void) { return true; }
