// A logger thread: lines are queued under a mutex and written to a CSV by a thread that waits on a condition
// variable (with a timeout, to flush now and then), so the control loop never waits on the file system.
#ifndef CSV_LOGGER_H
#define CSV_LOGGER_H

#include <condition_variable>
#include <cstdio>
#include <deque>
#include <mutex>
#include <string>
#include <thread>

class CsvLogger {
public:
    explicit CsvLogger(const std::string& path);
    ~CsvLogger();
    void log(const std::string& line);
    void stop();

private:
    void run();

    FILE* mFile;
    std::mutex mMutex;
    std::condition_variable mReady;
    std::deque<std::string> mQueue;
    bool mStopping = false;
    std::thread mThread;
};

#endif
