// `isotrace merge`: tiles of one frame (render --crop or --tile) back into
// the whole frame, bit for bit.
#include "geometry/errors.h"
#include "renderer/commands/command.h"
#include "renderer/image/film.h"
#include "renderer/image/image_output.h"

namespace isotrace {

namespace {

struct MergeCommand {
    std::vector<std::string> tiles;
    std::string output;
    bool half = false;
};

int runMerge(const MergeCommand& cmd) {
    checkOutputPath(cmd.output, cmd.tiles);
    std::vector<FilmTile> tiles;
    for (const std::string& path : cmd.tiles) {
        FilmTile tile;
        tile.file = path;
        try {
            tile.image = readImage(path, &tile.metadata);
        } catch (const std::exception& e) {
            throw geometry::InputError(path, "", e.what());
        }
        tiles.push_back(std::move(tile));
    }
    ImageMetadata metadata;
    const Image full = mergeTiles(tiles, &metadata);
    writeImage(cmd.output, full, metadata, cmd.half);
    return kExitSuccess;
}

}  // namespace

Subcommand addMergeCommand(CLI::App& app) {
    auto c = std::make_shared<MergeCommand>();
    CLI::App* sub = app.add_subcommand("merge", "Reassemble tiles (--crop/--tile renders) into the full frame");
    sub->add_option("tiles", c->tiles, "Tile EXRs")->required();
    sub->add_option("-o,--output", c->output, "The full frame")->required();
    sub->add_flag("--half", c->half, "Write half-float EXR");
    return {sub, [c] { return runMerge(*c); }};
}

}  // namespace isotrace
