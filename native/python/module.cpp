// purlcore: the Python face of the native core. Scenes come in as the JSON scene format
// (a str or dict) plus numpy arrays; renders run on native threads without the GIL.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <optional>
#include <thread>

#include "bsdf/bysdf_params.h"
#include "bsdf/fiber_bcsdf_params.h"
#include "bsdf/placeholder.h"
#include "yarn/yarn_description.h"
#include "yarn/fiber_maps.h"
#include "fit/fit_target.h"
#include "fit/fitter.h"
#include "fit/preset_file.h"
#include "io/image_io.h"
#include "reference/explicit_export.h"
#include "reference/explicit_models.h"
#include "render/renderer.h"
#include "scene/bcc.h"
#include "scene/curve_arrays.h"
#include "scene/input_error.h"
#include "scene/scene_json.h"

namespace py = pybind11;
using namespace purl;

namespace {

using FloatArray = py::array_t<float, py::array::c_style | py::array::forcecast>;
using IndexArray = py::array_t<int64_t, py::array::c_style | py::array::forcecast>;

py::dict required_dict(const py::dict& arrays, const std::string& name) {
    if (!arrays.contains(name.c_str()))
        throw InputError("<arrays>", name, "no array set of this name was given");
    py::object entry = arrays[name.c_str()];
    if (!py::isinstance<py::dict>(entry)) throw InputError("<arrays>", name, "must be a dict of arrays");
    return entry.cast<py::dict>();
}

template <class Array>
Array get_array(const py::dict& d, const char* key, const std::string& set, bool required = true) {
    if (!d.contains(key)) {
        if (required) throw InputError("<arrays>", set + "." + key, "is required");
        return Array();
    }
    try {
        return d[key].cast<Array>();
    } catch (const py::cast_error&) {
        throw InputError("<arrays>", set + "." + key, "cannot be read as a numeric array");
    }
}

// A numpy copy of a vector (numpy owns its memory; the vector may go away).
template <class T>
py::array_t<T> copy_to_numpy(const std::vector<T>& v) {
    py::array_t<T> a(static_cast<py::ssize_t>(v.size()));
    std::copy(v.begin(), v.end(), a.mutable_data());
    return a;
}

// Yarn curves as the dict load_bcc and explicit_curves return: control points (n, 3), radii,
// the curve and segment tables, closed flags and ids.
py::dict curves_to_numpy(const YarnCurves& c) {
    py::array_t<float> points({py::ssize_t(c.point_count()), py::ssize_t(3)});
    py::array_t<float> radii(py::ssize_t(c.point_count()));
    float* p = points.mutable_data();
    float* r = radii.mutable_data();
    for (size_t i = 0; i < c.point_count(); ++i) {
        const Vec4& v = c.control_points[i];
        p[3 * i] = v.x;
        p[3 * i + 1] = v.y;
        p[3 * i + 2] = v.z;
        r[i] = v.w;
    }
    py::dict d;
    d["points"] = points;
    d["radii"] = radii;
    d["offsets"] = copy_to_numpy(c.curve_offsets);
    d["segments"] = copy_to_numpy(c.segment_first);
    d["segment_offsets"] = copy_to_numpy(c.segment_offsets);
    d["closed"] = copy_to_numpy(c.closed).attr("astype")("bool");
    d["ids"] = copy_to_numpy(c.curve_ids);
    return d;
}

YarnCurves yarns_from_python(const py::dict& arrays, const std::string& name) {
    const py::dict d = required_dict(arrays, name);
    const FloatArray points = get_array<FloatArray>(d, "points", name);
    const FloatArray radii = get_array<FloatArray>(d, "radii", name);
    const IndexArray offsets = get_array<IndexArray>(d, "offsets", name);
    if (points.ndim() != 2 || points.shape(1) != 3)
        throw InputError("<arrays>", name + ".points", "must have shape (N, 3)");
    if (radii.ndim() != 1 || radii.shape(0) != points.shape(0))
        throw InputError("<arrays>", name + ".radii", "must have shape (N,) matching points");
    if (offsets.ndim() != 1 || offsets.shape(0) < 2)
        throw InputError("<arrays>", name + ".offsets", "must have shape (C + 1,) with C >= 1");
    CurveArrays a;
    a.points = points.data();
    a.radii = radii.data();
    a.point_count = static_cast<size_t>(points.shape(0));
    a.offsets = offsets.data();
    a.curve_count = static_cast<size_t>(offsets.shape(0) - 1);
    py::array_t<uint8_t, py::array::c_style | py::array::forcecast> closed;
    py::array_t<int32_t, py::array::c_style | py::array::forcecast> ids;
    if (d.contains("closed")) {
        closed = d["closed"].cast<decltype(closed)>();
        if (closed.ndim() != 1 || size_t(closed.shape(0)) != a.curve_count)
            throw InputError("<arrays>", name + ".closed", "must have one value per curve");
        a.closed = closed.data();
    }
    if (d.contains("ids")) {
        ids = d["ids"].cast<decltype(ids)>();
        if (ids.ndim() != 1 || size_t(ids.shape(0)) != a.curve_count)
            throw InputError("<arrays>", name + ".ids", "must have one value per curve");
        a.ids = ids.data();
    }
    // One linear RGB colour per curve (float32 (C, 3)); replaces the material's body colour.
    FloatArray colors;
    if (d.contains("curve_colors")) {
        colors = get_array<FloatArray>(d, "curve_colors", name);
        if (colors.ndim() != 2 || size_t(colors.shape(0)) != a.curve_count || colors.shape(1) != 3)
            throw InputError("<arrays>", name + ".curve_colors",
                             "must have shape (C, 3) with one RGB colour per curve (C = " +
                                 std::to_string(a.curve_count) + ")");
        a.colors = colors.data();
    }
    if (d.contains("basis")) a.basis = parse_curve_basis(d["basis"].cast<std::string>(), "<arrays>: " + name);
    py::gil_scoped_release release;  // conversion of large curve sets needs no Python
    return curves_from_arrays(a, "<arrays>: " + name);
}

MeshDesc mesh_from_python(const py::dict& arrays, const std::string& name) {
    const py::dict d = required_dict(arrays, name);
    const FloatArray vertices = get_array<FloatArray>(d, "vertices", name);
    const IndexArray triangles = get_array<IndexArray>(d, "triangles", name);
    if (vertices.ndim() != 2 || vertices.shape(1) != 3)
        throw InputError("<arrays>", name + ".vertices", "must have shape (V, 3)");
    if (triangles.ndim() != 2 || triangles.shape(1) != 3)
        throw InputError("<arrays>", name + ".triangles", "must have shape (T, 3)");
    MeshDesc m;
    m.name = name;
    m.vertices.resize(vertices.shape(0));
    const float* v = vertices.data();
    for (size_t i = 0; i < m.vertices.size(); ++i) m.vertices[i] = Vec3(v[3 * i], v[3 * i + 1], v[3 * i + 2]);
    m.indices.resize(size_t(triangles.shape(0)) * 3);
    const int64_t* t = triangles.data();
    for (size_t i = 0; i < m.indices.size(); ++i) {
        if (t[i] < 0 || t[i] >= int64_t(m.vertices.size()))
            throw InputError("<arrays>", name + ".triangles", "index " + std::to_string(t[i]) + " out of range");
        m.indices[i] = static_cast<uint32_t>(t[i]);
    }
    return m;
}

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
        if (!m) throw py::value_error("mode must be 'near', 'multi', 'far' or 'auto', not '" + *mode + "'");
        desc.render.multiscale.mode = *m;
    }
    return desc;
}

