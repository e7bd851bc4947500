"""Per-yarn colours through purlcore: the optional curve_colors array (one linear RGB per curve)."""
import math

import numpy as np
import pytest

import purlcore


def two_yarns(colors=None):
    """Two straight yarns along x, one above the other, in front of the camera."""
    pts, offsets = [], [0]
    for z in (0.14, -0.14):
        pts += [(-0.9 + 0.2 * i, 0.0, z) for i in range(10)]
        offsets.append(len(pts))
    d = {
        "points": np.asarray(pts, dtype=np.float32),
        "radii": np.full(len(pts), 0.09, dtype=np.float32),
        "offsets": np.asarray(offsets, dtype=np.int64),
    }
    if colors is not None:
        d["curve_colors"] = colors
    return d


def scene(material):
    return {
        "camera": {"position": [0, -2, 0], "look_at": [0, 0, 0], "lens": 50},
        "film": {"width": 48, "height": 24},
        "render": {"spp": 4, "max_depth": 4},
        "world": {"color": [0.05, 0.05, 0.05]},
        "lights": [{"type": "area", "size": 0.5, "position": [0.3, -1.5, 0.8], "look_at": [0, 0, 0], "power": 40}],
        "yarns": [{"arrays": "two", "material": material}],
    }


RED_BLUE = np.array([[1.0, 0.1, 0.1], [0.1, 0.1, 1.0]], dtype=np.float32)


def yarn_means(passes):
    ids = passes["YarnID"][..., 0]
    rgb = passes["Combined"][..., :3]
    return [rgb[ids == k + 1].mean(axis=0) for k in range(2)]


@pytest.mark.parametrize("material", [
    {"model": "bysdf", "body_reflection_albedo": [0.6, 0.3, 0], "body_transmission_albedo": [0.8, 0.4, 0]},
    {"model": "placeholder", "color": [0.7, 0.7, 0.7]},
])
def test_each_curve_renders_in_its_colour(material):
    red, blue = yarn_means(purlcore.render(scene(material), {"two": two_yarns(RED_BLUE)}, threads=2))
    assert red[0] > 2 * red[2], red
    assert blue[2] > 2 * blue[0], blue


def test_float64_and_lists_are_accepted():
    passes = purlcore.render(scene({"model": "placeholder"}), {"two": two_yarns(RED_BLUE.astype(np.float64).tolist())})
    red, blue = yarn_means(passes)
    assert red[0] > red[2] and blue[2] > blue[0]


@pytest.mark.parametrize("colors, message", [
    (np.ones((3, 3), np.float32), r"two\.curve_colors.*shape \(C, 3\)"),
    (np.ones((2, 4), np.float32), r"two\.curve_colors.*shape \(C, 3\)"),
    (np.ones(6, np.float32), r"two\.curve_colors.*shape \(C, 3\)"),
    (np.array([[1, 0, 0], [0, math.nan, 0]], np.float32), r"two: curve_colors\[1\].*\[0, 1\]"),
    (np.array([[1, 0, 1.5], [0, 0, 0]], np.float32), r"two: curve_colors\[0\].*\[0, 1\].*1\.5"),
    (np.array([[1, 0, 0], [-0.2, 0, 0]], np.float32), r"two: curve_colors\[1\].*\[0, 1\]"),
])
def test_bad_colours_are_named(colors, message):
    with pytest.raises(purlcore.Error, match=message):
        purlcore.render(scene({"model": "placeholder"}), {"two": two_yarns(colors)})


def test_scene_json_colours_match_array_colours():
    # The same colours once from the arrays and once from the yarn object's "curve_colors".
    from_arrays = purlcore.render(scene({"model": "placeholder"}), {"two": two_yarns(RED_BLUE)}, seed=5, threads=2)
    s = scene({"model": "placeholder"})
    s["yarns"][0]["curve_colors"] = RED_BLUE.tolist()
    from_json = purlcore.render(s, {"two": two_yarns()}, seed=5, threads=2)
    assert np.array_equal(from_arrays["Combined"], from_json["Combined"])
