#ifndef LINE_TRACER_H
#define LINE_TRACER_H

#include <cstdint>

#include <libcpp/spike/ColorSensor.h>
#include <libcpp/spike/Motor.h>

/* PD control on the reflection of the line's right edge. Tuned on our robot: white 80, black 10. */
class LineTracer {
public:
  LineTracer(EPort left, EPort right, EPort color);
  void start();
  void run();
  int32_t distanceMm() const;

private:
  static constexpr int kWhite = 80;
  static constexpr int kBlack = 10;
  static constexpr float kKp = 0.9F;
  static constexpr float kKd = 4.0F;
  static constexpr int kBasePower = 45;
  static constexpr float kWheelMm = 56.0F;

  spikeapi::Motor mLeft;
  spikeapi::Motor mRight;
  spikeapi::ColorSensor mColor;
  float mLastError;
  bool mRunning;
};

#endif
