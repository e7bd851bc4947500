// purlcore's numpy side of scenes: named array sets in (yarn curves, meshes) with errors that
// name the set and key, and curves and BCC files out as numpy dicts.
#pragma once
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <algorithm>
#include <cstring>
#include <initializer_list>
#include <string>
#include <vector>

#include "base/input_error.h"
#include "scene/bcc.h"
#include "scene/curve_arrays.h"
#include "scene/scene.h"
#include "scene/yarn_spacing.h"

namespace purl::python {

namespace py = pybind11;

using FloatArray = py::array_t<float, py::array::c_style | py::array::forcecast>;
using IndexArray = py::array_t<int64_t, py::array::c_style | py::array::forcecast>;

// The array set `name`, a dict whose every key is one of `known` (a typo such as
// "curve_colours" would otherwise drop the colours without a word).
inline py::dict required_dict(const py::dict& arrays, const std::string& name, std::initializer_list<const char*> known) {
    if (!arrays.contains(name.c_str()))
        throw InputError("<arrays>", name, "no array set of this name was given");
    py::object entry = arrays[name.c_str()];
    if (!py::isinstance<py::dict>(entry)) throw InputError("<arrays>", name, "must be a dict of arrays");
    const py::dict d = entry.cast<py::dict>();
    for (const auto& item : d) {
        const std::string key = py::str(item.first);
        bool ok = false;
        std::string list;
        for (const char* k : known) {
            ok = ok || key == k;
            list += (list.empty() ? "" : ", ") + std::string(k);
        }
        if (!ok) throw InputError("<arrays>", name + "." + key, "unknown key (known: " + list + ")");
    }
    return d;
}

template <class Array>
inline Array get_array(const py::dict& d, const char* key, const std::string& set, bool required = true) {
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
inline py::array_t<T> copy_to_numpy(const std::vector<T>& v) {
    py::array_t<T> a(static_cast<py::ssize_t>(v.size()));
    std::copy(v.begin(), v.end(), a.mutable_data());
    return a;
}

// Yarn curves as the dict load_bcc and explicit_curves return: control points (n, 3), radii,
// the curve and segment tables, closed flags and ids.
inline py::dict curves_to_numpy(const YarnCurves& c) {
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

// A BCC file as stored (curve type, points per curve, closed flags), Z-up, with the yarn radius
// its spacing implies: what the Blender importer needs in one call.
inline py::dict read_bcc_for_import(const std::string& path) {
    BccCurves file;
    YarnSpacing spacing;
    {
        py::gil_scoped_release release;
        file = read_bcc(path);
        if (file.header.up_axis == 1)
            for (Vec3& p : file.points) p = bcc_y_up_to_z_up(p);
        spacing = estimate_yarn_spacing(load_bcc(path, 1.0f));
    }
    py::array_t<float> points({py::ssize_t(file.points.size()), py::ssize_t(3)});
    static_assert(sizeof(Vec3) == 3 * sizeof(float), "points are copied as packed float triples");
    std::memcpy(points.mutable_data(), file.points.data(), file.points.size() * sizeof(Vec3));
    py::dict d;
    d["type"] = file.header.type;
    d["up_axis"] = file.header.up_axis == 1 ? "Y" : "Z";
    d["info"] = py::bytes(file.header.info).attr("decode")("utf-8", "replace");  // free text, any bytes
    d["points"] = points;
    d["offsets"] = copy_to_numpy(file.curve_offsets);
    d["closed"] = copy_to_numpy(file.closed).attr("astype")("bool");
    d["radius_estimate"] = spacing.radius;
    return d;
}

inline YarnCurves yarns_from_python(const py::dict& arrays, const std::string& name) {
    const py::dict d =
        required_dict(arrays, name, {"points", "radii", "offsets", "closed", "ids", "curve_colors", "basis"});
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

inline MeshDesc mesh_from_python(const py::dict& arrays, const std::string& name) {
    const py::dict d = required_dict(arrays, name, {"vertices", "triangles"});
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

}  // namespace purl::python
