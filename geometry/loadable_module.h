// Libraries that only some inputs need live in modules of their own,
// loaded on first use: Assimp (polygon model files) and OpenImageIO
// (images other than EXR and PNG previews). Linked in, their relocations
// and page faults cost every process, `isotrace --version` included.
#pragma once

#include <string>

namespace isotrace::geometry {

/// Where a module is and what it is for.
struct ModuleDescription {
    std::string library;           ///< what it wraps, for messages: "Assimp"
    std::string file;              ///< "isotrace_assimp.so"
    std::string entryPoint;        ///< a function with C linkage
    std::string overrideVariable;  ///< environment variable naming the file
    std::string neededFor;         ///< for messages: "polygon model files"
};

/// The address of the module's entry point, the module loaded once per
/// process (later calls return the same address). Looked for in
/// $overrideVariable when that is set (only there), else next to the
/// executable, in the folder above it (build trees: tests/, bench/), in
/// ../lib/isotrace beside it (an installed tree) and in lib/isotrace of the
/// configured install prefix. Throws std::runtime_error naming the module,
/// what it is needed for and every place tried.
void* loadModuleEntryPoint(const ModuleDescription& module);

}  // namespace isotrace::geometry
