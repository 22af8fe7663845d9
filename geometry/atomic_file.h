// Files that appear only when complete: written under a temporary name in
// the same folder (so the rename is atomic) and renamed at the end.
#pragma once

#include <string>

namespace isotrace::geometry {

/// Throws std::runtime_error naming `path` when it cannot be written; no
/// partial file is left behind.
void writeFileAtomically(const std::string& path, const std::string& bytes);

}  // namespace isotrace::geometry
