// purlcore: the Python face of the native core. Scenes come in as the JSON scene format
// (a str or dict) plus numpy arrays; renders run on native threads without the GIL.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <optional>

#include "base/input_error.h"
#include "base/registry.h"
#include "bsdf/artist_params.h"
#include "bsdf/bysdf_params.h"
#include "bsdf/fiber_bcsdf_params.h"
#include "bsdf/placeholder.h"
#include "yarn/yarn_description.h"
#include "yarn/fiber_maps.h"
#include "fit/fit_target.h"
#include "fit/fitter.h"
#include "fit/preset_file.h"
#include "io/image_io.h"
#include "render_job.h"
#include "scene_arrays.h"
#include "reference/explicit_export.h"
#include "reference/explicit_models.h"
#include "render/denoise.h"
#include "render/renderer.h"
#include "scene/bcc.h"

#include "scene/scene_json.h"

namespace py = pybind11;
using namespace purl;
using namespace purl::python;

namespace {

std::string scene_text(const py::object& scene) {
    if (py::isinstance<py::str>(scene)) return scene.cast<std::string>();
    if (py::isinstance<py::dict>(scene)) return py::module_::import("json").attr("dumps")(scene).cast<std::string>();
    throw py::type_error("scene must be a JSON string or a dict");
}

SceneDesc build_scene(const py::object& scene, const py::object& arrays, const std::string& base_dir,
                      const std::optional<std::string>& model, const std::optional<std::string>& mode = std::nullopt) {
    py::dict array_dict = arrays.is_none() ? py::dict() : arrays.cast<py::dict>();
    ExternalArrays external;
    external.yarns = [&](const std::string& name) {
        py::gil_scoped_acquire gil;
        return yarns_from_python(array_dict, name);
    };
    external.meshes = [&](const std::string& name) {
        py::gil_scoped_acquire gil;
        return mesh_from_python(array_dict, name);
    };
    const std::string text = scene_text(scene);
    SceneDesc desc = parse_scene_text(text, "<scene>", base_dir, &external);
    if (model) desc.render.model = parse_yarn_model(*model, "model");
    if (mode) {  // multi-scale mode of camera hits on BYSDF yarns
        const std::optional<MultiscaleMode> m = parse_multiscale_mode(*mode);
        if (!m) throw py::value_error("mode must be " + choice_names_text(multiscale_modes()) + ", not '" + *mode + "'");
        desc.render.multiscale.mode = *m;
    }
    return desc;
}

// [{name, label, doc, value}] of one list of base/registry.h.
py::list describe_choices(const ChoiceList& list) {
    py::list out;
    for (const Choice& c : list.choices) {
        py::dict d;
        d["name"] = c.name;
        d["label"] = c.label;
        d["doc"] = c.doc;
        d["value"] = c.value;
        out.append(d);
    }
    return out;
}

py::list describe_parameters(const std::vector<ParamInfo>& table) {
    py::list out;
    for (const ParamInfo& p : table) {
        py::dict d;
        d["name"] = p.name;
        d["unit"] = p.unit;
        d["components"] = p.components;
        d["min"] = p.min_value;
        d["max"] = p.max_value;
        if (p.components == 1) d["default"] = p.default_value[0];
        else d["default"] = py::make_tuple(p.default_value[0], p.default_value[1], p.default_value[2]);
        d["doc"] = p.doc;
        d["is_color"] = p.is_color;
        d["is_integer"] = p.is_integer();
        d["is_sign"] = p.is_sign();
        d["kind"] = p.kind == ParamKind::Integer ? "integer" : p.kind == ParamKind::Enum ? "enum" : "float";
        if (p.choices) {
            d["choices"] = describe_choices(*p.choices);
            d["default_name"] = choice_name(*p.choices, p.default_value[0]);
        }
        d["label"] = p.label ? py::object(py::str(p.label)) : py::object(py::none());
        out.append(d);
    }
    return out;
}

// Fills the declared fields of `params` that `values` names (numbers or sequences of numbers);
// other keys are left to the caller. Range checks are the scene reader's job.
template <class Params>
void fill_params(const py::dict& values, const std::vector<ParamInfo>& table, Params& params) {
    for (const ParamInfo& info : table) {
        if (!values.contains(info.name)) continue;
        float* field = param_field(params, info);
        const py::object v = values[info.name];
        if (info.components == 1) {
            *field = v.cast<float>();
        } else {
            const auto list = v.cast<std::vector<float>>();
            if (int(list.size()) != info.components)
                throw py::value_error(std::string(info.name) + " needs " + std::to_string(info.components) + " numbers");
            std::copy(list.begin(), list.end(), field);
        }
    }
}

py::dict params_to_dict(const BysdfParams& p) {
    py::dict out;
    for (const ParamInfo& info : bysdf_param_table()) {
        const float* v = param_field(p, info);
        if (info.components == 1) out[info.name] = v[0];
        else out[info.name] = py::make_tuple(v[0], v[1], v[2]);
    }
    return out;
}

// A bysdf material object (physics parameters and artist controls, as in a scene) -> the BYSDF
// parameters the renderer uses, with the controls applied (bsdf/artist_params.h).
py::dict resolve_material(const py::dict& material) {
    if (material.contains("preset") || material.contains("preset_file"))
        throw py::value_error("resolve_material reads a material's own keys, not presets: put the preset's "
                              "\"material\" object under the overrides first");
    BysdfParams physics = default_bysdf_params();
    fill_params(material, bysdf_param_table(), physics);
    ArtistControls artist;
    artist.has_color = material.contains("color");
    fill_params(material, artist_param_table(), artist);
    return params_to_dict(apply_artist_controls(physics, artist));
}

const std::vector<ParamInfo>& parameter_table(const std::string& model) {
    if (model == "placeholder") return placeholder_param_table();
    if (model == "bysdf") return bysdf_param_table();
    if (model == "fiber") return fiber_bcsdf_param_table();
    throw py::value_error("unknown material model '" + model + "'");
}

// purlcore.fit: each target is {"scene": str|dict, "image": path or float array (H, W, >=3),
// "mask": optional path or array (H, W)}; returns the preset dict `purl fit` would write.
py::dict fit_from_python(const py::list& target_list, const py::object& arrays, const std::string& base_dir,
                         const std::string& params, int iterations, std::optional<int> spp,
                         std::optional<long long> seed, int threads, double tolerance, const py::object& progress,
                         const std::string& name, int block, const std::string& error) {
    std::vector<FitTarget> targets;
    std::vector<FitSource> sources;
    for (size_t i = 0; i < target_list.size(); ++i) {
        const py::dict d = target_list[i].cast<py::dict>();
        FitTarget t;
        t.name = "targets[" + std::to_string(i) + "]";
        if (!d.contains("scene") || !d.contains("image")) throw InputError(t.name, "", "needs \"scene\" and \"image\"");
        t.scene = build_scene(d["scene"], arrays, base_dir, std::nullopt);
        FitSource source{"<scene>", "<array>", ""};
        if (py::isinstance<py::str>(d["image"])) {
            source.image = t.name = d["image"].cast<std::string>();
            read_target_image(source.image, t.width, t.height, t.rgb);
        } else {
            const FloatArray image = d["image"].cast<FloatArray>();
            if (image.ndim() != 3 || image.shape(2) < 3) throw InputError(t.name, "image", "must have shape (H, W, 3 or 4)");
            t.height = int(image.shape(0));
            t.width = int(image.shape(1));
            for (py::ssize_t y = 0; y < image.shape(0); ++y)
                for (py::ssize_t x = 0; x < image.shape(1); ++x)
                    for (int c = 0; c < 3; ++c) t.rgb.push_back(image.at(y, x, c));
        }
        if (d.contains("mask") && !d["mask"].is_none()) {
            int mw = 0, mh = 0;
            std::vector<float> rgb;
            if (py::isinstance<py::str>(d["mask"])) {
                source.mask = d["mask"].cast<std::string>();
                read_target_image(source.mask, mw, mh, rgb);
                for (size_t k = 0; k < rgb.size(); k += 3) t.weight.push_back(std::clamp(rgb[k], 0.0f, 1.0f));
            } else {
                const FloatArray mask = d["mask"].cast<FloatArray>();
                if (mask.ndim() != 2) throw InputError(t.name, "mask", "must have shape (H, W)");
                if (mask.shape(0) != t.height || mask.shape(1) != t.width)
                    throw InputError(t.name, "mask", "does not match the target's size");
                t.weight.assign(mask.data(), mask.data() + mask.size());
            }
        }
        check_fit_target(t);
        targets.push_back(std::move(t));
        sources.push_back(source);
    }
    FitOptions options;
    options.unknowns = parse_fit_parameters(params, "params");
    options.max_iterations = iterations;
    options.spp = spp.value_or(0);
    options.seed = seed.value_or(-1);
    options.threads = threads;
    options.tolerance = tolerance;
    if (block < 1) throw py::value_error("block must be at least 1");
    options.block = block;
    options.error = fit_error_from_name(error, "error");
    if (!progress.is_none())
        options.progress = [&progress](const FitProgress& p) {
            py::gil_scoped_acquire gil;
            py::dict d;
            d["iteration"] = p.iteration;
            d["renders"] = p.renders;
            d["mse"] = p.error;
            d["seconds"] = p.seconds;
            d["seconds_left"] = p.seconds_left;
            d["seconds_per_iteration"] = p.seconds_per_iteration;
            d["event"] = p.event;
            d["column"] = p.column;
            d["columns"] = p.columns;
            return !progress(d).equal(py::bool_(false));
        };
    const BysdfParams start = starting_params(targets);
    FitResult result;
    {
        py::gil_scoped_release release;
        result = fit_bysdf(targets, start, options);
    }
    MaterialDesc base;
    for (const YarnSetDesc& y : targets[0].scene.yarns)
        if (y.material.model == MaterialModel::Bysdf) {
            base = y.material;
            break;
        }
    const std::string preset = fit_preset_json(name, base, result, sources, options).dump();
    return py::module_::import("json").attr("loads")(preset).cast<py::dict>();
}

}  // namespace

