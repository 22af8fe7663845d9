// Assembles a Scene piece by piece: the one way scenes are made, whether
// from a scene file (scene_loader), by `isotrace preview`, or by a test.
#pragma once

#include <map>
#include <memory>
#include <optional>
#include <string>

#include "renderer/integrator.h"
#include "renderer/scene.h"

namespace isotrace {

class SceneBuilder {
public:
    SceneBuilder();

    /// The file the scene came from (for metadata and messages).
    void setSourceFile(const std::string& path) { scene_->sourceFile = path; }
    void setCamera(const CameraSettings& camera) { scene_->camera = camera; }
    void setFilm(const FilmSettings& film) { scene_->film = film; }
    void setIntegrator(std::shared_ptr<const Integrator> integrator) { scene_->integrator = std::move(integrator); }
    /// An integrator as a scene file's "integrator" describes it.
    void setIntegrator(const geometry::Json& description);
    const CameraSettings& camera() const { return scene_->camera; }
    const FilmSettings& film() const { return scene_->film; }

    /// Adds a material under its name (which must be new); returns its index.
    int addMaterial(Material material);
    /// The same from a description as a scene file's "materials" hold it
    /// ({"type": "diffuse", "albedo": [...]}), made by the same factories.
    int addMaterial(const std::string& name, const geometry::Json& description);
    /// The index of a material added under `name`.
    std::optional<int> findMaterial(const std::string& name) const;
    std::vector<std::string> materialNames() const;

    /// Adds shapes that objects place; each returns the shape's index.
    int addMesh(TriangleMesh mesh);
    int addSurface(std::unique_ptr<geometry::ImplicitSurface> surface);
    int addDiscs(DiscPoints discs);

    /// Places a shape: `object.kind` and `object.shape` name it.
    int addObject(const SceneObject& object);
    /// A mesh that emits, placed as is: its own material and object. Like
    /// every emissive mesh, it becomes an area light when the scene is built.
    int addEmitter(TriangleMesh mesh, const Emission& emission, const std::string& name);

    void addLight(std::unique_ptr<Light> light);
    /// A light as a scene file's "lights" hold it (quads and disks add their
    /// emitting geometry).
    void addLight(const geometry::Json& description);
    /// The light that rays leaving the scene see; at most one.
    void setEnvironment(std::unique_ptr<Light> light);
    bool hasEnvironment() const { return scene_->environmentLight >= 0; }

    /// Something a user should hear about that is not an error.
    void addWarning(const std::string& warning) { scene_->warnings.push_back(warning); }

    /// Adds an area light for every emissive mesh object, builds Embree's
    /// structures and hands the scene over; the builder is spent.
    std::unique_ptr<Scene> build();

private:
    std::unique_ptr<Scene> scene_;
    std::map<std::string, int> materialIndex_;
    size_t lightDescriptions_ = 0;  ///< lights added from descriptions, for their names
};

}  // namespace isotrace