py::dict passes_to_numpy(const RenderImage& image) {
    py::dict out;
    for (const ImagePass& pass : image.passes) {
        py::array_t<float> a({image.height, image.width, pass.channels()});
        std::memcpy(a.mutable_data(), pass.pixels.data(), pass.pixels.size() * sizeof(float));
        out[pass.name.c_str()] = a;
    }
    return out;
}

py::dict stats_to_dict(const RenderStats& s) {
    py::dict d;
    d["build_seconds"] = s.build_seconds;
    d["render_seconds"] = s.render_seconds;
    d["samples"] = s.samples;
    d["samples_per_second"] = s.samples_per_second();
    d["rays"] = s.rays;
    d["mean_path_length"] = s.mean_path_length;
    d["invalid_samples"] = s.invalid_samples;
    d["acceleration_bytes"] = s.acceleration_bytes;
    d["control_points"] = s.control_points;
    d["curves"] = s.curves;
    d["shading_bytes"] = s.shading_bytes;
    d["peak_resident_bytes"] = s.peak_resident_bytes;
    d["threads"] = s.threads;
    d["multiscale_hits"] = py::dict(py::arg("near") = s.hits_near, py::arg("multi") = s.hits_multi,
                                    py::arg("far") = s.hits_far);
    d["mean_h_samples"] = s.mean_h_samples();
    d["warnings"] = s.warnings;
    return d;
}

