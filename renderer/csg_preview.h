// `isotrace preview`: a labelled contact sheet of a CSG node of a scene's
// fields. Operand A, operand B (the union of the remaining operands when
// there are more than two), then A union B, A intersect B, A minus B and
// B minus A, each framed by the same camera so the panels line up. Smooth
// nodes keep their blend radius in every combination.
#pragma once

#include <string>

namespace isotrace {

struct PreviewCommand {
    std::string scene, field, output;
    int panelWidth = 240, panelHeight = 180, spp = 4, threads = 0;
    /// Empty: shaded renders (whitted). Otherwise "x", "y" or "z",
    /// optionally "=OFFSET": a plane cut coloured by the field's value.
    std::string section;
    bool quiet = false;
};

/// Writes the sheet (PNG or any OpenImageIO format; EXR keeps linear
/// values). Bad input throws geometry::InputError naming the file and place.
void runPreview(const PreviewCommand& command);

/// The sheet's default name: SCENE-FIELD-preview.png next to the working folder.
std::string defaultPreviewPath(const std::string& scene, const std::string& field, bool section);

}  // namespace isotrace
