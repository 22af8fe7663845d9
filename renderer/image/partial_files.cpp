#include "renderer/image/partial_files.h"

#include <atomic>
#include <csignal>
#include <cstring>
#include <unistd.h>

namespace isotrace {

namespace {

// Fixed storage: a signal handler may only touch what exists already, and
// call async-signal-safe functions (unlink, signal, raise).
constexpr int kSlots = 8;
constexpr size_t kPathBytes = 4096;
char paths[kSlots][kPathBytes];
std::atomic<bool> claimed[kSlots];  ///< a slot owned by a PartialFile
std::atomic<bool> ready[kSlots];    ///< its path is complete: the handler may remove it

extern "C" void onSignal(int signal) {
    for (int i = 0; i < kSlots; ++i)
        if (ready[i].load()) unlink(paths[i]);
    std::signal(signal, SIG_DFL);
    std::raise(signal);
}

}  // namespace

void removePartialFilesOnSignal() {
    std::signal(SIGINT, onSignal);
    std::signal(SIGTERM, onSignal);
}

PartialFile::PartialFile(const std::string& path) {
    if (path.size() >= kPathBytes) return;
    for (int i = 0; i < kSlots; ++i) {
        bool expected = false;
        if (claimed[i].compare_exchange_strong(expected, true)) {
            std::memcpy(paths[i], path.c_str(), path.size() + 1);
            ready[i].store(true);
            slot_ = i;
            return;
        }
    }
}

PartialFile::~PartialFile() {
    if (slot_ < 0) return;
    ready[slot_].store(false);
    claimed[slot_].store(false);
}

}  // namespace isotrace
