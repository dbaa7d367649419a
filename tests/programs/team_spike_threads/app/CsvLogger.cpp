#include "CsvLogger.h"

#include <chrono>
#include <ctime>

CsvLogger::CsvLogger(const std::string& path) : mFile(std::fopen(path.c_str(), "w"))
{
    std::time_t now = std::time(nullptr);
    char stamp[32];
    std::strftime(stamp, sizeof stamp, "%Y-%m-%d %H:%M:%S", std::localtime(&now));
    if (mFile != nullptr) {
        std::fprintf(mFile, "# run of %s\ntime_ms,reflection,turn,heading\n", stamp);
    }
    mThread = std::thread(&CsvLogger::run, this);
}

CsvLogger::~CsvLogger() { stop(); }

void CsvLogger::log(const std::string& line)
{
    {
        std::lock_guard<std::mutex> lock(mMutex);
        mQueue.push_back(line);
    }
    mReady.notify_one();
}

void CsvLogger::stop()
{
    {
        std::lock_guard<std::mutex> lock(mMutex);
        mStopping = true;
    }
    mReady.notify_one();
    if (mThread.joinable()) {
        mThread.join();
    }
    if (mFile != nullptr) {
        std::fclose(mFile);
        mFile = nullptr;
    }
}

void CsvLogger::run()
{
    std::unique_lock<std::mutex> lock(mMutex);
    for (;;) {
        mReady.wait_for(lock, std::chrono::milliseconds(200), [this] { return mStopping || !mQueue.empty(); });
        while (!mQueue.empty()) {
            std::string line = std::move(mQueue.front());
            mQueue.pop_front();
            lock.unlock();
            if (mFile != nullptr) {
                std::fprintf(mFile, "%s\n", line.c_str());
            }
            lock.lock();
        }
        if (mFile != nullptr) {
            std::fflush(mFile);
        }
        if (mStopping) {
            return;
        }
    }
}
