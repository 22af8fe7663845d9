// Scene files that are wrong as a whole: malformed JSON, impossible values
// that are the right type, and the files a scene points to (meshes, point
// sets, images, saved fits) broken in every way a user meets.
#include <nlohmann/json.hpp>

#include <cmath>
#include <sstream>

#include "bad_inputs/bad_input_case.h"

namespace isotrace::testing {
namespace {

using Json = nlohmann::ordered_json;

const char* kSmallScene = R"({"film": {"width": 12, "height": 8, "spp": 1},
  "materials": {"clay": {"type": "diffuse"}}, "fields": {"ball": {"type": "sphere", "radius": 1}},
  "objects": [{"field": "ball", "material": "clay"}], "lights": [{"type": "environment", "radiance": [1, 1, 1]}]})";

BadInputCase renderOf(const std::string& name, const std::string& sceneText, std::vector<std::string> mentions,
                      std::map<std::string, std::string> files = {}) {
    BadInputCase c;
    c.name = name;
    c.files = std::move(files);
    c.files["bad.json"] = sceneText;
    c.arguments = "render bad.json -o out.exr --quiet";
    mentions.insert(mentions.begin(), "bad.json");
    c.mentions = std::move(mentions);
    return c;
}

/// The small scene with the value at `pointer` set to `value` (JSON text).
std::string smallWith(const std::string& pointer, const std::string& value) {
    Json scene = Json::parse(kSmallScene);
    scene[Json::json_pointer(pointer)] = Json::parse(value);
    return scene.dump();
}

/// The small scene with one more object (JSON text) and its files.
std::string smallWithObject(const std::string& object) {
    Json scene = Json::parse(kSmallScene);
    scene["objects"].push_back(Json::parse(object));
    return scene.dump();
}

/// The small scene showing one more field (JSON text), named "extra".
std::string smallWithField(const std::string& field) {
    Json scene = Json::parse(kSmallScene);
    scene["fields"]["extra"] = Json::parse(field);
    scene["objects"].push_back({{"field", "extra"}, {"material", "clay"}});
    return scene.dump();
}

std::string nested(const std::string& open, const std::string& close, int depth, const std::string& inner) {
    std::string s;
    for (int i = 0; i < depth; ++i) s += open;
    s += inner;
    for (int i = 0; i < depth; ++i) s += close;
    return s;
}

std::string points(int n, const std::string& last = "") {
    std::ostringstream out;
    for (int i = 0; i < n; ++i) out << std::cos(0.7 * i) << ' ' << std::sin(0.7 * i) << ' ' << 0.1 * (i % 7) - 0.3 << " 1 0 0\n";
    out << last;
    return out.str();
}

}  // namespace

