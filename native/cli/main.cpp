// The `purl` command: render a scene, inspect a BCC file, generate a swatch, export the
// explicit reference curves of a scene.
#include <CLI/CLI.hpp>

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <thread>
#include <unistd.h>

#include "base/input_error.h"
#include "base/registry.h"
#include "fit/fit_command.h"
#include "io/image_io.h"
#include "reference/explicit_export.h"
#include "reference/explicit_models.h"
#include "render/denoise.h"
#include "render/renderer.h"
#include "scene/bcc.h"
#include "scene/scene_files.h"
#include "scene/scene_json.h"
#include "scene/swatch.h"

namespace fs = std::filesystem;
using namespace purl;

namespace {

std::atomic<RenderControl*> g_control{nullptr};
volatile std::sig_atomic_t g_stop_signal = 0;

// Ctrl-C and SIGTERM: while rendering, stop and write nothing; while writing, remove the
// partial file and end as the signal would.
void on_stop_signal(int sig) {
    if (RenderControl* control = g_control.load()) {
        g_stop_signal = sig;
        control->cancel = true;
        return;
    }
    discard_partial_output();
    std::signal(sig, SIG_DFL);
    std::raise(sig);
}

std::string lowercase_extension(const std::string& path) {
    std::string ext = fs::path(path).extension().string();
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return ext;
}

// The two outputs of a render, checked before the scene is read: every failure here would
// otherwise lose a finished render.
void check_render_outputs(const std::string& output, const std::string& png) {
    check_output_path(output, "-o");
    if (png.empty()) return;
    check_output_path(png, "--png", true);
    std::error_code ec;
    const fs::path a = fs::weakly_canonical(output, ec), b = fs::weakly_canonical(png, ec);
    if (a == b) throw InputError(png, "--png", "is the -o output itself; give the PNG a name of its own");
}

// Draws a progress bar on stderr until `finished` is set.
void show_progress(const RenderControl& control, const std::atomic<bool>& finished) {
    const bool tty = isatty(STDERR_FILENO);
    const auto start = std::chrono::steady_clock::now();
    int last_decile = -1;
    while (!finished) {
        const double p = control.progress();
        const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        if (tty) {
            const int filled = static_cast<int>(p * 30);
            const double eta = p > 0.01 ? elapsed * (1 - p) / p : 0;
            std::fprintf(stderr, "\r[%s%s] %5.1f%%  %.1fs elapsed, ~%.0fs left ",
                         std::string(filled, '#').c_str(), std::string(30 - filled, ' ').c_str(), 100 * p,
                         elapsed, eta);
        } else if (static_cast<int>(p * 10) > last_decile) {
            last_decile = static_cast<int>(p * 10);
            std::fprintf(stderr, "rendering: %3d%% (%.1fs)\n", last_decile * 10, elapsed);
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(tty ? 200 : 500));
    }
    if (tty) std::fprintf(stderr, "\r%*s\r", 70, "");
}

void print_stats(const RenderStats& s) {
    std::fprintf(stderr,
                 "build %.3f s, render %.3f s, %d threads\n"
                 "samples %llu (%.0f/s), rays %llu, mean path length %.2f, invalid samples %llu\n"
                 "curves %zu, control points %zu, acceleration structure %.2f MB, frames and maps %.3f MB, "
                 "peak resident memory %.1f MB\n",
                 s.build_seconds, s.render_seconds, s.threads, (unsigned long long)s.samples,
                 s.samples_per_second(), (unsigned long long)s.rays, s.mean_path_length,
                 (unsigned long long)s.invalid_samples, s.curves, s.control_points, s.acceleration_bytes / 1048576.0,
                 s.shading_bytes / 1048576.0, s.peak_resident_bytes / 1048576.0);
    if (s.hits_near + s.hits_multi + s.hits_far > 0)
        std::fprintf(stderr, "multiscale: camera hits near %llu, multi %llu, far %llu; mean h samples per hit %.2f\n",
                     (unsigned long long)s.hits_near, (unsigned long long)s.hits_multi,
                     (unsigned long long)s.hits_far, s.mean_h_samples());
    if (s.bysdf_evaluations > 0)
        std::fprintf(stderr, "BYSDF evaluations %llu (%.2f per sample)\n", (unsigned long long)s.bysdf_evaluations,
                     s.samples ? double(s.bysdf_evaluations) / double(s.samples) : 0.0);
}

int run_render(const std::string& scene_path, const std::string& output, const std::string& png,
               int spp, int threads, long long seed, const std::string& model, bool stats,
               const std::string& integrator, const std::string& multiscale_mode, const std::string& ply_method,
               bool denoise) {
    check_render_outputs(output, png);
    const std::string ext = lowercase_extension(output);
    std::signal(SIGINT, on_stop_signal);
    std::signal(SIGTERM, on_stop_signal);
    SceneDesc scene = load_scene_file(scene_path);
    if (spp > 0) scene.render.spp = spp;
    if (threads > 0) scene.render.threads = threads;
    if (seed >= 0) scene.render.seed = static_cast<uint64_t>(seed);
    if (!model.empty()) scene.render.model = parse_yarn_model(model, "--model");
    if (!multiscale_mode.empty()) scene.render.multiscale.mode = *parse_multiscale_mode(multiscale_mode);
    if (!integrator.empty())
        scene.render.trace_only = parse_choice(integrators(), integrator, "--integrator", "") ==
                                  find_choice(integrators(), "trace")->value;
    if (!ply_method.empty()) scene.render.ply_method = parse_ply_method(ply_method, "--ply-method");
    if (denoise) scene.render.denoise = true;
    if (scene.render.denoise) Denoiser::load();  // a missing OIDN is reported before the scene is built

    Renderer renderer(std::move(scene), make_explicit_scene);
    RenderControl control;
    g_control = &control;
    std::atomic<bool> finished{false};
    std::thread progress(show_progress, std::cref(control), std::cref(finished));
    RenderResult result;
    try {
        result = renderer.render(control);
    } catch (...) {
        g_control = nullptr;
        finished = true;
        progress.join();
        throw;
    }
    g_control = nullptr;
    finished = true;
    progress.join();
    if (result.cancelled) {
        std::fprintf(stderr, "purl: render cancelled; nothing written\n");
        return 128 + (g_stop_signal ? int(g_stop_signal) : SIGINT);
    }
    if (ext == ".exr") write_multilayer_exr(output, result.image, "ViewLayer");
    else write_png(output, result.image);
    if (!png.empty()) write_png(png, result.image);
    for (const std::string& w : result.stats.warnings) std::fprintf(stderr, "purl: warning: %s\n", w.c_str());
    if (stats) print_stats(result.stats);
    if (result.stats.denoise_seconds > 0)
        std::fprintf(stderr, "purl: denoised with Open Image Denoise in %.2f s\n", result.stats.denoise_seconds);
    std::fprintf(stderr, "purl: wrote %s%s%s (%d x %d, %d spp) in %.2f s\n", output.c_str(),
                 png.empty() ? "" : " and ", png.c_str(), result.image.width, result.image.height,
                 renderer.scene().render.spp, result.stats.render_seconds);
    return 0;
}

int run_info(const std::string& path) {
    const BccHeader header = read_bcc_header(path);
    const YarnCurves curves = load_bcc(path, 1.0f);
    Vec3 lo(1e30f), hi(-1e30f);
    for (const Vec4& p : curves.control_points) {
        lo = min(lo, p.xyz());
        hi = max(hi, p.xyz());
    }
    size_t closed = 0;
    for (uint8_t c : curves.closed) closed += c;
    std::printf("file         %s\n", path.c_str());
    std::printf("curve type   %s\n", header.type.c_str());
    std::printf("up axis      %s (converted to Z-up)\n", header.up_axis == 1 ? "Y" : "Z");
    std::printf("curves       %llu (%zu closed, %zu open)\n", (unsigned long long)header.curve_count, closed,
                curves.curve_count() - closed);
    std::printf("points       %llu in the file, %zu B-spline control points\n",
                (unsigned long long)header.point_count, curves.point_count());
    std::printf("bounds (Z-up) min %.4g %.4g %.4g  max %.4g %.4g %.4g  size %.4g x %.4g x %.4g\n", lo.x, lo.y,
                lo.z, hi.x, hi.y, hi.z, hi.x - lo.x, hi.y - lo.y, hi.z - lo.z);
    std::string info;  // the header's free text; keep only printable characters
    for (char c : header.info)
        if (c >= 32 && c < 127) info += c;
    if (info.find_first_not_of(" ") != std::string::npos) std::printf("info         %s\n", info.c_str());
    return 0;
}

// The explicit curves as BCC plus float32 radii, for renderers that should trace the same plies
// or fibers (reference/explicit_export.h).
int run_export_explicit(const std::string& scene_path, const std::string& model, const std::string& output,
                        std::string radii) {
    if (radii.empty()) radii = fs::path(output).replace_extension(".radii").string();
    const SceneDesc scene = load_scene_file(scene_path);
    const SceneDesc explicit_scene = make_explicit_scene(scene, parse_yarn_model(model, "--model"));
    const ExplicitExport e = write_explicit_curves(explicit_scene, output, radii);
    std::fprintf(stderr, "purl: wrote %s (%zu %s curves, %zu control points, uniform cubic B-spline, Z-up) and %s\n",
                 output.c_str(), e.curves, model.c_str(), e.points, radii.c_str());
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"Purl: yarn-level cloth rendering with the BYSDF"};
    app.require_subcommand(1);

