/* The tracer's gains and speed; a build may set any of them with -DKP=... (tests/programs/garage.toml). */
#ifndef KP
#define KP 2.0f
#endif
#ifndef KD
#define KD 2.0f
#endif
#ifndef POWER
#define POWER 25
#endif
