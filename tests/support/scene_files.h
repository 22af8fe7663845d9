// Loading scenes written inline in tests.
#pragma once

#include <memory>
#include <string>

#include "renderer/scene_loader.h"
#include "support/temporary_files.h"

namespace isotrace::testing {

inline std::unique_ptr<Scene> loadSceneText(const TemporaryFolder& folder, const std::string& json,
                                            const SceneOverrides& overrides = {}) {
    return loadScene(folder.write("scene.json", json), overrides);
}

/// The InputError text of loading `json`, or "" when it loads.
inline std::string sceneError(const TemporaryFolder& folder, const std::string& json) {
    try {
        loadSceneText(folder, json);
    } catch (const geometry::InputError& e) {
        return e.what();
    }
    return "";
}

}  // namespace isotrace::testing
