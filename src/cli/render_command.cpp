// `rayverify render --scene FILE --variant NAME -o DIR`: the exact render, the
// variant's render and a difference image per ray kind, as PNG, with a
// legend.md that names every colour and counts the pixels of each.
#include <fmt/format.h>

#include <filesystem>
#include <memory>

#include "cli/commands.h"
#include "core/input_error.h"
#include "report/png_image.h"
#include "scene/scene.h"
#include "scene/scene_audit.h"
#include "scene/scene_render.h"

namespace rayverify::cli {
namespace {

struct render_options {
    std::string scene_file;
    std::string variant_name;
    std::vector<std::string> plugins;
    plugin_isolation isolation;
    std::string out_dir;
};

std::string hex(rgb c) { return fmt::format("#{:02x}{:02x}{:02x}", c.r, c.g, c.b); }

std::string legend_text(const scene& s, const audit_target& target, const scene_picture_counts& p,
                        const std::vector<std::string>& files) {
    std::string out = fmt::format("# {} rendered exactly and by {}\n\n", s.name, target.label());
    if (!s.comment.empty()) out += s.comment + "\n\n";
    out += fmt::format("Scene file: `{}`; {} × {} pixels, {}.\n\n", s.file.string(), s.camera.width, s.camera.height,
                       precision_name(s.prec));
    out += "| file | what it shows |\n|---|---|\n";
    for (const std::string& f : files) {
        std::string what;
        if (f == "exact.png")
            what = "each pixel's exact nearest hit (oracle), shaded by its normal, colour = (n + 1)/2, darker where "
                   "exact shadow rays are blocked; black: no hit";
        else if (f == "variant.png")
            what = "the same from " + target.label() + "'s answers (normal at o + t·d for its t and sphere)";
        else
            what = "per pixel, the verdict of its " + f.substr(11, f.size() - 15) + " ray(s) under " + target.label() +
                   " (colours below)";
        out += fmt::format("| `{}` | {} |\n", f, what);
    }
    out += fmt::format("\nColours of the difference images (agreeing hits shade from agree_hit_exact to agree_hit_max "
                       "by log2(1 + ulp) / log2(1 + {:g}) of the nearest root's ULP error):\n\n",
                       p.ramp_full_scale);
    out += "| colour | name | meaning |\n|---|---|---|\n";
    for (const palette_entry& e : scene_palette())
        out += fmt::format("| `{}` | {} | {} |\n", hex(e.colour), e.name, e.meaning);
    out += "\nPixels by verdict:\n\n| ray kind |";
    for (int v = 0; v < verdict_kind_count; ++v) out += fmt::format(" {} |", verdict_name(static_cast<verdict_kind>(v)));
    out += "\n|---|";
    for (int v = 0; v < verdict_kind_count; ++v) out += "---|";
    out += "\n";
    for (const ray_kind kind : every_ray_kind) {
        const std::size_t k = static_cast<std::size_t>(kind);
        if (!p.kind_drawn[k]) continue;
        out += fmt::format("| {} |", ray_kind_name(kind));
        for (int v = 0; v < verdict_kind_count; ++v) out += fmt::format(" {} |", p.pixels_by_verdict[k][static_cast<std::size_t>(v)]);
        out += "\n";
    }
    return out;
}

int run(const render_options& options) {
    const scene s = read_scene(options.scene_file);
    if (options.variant_name.empty() == options.plugins.empty())
        throw input_error("", 0, "--variant", "name exactly one variant: --variant NAME or one --plugin LIBRARY");
    std::vector<std::string> names;
    if (!options.variant_name.empty()) names.push_back(options.variant_name);
    const std::vector<audit_target> targets = scene_audit_targets(s, names, options.plugins, options.isolation);
    if (targets.size() != 1)
        throw input_error("", 0, "--variant", "name exactly one variant (built-in, or the one --plugin) to render");
    const audit_target& target = targets.front();
    if (auto why = not_applicable_reason(s, target))
        throw input_error(options.scene_file, 0, "--variant", target.label() + " is not applicable: " + *why);

    // The outputs, declared before the work: the directory (locked), the
    // images and the legend; they appear together, or none does. Each image
    // is encoded row by row as the rays are judged (rays and pixels are
    // streamed: memory does not grow with the resolution).
    const std::filesystem::path dir(options.out_dir);
    run_outputs outputs;
    declare_inputs(outputs, {options.scene_file}, "--scene");
    declare_inputs(outputs, {options.plugins.begin(), options.plugins.end()}, "--plugin");
    outputs.directory(dir, "-o");
    std::vector<std::string> files;
    std::vector<std::unique_ptr<png_writer>> images;
    for (scene_picture picture : scene_pictures_of(s)) {
        files.push_back(picture_file_name(picture));
        images.push_back(std::make_unique<png_writer>(outputs.file(dir / files.back(), "-o").stream(),
                                                      (dir / files.back()).string(), s.camera.width, s.camera.height));
    }
    output_file& legend = outputs.file(dir / "legend.md", "-o");
    scene_picture_builder builder(s, 0, [&](int, std::span<const std::vector<std::uint8_t>> rows) {
        for (std::size_t i = 0; i < images.size(); ++i) images[i]->write_row(rows[i]);
    });
    const scene_audit_result result = audit_scene(s, targets, [&](const judged_ray& r) { builder.add(r); });
    const scene_picture_counts pictures = builder.finish();
    for (const auto& image : images) image->finish();
    legend.stream() << legend_text(s, target, pictures, files);

    fmt::print("render: {} by {} → {}\n", s.name, target.label(), dir.string());
    for (const std::string& f : files) fmt::print("  {}\n", (dir / f).string());
    fmt::print("  {}\n", (dir / "legend.md").string());
    const std::size_t disagreements = result.targets.front().disagreements();
    std::size_t rays = 0;
    for (const exact_kind_figures& kind : result.exact) rays += kind.rays;
    fmt::print("{} of {} rays disagree with the exact answer\n", disagreements, rays);
    check_standard_output();
    outputs.commit();
    return disagreements > 0 ? exit_findings : exit_ok;
}

}  // namespace

command add_render_command(CLI::App& app) {
    auto options = std::make_shared<render_options>();
    auto* sub = app.add_subcommand("render", "Render a scene exactly and with one variant, as PNG images, with a "
                                             "difference image per ray kind colouring each disagreement. Exit 1 "
                                             "when the variant disagrees on some ray.");
    sub->add_option("--scene", options->scene_file, "Scene file (corpus/scenes/README.md)")->required();
    sub->add_option("--variant", options->variant_name, "The variant to render (its scene precision is the scene's)");
    sub->add_option("--plugin", options->plugins, "Shared library implementing rayverify_plugin.h, rendered instead");
    add_isolation_options(sub, options->isolation);
    sub->add_option("-o,--output", options->out_dir, "Directory for the PNG images and legend.md")->required();
    return {sub, [options] { return run(*options); }};
}

}  // namespace rayverify::cli
