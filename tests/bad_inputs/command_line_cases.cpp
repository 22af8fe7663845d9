// Bad command lines of every command: options out of range or of the
// wrong kind, missing and unreadable inputs, and outputs that would
// overwrite an input (by any name) or are not regular files.
#include "bad_inputs/bad_input_case.h"

namespace isotrace::testing {

std::vector<BadInputCase> commandLineCases() {
    std::vector<BadInputCase> cases;
    auto add = [&](BadInputCase c) { cases.push_back(std::move(c)); };
    // Tiles and images to break, made by isotrace itself.
    const std::vector<std::string> tiles = {"isotrace render small.json --tile 0/2 -o t0.exr --quiet --no-preview",
                                            "isotrace render small.json --tile 1/2 -o t1.exr --quiet --no-preview"};
    const std::vector<std::string> images = {"isotrace render small.json -o a.exr --quiet --no-preview",
                                             "isotrace render small.json -o b.exr --quiet --no-preview --seed 2"};

    add(makeCase("no_command", "", {}));
    add(makeCase("unknown_command", "draw small.json", {"draw"}));
    add(makeCase("unknown_global_option", "--colour small.json", {"--colour"}));

    // render
    const std::string render = "render small.json -o out.exr ";
    add(makeCase("render_no_scene", "render", {"scene"}));
    add(makeCase("render_missing_scene", "render gone.json -o out.exr", {"gone.json"}));
    add(makeCase("render_scene_is_folder", "render folder -o out.exr", {"folder"}, {"mkdir folder"}));
    add(makeCase("render_unknown_option", render + "--samples 4", {"--samples"}));
    add(makeCase("render_two_scenes", "render small.json scene.json -o out.exr", {"scene.json"}));
    for (const auto& [option, value] : std::vector<std::pair<std::string, std::string>>{
             {"spp", "0"}, {"spp", "-1"}, {"spp", "nan"}, {"spp", "2.5"}, {"spp", "99999999999"}, {"spp", "four"},
             {"threads", "0"}, {"threads", "-2"}, {"threads", "5000"}, {"seed", "-1"}, {"seed", "1.5"},
             {"seed", "99999999999999999999999"}, {"width", "0"}, {"width", "70000"}, {"height", "-5"},
             {"exposure", "nan"}, {"exposure", "inf"}, {"exposure", "-inf"}, {"exposure", "bright"}, {"as", "voxels"},
             {"tile", "2/2"}, {"tile", "0/0"}, {"tile", "a/b"}, {"tile", "1"}, {"tile", "-1/2"}, {"aov", "albedo,bogus"},
             {"aov", ""}, {"crop", "0 0 4"}, {"crop", "4 0 2 4"}, {"crop", "0 0 13 4"}, {"crop", "0 0 0 4"},
             {"crop", "-1 0 4 4"}}) {
        add(makeCase("render_" + option + "_" + value, render + "--" + option + " '" + value + "'", {"--" + option}));
    }
    add(makeCase("render_crop_and_tile", render + "--crop 0 0 4 4 --tile 0/2", {"--"}));
    add(makeCase("render_output_is_scene", "render small.json -o small.json", {"small.json"}));
    add(makeCase("render_output_is_scene_by_other_name", "render small.json -o ./sub/../small.json", {"small.json"},
                {"mkdir sub"}));
    add(makeCase("render_output_is_scene_through_link", "render small.json -o link.exr", {"link.exr"},
                {"ln -s small.json link.exr"}));
    add(makeCase("render_output_is_hard_link_of_scene", "render small.json -o hard.exr", {"hard.exr"},
                {"ln small.json hard.exr"}));
    add(makeCase("render_output_is_mesh_input", "render scene.json -o tet.off", {"tet.off"}));
    add(makeCase("render_output_is_environment_map", "render scene.json -o sky.exr", {"sky.exr"}));
    add(makeCase("render_preview_would_replace_texture", "render scene.json -o tiles.exr", {"tiles.png"}));
    add(makeCase("render_output_is_folder", "render small.json -o folder", {"folder"}, {"mkdir folder"}));
    add(makeCase("render_output_is_device", "render small.json -o /dev/null", {"/dev/null"}));
    add(makeCase("render_output_in_missing_folder", "render small.json -o gone/out.exr", {"gone"}));
    add(makeCase("render_output_unknown_format", "render small.json -o out.xyz", {"out.xyz"}));
    add(makeCase("render_output_without_extension", "render small.json -o out", {"out"}));
    add(makeCase("render_output_half_png", "render small.json -o out.png --half", {"--half"}));

    // polygonize
    add(makeCase("polygonize_no_field", "polygonize small.json -o out.ply", {"--field"}));
    add(makeCase("polygonize_unknown_field", "polygonize small.json --field cube -o out.ply", {"cube"}));
    add(makeCase("polygonize_unknown_format", "polygonize small.json --field ball -o out.stl", {"out.stl"}));
    add(makeCase("polygonize_resolution_zero", "polygonize small.json --field ball -o out.ply --resolution 0", {"--resolution"}));
    add(makeCase("polygonize_tolerance_nan", "polygonize small.json --field ball -o out.ply --tolerance nan", {"--tolerance"}));
    add(makeCase("polygonize_tolerance_negative", "polygonize small.json --field ball -o out.ply --tolerance -1",
                {"--tolerance"}));
    add(makeCase("polygonize_unknown_method", "polygonize small.json --field ball -o out.ply --method dual", {"--method"}));
    add(makeCase("polygonize_output_is_scene", "polygonize small.json --field ball -o small.json", {"small.json"}));
    add(makeCase("polygonize_output_is_mesh_input", "polygonize scene.json --field ball -o tet.off", {"tet.off"}));
    add(makeCase("polygonize_output_is_folder", "polygonize small.json --field ball -o folder.ply", {"folder.ply"},
                {"mkdir folder.ply"}));
    add(makeCase("polygonize_unbounded_field", "polygonize bad.json --field flat -o out.ply", {"flat"},
                {"printf '{\"materials\": {\"c\": {\"type\": \"diffuse\"}}, \"fields\": {\"flat\": {\"type\": \"plane\"}, "
                 "\"b\": {\"type\": \"sphere\", \"radius\": 1}}, \"objects\": [{\"field\": \"b\", \"material\": \"c\"}]}' "
                 "> bad.json"}));
    add(makeCase("polygonize_missing_scene", "polygonize gone.json --field ball -o out.ply", {"gone.json"}));

    // merge
    add(makeCase("merge_nothing", "merge -o out.exr", {}));
    add(makeCase("merge_one_tile_missing", "merge t0.exr -o out.exr", {"missing"}, tiles));
    add(makeCase("merge_missing_file", "merge t0.exr gone.exr -o out.exr", {"gone.exr"}, tiles));
    add(makeCase("merge_same_tile_twice", "merge t0.exr t0.exr -o out.exr", {"t0.exr"}, tiles));
    add(makeCase("merge_not_a_tile", "merge t0.exr sky.exr -o out.exr", {"sky.exr"}, tiles));
    add(makeCase("merge_tiles_of_other_seed", "merge t0.exr t1.exr -o out.exr", {"t1.exr"},
                {tiles[0], "isotrace render small.json --tile 1/2 -o t1.exr --quiet --no-preview --seed 9"}));
    add(makeCase("merge_corrupt_tile", "merge t0.exr t1.exr -o out.exr", {"t1.exr"},
                {tiles[0], "printf 'v/1\\001' > t1.exr"}));
    add(makeCase("merge_output_is_tile", "merge t0.exr t1.exr -o t0.exr", {"t0.exr"}, tiles));
    add(makeCase("merge_output_is_tile_through_link", "merge t0.exr t1.exr -o whole.exr", {"whole.exr"},
                {tiles[0], tiles[1], "ln -s t1.exr whole.exr"}));
    add(makeCase("merge_output_is_folder", "merge t0.exr t1.exr -o folder", {"folder"}, {tiles[0], tiles[1], "mkdir folder"}));
    add(makeCase("merge_half_and_unknown", "merge t0.exr t1.exr -o out.exr --quarter", {"--quarter"}, tiles));

    // compare
    add(makeCase("compare_one_image", "compare a.exr", {}, images));
    add(makeCase("compare_missing_test", "compare gone.exr b.exr", {"gone.exr"}, images));
    add(makeCase("compare_missing_reference", "compare a.exr gone.exr", {"gone.exr"}, images));
    add(makeCase("compare_text_as_image", "compare a.exr small.json", {"small.json"}, images));
    add(makeCase("compare_other_size", "compare a.exr sky.exr", {"sky.exr"}, images));
    add(makeCase("compare_unknown_metric", "compare a.exr b.exr --metric ssim", {"--metric"}, images));
    add(makeCase("compare_fail_nan", "compare a.exr b.exr --fail nan", {"--fail"}, images));
    add(makeCase("compare_fail_percent_150", "compare a.exr b.exr --fail-percent 150", {"--fail-percent"}, images));
    add(makeCase("compare_ppd_zero", "compare a.exr b.exr --metric flip --ppd 0", {"--ppd"}, images));
    add(makeCase("compare_pixel_threshold_zero", "compare a.exr b.exr --pixel-threshold 0", {"--pixel-threshold"}, images));
    add(makeCase("compare_noise_missing", "compare a.exr b.exr --metric noise --noise gone.exr", {"gone.exr"}, images));
    add(makeCase("compare_diff_is_test", "compare a.exr b.exr --diff a.exr", {"a.exr"}, images));
    add(makeCase("compare_diff_is_reference", "compare a.exr b.exr --diff ./b.exr", {"b.exr"}, images));
    add(makeCase("compare_diff_is_noise", "compare a.exr b.exr --metric noise --noise n.exr --diff n.exr", {"n.exr"},
                {images[0], images[1], "isotrace render small.json -o n.exr --quiet --no-preview --seed 3"}));
    add(makeCase("compare_diff_is_folder", "compare a.exr b.exr --diff folder", {"folder"}, {images[0], images[1], "mkdir folder"}));
    add(makeCase("compare_diff_unknown_format", "compare a.exr b.exr --diff d.json", {"d.json"}, images));

    // fit
    add(makeCase("fit_no_input", "fit -o out.json", {}));
    add(makeCase("fit_no_output", "fit tet.off", {"--output"}));
    add(makeCase("fit_missing_input", "fit gone.off -o out.json", {"gone.off"}));
    add(makeCase("fit_unknown_extension", "fit small.json -o out.json", {"small.json"}));
    add(makeCase("fit_output_is_input", "fit ball.off -o ball.off", {"ball.off"}));
    add(makeCase("fit_output_is_input_through_link", "fit ball.off -o fit.json", {"fit.json"}, {"ln -s ball.off fit.json"}));
    add(makeCase("fit_output_is_folder", "fit ball.off -o folder", {"folder"}, {"mkdir folder"}));
    add(makeCase("fit_normal_offset_nan", "fit ball.off -o out.json --normal-offset nan", {"--normal-offset"}));
    add(makeCase("fit_normal_offset_zero", "fit ball.off -o out.json --normal-offset 0", {"--normal-offset"}));
    add(makeCase("fit_margin_nan", "fit ball.off -o out.json --margin nan", {"--margin"}));
    add(makeCase("fit_margin_negative", "fit ball.off -o out.json --margin -1", {"--margin"}));
    add(makeCase("fit_unknown_option", "fit ball.off -o out.json --method rbf", {"--method"}));
    add(makeCase("fit_report_resolution_four", "fit ball.off -o out.json --report --report-resolution 4", {"--report-resolution"}));
    add(makeCase("fit_report_resolution_without_report", "fit ball.off -o out.json --report-resolution 64",
                 {"--report-resolution", "--report"}));
    add(makeCase("fit_mpu_support_nine", "fit ring.xyz -o out.json --method mpu --support 9", {"--support"}));
    add(makeCase("fit_mpu_accuracy_zero", "fit ring.xyz -o out.json --method mpu --accuracy 0", {"--accuracy"}));
    add(makeCase("fit_mpu_depth_zero", "fit ring.xyz -o out.json --method mpu --max-depth 0", {"--max-depth"}));
    add(makeCase("fit_mpu_min_points_five", "fit ring.xyz -o out.json --method mpu --min-points 5", {"--min-points"}));
    add(makeCase("fit_variational_smooth_only", "fit ring.xyz -o out.json --smooth-only", {"--method"}));
    add(makeCase("fit_mpu_with_hermite", "fit ring.xyz -o out.json --method mpu --hermite", {"--method"}));
    add(makeCase("fit_variational_with_accuracy", "fit ring.xyz -o out.json --accuracy 0.01", {"--method"}));
    add(makeCase("fit_mpu_too_few_points", "fit few.xyz -o out.json --method mpu", {"few.xyz", "at least 15 points"}, {},
                 {{"few.xyz", "0 0 0 0 0 1\n1 0 1 0 0 1\n0 1 2 0 0 1\n1 1 0 0 0 1\n2 0 1 0 0 1\n0 2 2 0 0 1\n2 2 0 0 0 1\n"}}));
    add(makeCase("fit_mpu_zero_normal", "fit flat.xyz -o out.json --method mpu", {"flat.xyz", "line 2"}, {},
                 {{"flat.xyz", "0 0 0 0 0 1\n1 0 0 0 0 0\n"}}));
    add(makeCase("fit_mpu_nan_point", "fit nan.xyz -o out.json --method mpu", {"nan.xyz", "line 3"}, {},
                 {{"nan.xyz", "0 0 0 0 0 1\n1 0 0 0 0 1\n1 nan 0 0 0 1\n"}}));
    add(makeCase("fit_mpu_points_in_a_plane", "fit plane.xyz -o out.json --method mpu", {"plane.xyz", "one plane"}, {},
                 {{"plane.xyz", "0 0 0 0 0 1\n1 0 0 0 0 1\n2 0 0 0 0 1\n3 0 0 0 0 1\n4 0 0 0 0 1\n0 1 0 0 0 1\n1 1 0 0 0 1\n2 1 0 0 0 1\n3 1 0 0 0 1\n4 1 0 0 0 1\n0 2 0 0 0 1\n1 2 0 0 0 1\n2 2 0 0 0 1\n3 2 0 0 0 1\n4 2 0 0 0 1\n0 3 0 0 0 1\n1 3 0 0 0 1\n2 3 0 0 0 1\n3 3 0 0 0 1\n4 3 0 0 0 1\n"}}));
    add(makeCase("fit_unknown_solver", "fit flat.xyz --solver fastest -o out.json", {"--solver", "fastest"}, {},
                 {{"flat.xyz", "0 0 0 0 0 1\n1 0 1 0 0 1\n"}}));
    // Past 20,000 unknowns the automatic solver partitions; forcing the dense one is refused.
    add(makeCase("fit_too_many_unknowns", "fit big.xyz --solver dense -o out.json", {"big.xyz", "above the limit of 20000"},
                {"awk 'BEGIN { for (i = 0; i < 12000; i++) { z = -1 + 2 * (i + 0.5) / 12000; r = sqrt(1 - z * z); "
                 "a = i * 2.39996; printf \"%.6f %.6f %.6f %.6f %.6f %.6f\\n\", r * cos(a), r * sin(a), z, "
                 "r * cos(a), r * sin(a), z } }' > big.xyz"}));

    // preview
    add(makeCase("preview_no_field", "preview small.json", {"--field"}));
    add(makeCase("preview_unknown_field", "preview small.json --field cube", {"cube"}));
    add(makeCase("preview_not_csg", "preview small.json --field ball", {"ball"}));
    add(makeCase("preview_panel_too_small", "preview small.json --field duo --panel-width 8", {"--panel-width"}));
    add(makeCase("preview_spp_zero", "preview small.json --field duo --spp 0", {"--spp"}));
    add(makeCase("preview_section_axis_w", "preview small.json --field duo --section w", {"--section"}));
    add(makeCase("preview_section_offset_nan", "preview small.json --field duo --section x=nan", {"--section"}));
    add(makeCase("preview_section_offset_text", "preview small.json --field duo --section y=up", {"--section"}));
    add(makeCase("preview_output_is_scene", "preview small.json --field duo -o small.json", {"small.json"}));
    add(makeCase("preview_output_is_texture", "preview scene.json --field cut -o tiles.png", {"tiles.png"}));
    add(makeCase("preview_output_is_folder", "preview small.json --field duo -o folder.png", {"folder.png"},
                {"mkdir folder.png"}));
    add(makeCase("preview_output_unknown_format", "preview small.json --field duo -o sheet.json", {"sheet.json"}));

    // sample
    add(makeCase("sample_no_field", "sample small.json -o out.ply", {"--field"}));
    add(makeCase("sample_unknown_field", "sample small.json --field cube -o out.ply --count 50", {"cube"}));
    add(makeCase("sample_count_zero", "sample small.json --field ball -o out.ply --count 0", {"--count"}));
    add(makeCase("sample_count_too_many", "sample small.json --field ball -o out.ply --count 20000000", {"--count"}));
    add(makeCase("sample_spacing_zero", "sample small.json --field ball -o out.ply --spacing 0", {"--spacing"}));
    add(makeCase("sample_count_and_spacing", "sample small.json --field ball -o out.ply --count 10 --spacing 0.1", {"--"}));
    add(makeCase("sample_seed_negative", "sample small.json --field ball -o out.ply --seed -1", {"--seed"}));
    add(makeCase("sample_unknown_format", "sample small.json --field ball -o out.obj --count 50", {"out.obj"}));
    add(makeCase("sample_output_is_points_input", "sample scene.json --field ball -o ring.xyz --count 50", {"ring.xyz"}));
    add(makeCase("sample_output_is_scene", "sample small.json --field ball -o small.json --count 50", {"small.json"}));
    add(makeCase("sample_output_is_folder", "sample small.json --field ball -o folder.ply --count 50", {"folder.ply"},
                {"mkdir folder.ply"}));
    return cases;
}

}  // namespace isotrace::testing
