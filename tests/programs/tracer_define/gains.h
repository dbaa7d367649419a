/* The tracer's gains; a build may set any of them with -DKP=... */
#ifndef KP
#define KP 1.0f
#endif
#ifndef KI
#define KI 0.5f
#endif
#ifndef KD
#define KD 0.5f
#endif
#ifndef MOTOR_POWER
#define MOTOR_POWER 15.0f
#endif
