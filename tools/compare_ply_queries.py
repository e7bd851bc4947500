#!/usr/bin/env python3
"""Compare implicit ply query dumps (bench/native/dump_ply_queries.cpp) ray by ray.

Two builds, every method:   compare_ply_queries.py OLD_PREFIX NEW_PREFIX
Two methods of one dump:    compare_ply_queries.py PREFIX --methods straight elliptical

For each scene (and method) it prints how many rays differ in any output bit, how many change
hit state, ply or N_i, how far the hit point moves (in yarn radii R) and how far the ply tangent
turns (degrees) where both answers hit the same ply. The dump's `explicit` method is the truth:
`--methods explicit elliptical` measures a method's error in cloth (rays where the explicit
answer did not converge, e.g. met another passage of the yarn, are left out and counted). Exit status 1 when
a dump cannot be read or the dumps do not match in layout, so scripts cannot compare the wrong files.
"""
import argparse
import json
import sys

import numpy as np


def load(prefix):
    with open(prefix + ".json") as f:
        meta = json.load(f)
    data = {}
    for scene in meta["scenes"]:
        raw = np.fromfile(f"{prefix}.{scene}.bin", dtype=np.float32)
        data[scene] = raw.reshape(-1, len(meta["methods"]), len(meta["fields"]))
    return meta, data


def load_or_exit(prefix, tool):
    """load(prefix), or exit with status 1 and a message naming the dump and the reason."""
    try:
        return load(prefix)
    except (OSError, ValueError, KeyError) as e:  # a missing file, a wrong size, a bad header
        raise SystemExit(f"{tool}: cannot read the dump {prefix}: {e}")


def tangent_turn(a, b, col):
    """Degrees between the tangents of answers a and b (rays x fields), for each ray. By atan2 of
    sine and cosine in double: arccos of a float32 cosine is blind below ~0.03 deg."""
    t = slice(col["tangent_x"], col["tangent_z"] + 1)
    ta, tb = a[:, t].astype(np.float64), b[:, t].astype(np.float64)
    return np.degrees(np.arctan2(np.linalg.norm(np.cross(ta, tb), axis=1), np.abs(np.sum(ta * tb, axis=1))))


def mismatch(m, e, col, comparable):
    """Rays whose hit state, ply or N_i in answers m differ from the explicit answers e."""
    hit = e[:, col["hit"]] == 1
    return comparable & ((m[:, col["hit"]] != e[:, col["hit"]]) |
                         (hit & (m[:, col["ply"]] != e[:, col["ply"]])) |
                         (hit & (m[:, col["plies_crossed"]] != e[:, col["plies_crossed"]])))


def same_ply(m, e, col, comparable):
    """Rays on which answers m and the explicit answers e hit the same ply."""
    return comparable & (e[:, col["hit"]] == 1) & (m[:, col["hit"]] == 1) & (m[:, col["ply"]] == e[:, col["ply"]])


def summary(a, b, fields):
    """One line on how answers b differ from answers a (arrays: rays x fields)."""
    col = {name: i for i, name in enumerate(fields)}
    same_bits = np.all(a.view(np.uint32) == b.view(np.uint32), axis=1)
    hit = a[:, col["hit"]] != b[:, col["hit"]]
    both = (a[:, col["hit"]] == 1) & (b[:, col["hit"]] == 1)
    ply = both & (a[:, col["ply"]] != b[:, col["ply"]])
    crossed = both & (a[:, col["plies_crossed"]] != b[:, col["plies_crossed"]])
    point = slice(col["point_x"], col["point_z"] + 1)
    moved = np.linalg.norm(a[:, point] - b[:, point], axis=1) / a[:, col["radius"]]
    moved = np.where(both & ~ply, moved, 0.0)
    turned = tangent_turn(a[both & ~ply], b[both & ~ply], col)
    n = len(a)
    return (f"{n} rays: {n - same_bits.sum()} differ in some bit; hit state {hit.sum()}, ply {ply.sum()}, "
            f"N_i {crossed.sum()} changed (same hit state {1 - hit.mean():.4f}, same ply {1 - (hit | ply).mean():.4f}, "
            f"same N_i {1 - (hit | crossed).mean():.4f}); same ply but moved > 1e-4 R: {(moved > 1e-4).sum()}, "
            f"most {moved.max():.3g} R; tangent turned (same ply) mean {turned.mean() if len(turned) else 0:.3g}, "
            f"p99 {np.percentile(turned, 99) if len(turned) else 0:.3g} deg")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("prefix")
    parser.add_argument("other", nargs="?", help="a second dump: compare it with the first, method by method")
    parser.add_argument("--methods", nargs=2, metavar=("A", "B"), help="compare two methods of one dump")
    args = parser.parse_args()
    if (args.other is None) == (args.methods is None):
        parser.error("give either a second dump or --methods A B")
    meta, data = load_or_exit(args.prefix, "compare_ply_queries")
    if args.methods:
        for name in args.methods:
            if name not in meta["methods"]:
                parser.error(f"unknown method {name!r}; the dump has {', '.join(meta['methods'])}")
        i, j = (meta["methods"].index(m) for m in args.methods)
        converged = meta["fields"].index("converged")
        for scene, d in data.items():
            # The explicit answer is not comparable where it did not converge (another passage of
            # the yarn, or out of steps): those rays are left out, and counted.
            keep = np.ones(len(d), dtype=bool)
            for k, name in ((i, args.methods[0]), (j, args.methods[1])):
                if name == "explicit":
                    keep &= d[:, k, converged] == 1
            left_out = f" ({(~keep).sum()} rays without an explicit answer left out)" if not keep.all() else ""
            print(f"{scene}, {args.methods[1]} against {args.methods[0]}{left_out}: "
                  f"{summary(d[keep, i], d[keep, j], meta['fields'])}")
        return 0
    other_meta, other = load_or_exit(args.other, "compare_ply_queries")
    if other_meta != meta or any(other[s].shape != d.shape for s, d in data.items()):
        print(f"{args.prefix} and {args.other} differ in layout or ray count; nothing compared", file=sys.stderr)
        return 1
    for scene, d in data.items():
        for k, method in enumerate(meta["methods"]):
            print(f"{scene}, {method}: {summary(d[:, k], other[scene][:, k], meta['fields'])}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
