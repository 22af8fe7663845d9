// Runs the isotrace executable as a user would, capturing exit status and output.
#pragma once

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

namespace isotrace::testing {

struct CommandResult {
    int exitCode = -1;
    std::string output;  ///< stdout and stderr together
};

inline CommandResult runIsotrace(const std::string& arguments) {
    const std::string command = std::string(ISOTRACE_EXECUTABLE) + " " + arguments + " 2>&1";
    CommandResult result;
    FILE* pipe = popen(command.c_str(), "r");
    if (!pipe) return result;
    std::array<char, 4096> buffer;
    size_t n;
    while ((n = fread(buffer.data(), 1, buffer.size(), pipe)) > 0) result.output.append(buffer.data(), n);
    const int status = pclose(pipe);
    result.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return result;
}

}  // namespace isotrace::testing
