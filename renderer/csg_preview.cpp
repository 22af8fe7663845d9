#include "renderer/csg_preview.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <tbb/parallel_for.h>

#include "geometry/description/field_parser.h"
#include "geometry/errors.h"
#include "renderer/field_hosting.h"
#include "renderer/image/openimageio_library.h"
#include "renderer/image/image_output.h"
#include "renderer/render.h"
#include "renderer/scene_builder.h"
#include "renderer/scene_loader.h"

namespace isotrace {

namespace {

using geometry::Box3;
using geometry::InputError;
using geometry::Json;
using geometry::Vec3;

// The plain and smooth families of CSG node types, by the node's type.
struct CsgFamily {
    const char* unite;
    const char* intersect;
    const char* subtract;
};
const std::map<std::string, CsgFamily>& csgFamilies() {
    static const CsgFamily plain{"union", "intersection", "difference"};
    static const CsgFamily smooth{"smooth_union", "smooth_intersection", "smooth_difference"};
    static const std::map<std::string, CsgFamily> families{
        {"union", plain},         {"intersection", plain},         {"difference", plain},
        {"smooth_union", smooth}, {"smooth_intersection", smooth}, {"smooth_difference", smooth}};
    return families;
}

struct Panel {
    std::string label;
    Json description;
};

std::string operandLabel(const Json& operand) {
    if (operand.is_string()) return operand.get<std::string>();
    if (operand.is_object() && operand.contains("type") && operand["type"].is_string())
        return "(" + operand["type"].get<std::string>() + ")";
    return "(inline)";
}

// The six panels of a CSG node: A, B, A ∪ B, A ∩ B, A − B, B − A.
std::vector<Panel> panelsOf(const Json& node, const std::string& file, const std::string& pointer) {
    const std::string type = node.value("type", "");
    const auto family = csgFamilies().find(type);
    if (family == csgFamilies().end()) {
        std::string names;
        for (const auto& [name, unused] : csgFamilies()) names += (names.empty() ? "" : ", ") + name;
        throw InputError(file, pointer, "is a \"" + type + "\" field, not a CSG node (" + names + ")");
    }
    const Json& of = node.at("of");
    if (!of.is_array() || of.size() < 2)
        throw InputError(file, pointer + "/of",
                         "a CSG node needs two operands or more to preview; this one has " +
                             std::to_string(of.is_array() ? of.size() : 0));
    const bool smooth = type.rfind("smooth_", 0) == 0;
    auto combine = [&](const char* op, const std::vector<Json>& operands) {
        Json j = {{"type", op}, {"of", operands}};
        if (smooth && operands.size() > 1) j["radius"] = node.at("radius");
        return j;
    };
    const Json a = of[0];
    Json b = of[1];
    std::string bLabel = operandLabel(of[1]);
    if (of.size() > 2) {
        // More operands: B stands for the union of all but the first.
        b = combine(family->second.unite, std::vector<Json>(of.begin() + 1, of.end()));
        bLabel = "union of " + std::to_string(of.size() - 1);
    }
    const std::string suffix = smooth ? " (smooth " + node.at("radius").dump() + ")" : "";
    std::vector<Panel> panels = {
        {"A: " + operandLabel(a), combine("union", {a})},
        {"B: " + bLabel, combine("union", {b})},
        {"A union B" + suffix, combine(family->second.unite, {a, b})},
        {"A intersect B" + suffix, combine(family->second.intersect, {a, b})},
        {"A minus B" + suffix, combine(family->second.subtract, {a, b})},
        {"B minus A" + suffix, combine(family->second.subtract, {b, a})},
    };
    // The node's own placement applies to all of them.
    if (node.contains("transform"))
        for (Panel& p : panels) p.description["transform"] = node["transform"];
    return panels;
}

// The scene of one panel: the field alone on a floor, lit by a key light and
// sky, seen by the camera every panel shares.
std::unique_ptr<Scene> panelScene(geometry::FieldProgram field, const Box3& frame, const PreviewCommand& c) {
    SceneBuilder builder;
    const Vec3 center = frame.center();
    const double radius = std::max(frame.halfDiagonal(), 1e-3);
    CameraSettings camera;
    camera.verticalFovDegrees = 35.0;
    const Vec3 direction = Vec3(0.9, 0.75, 1.5).normalized();
    camera.from = center + direction * (1.1 * radius / std::sin(0.5 * camera.verticalFovDegrees * M_PI / 180.0));
    camera.to = center;
    camera.focusDistance = (camera.to - camera.from).norm();
    builder.setCamera(camera);
    FilmSettings film;
    film.width = c.panelWidth;
    film.height = c.panelHeight;
    film.samplesPerPixel = c.spp;
    builder.setFilm(film);
    builder.setIntegrator(Json{{"type", "whitted"}, {"max_depth", 3}});
    SceneObject shape;
    shape.kind = SceneObject::Kind::Implicit;
    shape.name = "preview_shape";
    shape.material = builder.addMaterial("preview_shape", {{"type", "diffuse"}, {"albedo", {0.8, 0.5, 0.25}}});
    shape.shape = builder.addSurface(std::make_unique<geometry::ImplicitSurface>(std::move(field)));
    builder.addObject(shape);

    const double floorY = frame.lower.y(), reach = 20.0 * radius;
    TriangleMesh floorMesh;
    for (const Vec3& p : {Vec3(center.x() - reach, floorY, center.z() - reach), Vec3(center.x() + reach, floorY, center.z() - reach),
                          Vec3(center.x() + reach, floorY, center.z() + reach), Vec3(center.x() - reach, floorY, center.z() + reach)})
        floorMesh.positions.insert(floorMesh.positions.end(), {float(p.x()), float(p.y()), float(p.z())});
    floorMesh.indices = {0, 2, 1, 0, 3, 2};
    SceneObject floor;
    floor.name = "preview_floor";
    floor.material = builder.addMaterial("preview_floor", {{"type", "diffuse"}, {"albedo", {0.5, 0.5, 0.5}}});
    floor.shape = builder.addMesh(std::move(floorMesh));
    builder.addObject(floor);

    builder.addLight({{"type", "directional"}, {"direction", {-0.5, -1.0, -0.35}}, {"irradiance", {2.6, 2.5, 2.4}}});
    builder.addLight({{"type", "environment"}, {"radiance", {0.22, 0.24, 0.28}}});
    return builder.build();
}

// Colours a plane cut of the field: blues inside (negative), oranges outside,
// darker with distance from the surface, thin lines every fifth of `scale`
// and black on the surface itself.
Image sectionImage(const geometry::FieldProgram& field, const Box3& frame, int axis, double offset, int width, int height) {
    const int u = axis == 0 ? 2 : 0, v = axis == 1 ? 2 : 1;
    const double pixel = 1.1 * std::max(frame.extent()[u] / width, frame.extent()[v] / height);
    const Vec3 center = frame.center();
    std::vector<double> values(size_t(width) * height);
    tbb::parallel_for(0, height, [&](int y) {
        for (int x = 0; x < width; ++x) {
            Vec3 p = center;
            p[axis] = offset;
            p[u] += (x + 0.5 - 0.5 * width) * pixel;
            p[v] -= (y + 0.5 - 0.5 * height) * pixel;  // rows run downwards
            values[size_t(y) * width + x] = field.value(p);
        }
    });
    const double scale = std::max(frame.halfDiagonal(), 1e-9), spacing = 0.2 * scale;
    Image image;
    image.width = width;
    image.height = height;
    image.rgb.resize(values.size() * 3);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const double f = values[size_t(y) * width + x];
            const double t = std::clamp(std::abs(f) / scale, 0.0, 1.0);
            Vec3 color = f < 0 ? Vec3(0.6, 0.75, 1.0) * (1 - t) + Vec3(0.01, 0.04, 0.35) * t
                               : Vec3(1.0, 0.8, 0.55) * (1 - t) + Vec3(0.45, 0.08, 0.0) * t;
            bool surface = false, contour = false;
            for (const auto& [dx, dy] : {std::pair{1, 0}, std::pair{0, 1}}) {
                if (x + dx >= width || y + dy >= height) continue;
                const double g = values[size_t(y + dy) * width + x + dx];
                surface |= (f < 0) != (g < 0);
                contour |= std::floor(f / spacing) != std::floor(g / spacing);
            }
            if (!std::isfinite(f)) color = Vec3(1, 0, 1);
            if (contour) color *= 0.55;
            if (surface) color.setZero();
            for (int k = 0; k < 3; ++k) image.pixel(x, y)[k] = float(color[k]);
        }
    return image;
}

// Parses "x", "y", "z" or "z=0.3".
std::pair<int, double> parseSection(const std::string& text, const Box3& frame) {
    const std::string where = "--section " + text;
    if (text.empty() || (text[0] != 'x' && text[0] != 'y' && text[0] != 'z') || (text.size() > 1 && text[1] != '='))
        throw InputError("command line", "", where + ": expected x, y or z, optionally =OFFSET (for example z=0.25)");
    const int axis = text[0] - 'x';
    double offset = frame.center()[axis];
    if (text.size() > 1) {
        size_t used = 0;
        try {
            offset = std::stod(text.substr(2), &used);
        } catch (const std::exception&) {
            used = 0;
        }
        if (used == 0 || used != text.size() - 2 || !std::isfinite(offset))
            throw InputError("command line", "", where + ": the offset is not a finite number");
    }
    return {axis, offset};
}

std::string shortNumber(double x) {
    char text[32];
    std::snprintf(text, sizeof text, "%.4g", x);
    return text;
}

void drawLabel(Image& sheet, int x, int y, const std::string& text, int size, std::vector<std::string>& warnings) {
    std::string problem;
    try {
        problem = openImageIo().drawText(sheet.rgb.data(), sheet.width, sheet.height, x, y, text, size, "DejaVuSans");
    } catch (const std::runtime_error& e) {
        problem = e.what();
    }
    if (!problem.empty())
        warnings.push_back("could not draw the label \"" + text + "\" (" + problem +
                           "; the DejaVu fonts, Debian package fonts-dejavu-core, provide it)");
}

}  // namespace

