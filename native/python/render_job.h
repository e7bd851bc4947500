// purlcore.RenderJob: a render on its own native thread, which Python polls, waits for (with
// Ctrl-C) or cancels; its passes and figures as numpy arrays and dicts.
#pragma once
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <chrono>
#include <condition_variable>
#include <cstring>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "base/input_error.h"
#include "io/image_io.h"
#include "reference/explicit_models.h"
#include "render/denoise.h"
#include "render/renderer.h"

namespace purl::python {

namespace py = pybind11;

inline py::dict passes_to_numpy(const RenderImage& image) {
    py::dict out;
    for (const ImagePass& pass : image.passes) {
        py::array_t<float> a({image.height, image.width, pass.channels()});
        std::memcpy(a.mutable_data(), pass.pixels.data(), pass.pixels.size() * sizeof(float));
        out[pass.name.c_str()] = a;
    }
    return out;
}

inline py::dict stats_to_dict(const RenderStats& s) {
    py::dict d;
    d["build_seconds"] = s.build_seconds;
    d["render_seconds"] = s.render_seconds;
    d["samples"] = s.samples;
    d["samples_per_second"] = s.samples_per_second();
    d["rays"] = s.rays;
    d["mean_path_length"] = s.mean_path_length;
    d["invalid_samples"] = s.invalid_samples;
    d["denoise_seconds"] = s.denoise_seconds;
    d["acceleration_bytes"] = s.acceleration_bytes;
    d["control_points"] = s.control_points;
    d["curves"] = s.curves;
    d["shading_bytes"] = s.shading_bytes;
    d["peak_resident_bytes"] = s.peak_resident_bytes;
    d["threads"] = s.threads;
    d["multiscale_hits"] = py::dict(py::arg("near") = s.hits_near, py::arg("multi") = s.hits_multi,
                                    py::arg("far") = s.hits_far);
    d["mean_h_samples"] = s.mean_h_samples();
    d["bysdf_evaluations"] = s.bysdf_evaluations;
    d["warnings"] = s.warnings;
    return d;
}

// A render running on its own thread; Python polls it, waits for it or cancels it.
class RenderJob {
public:
    explicit RenderJob(SceneDesc scene) {
        py::gil_scoped_release release;  // Embree's build: Blender's UI thread keeps running
        const ExplicitSceneBuilder make_explicit = make_explicit_scene;  // ply and fiber renders
        renderer_ = std::make_unique<Renderer>(std::move(scene), make_explicit);
    }
    ~RenderJob() {
        control_.cancel = true;
        if (worker_.joinable()) {
            py::gil_scoped_release release;
            worker_.join();
        }
    }

    void start(std::optional<int> spp, std::optional<long long> seed, int threads, std::optional<bool> denoise,
               int first_sample) {
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
        if (first_sample < 0) throw py::value_error("first_sample must be at least 0");
        settings.first_sample = first_sample;
        if (threads > 0) settings.threads = threads;
        if (denoise) settings.denoise = *denoise;
        if (settings.denoise) Denoiser::load();  // DenoiserUnavailable (RuntimeError) here, not in the worker
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
    void set_view(const SceneDesc& view) {
        if (worker_.joinable() && !done()) throw std::runtime_error("this job is still rendering");
        renderer_->set_view(view.camera, view.film, view.origin);
    }
    // Waits in steps of 0.1 s, between which Python's signal handlers run: Ctrl-C raises
    // KeyboardInterrupt here at once (the job goes on until cancelled or collected).
    bool wait(std::optional<double> timeout) {
        if (!worker_.joinable()) throw std::runtime_error("the job has not been started");
        using Clock = std::chrono::steady_clock;
        const Clock::time_point end =
            Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(timeout.value_or(0)));
        for (;;) {
            if (PyErr_CheckSignals() != 0) throw py::error_already_set();
            Clock::time_point step = Clock::now() + std::chrono::milliseconds(100);
            if (timeout && end < step) step = end;
            {
                py::gil_scoped_release release;
                std::unique_lock<std::mutex> lock(mutex_);
                if (finished_.wait_until(lock, step, [&] { return done_; })) return true;
            }
            if (timeout && Clock::now() >= end) return false;
        }
    }
    void join() {  // after cancel(): the render ends within a pixel's work
        if (worker_.joinable()) worker_.join();
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
    // Writes the render, or with `passes` pixels from Python (an accumulation of sample passes)
    // under this job's pass and channel names; then only the passes given are written.
    void write(const std::string& exr, std::optional<std::string> png, const std::string& layer,
               const std::optional<py::dict>& passes) {
        const RenderResult& r = finished_result();
        if (!passes && r.cancelled) throw std::runtime_error("the render was cancelled; nothing written");
        check_output_path(exr, "exr_path");
        if (png) check_output_path(*png, "png_path", true);
        const RenderImage image = passes ? image_from(*passes, r.image) : RenderImage{};
        const RenderImage& out = passes ? image : r.image;
        py::gil_scoped_release release;
        write_multilayer_exr(exr, out, layer);
        if (png) write_png(*png, out);
    }

private:
    static RenderImage image_from(const py::dict& passes, const RenderImage& own_image) {
        using FloatArray = py::array_t<float, py::array::c_style | py::array::forcecast>;
        RenderImage image;
        image.width = own_image.width;
        image.height = own_image.height;
        for (const ImagePass& own : own_image.passes) {
            if (!passes.contains(own.name.c_str())) continue;
            const FloatArray pixels = passes[own.name.c_str()].cast<FloatArray>();
            if (size_t(pixels.size()) != own.pixels.size())
                throw InputError("<passes>", own.name, "must have shape (" + std::to_string(image.height) + ", " +
                                                           std::to_string(image.width) + ", " +
                                                           std::to_string(own.channels()) + ")");
            image.passes.push_back({own.name, own.channel_names, {pixels.data(), pixels.data() + pixels.size()}});
        }
        return image;
    }

    std::unique_ptr<Renderer> renderer_;
    RenderControl control_;
    std::thread worker_;
    std::mutex mutex_;
    std::condition_variable finished_;
    bool done_ = false;
    std::optional<RenderResult> result_;
    std::optional<std::string> error_;
};

}  // namespace purl::python
