// How the renderer hosts the geometry library's field parser: one fit
// cache for the process in the user's cache folder, and warnings on stderr.
// The library itself reads no environment and prints nothing.
#pragma once

#include <memory>
#include <string>

#include "geometry/description/field_parser.h"

namespace isotrace {

/// $ISOTRACE_CACHE_DIR, else $XDG_CACHE_HOME/isotrace, else
/// ~/.cache/isotrace; "" when none of them is set (fits then stay in memory).
std::string userCacheDirectory();
/// The fit cache every scene of this process shares, in userCacheDirectory().
std::shared_ptr<geometry::FitCache> processFitCache();
/// The process's fit cache, and warnings printed as "warning: FILE: WHERE: ...".
geometry::FieldLibraryOptions printingFieldOptions();
/// A named field of a scene file's "fields", compiled (for commands that
/// work on one field). Unknown names fail at "/fields" with the nearest
/// name suggested.
geometry::FieldProgram compileSceneField(const std::string& scenePath, const std::string& field);

}  // namespace isotrace