    std::string scene_path, output, png;
    int spp = 0, threads = 0;
    long long seed = -1;
    bool stats = false;
    std::string model;
    CLI::App* render = app.add_subcommand("render", "Render a JSON scene to EXR/PNG");
    render->add_option("scene", scene_path, "scene file (JSON)")->required();
    render->add_option("-o,--output", output, "output image (.exr: multilayer passes, .png: sRGB)")->required();
    render->add_option("--png", png, "also write an sRGB PNG here");
    // Ranges, names and help of the render settings come from base/registry.h.
    const auto range = [](const char* name) {
        const ParamInfo& s = render_setting(name);
        if (s.is_integer()) return CLI::Range((long long)s.min_value, (long long)s.max_value);
        return CLI::Range(s.min_value, s.max_value);
    };
    const auto help = [](const char* name, const char* what) {  // "Doc (what)."
        std::string doc = render_setting(name).doc;
        if (!doc.empty() && doc.back() == '.') doc.pop_back();
        return doc + " " + what + ".";
    };
    const auto one_of = [](const ChoiceList& list, const char* what) {
        std::string text = what;
        for (const Choice& c : list.choices) text += std::string("\n  ") + c.name + ": " + c.doc;
        return text;
    };
    render->add_option("--spp", spp, help("spp", "(overrides the scene)"))->check(range("spp"));
    render->add_option("--threads", threads, render_setting("threads").doc)->check(range("threads"));
    render->add_option("--seed", seed, help("seed", "(overrides the scene)"))->check(range("seed"));
    render->add_option("--model", model, one_of(yarn_models(), "yarn model (overrides the scene):"))
        ->check(CLI::IsMember(choice_names(yarn_models())));
    render->add_flag("--stats", stats, "print timing, ray and memory figures");
    std::string integrator;
    render->add_option("--integrator", integrator, one_of(integrators(), "integrator (overrides the scene):"))
        ->check(CLI::IsMember(choice_names(integrators())));

