// Field descriptions (the JSON of a scene's "fields") turned into compiled
// FieldPrograms. This is the one parser of field descriptions: the renderer
// and any host using the plugin API share it. See docs/scene-format.md for
// every type and parameter.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "geometry/field_program.h"
#include "geometry/description/fit_cache.h"
#include "geometry/description/json_reader.h"

namespace isotrace::geometry {

/// What the host lends the parser: nothing here is read from the
/// environment or printed.
struct FieldLibraryOptions {
    /// Where variational fits are looked up and kept; null: a cache of the
    /// library's own, in memory.
    std::shared_ptr<FitCache> fitCache;
    /// Told of what is not an error but a user should hear of (a fit of an
    /// ill-conditioned system): the file, the JSON pointer, the message.
    std::function<void(const std::string& file, const std::string& pointer, const std::string& message)> warn;
};

class FieldLibrary {
public:
    FieldLibrary() = default;
    /// `fields` maps names to descriptions; `pointer` is where it sits in
    /// its file ("/fields"), `file` the file's name, both for errors.
    FieldLibrary(const Json& fields, std::string pointer, std::string file, FieldLibraryOptions options = {});

    bool contains(const std::string& name) const;
    std::vector<std::string> names() const;
    const std::string& file() const { return file_; }

    /// Compiles a named field. Unknown names, cycles in the field graph and
    /// invalid parameters throw InputError with the JSON pointer.
    FieldProgram compile(const std::string& name) const;
    /// Compiles a description that may refer to the library's names.
    FieldProgram compileDescription(const Json& description, const std::string& pointer) const;

    /// The registered field type names.
    static std::vector<std::string> typeNames();

private:
    /// Fails on an entry that is neither a description with a known type
    /// nor the name of another field, used or not.
    void checkShapes() const;
    /// Fails on a cycle among the fields, used or not (names the chain).
    void checkForCycles() const;

    Json fields_ = Json::object();
    std::string pointer_;
    std::string file_;
    FieldLibraryOptions options_;
};

/// Named polynomial presets: "tangle", "heart", "decocube", "pretzel2", "pretzel4".
std::vector<std::string> polynomialPresetNames();
PolynomialField polynomialPreset(const std::string& name);

}  // namespace isotrace::geometry
