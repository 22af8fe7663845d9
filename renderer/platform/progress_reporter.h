// Render progress on stderr: a bar with ETA on a terminal, a few plain lines
// otherwise (logs, CI). Updated once per tile, never per sample.
#pragma once

#include <atomic>
#include <chrono>
#include <mutex>
#include <string>

namespace isotrace {

class ProgressReporter {
public:
    ProgressReporter(long long totalWork, std::string title, bool quiet);
    void update(long long work);
    void done();

private:
    void print(long long completed, bool final);
    long long total_;
    std::string title_;
    bool quiet_, terminal_;
    std::atomic<long long> completed_{0};
    std::mutex mutex_;
    int lastQuarter_ = 0;
    double lastPrint_ = -1.0;
    std::chrono::steady_clock::time_point start_;
};

}  // namespace isotrace
