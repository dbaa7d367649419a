/* The target header TOPPERS sample programs include from app.h; EV3RT's definitions are in ev3.h. */
#ifndef HAKO_TARGET_TEST_H
#define HAKO_TARGET_TEST_H

#include "ev3.h"

#endif /* HAKO_TARGET_TEST_H */
