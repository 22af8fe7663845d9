// A field description compiled on its own (no named fields to refer to),
// as most geometry tests need it.
#pragma once

#include <string>

#include "geometry/description/field_parser.h"

namespace isotrace::testing {

inline geometry::FieldProgram compileField(const std::string& json) {
    return geometry::FieldLibrary(geometry::Json::object(), "/fields", "test")
        .compileDescription(geometry::Json::parse(json), "");
}

}  // namespace isotrace::testing
