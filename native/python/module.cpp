// purlcore: the Python face of the native core. Scenes come in as the JSON scene format
// (a str or dict) plus numpy arrays; renders run on native threads without the GIL.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <optional>
#include <thread>

#include "bsdf/bysdf_params.h"
#include "bsdf/fiber_bcsdf_params.h"
#include "bsdf/placeholder.h"
#include "yarn/yarn_description.h"
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
    std::memcpy(m.vertices.data(), vertices.data(), sizeof(float) * 3 * m.vertices.size());
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
                      const std::optional<std::string>& model) {
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
    return d;
}

// A render running on its own thread; Python polls it, waits for it or cancels it.
class RenderJob {
public:
    RenderJob(const py::object& scene, const py::object& arrays, const std::string& base_dir,
              const std::optional<std::string>& model)
        : renderer_(std::make_unique<Renderer>(build_scene(scene, arrays, base_dir, model))) {}
    ~RenderJob() {
        control_.cancel = true;
        if (worker_.joinable()) {
            py::gil_scoped_release release;
            worker_.join();
        }
    }

    void start(std::optional<int> spp, std::optional<long long> seed, int threads) {
        if (worker_.joinable()) throw std::runtime_error("this job has already been started");
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

}  // namespace

PYBIND11_MODULE(purlcore, m) {
    m.doc() = "Purl's native core: yarn-level cloth rendering with the BYSDF";
    m.attr("__version__") = PURL_VERSION;
    static py::exception<InputError> error(m, "Error", PyExc_RuntimeError);
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const InputError& e) {
            error(e.what());
        }
    });

    py::class_<RenderJob>(m, "RenderJob")
        .def(py::init<const py::object&, const py::object&, const std::string&, const std::optional<std::string>&>(),
             py::arg("scene"), py::arg("arrays") = py::none(), py::arg("base_dir") = "", py::arg("model") = py::none(),
             "Parse and build a scene (JSON text or dict, plus named numpy arrays).")
        .def("start", &RenderJob::start, py::arg("spp") = py::none(), py::arg("seed") = py::none(),
             py::arg("threads") = 0, "Start rendering on native threads; returns at once.")
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
           const std::optional<std::string>& model) {
            RenderJob job(scene, arrays, base_dir, model);
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
            return job.passes();
        },
        py::arg("scene"), py::arg("arrays") = py::none(), py::arg("base_dir") = "", py::arg("spp") = py::none(),
        py::arg("seed") = py::none(), py::arg("threads") = 0, py::arg("progress") = py::none(),
        py::arg("model") = py::none(), "Render and return the passes; progress(fraction) returning False cancels.");
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
            d["offsets"] = py::array_t<uint32_t>(c.curve_offsets.size(), c.curve_offsets.data());
            d["segments"] = py::array_t<uint32_t>(c.segment_first.size(), c.segment_first.data());
            d["segment_offsets"] = py::array_t<uint32_t>(c.segment_offsets.size(), c.segment_offsets.data());
            d["closed"] = py::array_t<uint8_t>(c.closed.size(), c.closed.data()).attr("astype")("bool");
            d["ids"] = py::array_t<int32_t>(c.curve_ids.size(), c.curve_ids.data());
            d["yarn_set"] = py::array_t<uint32_t>(set_of_curve.size(), set_of_curve.data());
            d["basis"] = "bspline";
            return d;
        },
        py::arg("scene"), py::arg("arrays") = py::none(), py::arg("base_dir") = "", py::arg("model") = "ply",
        "The explicit ply or fiber curves the 'ply'/'fiber' models render, as uniform cubic B-spline control points "
        "(Z-up, scene units) with per-point radii, segment tables, closed flags, yarn ids and the yarn set of each curve.");
    m.def("yarn_parameters", [] { return describe_parameters(yarn_description_params()); },
          "The yarn geometry parameters (plies, twist, fibers, migration) of the bysdf model.");
    m.def("yarn_presets", &yarn_preset_names, "Names accepted by material.yarn.preset.");
    m.def("material_parameters", [](const std::string& model) { return describe_parameters(parameter_table(model)); },
          py::arg("model") = "placeholder", "Every parameter of a material model with unit, range, default and doc.");
    m.def(
        "load_bcc",
        [](const std::string& path, float radius) {
            const YarnCurves c = load_bcc(path, radius);
            py::array_t<float> points({py::ssize_t(c.point_count()), py::ssize_t(3)});
            py::array_t<float> radii(py::ssize_t(c.point_count()));
            for (size_t i = 0; i < c.point_count(); ++i) {
                const Vec4& p = c.control_points[i];
                points.mutable_at(i, 0) = p.x;
                points.mutable_at(i, 1) = p.y;
                points.mutable_at(i, 2) = p.z;
                radii.mutable_at(i) = p.w;
            }
            py::dict d;
            d["points"] = points;
            d["radii"] = radii;
            d["offsets"] = py::array_t<uint32_t>(c.curve_offsets.size(), c.curve_offsets.data());
            d["segments"] = py::array_t<uint32_t>(c.segment_first.size(), c.segment_first.data());
            d["segment_offsets"] = py::array_t<uint32_t>(c.segment_offsets.size(), c.segment_offsets.data());
            d["closed"] = py::array_t<uint8_t>(c.closed.size(), c.closed.data()).attr("astype")("bool");
            d["ids"] = py::array_t<int32_t>(c.curve_ids.size(), c.curve_ids.data());
            return d;
        },
        py::arg("path"), py::arg("radius"),
        "Read a BCC file as B-spline control points (Z-up), with segment tables.");
}
