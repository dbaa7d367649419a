#include "LineTracer.h"

#include <cmath>

#include <syssvc/syslog.h>

using spikeapi::Motor;

LineTracer::LineTracer(EPort left, EPort right, EPort color)
    : mLeft(left, Motor::EDirection::COUNTERCLOCKWISE, true),
      mRight(right, Motor::EDirection::CLOCKWISE, true),
      mColor(color),
      mLastError(0.0F),
      mRunning(false)
{
}

void LineTracer::start()
{
  mLeft.resetCount();
  mRight.resetCount();
  mRunning = true;
}

void LineTracer::run()
{
  if (!mRunning) {
    return;
  }
  const int target = (kWhite + kBlack) / 2;
  const float error = static_cast<float>(target - mColor.getReflection());
  const float turn = kKp * error + kKd * (error - mLastError);
  mLastError = error;

  int left = static_cast<int>(std::lround(kBasePower + turn));
  int right = static_cast<int>(std::lround(kBasePower - turn));
  mLeft.setPower(left);
  mRight.setPower(right);
  syslog(LOG_DEBUG, "ref error %d power %d %d", static_cast<int>(error), left, right);
}

int32_t LineTracer::distanceMm() const
{
  const float degrees = (mLeft.getCount() + mRight.getCount()) / 2.0F;
  return static_cast<int32_t>(degrees * static_cast<float>(M_PI) * kWheelMm / 360.0F);
}
