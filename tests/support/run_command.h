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

/// A shell command line with stderr folded into stdout; a process ended by
/// a signal reports 128 + the signal, as shells do.
inline CommandResult runShell(const std::string& commandLine) {
    const std::string command = commandLine + " 2>&1";
    CommandResult result;
    FILE* pipe = popen(command.c_str(), "r");
    if (!pipe) return result;
    std::array<char, 4096> buffer;
    size_t n;
    while ((n = fread(buffer.data(), 1, buffer.size(), pipe)) > 0) result.output.append(buffer.data(), n);
    const int status = pclose(pipe);
    result.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : WIFSIGNALED(status) ? 128 + WTERMSIG(status) : -1;
    return result;
}

inline CommandResult runIsotrace(const std::string& arguments) {
    return runShell(std::string(ISOTRACE_EXECUTABLE) + " " + arguments);
}

}  // namespace isotrace::testing
