// One bad input of the corpus: the files a user has, the command they run,
// and what the error must name. Every case must end with exit 2, a message
// naming the place of the fault, no crash, no hang, no sanitizer report,
// and the folder exactly as it was (no output, no temporary file, no input
// changed).
#pragma once

#include <map>
#include <ostream>
#include <string>
#include <vector>

namespace isotrace::testing {

struct BadInputCase {
    std::string name;                          ///< unique, letters, digits and '_' (a test name)
    std::map<std::string, std::string> files;  ///< written into the case's folder (besides the fixtures)
    std::vector<std::string> setup;            ///< isotrace commands that must succeed first (tiles, fits)
    std::string arguments;                     ///< isotrace's arguments, run in the case's folder
    std::vector<std::string> mentions;         ///< the message must contain each
};

/// A case of `arguments`, after `setup`, with `files` besides the fixtures.
inline BadInputCase makeCase(std::string name, std::string arguments, std::vector<std::string> mentions,
                             std::vector<std::string> setup = {}, std::map<std::string, std::string> files = {}) {
    return {std::move(name), std::move(files), std::move(setup), std::move(arguments), std::move(mentions)};
}

/// Test output names the case, not its bytes.
inline void PrintTo(const BadInputCase& c, std::ostream* out) { *out << c.name; }

/// A valid scene using every section, material, texture, field and light
/// type, and the fixture files: every mutation of it must be refused.
const char* completeScene();
/// A second valid scene for the settings the first cannot hold at once
/// (Whitted, box filter, constant environment, inline constraints ...).
const char* alternativeScene();

/// Fixture files every case folder holds: scene.json (completeScene),
/// other.json (alternativeScene), small.json (a quick scene for tiles and
/// images), a tetrahedron (tet.off), oriented points on a sphere
/// (ring.xyz), an environment map (sky.exr), a texture (tiles.png) and a
/// level set (torus.vdb).
std::map<std::string, std::string> fixtureFiles();
/// The bytes of a file of the source tree (`relative` to its root).
std::string readSourceFile(const std::string& relative);

/// Scene mutations: every value replaced by one of a type it can never
/// have, every array emptied, an unknown key in every object.
std::vector<BadInputCase> sceneMutationCases();
/// Malformed JSON, impossible scenes, bad files the scene points to.
std::vector<BadInputCase> sceneFileCases();
/// Bad command lines of every command, and outputs that would destroy inputs.
std::vector<BadInputCase> commandLineCases();
/// Bad meshes, point sets, images and saved fits given to commands directly.
std::vector<BadInputCase> inputFileCases();
/// OpenVDB files a vdb field cannot read, and voxelize requests that cannot be met.
std::vector<BadInputCase> vdbFileCases();

}  // namespace isotrace::testing