// A render running on its own thread; Python polls it, waits for it or cancels it.
class RenderJob {
public:
    RenderJob(const py::object& scene, const py::object& arrays, const std::string& base_dir,
              const std::optional<std::string>& model, const std::optional<std::string>& mode)
        : renderer_(std::make_unique<Renderer>(build_scene(scene, arrays, base_dir, model, mode))) {}
    ~RenderJob() {
        control_.cancel = true;
        if (worker_.joinable()) {
            py::gil_scoped_release release;
            worker_.join();
        }
    }

    void start(std::optional<int> spp, std::optional<long long> seed, int threads) {
        // A finished job may render again (other spp or seed) on the scene it has built: the
        // benchmarks (bench/) time many sample counts without rebuilding explicit geometry.
        if (worker_.joinable()) {
            if (!done()) throw std::runtime_error("this job is still rendering");
            worker_.join();
            done_ = false;
            result_.reset();
            error_.reset();
            control_.cancel = false;
        }
        RenderSettings settings = renderer_->scene().render;
        if (spp) {
            if (*spp < 1) throw py::value_error("spp must be at least 1");
            settings.spp = *spp;
        }
        if (seed) settings.seed = static_cast<uint64_t>(*seed);
        if (threads > 0) settings.threads = threads;
        worker_ = std::thread([this, settings] {
            try {
                RenderResult r = renderer_->render(settings, control_);
                std::lock_guard<std::mutex> lock(mutex_);
                result_ = std::move(r);
            } catch (const std::exception& e) {
                std::lock_guard<std::mutex> lock(mutex_);
                error_ = e.what();
            }
            std::lock_guard<std::mutex> lock(mutex_);
            done_ = true;
            finished_.notify_all();
        });
    }
    bool wait(std::optional<double> timeout) {
        if (!worker_.joinable()) throw std::runtime_error("the job has not been started");
        py::gil_scoped_release release;
        std::unique_lock<std::mutex> lock(mutex_);
        if (timeout) return finished_.wait_for(lock, std::chrono::duration<double>(*timeout), [&] { return done_; });
        finished_.wait(lock, [&] { return done_; });
        return true;
    }
    double progress() const { return control_.progress(); }
    bool done() {
        std::lock_guard<std::mutex> lock(mutex_);
        return done_;
    }
    void cancel() { control_.cancel = true; }
    bool cancelled() {
        std::lock_guard<std::mutex> lock(mutex_);
        return done_ && result_ && result_->cancelled;
    }
    std::optional<std::string> error() {
        std::lock_guard<std::mutex> lock(mutex_);
        return error_;
    }
    const RenderResult& finished_result() {
        std::lock_guard<std::mutex> lock(mutex_);
        if (!done_) throw std::runtime_error("the render has not finished; call wait() first");
        if (error_) throw std::runtime_error(*error_);
        return *result_;
    }
    py::dict passes() { return passes_to_numpy(finished_result().image); }
    py::dict stats() { return stats_to_dict(finished_result().stats); }
    const RenderStats& finished_stats() { return finished_result().stats; }
    void write(const std::string& exr, std::optional<std::string> png, const std::string& layer) {
        const RenderResult& r = finished_result();
        if (r.cancelled) throw std::runtime_error("the render was cancelled; nothing written");
        py::gil_scoped_release release;
        write_multilayer_exr(exr, r.image, layer);
        if (png) write_png(*png, r.image);
    }

private:
    std::unique_ptr<Renderer> renderer_;
    RenderControl control_;
    std::thread worker_;
    std::mutex mutex_;
    std::condition_variable finished_;
    bool done_ = false;
    std::optional<RenderResult> result_;
    std::optional<std::string> error_;
};

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
        d["is_integer"] = p.is_integer;
        out.append(d);
    }
    return out;
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
                         const std::string& name, int block) {
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
    if (!progress.is_none())
        options.progress = [&progress](const FitProgress& p) {
            py::gil_scoped_acquire gil;
            py::dict d;
            d["iteration"] = p.iteration;
            d["renders"] = p.renders;
            d["mse"] = p.error;
            d["seconds"] = p.seconds;
            d["event"] = p.event;
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
        if (y.material.model == "bysdf") {
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

    py::class_<RenderJob>(m, "RenderJob")
        .def(py::init<const py::object&, const py::object&, const std::string&, const std::optional<std::string>&,
                      const std::optional<std::string>&>(),
             py::arg("scene"), py::arg("arrays") = py::none(), py::arg("base_dir") = "", py::arg("model") = py::none(),
             py::arg("mode") = py::none(),
             "Parse and build a scene (JSON text or dict, plus named numpy arrays).")
        .def("start", &RenderJob::start, py::arg("spp") = py::none(), py::arg("seed") = py::none(),
             py::arg("threads") = 0, "Start rendering on native threads; returns at once. A finished job may be started again.")
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
             py::arg("layer") = "ViewLayer", "Write a multilayer EXR (and optionally an sRGB PNG) atomically.");

    m.def(
        "render",
        [](const py::object& scene, const py::object& arrays, const std::string& base_dir, std::optional<int> spp,
           std::optional<long long> seed, int threads, const py::object& progress,
           const std::optional<std::string>& model, const std::optional<std::string>& mode) {
            RenderJob job(scene, arrays, base_dir, model, mode);
            job.start(spp, seed, threads);
            while (!job.wait(0.1)) {
                if (!progress.is_none() && progress(job.progress()).equal(py::bool_(false))) job.cancel();
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
        [](const py::object& scene, const FloatArray& points) {
            if (points.ndim() != 2 || points.shape(1) != 3) throw py::value_error("points must have shape (N, 3)");
            const SceneDesc desc = parse_view_text(scene_text(scene), "<scene>");
            const Camera camera(desc.camera, desc.film);
            py::array_t<float> out({points.shape(0), py::ssize_t(2)});
            for (py::ssize_t i = 0; i < points.shape(0); ++i) {
                float x = NAN, y = NAN;
                if (!camera.project({points.at(i, 0), points.at(i, 1), points.at(i, 2)}, x, y)) x = y = NAN;
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
          "Fit BYSDF parameters to target images (docs/fitting.md); returns the preset dict, whose "
          "provenance holds the errors. progress(dict) returning False stops early, keeping the best so far.");
    m.def("material_models", [] { return std::vector<std::string>{"bysdf", "placeholder", "fiber"}; });
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
    m.def("multiscale_modes", [] { return std::vector<std::string>{"near", "multi", "far", "auto"}; });
    m.def("ply_methods", &ply_method_names,
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
        "load_bcc",
        [](const std::string& path, float radius) {
            return curves_to_numpy(load_bcc(path, radius));
        },
        py::arg("path"), py::arg("radius"),
        "Read a BCC file as B-spline control points (Z-up), with segment tables.");
}
