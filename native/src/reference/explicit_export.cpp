#include "reference/explicit_export.h"

#include <fstream>

#include "base/input_error.h"
#include "scene/bcc.h"

namespace purl {

YarnCurves gather_explicit_curves(const SceneDesc& scene, std::vector<uint32_t>* set_of_curve) {
    YarnCurves all;
    for (size_t y = 0; y < scene.yarns.size(); ++y) {
        const YarnSetDesc& set = scene.yarns[y];
        if (set.material.model != MaterialModel::Ply && set.material.model != MaterialModel::Fiber) continue;
        const YarnCurves& c = set.curves;
        const uint32_t point_base = static_cast<uint32_t>(all.control_points.size());
        const uint32_t segment_base = static_cast<uint32_t>(all.segment_first.size());
        for (const Vec4& p : c.control_points)  // back in world space (SceneDesc::origin), as floats
            all.control_points.emplace_back(float(p.x + scene.origin[0]), float(p.y + scene.origin[1]),
                                            float(p.z + scene.origin[2]), p.w);
        for (uint32_t s : c.segment_first) all.segment_first.push_back(point_base + s);
        for (size_t k = 1; k < c.curve_offsets.size(); ++k) {
            all.curve_offsets.push_back(point_base + c.curve_offsets[k]);
            all.segment_offsets.push_back(segment_base + c.segment_offsets[k]);
        }
        all.closed.insert(all.closed.end(), c.closed.begin(), c.closed.end());
        all.curve_ids.insert(all.curve_ids.end(), c.curve_ids.begin(), c.curve_ids.end());
        if (set_of_curve) set_of_curve->insert(set_of_curve->end(), c.curve_count(), static_cast<uint32_t>(y));
    }
    return all;
}

std::vector<float> bcc_point_radii(const YarnCurves& curves) {
    std::vector<float> radii;
    radii.reserve(curves.point_count());
    for_each_bcc_curve(curves, [&](const Vec4* p, size_t n, bool) {
        for (size_t i = 0; i < n; ++i) radii.push_back(p[i].w);
    });
    return radii;
}

ExplicitExport write_explicit_curves(const SceneDesc& scene, const std::string& bcc_path,
                                     const std::string& radii_path) {
    const YarnCurves curves = gather_explicit_curves(scene);
    if (curves.curve_count() == 0)
        throw InputError(scene.source, "yarns", "no yarn set has the bysdf material: nothing explicit to export");
    write_bcc(bcc_path, curves, "purl explicit reference curves");
    const std::vector<float> radii = bcc_point_radii(curves);
    std::ofstream out(radii_path, std::ios::binary | std::ios::trunc);
    if (!out) throw InputError(radii_path, "", "cannot open file for writing");
    // float32 little-endian: the byte order of every machine Purl builds on (x86-64, arm64).
    out.write(reinterpret_cast<const char*>(radii.data()), static_cast<std::streamsize>(radii.size() * sizeof(float)));
    if (!out) throw InputError(radii_path, "", "write failed");
    ExplicitExport e;
    e.curves = curves.curve_count();  // every explicit curve is a chain: one BCC curve each
    e.points = radii.size();
    return e;
}

}  // namespace purl
