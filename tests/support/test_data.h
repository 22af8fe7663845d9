// Files under tests/data (see its README for their origin).
#pragma once

#include <string>

namespace isotrace::testing {

inline std::string testDataFile(const std::string& name) { return std::string(ISOTRACE_TEST_DATA_DIR) + "/" + name; }

}  // namespace isotrace::testing
