// A command file of the team's: one CSV row per section of the course, its first field the command.
#ifndef COMMAND_FILE_H
#define COMMAND_FILE_H

#include <string>

struct TraceParams {
    int distance_mm = 99999;
    int power = 50;
    float kp = 1.0f;
    float ki = 0.0f;
    float kd = 0.0f;
};

class CommandFile {
public:
    explicit CommandFile(std::string path) : mPath(std::move(path)) {}
    bool find(const std::string& command, TraceParams& out) const;
    const std::string& path() const { return mPath; }

private:
    std::string mPath;
};

#endif
