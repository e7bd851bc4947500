// Dumps the data behind the implicit-geometry figures and tables as .npy / .csv files;
// draw_maps.py builds this program, runs it and draws the PNGs.
//
//   yarn_maps images <dir>   tangent/normal pictures, explicit vs elliptical vs circular
//   yarn_maps table <file>   accuracy sweep (plies x bend x view angle) as CSV
//   yarn_maps fibers <dir>   one ply cross-section, its fiber maps and the ply-shadowing map
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "reference/ply_validation.h"
#include "yarn/fiber_maps.h"
#include "yarn/ply_cross_section.h"

namespace {

using namespace purl;

// Minimal NumPy .npy writer for little-endian float32 arrays.
void write_npy(const std::string& path, const std::vector<float>& data, const std::vector<int>& shape) {
    std::string dims;
    for (size_t i = 0; i < shape.size(); ++i) dims += std::to_string(shape[i]) + (shape.size() == 1 || i + 1 < shape.size() ? "," : "");
    std::string header = "{'descr': '<f4', 'fortran_order': False, 'shape': (" + dims + "), }";
    while ((10 + header.size() + 1) % 64 != 0) header += ' ';
    header += '\n';
    std::ofstream out(path, std::ios::binary);
    out.write("\x93NUMPY\x01\x00", 8);
    const uint16_t len = static_cast<uint16_t>(header.size());
    out.write(reinterpret_cast<const char*>(&len), 2);
    out.write(header.data(), header.size());
    out.write(reinterpret_cast<const char*>(data.data()), data.size() * sizeof(float));
}

void images(const std::string& dir) {
    struct View {
        const char* name;
        int plies;
        float angle, bend;
    };
    const View views[] = {{"straight60", 3, 60, 0}, {"bend2_top", 3, 0, 2}, {"bend2_45", 5, 45, 2}, {"straight80", 5, 80, 0}};
    for (const View& v : views) {
        ValidationCase c;
        c.description = touching_plies(v.plies);
        c.view_angle = v.angle;
        c.curvature_radius = v.bend;
        const int w = 240, h = 240;
        const ValidationImage img = render_validation_image(c, w, h);
        // Channels: tube, hit flags (explicit, elliptical, circular), then 3 x 3 tangents and normals.
        std::vector<float> out;
        out.reserve(size_t(w) * h * 22);
        for (size_t i = 0; i < size_t(w) * h; ++i) {
            out.push_back(img.tube[i]);
            out.push_back(img.explicit_hit[i]);
            out.push_back(img.elliptical_hit[i]);
            out.push_back(img.circular_hit[i]);
            for (const std::vector<Vec3>* t : {&img.explicit_tangent, &img.elliptical_tangent, &img.circular_tangent,
                                               &img.explicit_normal, &img.elliptical_normal, &img.circular_normal})
                for (int k = 0; k < 3; ++k) out.push_back((*t)[i][k]);
        }
        write_npy(dir + "/" + v.name + ".npy", out, {h, w, 22});
        std::printf("%s\n", v.name);
    }
}

void table(const std::string& path) {
    std::ofstream csv(path);
    csv << "method,plies,bend,view,rays,agreement,false_hits,false_misses,same_ply,both_hit,tangent_mean,"
           "tangent_p95,normal_mean,distance_mean,evals_mean,evals_max,unconverged,non_finite\n";
    for (int plies : {2, 3, 5, 12})
        for (float bend : {0.0f, 8.0f, 4.0f, 2.0f})
            for (float view : {0.0f, 30.0f, 45.0f, 60.0f, 70.0f, 80.0f, 85.0f}) {
                ValidationCase c;
                c.description = touching_plies(plies);
                c.view_angle = view;
                c.curvature_radius = bend;
                c.rays = bend > 0 ? 200 : 400;
                c.count_crossings_every = 0;
                c.seed = 77 + plies * 1000 + static_cast<uint64_t>(view) + 31 * static_cast<uint64_t>(bend);
                const ValidationResult r = validate_plies(c);
                auto row = [&](const char* name, const MethodStats& m) {
                    double evals = 0;
                    int evals_max = 0;
                    for (int e : m.iterations) evals += e, evals_max = std::max(evals_max, e);
                    csv << name << ',' << plies << ',' << bend << ',' << view << ',' << m.rays << ','
                        << m.agreement() << ',' << m.false_hits << ',' << m.false_misses << ',' << m.same_ply << ','
                        << m.both_hit << ',' << m.mean(m.tangent_error) << ',' << m.percentile(m.tangent_error, 0.95)
                        << ',' << m.mean(m.normal_error) << ',' << m.mean(m.distance_error) << ','
                        << (m.iterations.empty() ? 0 : evals / m.iterations.size()) << ',' << evals_max << ','
                        << m.unconverged << ',' << m.non_finite << '\n';
                };
                row("elliptical", r.elliptical);
                row("circular", r.circular);
                std::printf("plies %d bend %g view %g\n", plies, bend, view);
                std::fflush(stdout);
            }
}

void fibers(const std::string& dir) {
    const YarnDescription d = default_yarn_description();
    const FiberMaps maps(d);
    std::vector<float> centres;
    for (int v = 0; v < maps.variants(); ++v)
        for (const Vec2& c : ply_fibers(d, 2 * kPi * v / maps.variants()).centres) {
            centres.push_back(float(v));
            centres.push_back(c.x);
            centres.push_back(c.y);
        }
    write_npy(dir + "/fiber_centres.npy", centres, {static_cast<int>(centres.size() / 3), 3});
    const int n = 720;
    std::vector<float> fiber, ply;
    for (int v = 0; v < maps.variants(); ++v)
        for (int i = 0; i < n; ++i) {
            const FiberSample s = maps.sample(v, 2 * kPi * i / n);
            fiber.insert(fiber.end(), {s.normal_angle, s.fiber_phase, s.fiber_distance, s.shadowing});
        }
    for (int i = 0; i < n; ++i) ply.push_back(maps.ply_shadowing(2 * kPi * i / n));
    write_npy(dir + "/fiber_maps.npy", fiber, {maps.variants(), n, 4});
    write_npy(dir + "/ply_shadowing.npy", ply, {n});
    // The migration blend along one ply at one angle, over 12 cells.
    std::vector<float> along;
    for (int i = 0; i < 1200; ++i) {
        const FiberSample s = maps.lookup(1.0f, i * 0.01f, 7);
        along.insert(along.end(), {i * 0.01f, s.normal_angle, s.shadowing});
    }
    write_npy(dir + "/migration.npy", along, {1200, 3});
    std::printf("fiber radius %g, %d fibers, maps %zu bytes\n", d.fiber_radius, d.fibers(), maps.memory_bytes());
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 3) {
        std::fprintf(stderr, "usage: yarn_maps images|table|fibers <path>\n");
        return 2;
    }
    const std::string what = argv[1];
    if (what == "images") images(argv[2]);
    else if (what == "table") table(argv[2]);
    else if (what == "fibers") fibers(argv[2]);
    else {
        std::fprintf(stderr, "unknown command %s\n", argv[1]);
        return 2;
    }
    return 0;
}
