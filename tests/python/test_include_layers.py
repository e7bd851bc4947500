"""Layers only point down: every #include in native/src names a folder below its own (or its own),
and CMakeLists.txt links every module only to modules below it. The order is written once, here
(LAYERS); docs/architecture.md draws it. Needs no build."""
import os
import re
import sys

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
SRC = os.path.join(ROOT, "native", "src")

# Bottom first. Folders on one line share a rank and must not include each other.
LAYERS = [
    ["base"],
    ["math"],
    ["yarn"],
    ["bsdf"],
    ["scene", "io"],
    ["render"],
    ["reference"],
    ["fit"],
]
RANK = {folder: rank for rank, folders in enumerate(LAYERS) for folder in folders}

# Known upward includes, each as (folder, folder it includes) with the issue that removes it.
# None today; an entry nobody needs any more fails test_allowed_exceptions_are_still_needed.
ALLOWED = set()

INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)


def source_files():
    for folder, _, files in os.walk(SRC):
        for name in files:
            if name.endswith((".h", ".cpp")):
                yield os.path.join(folder, name)


def includes():
    """(file relative to native/src, its folder, the folder it includes) for every project include."""
    for path in source_files():
        rel = os.path.relpath(path, SRC)
        folder = rel.split(os.sep)[0]
        with open(path, encoding="utf-8") as f:
            text = f.read()
        for target in INCLUDE.findall(text):
            parts = target.split("/")
            # Includes without a folder ("exact_model.h") are the file's own folder: allowed.
            if len(parts) > 1 and parts[0] in RANK:
                yield rel, folder, parts[0], target


def test_every_folder_of_native_src_has_a_layer():
    folders = {d for d in os.listdir(SRC) if os.path.isdir(os.path.join(SRC, d))}
    assert folders == set(RANK), "folders without a layer: {}; layers without a folder: {}".format(
        sorted(folders - set(RANK)), sorted(set(RANK) - folders))


def test_includes_point_down():
    upward = sorted("{} includes {} ({} -> {})".format(rel, target, src, dst)
                    for rel, src, dst, target in includes()
                    if src != dst and RANK[dst] >= RANK[src] and (src, dst) not in ALLOWED)
    assert not upward, "includes that do not point down:\n  " + "\n  ".join(upward)


def test_allowed_exceptions_are_still_needed():
    """An exception nobody uses any more is stale: remove it from ALLOWED."""
    used = {(src, dst) for _, src, dst, _ in includes() if src != dst and RANK[dst] >= RANK[src]}
    assert ALLOWED <= used, "stale exceptions: {}".format(sorted(ALLOWED - used))


def test_cmake_links_point_down():
    with open(os.path.join(ROOT, "CMakeLists.txt"), encoding="utf-8") as f:
        text = f.read()
    wrong = []
    for module, deps in re.findall(r"^purl_module\((\w+)([^)]*)\)", text, re.M):
        assert module in RANK, "CMakeLists.txt declares module {} with no layer".format(module)
        for dep in re.findall(r"\bpurl_(\w+)", deps):
            if RANK[dep] >= RANK[module] and (module, dep) not in ALLOWED:
                wrong.append("{} -> {}".format(module, dep))
    assert not wrong, "CMakeLists.txt links modules upward or sideways: " + ", ".join(wrong)


def test_the_check_sees_an_upward_include(tmp_path, monkeypatch):
    """The test itself can fail: a yarn/ file including bsdf/ is reported."""
    (tmp_path / "yarn").mkdir()
    (tmp_path / "yarn" / "x.h").write_text('#include "bsdf/bysdf.h"\n#include "math/vec.h"\n')
    monkeypatch.setattr(sys.modules[__name__], "SRC", str(tmp_path))
    found = [(src, dst) for _, src, dst, _ in includes() if RANK[dst] >= RANK[src]]
    assert found == [("yarn", "bsdf")]
