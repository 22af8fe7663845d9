#include "renderer/platform/progress_reporter.h"

#include <cstdio>
#include <unistd.h>

namespace isotrace {

ProgressReporter::ProgressReporter(long long totalWork, std::string title, bool quiet)
    : total_(std::max(1LL, totalWork)), title_(std::move(title)), quiet_(quiet), terminal_(isatty(STDERR_FILENO)),
      start_(std::chrono::steady_clock::now()) {}

void ProgressReporter::update(long long work) {
    const long long completed = completed_.fetch_add(work) + work;
    if (quiet_) return;
    std::lock_guard<std::mutex> lock(mutex_);
    print(completed, false);
}

void ProgressReporter::done() {
    if (quiet_) return;
    std::lock_guard<std::mutex> lock(mutex_);
    print(total_, true);
}

void ProgressReporter::print(long long completed, bool final) {
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    const double fraction = std::min(1.0, double(completed) / double(total_));
    const double eta = fraction > 0 ? elapsed * (1.0 - fraction) / fraction : 0.0;
    if (terminal_) {
        if (!final && elapsed - lastPrint_ < 0.1) return;
        lastPrint_ = elapsed;
        constexpr int width = 40;
        const int filled = int(fraction * width);
        std::string bar(filled, '#');
        bar += std::string(width - filled, ' ');
        std::fprintf(stderr, "\r%s [%s] %5.1f%%  %.1fs elapsed, ETA %.1fs ", title_.c_str(), bar.c_str(),
                     100.0 * fraction, elapsed, eta);
        if (final) std::fprintf(stderr, "\n");
    } else {
        const int quarter = int(fraction * 4.0);
        if (!final && quarter <= lastQuarter_) return;
        if (final && lastQuarter_ >= 4) return;
        lastQuarter_ = final ? 4 : quarter;
        std::fprintf(stderr, "%s: %3d%% after %.1fs, ETA %.1fs\n", title_.c_str(), int(100.0 * fraction), elapsed, eta);
    }
    std::fflush(stderr);
}

}  // namespace isotrace
