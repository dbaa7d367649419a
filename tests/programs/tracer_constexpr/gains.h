// The tracer's gains as C++ constants of a header, which only a source parameter can reach.
#ifndef GAINS_H
#define GAINS_H

namespace gains {
constexpr float KP = 1.0f;
constexpr float KI = 0.5f;
constexpr float KD = 0.5f;
constexpr float POWER = 15.0f;
}  // namespace gains

#endif
