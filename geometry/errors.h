// The one exception type for bad input: it names the file and the place in it
// (line and column for syntax, a JSON pointer for content).
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

}  // namespace isotrace::geometry
