// Reads a scene file (JSON, see docs/scene-format.md) into a Scene. Every
// error is a geometry::InputError naming the file and the JSON pointer.
#pragma once

#include <memory>
#include <string>

#include "geometry/errors.h"
#include "geometry/description/fit_cache.h"
#include "geometry/description/json_reader.h"
#include "renderer/scene.h"

namespace isotrace {

struct SceneOverrides {
    int width = 0, height = 0, samplesPerPixel = 0;  ///< 0: as in the file
    enum class FieldMode { AsWritten, Mesh, Implicit };
    FieldMode fieldMode = FieldMode::AsWritten;
    /// Where variational fits are kept; null: the process's cache in the
    /// user's cache folder (field_hosting.h).
    std::shared_ptr<geometry::FitCache> fitCache;
};

std::unique_ptr<Scene> loadScene(const std::string& path, const SceneOverrides& overrides = {});
/// A scene description already in memory; `path` names it in errors and
/// anchors relative file names.
std::unique_ptr<Scene> loadSceneDescription(const geometry::Json& root, const std::string& path,
                                            const SceneOverrides& overrides = {});

/// The scene file and every existing file it names (meshes, images, point
/// sets, saved fits): the files no output of a command on it may replace.
/// A file that cannot be parsed yields just itself; loading reports why.
std::vector<std::string> sceneInputFiles(const std::string& path);

}  // namespace isotrace
