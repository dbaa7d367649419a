#ifndef STARTER_H
#define STARTER_H

#include <libcpp/spike/ForceSensor.h>

/* The start: the force sensor pushed and let go, as the 2026 rules allow a run to start only by it. */
class Starter {
public:
  explicit Starter(EPort port);
  bool isPushed();

private:
  spikeapi::ForceSensor mForce;
  bool mWasTouched;
};

#endif