    std::string multiscale_mode;
    render->add_option("--mode", multiscale_mode,
                       one_of(multiscale_modes(), "multi-scale shading of camera hits on BYSDF yarns (overrides the "
                                                  "scene; docs/multiscale.md):"))
        ->check(CLI::IsMember(choice_names(multiscale_modes())));
    std::string ply_method;
    render->add_option("--ply-method", ply_method,
                       one_of(ply_methods(), "how BYSDF yarns find the ply under a hit (overrides the scene):"))
        ->check(CLI::IsMember(choice_names(ply_methods())));

    bool denoise = false;
    render->add_flag("--denoise", denoise,
                     "denoise with Intel Open Image Denoise (pip install pyoidn), guided by the Denoising Albedo and "
                     "Normal passes; the EXR keeps the input as \"Noisy Image\"");
    std::string info_path;
    CLI::App* info = app.add_subcommand("info", "Describe a BCC curve file");
    info->add_option("file", info_path, "BCC file")->required();

    std::string kind, generate_output;
    SwatchOptions swatch;
    CLI::App* generate = app.add_subcommand("generate", "Write a yarn-level swatch as a BCC file");
    generate->add_option("kind", kind, "knit, plain, twill or satin")->required();
    generate->add_option("-o,--output", generate_output, "output BCC file")->required();
    generate->add_option("--radius", swatch.yarn_radius, "yarn radius in metres");

