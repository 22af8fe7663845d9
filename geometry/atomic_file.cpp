#include "geometry/atomic_file.h"
#include "geometry/errors.h"

#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <unistd.h>

namespace isotrace::geometry {

void writeFileAtomically(const std::string& path, const std::string& bytes) {
    const std::string temporary = path + ".partial-" + std::to_string(getpid());
    {
        std::ofstream out(temporary, std::ios::binary);
        out << bytes;
        if (!out) {
            std::error_code ignored;
            std::filesystem::remove(temporary, ignored);
            throw IoError(path, "cannot write the file");
        }
    }
    std::filesystem::rename(temporary, path);
}

}  // namespace isotrace::geometry