std::vector<BadInputCase> sceneFileCases() {
    std::vector<BadInputCase> cases;
    auto add = [&](BadInputCase c) { cases.push_back(std::move(c)); };

    // Malformed JSON: the message gives line and column.
    add(renderOf("json_empty_file", "", {}));
    add(renderOf("json_truncated", R"({"objects": [{"field": "ball")", {"line 1"}));
    add(renderOf("json_array_root", "[]", {}));
    add(renderOf("json_null_root", "null", {}));
    add(renderOf("json_number_root", "42", {}));
    add(renderOf("json_trailing_comma", R"({"objects": [],})", {"line 1"}));
    add(renderOf("json_comment", "// a scene\n" + std::string(kSmallScene), {"line 1"}));
    add(renderOf("json_nan_literal", smallWith("/film/width", "12").replace(0, 1, "{\"x\": NaN, "), {"line 1"}));
    add(renderOf("json_infinity_literal", std::string("{\"x\": Infinity}"), {"line 1"}));
    add(renderOf("json_number_overflow", smallWith("/film/width", "12").replace(0, 1, "{\"camera\": {\"fov\": 1e999}, "), {"line 1"}));
    add(renderOf("json_invalid_utf8", "{\"objects\": [{\"name\": \"\xff\xfe\"}]}", {}));
    add(renderOf("json_binary_garbage", std::string("\x89PNG\r\n\x1a\n\0\0\0\rIHDR", 16), {}));
    add(renderOf("json_single_quotes", "{'objects': []}", {"line 1"}));
    add(renderOf("json_unclosed_string", "{\"objects\": \"ball", {"line 1"}));
    add(renderOf("json_nested_5000_deep", "{\"x\": " + nested("[", "]", 5000, "0") + "}", {"deep"}));
    add(renderOf("json_two_documents", std::string(kSmallScene) + std::string(kSmallScene), {}));
    add(renderOf("json_duplicate_section_wrong_type", R"({"objects": 3})", {"/objects"}));

    // Deep and cyclic field graphs.
    {
        std::string chain = R"({"film": {"width": 8, "height": 6, "spp": 1}, "materials": {"clay": {"type": "diffuse"}},
          "objects": [{"field": "f99999", "material": "clay"}], "fields": {"f0": {"type": "sphere", "radius": 1})";
        for (int i = 1; i < 100000; ++i)
            chain += ",\n\"f" + std::to_string(i) + R"(": {"type": "offset", "distance": 0, "of": "f)" + std::to_string(i - 1) + "\"}";
        add(renderOf("graph_100000_named_offsets", chain + "}}", {"deep"}));
        std::string inline_ = R"({"type": "sphere", "radius": 1})";
        for (int i = 0; i < 2500; ++i) inline_ = R"({"type": "union", "of": [)" + inline_ + "]}";
        add(renderOf("graph_2500_nested_unions", smallWith("/fields/ball", inline_), {"deep"}));
    }
    add(renderOf("graph_cycle_used", smallWith("/fields", R"({"ball": {"type": "offset", "of": "b", "distance": 0},
        "b": {"type": "union", "of": ["ball"]}})"), {"cycle"}));
    add(renderOf("graph_cycle_unused", smallWith("/fields", R"({"ball": {"type": "sphere", "radius": 1},
        "a": {"type": "offset", "of": "b", "distance": 0}, "b": {"type": "union", "of": ["a"]}})"), {"cycle"}));
    add(renderOf("graph_self_reference", smallWith("/fields/ball", R"({"type": "offset", "of": "ball", "distance": 0})"),
                 {"cycle"}));
    add(renderOf("graph_alias_of_unknown", smallWith("/fields/other", R"("nothing")"), {"/fields/other"}));
    add(renderOf("graph_blend_of_itself", smallWith("/fields/ball", R"({"type": "variational", "blend": ["ball", "ball"]})"),
                 {"/fields/ball"}));

    // Structure.
    add(renderOf("scene_without_objects", R"({"materials": {}})", {"objects"}));
    add(renderOf("scene_objects_empty", smallWith("/objects", "[]"), {"/objects"}));
    add(renderOf("object_unknown_material", smallWith("/objects/0/material", R"("stone")"), {"/objects/0/material"}));
    add(renderOf("object_unknown_field", smallWith("/objects/0/field", R"("cube")"), {"/objects/0/field"}));
    add(renderOf("object_without_material", smallWith("/objects/0", R"({"field": "ball"})"), {"/objects/0"}));
    add(renderOf("object_field_and_mesh", smallWith("/objects/0/mesh", R"("tet.off")"), {"/objects/0"}));
    add(renderOf("object_nothing_to_show", smallWith("/objects/0", R"({"material": "clay"})"), {"/objects/0"}));
    add(renderOf("object_unknown_as", smallWith("/objects/0/as", R"("voxels")"), {"/objects/0/as"}));
    add(renderOf("two_environments", smallWith("/lights", R"([{"type": "environment", "radiance": [1, 1, 1]},
        {"type": "environment", "radiance": [1, 1, 1]}])"), {"/lights/1"}));
    add(renderOf("integrator_unknown", smallWith("/integrator", R"({"type": "bidirectional"})"), {"/integrator/type"}));
    add(renderOf("material_unknown_type", smallWith("/materials/clay/type", R"("velvet")"), {"/materials/clay/type"}));
    add(renderOf("field_unknown_type", smallWith("/fields/ball/type", R"("hypersphere")"), {"/fields/ball/type"}));
    add(renderOf("light_unknown_type", smallWith("/lights/0/type", R"("lamp")"), {"/lights/0/type"}));
    add(renderOf("film_unknown_sampler", smallWith("/film/sampler", R"("halton")"), {"/film/sampler"}));
    add(renderOf("filter_unknown_type", smallWith("/film/filter", R"({"type": "mitchell"})"), {"/film/filter/type"}));

    // Right type, impossible value.
    struct Value {
        const char* name;
        const char* pointer;
        const char* value;
    };
    const Value values[] = {
        {"camera_from_equals_to", "/camera", R"({"from": [0, 0, 0], "to": [0, 0, 0]})"},
        {"camera_up_along_view", "/camera", R"({"from": [0, 0, 5], "to": [0, 0, 0], "up": [0, 0, 1]})"},
        {"camera_up_zero", "/camera/up", "[0, 0, 0]"},
        {"camera_fov_zero", "/camera/fov", "0"},
        {"camera_fov_180", "/camera/fov", "180"},
        {"camera_fov_negative", "/camera/fov", "-30"},
        {"camera_aperture_negative", "/camera/aperture", "-0.1"},
        {"camera_aperture_huge", "/camera/aperture", "1e16"},
        {"camera_focus_zero", "/camera/focus_distance", "0"},
        {"camera_from_9e18", "/camera/from", "[0, 0, 9.2e18]"},
        {"camera_to_1e300", "/camera/to", "[0, 0, -1e300]"},
        {"camera_vector_two", "/camera/from", "[0, 5]"},
        {"camera_vector_four", "/camera/from", "[0, 0, 5, 1]"},
        {"film_width_zero", "/film/width", "0"},
        {"film_width_negative", "/film/width", "-8"},
        {"film_width_fraction", "/film/width", "12.5"},
        {"film_width_too_large", "/film/width", "65537"},
        {"film_too_much_memory", "/film", R"({"width": 65536, "height": 65536, "spp": 1})"},
        {"film_spp_zero", "/film/spp", "0"},
        {"film_spp_too_many", "/film/spp", "2097152"},
        {"film_width_1e300", "/film/width", "1e300"},
        {"filter_radius_1e308", "/film/filter", R"({"type": "box", "radius": 1e308})"},
        {"filter_radius_zero", "/film/filter", R"({"type": "box", "radius": 0})"},
        {"filter_sigma_negative", "/film/filter", R"({"type": "gaussian", "radius": 1.5, "sigma": -1})"},
        {"filter_sigma_on_box", "/film/filter", R"({"type": "box", "radius": 0.5, "sigma": 1})"},
        {"integrator_depth_zero", "/integrator", R"({"type": "path", "max_depth": 0})"},
        {"integrator_depth_too_deep", "/integrator", R"({"type": "path", "max_depth": 100001})"},
        {"whitted_depth_too_deep", "/integrator", R"({"type": "whitted", "max_depth": 1001})"},
        {"integrator_roulette_too_deep", "/integrator", R"({"type": "path", "rr_depth": 100001})"},
        {"diffuse_albedo_above_one", "/materials/clay", R"({"type": "diffuse", "albedo": [2, 0, 0]})"},
        {"diffuse_albedo_negative", "/materials/clay", R"({"type": "diffuse", "albedo": [-0.1, 0.5, 0.5]})"},
        {"diffuse_albedo_two_channels", "/materials/clay", R"({"type": "diffuse", "albedo": [0.5, 0.5]})"},
        {"mirror_reflectance_above_one", "/materials/clay", R"({"type": "mirror", "reflectance": 1.5})"},
        {"emissive_negative", "/materials/clay", R"({"type": "emissive", "radiance": [-1, 1, 1]})"},
        {"emissive_1e300", "/materials/clay", R"({"type": "emissive", "radiance": [1e300, 1, 1]})"},
        {"conductor_unknown_metal", "/materials/clay", R"({"type": "conductor", "metal": "unobtainium"})"},
        {"conductor_metal_and_eta", "/materials/clay", R"({"type": "conductor", "metal": "gold", "eta": [1, 1, 1]})"},
        {"conductor_eta_zero", "/materials/clay", R"({"type": "conductor", "eta": [0, 1, 1], "k": [1, 1, 1]})"},
        {"conductor_k_negative", "/materials/clay", R"({"type": "conductor", "eta": [1, 1, 1], "k": [-1, 1, 1]})"},
        {"conductor_roughness_above_one", "/materials/clay", R"({"type": "conductor", "roughness": 1.5})"},
        {"conductor_multiple_scattering_text", "/materials/clay", R"({"type": "conductor", "roughness": 0.5, "multiple_scattering": "yes"})"},
        {"dielectric_ior_zero", "/materials/clay", R"({"type": "dielectric", "ior": 0})"},
        {"dielectric_ior_eleven", "/materials/clay", R"({"type": "dielectric", "ior": 11})"},
        {"dielectric_roughness_negative", "/materials/clay", R"({"type": "dielectric", "roughness": -0.1})"},
        {"dielectric_multiple_scattering_number", "/materials/clay", R"({"type": "dielectric", "roughness": 0.5, "multiple_scattering": 1})"},
        {"plastic_ior_below_one", "/materials/clay", R"({"type": "plastic", "ior": 0.9})"},
        {"plastic_multiple_scattering_null", "/materials/clay", R"({"type": "plastic", "roughness": 0.5, "multiple_scattering": null})"},
        {"checker_scale_zero", "/materials/clay", R"({"type": "diffuse", "albedo": {"type": "checker", "scale": 0}})"},
        {"checker_one_colour", "/materials/clay", R"({"type": "diffuse", "albedo": {"type": "checker", "colors": [[1, 1, 1]]}})"},
        {"noise_octaves_17", "/materials/clay", R"({"type": "diffuse", "albedo": {"type": "noise", "octaves": 17}})"},
        {"noise_too_bright", "/materials/clay", R"({"type": "diffuse", "albedo": {"type": "noise", "colors": [0, 2]}})"},
        {"texture_unknown_type", "/materials/clay", R"({"type": "diffuse", "albedo": {"type": "marble"}})"},
        {"ramp_unknown_field", "/materials/clay",
         R"({"type": "diffuse", "albedo": {"type": "field_ramp", "field": "cube", "ramp": [[0, 0], [1, 1]]}})"},
        {"ramp_one_stop", "/materials/clay",
         R"({"type": "diffuse", "albedo": {"type": "field_ramp", "field": "ball", "ramp": [[0, 0]]}})"},
        {"ramp_decreasing", "/materials/clay",
         R"({"type": "diffuse", "albedo": {"type": "field_ramp", "field": "ball", "ramp": [[1, 0], [0, 1]]}})"},
        {"ramp_unknown_quantity", "/materials/clay", R"({"type": "diffuse", "albedo": {"type": "field_ramp",
          "field": "ball", "quantity": "gaussian_curvature", "ramp": [[0, 0], [1, 1]]}})"},
        {"roughness_rgb_texture", "/materials/clay", R"({"type": "conductor", "roughness": {"type": "checker",
          "colors": [[0.1, 0.2, 0.3], [0.4, 0.5, 0.6]]}})"},
        {"sphere_radius_zero", "/fields/ball/radius", "0"},
        {"sphere_radius_negative", "/fields/ball/radius", "-1"},
        {"sphere_radius_1e300", "/fields/ball/radius", "1e300"},
        {"sphere_center_1e300", "/fields/ball/center", "[1e300, 0, 0]"},
        {"box_size_negative", "/fields/ball", R"({"type": "box", "size": [1, -1, 1]})"},
        {"box_rounding_too_big", "/fields/ball", R"({"type": "box", "size": [1, 1, 1], "rounding": 0.6})"},
        {"torus_minor_zero", "/fields/ball", R"({"type": "torus", "major": 1, "minor": 0})"},
        {"cylinder_height_zero", "/fields/ball", R"({"type": "cylinder", "radius": 1, "height": 0})"},
        {"cone_radius_negative", "/fields/ball", R"({"type": "cone", "radius": -1, "height": 1})"},
        {"capsule_radius_zero", "/fields/ball", R"({"type": "capsule", "from": [0, 0, 0], "to": [0, 1, 0], "radius": 0})"},
        {"ellipsoid_radius_zero", "/fields/ball", R"({"type": "ellipsoid", "radii": [1, 0, 1]})"},
        {"octahedron_size_zero", "/fields/ball", R"({"type": "octahedron", "size": 0})"},
        {"octahedron_size_missing", "/fields/ball", R"({"type": "octahedron", "center": [0, 0, 0]})"},
        {"octahedron_size_string", "/fields/ball", R"({"type": "octahedron", "size": "big"})"},
        {"plane_alone", "/fields/ball", R"({"type": "plane"})"},
        {"plane_normal_zero", "/fields/ball", R"({"type": "intersection", "of": [{"type": "sphere", "radius": 1}, {"type": "plane", "normal": [0, 0, 0]}]})"},
        {"complement_alone", "/fields/ball", R"({"type": "complement", "of": {"type": "sphere", "radius": 1}})"},
        {"bounds_inverted", "/fields/ball", R"({"type": "sphere", "radius": 1, "bounds": [[1, 1, 1], [-1, -1, -1]]})"},
        {"bounds_empty_box", "/fields/ball", R"({"type": "sphere", "radius": 1, "bounds": [[0, 0, 0], [0, 0, 0]]})"},
        {"lipschitz_claim_false", "/fields/ball", R"({"type": "sphere", "radius": 1, "lipschitz": 0.5})"},
        {"lipschitz_negative", "/fields/ball", R"({"type": "sphere", "radius": 1, "lipschitz": -1})"},
        {"polynomial_power_25", "/fields/ball",
         R"({"type": "polynomial", "terms": [[1, 25, 0, 0], [-1, 0, 0, 0]], "domain": [[-1, -1, -1], [1, 1, 1]]})"},
        {"polynomial_without_domain", "/fields/ball", R"({"type": "polynomial", "terms": [[1, 2, 0, 0], [-1, 0, 0, 0]]})"},
        {"polynomial_unknown_preset", "/fields/ball", R"({"type": "polynomial", "preset": "klein"})"},
        {"polynomial_negative_power", "/fields/ball",
         R"({"type": "polynomial", "terms": [[1, -2, 0, 0]], "domain": [[-1, -1, -1], [1, 1, 1]]})"},
        {"quadric_nine_coefficients", "/fields/ball",
         R"({"type": "quadric", "coefficients": [1, 1, 1, 0, 0, 0, 0, 0, 0], "domain": [[-1, -1, -1], [1, 1, 1]]})"},
        {"blobby_no_blobs", "/fields/ball", R"({"type": "blobby", "blobs": []})"},
        {"blobby_threshold_zero", "/fields/ball",
         R"({"type": "blobby", "threshold": 0, "blobs": [{"center": [0, 0, 0], "radius": 1}]})"},
        {"blobby_unknown_kernel", "/fields/ball",
         R"({"type": "blobby", "kernel": "gauss", "blobs": [{"center": [0, 0, 0], "radius": 1}]})"},
        {"blobby_radius_zero", "/fields/ball", R"({"type": "blobby", "blobs": [{"center": [0, 0, 0], "radius": 0}]})"},
        {"blobby_blobbiness_on_soft", "/fields/ball",
         R"({"type": "blobby", "kernel": "soft", "blobbiness": 3, "blobs": [{"center": [0, 0, 0], "radius": 1}]})"},
        {"blobby_half_size_negative", "/fields/ball",
         R"({"type": "blobby", "blobs": [{"center": [0, 0, 0], "radius": 1, "half_size": [1, -0.5, 0]}]})"},
        {"blobby_axes_in_one_plane", "/fields/ball",
         R"({"type": "blobby", "blobs": [{"center": [0, 0, 0], "radius": 1, "axes": [[1, 0, 0], [0, 1, 0], [1, 1, 0]]}]})"},
        {"blobby_two_axes", "/fields/ball",
         R"({"type": "blobby", "blobs": [{"center": [0, 0, 0], "radius": 1, "axes": [[1, 0, 0], [0, 1, 0]]}]})"},
        {"blobby_axis_1e300", "/fields/ball",
         R"({"type": "blobby", "blobs": [{"center": [0, 0, 0], "radius": 1, "axes": [[1, 0, 0], [0, 1, 0], [0, 0, 1e300]]}]})"},
        {"distance_no_skeleton", "/fields/ball", R"({"type": "distance", "radius": 0.1})"},
        {"distance_points_and_circle", "/fields/ball", R"({"type": "distance", "radius": 0.1, "points": [[0, 0, 0]],
          "circle": {"radius": 1}})"},
        {"convolution_zero_length", "/fields/ball",
         R"({"type": "convolution", "segments": [{"from": [0, 0, 0], "to": [0, 0, 0], "radius": 0}]})"},
        {"union_of_nothing", "/fields/ball", R"({"type": "union", "of": []})"},
        {"difference_of_one", "/fields/ball", R"({"type": "difference", "of": [{"type": "sphere", "radius": 1}]})"},
        {"smooth_radius_negative", "/fields/ball", R"({"type": "smooth_union", "of": [{"type": "sphere", "radius": 1},
          {"type": "sphere", "radius": 1, "center": [1, 0, 0]}], "radius": -0.1})"},
        {"offset_of_unknown", "/fields/ball", R"({"type": "offset", "of": "cube", "distance": 0.1})"},
        {"transform_scale_zero", "/fields/ball", R"({"type": "transform", "of": {"type": "sphere", "radius": 1}, "scale": 0})"},
        {"transform_axis_zero", "/fields/ball", R"({"type": "transform", "of": {"type": "sphere", "radius": 1},
          "rotate": {"axis": [0, 0, 0], "angle": 30}})"},
        {"variational_nothing", "/fields/ball", R"({"type": "variational"})"},
        {"variational_all_zero", "/fields/ball", R"({"type": "variational", "boundary": [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]})"},
        {"variational_coincident", "/fields/ball", R"({"type": "variational", "boundary": [[1, 0, 0], [1, 0, 0]],
          "interior": [[0, 0, 0]], "exterior": [[3, 3, 3]]})"},
        {"variational_planar", "/fields/ball", R"({"type": "variational", "boundary": [[1, 0, 0], [0, 1, 0], [-1, 0, 0]],
          "interior": [[0, 0, 0]]})"},
        {"variational_zero_normal", "/fields/ball", R"({"type": "variational", "normals": [[1, 0, 0, 0, 0, 0]]})"},
        {"variational_sample_count_two", "/fields/ball", R"({"type": "variational", "sample": {"type": "sphere", "radius": 1}, "count": 2})"},
        {"variational_sample_unbounded", "/fields/ball", R"({"type": "variational", "sample": {"type": "plane"}})"},
        {"variational_blend_one", "/fields/ball", R"({"type": "variational", "blend": [{"type": "variational",
          "sample": {"type": "sphere", "radius": 1}}]})"},
        {"variational_blend_of_sphere", "/fields/ball", R"({"type": "variational", "blend": [{"type": "sphere", "radius": 1},
          {"type": "sphere", "radius": 1}]})"},
        {"variational_fitted_and_points", "/fields/ball", R"({"type": "variational", "fitted": "x.json", "boundary": [[0, 0, 0]]})"},
        {"mpu_accuracy_zero", "/fields/ball", R"({"type": "mpu", "points": "ring.xyz", "accuracy": 0})"},
        {"mpu_support_five", "/fields/ball", R"({"type": "mpu", "points": "ring.xyz", "support": 5})"},
        {"mpu_depth_21", "/fields/ball", R"({"type": "mpu", "points": "ring.xyz", "max_depth": 21})"},
        {"mpu_min_points_five", "/fields/ball", R"({"type": "mpu", "points": "ring.xyz", "min_points": 5})"},
        {"mpu_no_points", "/fields/ball", R"({"type": "mpu"})"},
        {"mpu_sharp_features_text", "/fields/ball", R"({"type": "mpu", "points": "ring.xyz", "sharp_features": "yes"})"},
        {"mpu_fitted_and_points", "/fields/ball", R"({"type": "mpu", "fitted": "x.json", "points": "ring.xyz"})"},
        {"mpu_fitted_number", "/fields/ball", R"({"type": "mpu", "fitted": 3})"},
        {"particles_count_zero", "/objects/0", R"({"field": "ball", "material": "clay", "as": "particles", "count": 0})"},
        {"particles_count_too_many", "/objects/0", R"({"field": "ball", "material": "clay", "as": "particles", "count": 20000000})"},
        {"particles_spacing_zero", "/objects/0", R"({"field": "ball", "material": "clay", "as": "particles", "spacing": 0})"},
        {"particles_count_and_spacing", "/objects/0",
         R"({"field": "ball", "material": "clay", "as": "particles", "count": 10, "spacing": 0.1})"},
        {"particles_disc_scale_five", "/objects/0", R"({"field": "ball", "material": "clay", "as": "particles", "disc_scale": 5})"},
        {"mesh_resolution_zero", "/objects/0", R"({"field": "ball", "material": "clay", "as": "mesh", "resolution": 0})"},
        {"mesh_resolution_huge", "/objects/0", R"({"field": "ball", "material": "clay", "as": "mesh", "resolution": 100000})"},
        {"mesh_tolerance_negative", "/objects/0", R"({"field": "ball", "material": "clay", "as": "mesh", "tolerance": -1})"},
        {"mesh_unknown_method", "/objects/0", R"({"field": "ball", "material": "clay", "as": "mesh", "method": "dual_contouring"})"},
        {"transform_singular_matrix", "/objects/0", R"({"field": "ball", "material": "clay",
          "transform": {"matrix": [[1, 0, 0, 0], [0, 0, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]}})"},
        {"transform_projective_matrix", "/objects/0", R"({"field": "ball", "material": "clay",
          "transform": {"matrix": [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 1, 1]]}})"},
        {"transform_matrix_three_rows", "/objects/0", R"({"field": "ball", "material": "clay",
          "transform": {"matrix": [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0]]}})"},
        {"transform_matrix_and_translate", "/objects/0", R"({"field": "ball", "material": "clay",
          "transform": {"matrix": [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]], "translate": [1, 0, 0]}})"},
        {"transform_translate_1e300", "/objects/0", R"({"field": "ball", "material": "clay", "transform": {"translate": [1e300, 0, 0]}})"},
        {"transform_scale_1e-300", "/objects/0", R"({"field": "ball", "material": "clay", "transform": {"scale": 1e-300}})"},
        {"transform_scale_negative", "/objects/0", R"({"field": "ball", "material": "clay", "transform": {"scale": [1, -1, 1]}})"},
        {"inline_mesh_index_out_of_range", "/objects/0", R"({"vertices": [0, 0, 0, 1, 0, 0, 0, 1, 0], "indices": [0, 1, 3], "material": "clay"})"},
        {"inline_mesh_negative_index", "/objects/0", R"({"vertices": [0, 0, 0, 1, 0, 0, 0, 1, 0], "indices": [0, 1, -1], "material": "clay"})"},
        {"inline_mesh_indices_not_triples", "/objects/0", R"({"vertices": [0, 0, 0, 1, 0, 0, 0, 1, 0], "indices": [0, 1], "material": "clay"})"},
        {"inline_mesh_vertices_not_triples", "/objects/0", R"({"vertices": [0, 0, 0, 1, 0, 0, 0, 1], "indices": [0, 1, 2], "material": "clay"})"},
        {"inline_mesh_degenerate", "/objects/0", R"({"vertices": [0, 0, 0, 1, 0, 0, 2, 0, 0], "indices": [0, 1, 2], "material": "clay"})"},
        {"inline_mesh_repeated_vertex", "/objects/0", R"({"vertices": [0, 0, 0, 1, 0, 0, 0, 1, 0], "indices": [0, 1, 1], "material": "clay"})"},
        {"inline_mesh_vertex_1e300", "/objects/0", R"({"vertices": [0, 0, 0, 1e300, 0, 0, 0, 1, 0], "indices": [0, 1, 2], "material": "clay"})"},
        {"point_light_negative", "/lights/0", R"({"type": "point", "position": [0, 2, 0], "intensity": [-1, 1, 1]})"},
        {"spot_cone_angle_zero", "/lights/0", R"({"type": "spot", "position": [0, 2, 0], "direction": [0, -1, 0], "cone_angle": 0})"},
        {"spot_cone_angle_200", "/lights/0", R"({"type": "spot", "position": [0, 2, 0], "direction": [0, -1, 0], "cone_angle": 200})"},
        {"spot_blend_above_one", "/lights/0", R"({"type": "spot", "position": [0, 2, 0], "direction": [0, -1, 0], "blend": 1.5})"},
        {"spot_zero_direction", "/lights/0", R"({"type": "spot", "position": [0, 2, 0], "direction": [0, 0, 0]})"},
        {"directional_zero_direction", "/lights/0", R"({"type": "directional", "direction": [0, 0, 0], "irradiance": [1, 1, 1]})"},
        {"quad_parallel_edges", "/lights/0", R"({"type": "quad", "corner": [0, 2, 0], "edge1": [1, 0, 0], "edge2": [2, 0, 0], "radiance": [1, 1, 1]})"},
        {"disk_radius_zero", "/lights/0", R"({"type": "disk", "center": [0, 2, 0], "radius": 0, "radiance": [1, 1, 1]})"},
        {"disk_normal_zero", "/lights/0", R"({"type": "disk", "center": [0, 2, 0], "normal": [0, 0, 0], "radius": 1, "radiance": [1, 1, 1]})"},
        {"environment_radiance_and_file", "/lights/0", R"({"type": "environment", "radiance": [1, 1, 1], "file": "sky.exr"})"},
        {"environment_scale_negative", "/lights/0", R"({"type": "environment", "file": "sky.exr", "scale": -1})"},
        {"environment_scale_on_constant", "/lights/0", R"({"type": "environment", "radiance": [1, 1, 1], "scale": 2})"},
        {"integrator_unknown_light_sampler", "/integrator", R"({"type": "path", "light_sampler": "power"})"},
    };
    // Scatters put at /fields/ball, each error named at its own key.
    const Value scatters[] = {
        {"scatter_count_missing", "/fields/ball/count",
         R"({"type": "scatter", "region": [[-1, -1, -1], [1, 1, 1]], "shape": {"type": "sphere", "radius": 0.1}})"},
        {"scatter_count_zero", "/fields/ball/count",
         R"({"type": "scatter", "count": 0, "region": [[-1, -1, -1], [1, 1, 1]], "shape": {"type": "sphere", "radius": 0.1}})"},
        {"scatter_count_past_memory", "/fields/ball/count",
         R"({"type": "scatter", "count": 100000000, "region": [[-1, -1, -1], [1, 1, 1]], "shape": {"type": "sphere", "radius": 0.1}})"},
        {"scatter_count_fractional", "/fields/ball/count",
         R"({"type": "scatter", "count": 2.5, "region": [[-1, -1, -1], [1, 1, 1]], "shape": {"type": "sphere", "radius": 0.1}})"},
        {"scatter_region_missing", "/fields/ball/region", R"({"type": "scatter", "count": 10, "shape": {"type": "sphere", "radius": 0.1}})"},
        {"scatter_region_inverted", "/fields/ball/region",
         R"({"type": "scatter", "count": 10, "region": [[1, 1, 1], [-1, -1, -1]], "shape": {"type": "sphere", "radius": 0.1}})"},
        {"scatter_radius_negative", "/fields/ball/shape/radius",
         R"({"type": "scatter", "count": 10, "region": [[-1, -1, -1], [1, 1, 1]], "shape": {"type": "sphere", "radius": -0.1}})"},
        {"scatter_unknown_shape", "/fields/ball/shape/type",
         R"({"type": "scatter", "count": 10, "region": [[-1, -1, -1], [1, 1, 1]], "shape": {"type": "teapot", "radius": 0.1}})"},
        {"scatter_scale_reversed", "/fields/ball/scale", R"({"type": "scatter", "count": 10, "region": [[-1, -1, -1], [1, 1, 1]],
          "shape": {"type": "sphere", "radius": 0.1}, "scale": [2, 1]})"},
        {"scatter_blend_on_union", "/fields/ball/radius", R"({"type": "scatter", "count": 10, "region": [[-1, -1, -1], [1, 1, 1]],
          "shape": {"type": "sphere", "radius": 0.1}, "radius": 0.1})"},
        {"scatter_unknown_operation", "/fields/ball/operation", R"({"type": "scatter", "count": 10, "operation": "xor",
          "region": [[-1, -1, -1], [1, 1, 1]], "shape": {"type": "sphere", "radius": 0.1}})"},
        {"scatter_shape_missing", "/fields/ball/shape", R"({"type": "scatter", "count": 10, "region": [[-1, -1, -1], [1, 1, 1]]})"},
        {"scatter_seed_negative", "/fields/ball/seed", R"({"type": "scatter", "count": 10, "seed": -1,
          "region": [[-1, -1, -1], [1, 1, 1]], "shape": {"type": "sphere", "radius": 0.1}})"},
        {"scatter_file_number", "/fields/ball/file", R"({"type": "scatter", "file": 3, "shape": {"type": "sphere", "radius": 0.1}})"},
        {"scatter_smooth_without_radius", "/fields/ball/radius", R"({"type": "scatter", "count": 10, "operation": "smooth_union",
          "region": [[-1, -1, -1], [1, 1, 1]], "shape": {"type": "sphere", "radius": 0.1}})"},
    };
    for (const Value& v : scatters) add(renderOf(v.name, smallWith("/fields/ball", v.value), {v.pointer}));

    // Operand lists from PLY files, each broken one way.
    struct SphereFileCase {
        const char* name;
        const char* content;
        const char* mention;
    };
    const SphereFileCase sphereFiles[] = {
        {"scatter_file_not_ply", "solid\n", "line 1"},
        {"scatter_file_without_z", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                                   "property float radius\nend_header\n0 0 1\n", "x, y and z"},
        {"scatter_file_without_radius", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                                        "property float z\nend_header\n0 0 0\n", "radius"},
        {"scatter_file_nan", "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
                             "property float z\nproperty float radius\nend_header\n0 0 0 1\nnan 0 0 1\n", "vertex 1"},
        {"scatter_file_radius_zero", "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
                                     "property float z\nproperty float radius\nend_header\n0 0 0 1\n1 0 0 0\n", "vertex 1"},
        {"scatter_file_past_memory", "ply\nformat ascii 1.0\nelement vertex 100000000000\nproperty float x\n"
                                     "property float y\nproperty float z\nproperty float radius\nend_header\n0 0 0 1\n", "memory"},
        {"scatter_file_truncated", "ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty float x\n"
                                   "property float y\nproperty float z\nproperty float radius\nend_header\nabcdefghijklmnopqrst", "vertex 1"},
        {"scatter_file_list_property", "ply\nformat ascii 1.0\nelement vertex 1\nproperty list uchar float x\nend_header\n1 0\n", "list"},
        {"scatter_file_words", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                               "property float z\nproperty float radius\nend_header\n0 zero 0 1\n", "line 9"},
    };
    for (const SphereFileCase& f : sphereFiles)
        add(renderOf(f.name, smallWith("/fields/ball", R"({"type": "scatter", "file": "spheres.ply"})"),
                     {"/fields/ball/file", "spheres.ply", f.mention}, {{"spheres.ply", f.content}}));
    add(renderOf("scatter_file_missing", smallWith("/fields/ball", R"({"type": "scatter", "file": "none.ply"})"),
                 {"/fields/ball/file", "none.ply", "not found"}));
    add(renderOf("scatter_file_and_count",
                 smallWith("/fields/ball", R"({"type": "scatter", "file": "spheres.ply", "count": 5})"), {"/fields/ball/count"},
                 {{"spheres.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                                  "property float z\nproperty float radius\nend_header\n0 0 0 1\n"}}));

    // A field whose parameters put its surface out of reach is named as a whole.
    for (const Value& v : values)
        add(renderOf(v.name, smallWith(v.pointer, v.value),
                     {std::string(v.name).find("1e300") != std::string::npos && std::string(v.pointer).rfind("/fields/", 0) == 0
                          ? "/fields/ball"
                          : v.pointer}));

    // Files a scene points to.
    struct FileCase {
        const char* name;
        const char* file;
        std::string content;
    };
    const std::string offHeader = "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n";
    const FileCase meshes[] = {
        {"off_empty", "m.off", ""},
        {"off_bad_magic", "m.off", "FFO\n4 4 0\n"},
        {"off_index_out_of_range", "m.off", offHeader + "3 0 2 99\n3 0 1 3\n3 0 3 2\n3 1 2 3\n"},
        {"off_negative_index", "m.off", offHeader + "3 0 2 -1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n"},
        {"off_truncated_faces", "m.off", offHeader + "3 0 2 1\n"},
        {"off_truncated_vertices", "m.off", "OFF\n4 4 0\n0 0 0\n1 0\n"},
        {"off_nan_vertex", "m.off", "OFF\n4 4 0\n0 0 0\n1 0 nan\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n"},
        {"off_inf_vertex", "m.off", "OFF\n4 4 0\n0 0 0\n1 0 inf\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n"},
        {"off_billion_vertices", "m.off", "OFF\n1000000000 1 0\n0 0 0\n"},
        {"off_negative_count", "m.off", "OFF\n-4 4 0\n"},
        {"off_face_of_two", "m.off", offHeader + "2 0 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n"},
        {"off_face_count_huge", "m.off", offHeader + "4000000000 0 1 2\n"},
        {"off_text_in_numbers", "m.off", "OFF\n4 4 0\n0 0 zero\n"},
        {"off_no_faces", "m.off", "OFF\n4 0 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n"},
        {"obj_face_index_zero", "m.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n"},
        {"obj_face_index_beyond", "m.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n"},
        {"obj_short_vertex", "m.obj", "v 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"},
        {"obj_nan_vertex", "m.obj", "v 0 0 nan\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"},
        {"obj_no_faces", "m.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n"},
        {"ply_bad_header", "m.ply", "ply\nformat ascii 1.0\nelement vertex 3\nend_header\n"},
        {"ply_huge_count", "m.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 1000000000\nproperty float x\n"
                                    "property float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                                    "end_header\n\x01\x02"},
        {"ply_truncated_binary", "m.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
                                          "property float y\nproperty float z\nelement face 1\n"
                                          "property list uchar int vertex_indices\nend_header\n\x01\x02\x03"},
        {"ply_index_out_of_range", "m.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                            "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                                            "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n"},
        {"ply_not_ply", "m.ply", "solid cube\nfacet normal 0 0 1\n"},
        {"stl_refused", "m.stl", "solid cube\nendsolid cube\n"},
        {"unknown_extension", "m.mesh", "OFF\n"},
    };
    // Each as a mesh object and as a variational field's input.
    for (const FileCase& m : meshes) {
        const std::string object = std::string(R"({"mesh": ")") + m.file + R"(", "material": "clay"})";
        const std::string field = std::string(R"({"type": "variational", "mesh": ")") + m.file + "\"}";
        add(renderOf("mesh_object_" + std::string(m.name), smallWithObject(object), {m.file}, {{m.file, m.content}}));
        add(renderOf("variational_mesh_" + std::string(m.name), smallWithField(field), {m.file}, {{m.file, m.content}}));
    }
    // Texture coordinates are read for mesh objects only.
    add(renderOf("mesh_object_ply_nan_uv",
                 smallWithObject(R"({"mesh": "m.ply", "material": "clay"})"), {"m.ply", "texture coordinate"},
                 {{"m.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                            "property float z\nproperty float s\nproperty float t\nelement face 1\n"
                            "property list uchar int vertex_indices\nend_header\n0 0 0 0 0\n1 0 0 nan 0\n0 1 0 0 1\n3 0 1 2\n"}}));
    add(renderOf("mesh_object_missing_file", smallWithObject(R"({"mesh": "gone.off", "material": "clay"})"), {"gone.off"}));
    add(renderOf("mesh_object_is_folder", smallWithObject(R"({"mesh": "folder.off", "material": "clay"})"), {"folder.off"}));
    cases.back().setup = {"mkdir folder.off"};

    const FileCase pointFiles[] = {
        {"points_empty", "p.xyz", ""},
        {"points_nan", "p.xyz", points(30, "nan 0 0 1 0 0\n")},
        {"points_inf_normal", "p.xyz", points(30, "0 0 0 inf 0 0\n")},
        {"points_zero_normal", "p.xyz", points(30, "0.5 0.5 0.5 0 0 0\n")},
        {"points_five_columns", "p.xyz", points(30, "0.5 0.5 0.5 0 0\n")},
        {"points_text", "p.xyz", points(30, "one two three four five six\n")},
        {"points_two", "p.xyz", points(2)},
        {"points_all_in_a_plane", "p.xyz", "0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n1 1 0 0 0 1\n2 1 0 0 0 1\n1 2 0 0 0 1\n"
                                            "2 2 0 0 0 1\n3 1 0 0 0 1\n"},
        {"points_all_coincident", "p.xyz", "1 1 1 0 0 1\n1 1 1 0 0 1\n1 1 1 0 0 1\n1 1 1 0 0 1\n1 1 1 0 0 1\n"},
        {"points_binary", "p.xyz", std::string("\0\x01\x02\x03\xff\xfe", 6)},
        {"pwn_count_too_large", "p.pwn", "1000000000\n0 0 0\n"},
        {"pwn_count_mismatch", "p.pwn", "3\n0 0 0\n1 0 0\n0 1 0\n1 0 0\n0 1 0\n"},
        {"points_unknown_extension", "p.csv", points(30)},
    };
    for (const FileCase& p : pointFiles) {
        for (const char* type : {"variational", "mpu"}) {
            add(renderOf(std::string(type) + "_" + p.name,
                         smallWithField(std::string(R"({"type": ")") + type + R"(", "points": ")" + p.file + "\"}"),
                         {p.file}, {{p.file, p.content}}));
        }
    }
    add(renderOf("variational_points_missing", smallWithField(R"({"type": "variational", "points": "gone.xyz"})"), {"gone.xyz"}));
    add(renderOf("mpu_points_missing", smallWithField(R"({"type": "mpu", "points": "gone.xyz"})"), {"gone.xyz"}));

    const FileCase fits[] = {
        {"fitted_empty", "f.json", ""},
        {"fitted_not_json", "f.json", "weights: 1 2 3"},
        {"fitted_wrong_root", "f.json", "[1, 2, 3]"},
        {"fitted_missing_keys", "f.json", R"({"fit": {}})"},
        {"fitted_unknown_format", "f.json", R"({"format": "isotrace-variational-99", "centers": []})"},
    };
    for (const FileCase& f : fits)
        add(renderOf(f.name, smallWithField(R"({"type": "variational", "fitted": "f.json"})"), {"f.json"}, {{f.file, f.content}}));
    add(renderOf("fitted_missing", smallWithField(R"({"type": "variational", "fitted": "gone.json"})"), {"gone.json"}));
    const FileCase mpuFits[] = {
        {"mpu_fitted_empty", "f.json", ""},
        {"mpu_fitted_variational", "f.json", R"({"isotrace_variational_fit": 1})"},
        {"mpu_fitted_missing_keys", "f.json", R"({"isotrace_mpu_fit": 1, "source": {}, "fit": {}})"},
        {"mpu_fitted_bad_piece", "f.json", R"({"isotrace_mpu_fit": 1, "source": {}, "fit": {}, "domain": [[-1, -1, -1], [1, 1, 1]],
          "support": 0.75, "background_margin": 0.001, "locals": [[0, 0, 0, 1, 0, 1, "single"]], "pieces": [[0, 0, 0]]})"},
        {"mpu_fitted_piece_out_of_range", "f.json", R"({"isotrace_mpu_fit": 1, "source": {}, "fit": {}, "domain": [[-1, -1, -1], [1, 1, 1]],
          "support": 0.75, "background_margin": 0.001, "locals": [[0, 0, 0, 1, 4, 1, "single"]], "pieces": []})"},
    };
    for (const FileCase& f : mpuFits)
        add(renderOf(f.name, smallWithField(R"({"type": "mpu", "fitted": "f.json"})"), {"f.json"}, {{f.file, f.content}}));
    add(renderOf("mpu_fitted_missing", smallWithField(R"({"type": "mpu", "fitted": "gone.json"})"), {"gone.json"}));

    const FileCase images[] = {
        {"empty", "e.exr", ""},
        {"text", "e.exr", "not an image"},
        {"truncated_png", "e.png", "\x89PNG\r\n\x1a\n"},
    };
    for (const FileCase& i : images) {
        add(renderOf(std::string("environment_") + i.name,
                     smallWith("/lights/0", std::string(R"({"type": "environment", "file": ")") + i.file + "\"}"), {i.file},
                     {{i.file, i.content}}));
        add(renderOf(std::string("texture_") + i.name,
                     smallWith("/materials/clay",
                               std::string(R"({"type": "diffuse", "albedo": {"type": "image", "file": ")") + i.file + "\"}}"),
                     {i.file}, {{i.file, i.content}}));
    }
    add(renderOf("environment_not_two_to_one", smallWith("/lights/0", R"({"type": "environment", "file": "tiles.png"})"),
                 {"tiles.png"}));
    add(renderOf("environment_missing", smallWith("/lights/0", R"({"type": "environment", "file": "gone.exr"})"), {"gone.exr"}));
    add(renderOf("texture_missing", smallWith("/materials/clay",
                 R"({"type": "diffuse", "albedo": {"type": "image", "file": "gone.png"}})"), {"gone.png"}));
    add(renderOf("texture_rgb_for_roughness", smallWith("/materials/clay",
                 R"({"type": "conductor", "roughness": {"type": "image", "file": "tiles.png"}})"), {"tiles.png"}));
    add(renderOf("texture_mapping_unknown", smallWith("/materials/clay",
                 R"({"type": "diffuse", "albedo": {"type": "image", "file": "tiles.png", "mapping": "spherical"}})"),
                 {"/materials/clay/albedo/mapping", "spherical"}));
    add(renderOf("texture_color_space_unknown", smallWith("/materials/clay",
                 R"({"type": "diffuse", "albedo": {"type": "image", "file": "tiles.png", "color_space": "acescg"}})"),
                 {"/materials/clay/albedo/color_space", "acescg"}));
    add(renderOf("inline_mesh_uvs_short", smallWith("/objects/0",
                 R"({"vertices": [0, 0, 0, 1, 0, 0, 0, 1, 0], "indices": [0, 1, 2], "uvs": [0, 0, 1, 0], "material": "clay"})"),
                 {"/objects/0/uvs", "6 numbers, found 4"}));
    return cases;
}

}  // namespace isotrace::testing