PYBIND11_MODULE(purlcore, m) {
    m.doc() = "Purl's native core: yarn-level cloth rendering with the BYSDF";
    m.attr("__version__") = PURL_VERSION;
    // purlcore.Error, message "file: place: reason"; also raised when a render is cancelled.
    static py::exception<InputError>& error = py::register_exception<InputError>(m, "Error", PyExc_RuntimeError);
    // Every other native failure too (RenderJob misuse, a failed write, Embree): purlcore.Error,
    // which is a RuntimeError. Python's own exceptions (ValueError, TypeError ...) stay as they are.
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const py::builtin_exception&) {
            throw;
        } catch (const InputError&) {
            throw;
        } catch (const std::runtime_error& e) {
            PyErr_SetString(error.ptr(), e.what());
        }
    });

    py::class_<RenderJob>(m, "RenderJob")
        .def(py::init([](const py::object& scene, const py::object& arrays, const std::string& base_dir,
                         const std::optional<std::string>& model, const std::optional<std::string>& mode) {
                 return std::make_unique<RenderJob>(build_scene(scene, arrays, base_dir, model, mode));
             }),
             py::arg("scene"), py::arg("arrays") = py::none(), py::arg("base_dir") = "", py::arg("model") = py::none(),
             py::arg("mode") = py::none(),
             "Parse and build a scene (JSON text or dict, plus named numpy arrays).")
        .def("start", &RenderJob::start, py::arg("spp") = py::none(), py::arg("seed") = py::none(),
             py::arg("threads") = 0, py::arg("denoise") = py::none(), py::arg("first_sample") = 0,
             "Start rendering on native threads; returns at once. A finished job may be started again. denoise: "
             "run Open Image Denoise after the last sample (default: the scene's render.denoise); raises "
             "RuntimeError at once when OIDN is missing. first_sample: render samples first_sample .. "
             "first_sample + spp - 1, so passes over consecutive ranges, averaged with their spp as weights, "
             "equal one render of all of them.")
        .def(
            "set_view",
            [](RenderJob& job, const py::object& scene) {
                job.set_view(parse_view_text(scene_text(scene), "<scene>"));
            },
            py::arg("scene"),
             "Take the camera and film of a scene (JSON text or dict; the rest is not read) for the next start(), "
             "keeping the built geometry: a viewport's view changes. Not while rendering.")
        .def("wait", &RenderJob::wait, py::arg("timeout") = py::none(),
             "Block until the render ends (or timeout seconds pass); True when it has ended.")
        .def("cancel", &RenderJob::cancel, "Ask the render to stop; it ends within a pixel's work.")
        .def_property_readonly("progress", &RenderJob::progress)
        .def_property_readonly("done", &RenderJob::done)
        .def_property_readonly("cancelled", &RenderJob::cancelled)
        .def_property_readonly("error", &RenderJob::error)
        .def("passes", &RenderJob::passes, "Dict of pass name -> float32 array (H, W, C), rows top to bottom.")
        .def("stats", &RenderJob::stats, "Timing, ray and memory figures of the finished render.")
        .def("write", &RenderJob::write, py::arg("exr_path"), py::arg("png_path") = py::none(),
             py::arg("layer") = "ViewLayer", py::arg("passes") = py::none(),
             "Write a multilayer EXR (and optionally an sRGB PNG) atomically. passes: write these pixels (name -> "
             "float32 (H, W, C), e.g. an average of sample passes) instead of the job's own, only the passes given.");

    m.def(
        "render",
        [](const py::object& scene, const py::object& arrays, const std::string& base_dir, std::optional<int> spp,
           std::optional<long long> seed, int threads, const py::object& progress,
           const std::optional<std::string>& model, const std::optional<std::string>& mode) {
            RenderJob job(build_scene(scene, arrays, base_dir, model, mode));
            job.start(spp, seed, threads, std::nullopt, 0);
            try {
                while (!job.wait(0.1)) {
                    if (!progress.is_none() && progress(job.progress()).equal(py::bool_(false))) job.cancel();
                }
            } catch (py::error_already_set&) {  // Ctrl-C (or the progress callback raised): stop the render
                job.cancel();
                py::gil_scoped_release release;
                job.join();
                throw;
            }
            if (auto message = job.error()) throw std::runtime_error(*message);
            if (job.cancelled()) {
                PyErr_SetString(error.ptr(), "render cancelled");
                throw py::error_already_set();
            }
            if (!progress.is_none()) progress(1.0);
            // E.g. far mode forced on yarns wider than a pixel (also in RenderJob.stats()).
            for (const std::string& w : job.finished_stats().warnings)
                if (PyErr_WarnEx(PyExc_UserWarning, w.c_str(), 1) < 0) throw py::error_already_set();
            return job.passes();
        },
        py::arg("scene"), py::arg("arrays") = py::none(), py::arg("base_dir") = "", py::arg("spp") = py::none(),
        py::arg("seed") = py::none(), py::arg("threads") = 0, py::arg("progress") = py::none(),
        py::arg("model") = py::none(), py::arg("mode") = py::none(),
        "Render and return the passes; progress(fraction) returning False cancels. mode: multi-scale shading "
        "(near, multi, far, auto; default the scene's render.multiscale.mode).");
    m.def(
        "project_points",
        [](const py::object& scene, const py::array_t<double, py::array::c_style | py::array::forcecast>& points) {
            if (points.ndim() != 2 || points.shape(1) != 3) throw py::value_error("points must have shape (N, 3)");
            const SceneDesc desc = parse_view_text(scene_text(scene), "<scene>");
            const Camera camera(desc.camera, desc.film);
            py::array_t<float> out({points.shape(0), py::ssize_t(2)});
            for (py::ssize_t i = 0; i < points.shape(0); ++i) {
                float x = NAN, y = NAN;
                const Vec3 local(float(points.at(i, 0) - desc.origin[0]), float(points.at(i, 1) - desc.origin[1]),
                                 float(points.at(i, 2) - desc.origin[2]));  // the camera is relative to it
                if (!camera.project(local, x, y)) x = y = NAN;
                out.mutable_at(i, 0) = x;
                out.mutable_at(i, 1) = y;
            }
            return out;
        },
        py::arg("scene"), py::arg("points"),
        "Film positions (x right, y down from the top-left corner, in pixels) of world points as the scene's camera "
        "sees them; NaN for points behind the camera.");
    m.def("fit", &fit_from_python, py::arg("targets"), py::arg("arrays") = py::none(), py::arg("base_dir") = "",
          py::arg("params") = "kxB,kyB,sigma_t", py::arg("iterations") = 20, py::arg("spp") = py::none(),
          py::arg("seed") = py::none(), py::arg("threads") = 0, py::arg("tolerance") = 1e-3,
          py::arg("progress") = py::none(), py::arg("name") = "fitted", py::arg("block") = 1,
          py::arg("error") = "linear",
          "Fit BYSDF parameters to target images (docs/fitting.md); returns the preset dict, whose "
          "provenance holds the errors. progress(dict) returning False stops early, keeping the best so far.");
    m.def(
        "denoiser",
        [] {
            py::dict d;
            try {
                const auto denoiser = Denoiser::load();
                d["available"] = true;
                d["library"] = denoiser->library_path();
                d["message"] = "Open Image Denoise: " + denoiser->library_path();
            } catch (const DenoiserUnavailable& e) {
                d["available"] = false;
                d["library"] = py::none();
                d["message"] = e.what();
            }
            return d;
        },
        "Whether Open Image Denoise loads: {available, library (path or None), message (where it was looked for)}.");
    m.def(
        "denoise",
        [](const py::dict& passes, int threads, bool prefilter_guides) {
            RenderImage image;
            for (const auto& item : passes) {
                const FloatArray a = item.second.cast<FloatArray>();
                if (a.ndim() != 3) throw py::value_error("every pass must have shape (H, W, C)");
                if (image.passes.empty()) {
                    image.height = int(a.shape(0));
                    image.width = int(a.shape(1));
                } else if (a.shape(0) != image.height || a.shape(1) != image.width) {
                    throw py::value_error("passes differ in size");
                }
                ImagePass p{item.first.cast<std::string>(), std::vector<std::string>(size_t(a.shape(2))),
                            std::vector<float>(a.data(), a.data() + a.size())};
                image.passes.push_back(std::move(p));
            }
            {
                py::gil_scoped_release release;
                Denoiser::load()->denoise(image, {threads, prefilter_guides});
            }
            return passes_to_numpy(image);
        },
        py::arg("passes"), py::arg("threads") = 0, py::arg("prefilter_guides") = true,
        "Denoise a dict of passes (as RenderJob.passes() returns: Combined, and Denoising Albedo / Normal as "
        "guides) with Open Image Denoise; returns the dict with Combined denoised and the input as 'Noisy Image'.");
    m.def(
        "far_field_progress",
        [] {
            const FarFieldBuildProgress p = far_field_build_progress();
            return py::make_tuple(p.done, p.total);
        },
        "(done, total) view angles of the far-field tables being tabulated in this process, (0, 0) when none: "
        "a render waiting for its table shows this instead of a stalled progress.");
    m.def("material_models", [] { return choice_names(material_models()); });
    m.def(
        "material_model_labels",
        [] {
            py::dict d;  // what an artist reads in the model menu
            for (const Choice& c : material_models().choices) d[c.name] = c.label;
            return d;
        },
        "Display names of the material models.");
    m.def("render_settings", [] { return describe_parameters(render_settings()); },
          "The render settings of a scene's \"render\" object (spp, seed, max_depth, threads, clamp, filter_glossy, "
          "model, integrator, ply_method) with kind, range, default, doc, UI label and, for choices, their values.");
    m.def(
        "choices",
        [] {
            py::dict d;
            for (const ChoiceList* list : all_choice_lists()) {
                py::dict entry;
                entry["choices"] = describe_choices(*list);
                entry["default"] = list->default_name;
                d[list->key] = entry;
            }
            return d;
        },
        "Every named choice (render.model, render.ply_method, render.multiscale.mode, ...): "
        "{key: {choices: [{name, label, doc, value}], default}}.");
    m.def("artist_parameters", [] { return describe_parameters(artist_param_table()); },
          "The artist controls of the bysdf model (yarn colour, sheen, softness, translucency); each doc states "
          "the rule that maps it onto the BYSDF parameters (docs/artist-controls.md).");
    m.def("resolve_material", &resolve_material, py::arg("material"),
          "The BYSDF parameters a bysdf material object renders with: its physics parameters (defaults where "
          "absent) with its artist controls (color, sheen, softness, translucency) applied.");
    m.def("fiber_presets", &fiber_bcsdf_preset_names,
          "Names accepted by material.fiber.preset (Khungurn et al. 2015 fits).");
    m.def(
        "explicit_curves",
        [](const py::object& scene, const py::object& arrays, const std::string& base_dir, const std::string& model) {
            SceneDesc desc = build_scene(scene, arrays, base_dir, std::nullopt);
            const YarnModel which = parse_yarn_model(model, "model");
            if (which == YarnModel::Bysdf) throw py::value_error("model must be 'ply' or 'fiber'");
            YarnCurves c;
            std::vector<uint32_t> set_of_curve;
            {
                py::gil_scoped_release release;  // generating fibers takes a while
                c = gather_explicit_curves(make_explicit_scene(desc, which), &set_of_curve);
            }
            py::dict d = curves_to_numpy(c);
            d["yarn_set"] = copy_to_numpy(set_of_curve);
            d["basis"] = "bspline";
            return d;
        },
        py::arg("scene"), py::arg("arrays") = py::none(), py::arg("base_dir") = "", py::arg("model") = "ply",
        "The explicit ply or fiber curves the 'ply'/'fiber' models render, as uniform cubic B-spline control points "
        "(Z-up, scene units) with per-point radii, segment tables, closed flags, yarn ids and the yarn set of each curve.");
    m.def("yarn_parameters", [] { return describe_parameters(yarn_description_params()); },
          "The yarn geometry parameters (plies, twist, fibers, migration) of the bysdf model.");
    m.def("multiscale_parameters", [] { return describe_parameters(multiscale_param_table()); },
          "The multi-scale BYSDF parameters (render.multiscale in a scene; docs/multiscale.md).");
    m.def(
        "read_image",
        [](const std::string& path) {
            const ImageRGB image = read_image_rgb(path);
            py::array_t<float> out({image.height, image.width, 3});
            std::copy(image.rgb.begin(), image.rgb.end(), out.mutable_data());
            return out;
        },
        py::arg("path"), "Any image OpenImageIO reads, as linear RGB float32 (H, W, 3), rows top to bottom.");
    m.def(
        "write_image",
        [](const std::string& path, const py::array_t<float, py::array::c_style | py::array::forcecast>& rgb) {
            if (rgb.ndim() != 3 || rgb.shape(2) != 3) throw py::value_error("write_image wants an (H, W, 3) array");
            ImageRGB image;
            image.height = int(rgb.shape(0));
            image.width = int(rgb.shape(1));
            image.rgb.assign(rgb.data(), rgb.data() + rgb.size());
            write_rgb_exr(path, image);
        },
        py::arg("path"), py::arg("rgb"), "Linear RGB (H, W, 3) as a half-float, zip-compressed EXR.");
    m.def("multiscale_modes", [] { return choice_names(multiscale_modes()); });
    m.def("ply_methods", [] { return choice_names(ply_methods()); },
          "Values of render.ply_method: how BYSDF yarns find the ply under a hit.");
    m.def("yarn_presets", &yarn_preset_names, "Names accepted by material.yarn.preset.");
    m.def(
        "bake_yarn_maps",
        [](const py::dict& yarn) {
            // The native 1D maps of a yarn description (preset + overrides, as material.yarn in a
            // scene), for the Cycles OSL shader (addon/cycles_setup.py, docs/osl.md).
            YarnDescription d = yarn_preset(yarn.contains("preset") ? yarn["preset"].cast<std::string>() : "prototype");
            for (const auto& item : yarn) {
                const std::string key = item.first.cast<std::string>();
                if (key == "preset") continue;
                const auto& table = yarn_description_params();
                const auto it = std::find_if(table.begin(), table.end(), [&](const ParamInfo& i) { return key == i.name; });
                if (it == table.end()) throw InputError("<yarn>", key, "is not a yarn parameter");
                *param_field(d, *it) = item.second.cast<float>();
            }
            const FiberMaps maps(d);  // checks the description (InputError)
            const int n = maps.resolution(), variants = maps.variants();
            py::array_t<float> fiber({variants, n, 4});
            auto f = fiber.mutable_unchecked<3>();
            py::array_t<float> ply(n);
            auto g = ply.mutable_unchecked<1>();
            for (int i = 0; i < n; ++i) {
                const float angle = 2 * kPi * (i + 0.5f) / n;  // bin centres: the stored values
                for (int v = 0; v < variants; ++v) {
                    const FiberSample s = maps.sample(v, angle);
                    f(v, i, 0) = s.normal_angle;
                    f(v, i, 1) = s.fiber_phase;
                    f(v, i, 2) = s.fiber_distance;
                    f(v, i, 3) = s.shadowing;
                }
                g(i) = maps.ply_shadowing(angle);
            }
            py::dict out;
            out["fiber"] = fiber;
            out["ply_shadowing"] = ply;
            out["migration_frequency"] = d.migration_frequency;
            return out;
        },
        py::arg("yarn"),
        "The native fiber maps (variants x resolution x [normal angle rad, fiber phase rad, fiber distance in ply "
        "radii, G_f]) and the ply-shadowing map G_p (resolution) of a yarn description, at the bin centres.");
    m.def("material_parameters", [](const std::string& model) { return describe_parameters(parameter_table(model)); },
          py::arg("model") = "placeholder", "Every parameter of a material model with unit, range, default and doc.");
    m.def(
        "convert_curves",
        [](const py::dict& curves) {
            py::dict named;
            named["curves"] = curves;
            return curves_to_numpy(yarns_from_python(named, "curves"));
        },
        py::arg("curves"),
        "One array set as RenderJob takes it (points, radii, offsets, closed, basis, ...) converted as a render "
        "converts it: B-spline control points, segment tables and closed flags, as load_bcc returns them.");
    m.def("read_bcc", &read_bcc_for_import, py::arg("path"),
          "Read a BCC file as stored: type (C0, PL, BS, BZ), points (N, 3) turned Z-up, offsets (C + 1), closed (C), "
          "info, the file's up axis, and radius_estimate: half the median distance to the nearest other yarn (file "
          "units, 0 when the file has a single short yarn).");
    m.def(
        "load_bcc",
        [](const std::string& path, float radius) {
            return curves_to_numpy(load_bcc(path, radius));
        },
        py::arg("path"), py::arg("radius"),
        "Read a BCC file as B-spline control points (Z-up), with segment tables.");
}
