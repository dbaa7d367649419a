// A PID controller whose gains are constants of this header, as teams keep them.
#ifndef PID_H
#define PID_H

class Pid {
public:
    float control(float error);

private:
    static constexpr float KP = 0.9f;
    static constexpr float KI = 0.0f;
    static constexpr float KD = 1.0f;
    float mIntegral = 0.0f;
    float mLastError = 0.0f;
};

#endif
