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

/// The address of the module's entry point. Looked for in $overrideVariable
/// when that is set (only there), else next to the executable, in the folder
/// above it (build trees: tests/, bench/), in ../lib/isotrace beside it (an
/// installed tree) and in lib/isotrace of the configured install prefix.
/// Throws std::runtime_error naming the module, what it is needed for and
/// every place tried.
void* loadModuleEntryPoint(const ModuleDescription& module);

/// The object a module's entry point (`Library* entry()`, C linkage)
/// returns, the module loaded on the first call for this Library type. A
/// failure is not remembered: the next call tries again, so its error
/// repeats.
template <typename Library>
Library& moduleLibrary(const ModuleDescription& module) {
    using Entry = Library* (*)();
    static Library& library = *reinterpret_cast<Entry>(loadModuleEntryPoint(module))();
    return library;
}

}  // namespace isotrace::geometry
