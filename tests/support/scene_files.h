// Loading scenes written inline in tests.
#pragma once

#include <gtest/gtest.h>

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

/// Expects a scene error that names the file (scene.json), the place in it
/// and what is wrong.
inline void expectNamedError(const std::string& error, const std::string& where, const std::string& what) {
    EXPECT_NE(error.find("scene.json"), std::string::npos) << "no file name in: " << error;
    EXPECT_NE(error.find(where), std::string::npos) << "no place \"" << where << "\" in: " << error;
    EXPECT_NE(error.find(what), std::string::npos) << "no \"" << what << "\" in: " << error;
}

}  // namespace isotrace::testing
