/* The tracer's speed and how hard it steers; a build may set either with -DPOWER=... (tests/programs/garage.toml). */
#ifndef POWER
#define POWER 30
#endif
#ifndef TURN
#define TURN 80
#endif
