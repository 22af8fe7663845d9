// Files being written under a temporary name are removed if SIGINT or
// SIGTERM ends the process meanwhile, so an interrupted write leaves
// nothing behind (the finished file appears only by rename).
#pragma once

#include <string>

namespace isotrace {

/// Installs the SIGINT and SIGTERM handlers (idempotent). The handler
/// removes every registered file, then ends the process by the signal.
void removePartialFilesOnSignal();

/// Registers a temporary file for the lifetime of the object.
class PartialFile {
public:
    explicit PartialFile(const std::string& path);
    ~PartialFile();
    PartialFile(const PartialFile&) = delete;
    PartialFile& operator=(const PartialFile&) = delete;

private:
    int slot_ = -1;  ///< -1: every slot was taken (the file is not guarded)
};

}  // namespace isotrace
