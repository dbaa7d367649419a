#include "Starter.h"

Starter::Starter(EPort port) : mForce(port), mWasTouched(false) {}

bool Starter::isPushed()
{
  bool touched = mForce.isTouched();
  bool released = mWasTouched && !touched;
  mWasTouched = touched;
  return released;
}