std::string defaultPreviewPath(const std::string& scene, const std::string& field, bool section) {
    return std::filesystem::path(scene).stem().string() + "-" + field + (section ? "-section" : "-preview") + ".png";
}

void runPreview(const PreviewCommand& c) {
    const auto start = std::chrono::steady_clock::now();
    const std::string output = c.output.empty() ? defaultPreviewPath(c.scene, c.field, !c.section.empty()) : c.output;
    checkOutputPath(output, sceneInputFiles(c.scene));

    const Json root = geometry::parseJsonFile(c.scene);
    if (!root.is_object() || !root.contains("fields") || !root["fields"].is_object())
        throw InputError(c.scene, "/fields", "the scene has no \"fields\" object");
    const Json& fields = root["fields"];
    const geometry::FieldLibrary library(fields, "/fields", c.scene, printingFieldOptions());
    library.compile(c.field);  // unknown names (with a suggestion) and errors in the node come first
    const std::string pointer = geometry::jsonPointerAppend("/fields", c.field);
    const std::vector<Panel> panels = panelsOf(fields[c.field], c.scene, pointer);

    // One frame for all panels: the operands' bounds together (an unbounded
    // operand, a plane, is cut to the others').
    Box3 frame;
    for (int i = 0; i < 2; ++i) {
        const Box3 bounds = library.compileDescription(panels[i].description, pointer).bounds();
        if (bounds.isFinite()) {
            frame.extend(bounds.lower);
            frame.extend(bounds.upper);
        }
    }
    std::vector<std::string> warnings;
    if (frame.isEmpty()) {
        frame = Box3::around(Vec3::Zero(), 1.0);
        warnings.push_back("neither operand is bounded; showing the box [-1, 1]^3");
    }
    frame = frame.expanded(0.05 * frame.halfDiagonal());

    std::pair<int, double> section{-1, 0.0};
    if (!c.section.empty()) section = parseSection(c.section, frame);

    constexpr int columns = 3, labelHeight = 24, gap = 4;
    const int rows = int(panels.size() + columns - 1) / columns;
    Image sheet;
    sheet.width = columns * c.panelWidth + (columns + 1) * gap;
    const int footer = section.first >= 0 ? 20 : 0;  // the colour key
    sheet.height = rows * (c.panelHeight + labelHeight) + (rows + 1) * gap + footer;
    sheet.rgb.assign(size_t(sheet.width) * sheet.height * 3, 0.02f);
    for (size_t i = 0; i < panels.size(); ++i) {
        Image image;
        if (section.first >= 0) {
            image = sectionImage(library.compileDescription(panels[i].description, pointer), frame, section.first,
                                 section.second, c.panelWidth, c.panelHeight);
        } else {
            // The node's operands may be unbounded (a plane): every panel is cut to the frame.
            Json description = panels[i].description;
            description["bounds"] = Json::array({{frame.lower.x(), frame.lower.y(), frame.lower.z()},
                                                 {frame.upper.x(), frame.upper.y(), frame.upper.z()}});
            std::unique_ptr<Scene> loaded;
            try {
                loaded = panelScene(library.compileDescription(description, pointer), frame, c);
            } catch (const std::invalid_argument& e) {
                throw InputError(c.scene, pointer, e.what());
            }
            RenderOptions options;
            options.threads = c.threads;
            options.quiet = true;
            image = render(*loaded, options);
        }
        const int x0 = gap + int(i % columns) * (c.panelWidth + gap);
        const int y0 = gap + int(i / columns) * (c.panelHeight + labelHeight + gap);
        for (int y = 0; y < image.height; ++y)
            for (int x = 0; x < image.width; ++x) std::copy_n(image.pixel(x, y), 3, sheet.pixel(x0 + x, y0 + labelHeight + y));
        drawLabel(sheet, x0 + 4, y0 + labelHeight - 6, panels[i].label, 16, warnings);
    }
    if (section.first >= 0)
        drawLabel(sheet, gap + 4, sheet.height - 6,
                  std::string("section ") + char('x' + section.first) + " = " + shortNumber(section.second) +
                      ": blue inside, orange outside, black on the surface, lines every " +
                      shortNumber(0.2 * frame.halfDiagonal()),
                  12, warnings);

    if (std::filesystem::path(output).extension() == ".exr")
        writeImage(output, sheet, {}, false);
    else
        writePreviewPng(output, sheet, 0.0);
    for (const std::string& w : warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
    if (!c.quiet)
        std::fprintf(stderr, "wrote %s (%zu panels of %dx%d) in %.2fs\n", output.c_str(), panels.size(), c.panelWidth,
                     c.panelHeight,
                     std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
}

}  // namespace isotrace