    std::string export_scene, export_model = "ply", export_output, export_radii;
    CLI::App* export_explicit = app.add_subcommand(
        "export-explicit", "Write a scene's explicit ply or fiber curves as a BS-type BCC file plus radii");
    export_explicit->add_option("scene", export_scene, "scene file (JSON)")->required();
    std::vector<std::string> explicit_models;  // the yarn models but the BYSDF
    for (const Choice& c : yarn_models().choices)
        if (c.value != float(YarnModel::Bysdf)) explicit_models.push_back(c.name);
    export_explicit->add_option("--model", export_model, explicit_models[0] + " or " + explicit_models[1])
        ->check(CLI::IsMember(explicit_models));
    export_explicit->add_option("-o,--output", export_output, "output BCC file")->required();
    export_explicit->add_option("--radii", export_radii,
                                "radius side file: float32 per BCC point, scene units (default: output.radii)");

    std::string deps_scene;
    bool deps_json = false;
    CLI::App* deps = app.add_subcommand("deps", "List the files a scene reads besides itself (for render farms)");
    deps->add_option("scene", deps_scene, "scene file (JSON)")->required();
    deps->add_flag("--json", deps_json, "print JSON for tools instead of a table");

    FitCommand fit_command;
    CLI::App* fit = app.add_subcommand("fit", "Fit BYSDF parameters to target images; write a preset (docs/fitting.md)");
    fit->add_option("scene", fit_command.scenes, "scene(s): one for all targets or one per target")->required();
    // One value per --target/--mask, so `purl fit --target t.exr scene.json` leaves the scene positional.
    fit->add_option("--target", fit_command.targets, "target image (EXR/PNG) at the scene's film size; repeatable")
        ->required()
        ->allow_extra_args(false);
    fit->add_option("--mask", fit_command.masks, "per-target mask image (0 ignores a pixel); repeatable")
        ->allow_extra_args(false);
    fit->add_option("--params", fit_command.params, "parameters to fit (default kxB,kyB,sigma_t)");
    fit->add_option("-o,--output", fit_command.output, "preset JSON to write")->required();
    fit->add_option("--name", fit_command.name, "preset name (default: output file name)");
    fit->add_option("--iterations", fit_command.iterations, "most Levenberg-Marquardt iterations")
        ->check(CLI::Range(1, 1000));
    fit->add_option("--spp", fit_command.spp, "samples per pixel of every render (default: the scene's)")
        ->check(CLI::Range(1, 1 << 16));
    fit->add_option("--seed", fit_command.seed, "seed of every render (default: the scene's)")
        ->check(CLI::Range(0LL, 2147483647LL));
    fit->add_option("--threads", fit_command.threads, "worker threads (0: all cores)")->check(CLI::Range(0, 4096));
    fit->add_option("--tolerance", fit_command.tolerance, "stop when a step gains less than this fraction")
        ->check(CLI::Range(0.0, 1.0));
    fit->add_option("--block", fit_command.block, "compare b x b block means (less noise bias; default 1)")
        ->check(CLI::Range(1, 64));
    fit->add_option("--error", fit_command.error,
                    "what is compared: linear (RGB, the default), relative (RGB over each target's root mean "
                    "square) or srgb (sRGB-encoded, clamped to [0, 1], as LDR FLIP and a display see it)");

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        // --help and --version end well; any other parse error is bad input: exit 2, as
        // every input error is (CLI11's own codes 105, 106, 109 ... are not documented).
        const int code = app.exit(e);
        return code == 0 ? 0 : 2;
    }
    try {
        if (*render) return run_render(scene_path, output, png, spp, threads, seed, model, stats, integrator,
                                       multiscale_mode, ply_method, denoise);
        if (*info) return run_info(info_path);
        if (*deps) return run_deps_command(deps_scene, deps_json, stdout);
        if (*fit) return run_fit_command(fit_command);
        if (*export_explicit) return run_export_explicit(export_scene, export_model, export_output, export_radii);
        if (*generate) {
            const YarnCurves curves = generate_swatch(parse_swatch_kind(kind), swatch);
            write_bcc(generate_output, curves);
            std::fprintf(stderr, "purl: wrote %s (%zu curves, %zu control points)\n", generate_output.c_str(),
                         curves.curve_count(), curves.point_count());
            return 0;
        }
    } catch (const InputError& e) {
        std::fprintf(stderr, "purl: error: %s\n", e.what());
        return 2;
    } catch (const DenoiserUnavailable& e) {
        std::fprintf(stderr, "purl: error: %s\n", e.what());
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "purl: error: %s\n", e.what());
        return 1;
    }
    return 0;
}
