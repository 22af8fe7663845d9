// `isotrace preview`: a labelled contact sheet of a CSG node of a scene's
// fields (see csg_preview.h).
#include "renderer/commands/command.h"
#include "renderer/csg_preview.h"

namespace isotrace {

Subcommand addPreviewCommand(CLI::App& app) {
    auto c = std::make_shared<PreviewCommand>();
    CLI::App* sub = app.add_subcommand(
        "preview", "Contact sheet of a CSG node: each operand, union, intersection and both differences");
    sub->add_option("scene", c->scene, "Scene file whose \"fields\" hold the node")->required();
    sub->add_option("--field", c->field, "Name of the CSG node")->required();
    sub->add_option("-o,--output", c->output, "The sheet (default: SCENE-FIELD-preview.png)");
    sub->add_option("--section", c->section,
                           "Show plane cuts coloured by the field's value instead: x, y or z, optionally =OFFSET")
        ->type_name("AXIS[=OFFSET]");
    sub->add_option("--panel-width", c->panelWidth, "Width of each panel")->check(CLI::Range(16, 4096));
    sub->add_option("--panel-height", c->panelHeight, "Height of each panel")->check(CLI::Range(16, 4096));
    sub->add_option("--spp", c->spp, "Samples per pixel of each panel")->check(CLI::Range(1, 4096));
    sub->add_option("--threads", c->threads, "Worker threads (default: all cores)")->check(CLI::Range(1, 4096));
    sub->add_flag("-q,--quiet", c->quiet, "No timing line");
    return {sub, [c] {
                runPreview(*c);
                return int(kExitSuccess);
            }};
}

}  // namespace isotrace
