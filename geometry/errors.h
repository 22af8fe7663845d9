// The error categories of the library and the program built on it. Each
// maps to one exit status in one place (renderer/commands/command.cpp):
// - InputError: the input is wrong; it names the file and the place in it
//   (line and column for syntax, a JSON pointer for content).
// - IoError: a file cannot be read or written (missing, unreadable, a full
//   disk); it names the file.
// - InternalError: isotrace itself is wrong (a broken invariant, a library
//   called wrongly): a bug to report.
// Memory exhaustion stays std::bad_alloc.
#pragma once

#include <stdexcept>
#include <string>

namespace isotrace::geometry {

class InputError : public std::runtime_error {
public:
    /// `where` is a JSON pointer ("/fields/cut/of/1") or "line L, column C"; either may be empty.
    InputError(const std::string& file, const std::string& where, const std::string& message)
        : std::runtime_error(format(file, where, message)), file_(file), where_(where), message_(message) {}

    const std::string& file() const { return file_; }
    const std::string& where() const { return where_; }
    const std::string& message() const { return message_; }

private:
    static std::string format(const std::string& file, const std::string& where, const std::string& message) {
        std::string s = file.empty() ? std::string("<input>") : file;
        if (!where.empty()) s += ": " + where;
        return s + ": " + message;
    }
    std::string file_, where_, message_;
};

class IoError : public std::runtime_error {
public:
    /// "path: message".
    IoError(const std::string& path, const std::string& message)
        : std::runtime_error(path.empty() ? message : path + ": " + message), path_(path) {}
    /// A message that names its file already (a failure passed on).
    explicit IoError(const std::string& message) : std::runtime_error(message) {}

    const std::string& path() const { return path_; }

private:
    std::string path_;
};

class InternalError : public std::logic_error {
public:
    explicit InternalError(const std::string& message) : std::logic_error(message) {}
};

}  // namespace isotrace::geometry
