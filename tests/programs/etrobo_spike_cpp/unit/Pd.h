// A PD controller whose gains are constants of this header, as teams keep them.
#ifndef PD_H
#define PD_H

class Pd {
public:
    float control(float error);

private:
    static constexpr float KP = 1.6f;
    static constexpr float KD = 4.0f;
    float mLastError = 0.0f;
};

#endif
