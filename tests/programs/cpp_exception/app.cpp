// A task that catches one exception and lets a second escape: natively (as on RasPike, where EV3RT runs as a
// Linux process) the first is caught and the second ends the program through std::terminate, a crash.
#include "ev3api.h"

#include <cstdio>
#include <stdexcept>

extern "C" void main_task(intptr_t unused)
{
    try {
        throw std::runtime_error("caught in main_task");
    } catch (const std::exception& e) {
        syslog(LOG_NOTICE, "caught: %s", e.what());
    }
    ev3_motor_config(EV3_PORT_A, LARGE_MOTOR);
    ev3_motor_set_power(EV3_PORT_A, 30);
    tslp_tsk(50 * 1000);
    throw std::runtime_error("escaped from main_task");
}
