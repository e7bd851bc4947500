#!/usr/bin/env python3
"""Draws the implicit-geometry validation maps (docs/images/*.png).

Builds tools/yarn_maps/yarn_maps.cpp together with native/src/{base,yarn}/**/*.cpp and the ply
validation of native/src/reference/ (plain g++, no CMake needed), runs it, and plots with
matplotlib:

  implicit-plies-tangents.png   Fig. 3-style tangent maps: explicit, elliptical, circular, errors
  implicit-plies-accuracy.png   hit/miss agreement and tangent error against the view angle
  fiber-maps.png                ply cross-section, fiber maps, G_f, G_p and the migration blend

Usage: python3 tools/yarn_maps/draw_maps.py [--out docs/images] [--work /tmp/yarn_maps] [--no-table]
The accuracy sweep (--no-table skips it) takes a few minutes on one core.
"""
import argparse
import csv
import pathlib
import subprocess

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[2]


def build(work: pathlib.Path) -> pathlib.Path:
    exe = work / "yarn_maps"
    sources = sorted(str(p) for folder in ("base", "yarn") for p in (ROOT / "native/src" / folder).rglob("*.cpp"))
    sources += [str(ROOT / "native/src/reference" / name) for name in ("explicit_plies.cpp", "ply_validation.cpp")]
    cmd = ["g++", "-O2", "-std=c++17", "-I", str(ROOT / "native/src"), *sources,
           str(ROOT / "tools/yarn_maps/yarn_maps.cpp"), "-o", str(exe)]
    subprocess.run(cmd, check=True)
    return exe


def tangent_colour(t):
    """Unit tangents as colours; a tangent and its opposite get the same colour."""
    t = np.where(t[..., 2:3] < 0, -t, t)
    return np.clip(0.5 + 0.5 * t, 0, 1)


def angle_deg(a, b):
    return np.degrees(np.arccos(np.clip(np.abs(np.sum(a * b, axis=-1)), 0, 1)))


def draw_tangents(work: pathlib.Path, out: pathlib.Path):
    views = [("straight60", "straight yarn, 3 plies, 60°"), ("bend2_top", "bend radius 2R, 3 plies, 0°"),
             ("bend2_45", "bend radius 2R, 5 plies, 45°"), ("straight80", "straight yarn, 5 plies, 80°")]
    fig, axes = plt.subplots(len(views), 5, figsize=(15, 3.2 * len(views)))
    for row, (name, title) in enumerate(views):
        d = np.load(work / f"{name}.npy")
        tube, hit_x, hit_e, hit_c = (d[..., k] > 0.5 for k in range(4))
        t_x, t_e, t_c = d[..., 4:7], d[..., 7:10], d[..., 10:13]
        background = np.ones(tube.shape + (3,)) * 0.15
        background[tube] = 0.35

        def picture(hit, t):
            img = background.copy()
            img[hit] = tangent_colour(t)[hit]
            return img

        def error(hit, t):
            err = np.full(tube.shape, np.nan)
            both = hit & hit_x
            err[both] = angle_deg(t, t_x)[both]
            return err, (hit != hit_x) & tube

        for col, (label, img) in enumerate([("explicit plies", picture(hit_x, t_x)),
                                            ("elliptical (ours)", picture(hit_e, t_e)),
                                            ("circular", picture(hit_c, t_c))]):
            axes[row, col].imshow(img, interpolation="nearest")
            axes[row, col].set_title(f"{label}\n{title}" if col == 0 else label, fontsize=9)
        for col, (label, hit, t) in enumerate([("elliptical", hit_e, t_e), ("circular", hit_c, t_c)], start=3):
            err, mismatch = error(hit, t)
            im = axes[row, col].imshow(np.ones(tube.shape + (3,)) * 0.15, interpolation="nearest")
            im = axes[row, col].imshow(err, cmap="inferno", vmin=0, vmax=20, interpolation="nearest")
            over = np.zeros(tube.shape + (4,))
            over[mismatch] = (0.2, 0.9, 1.0, 1.0)
            axes[row, col].imshow(over, interpolation="nearest")
            mean = np.nanmean(err) if np.any(~np.isnan(err)) else 0
            axes[row, col].set_title(f"{label} tangent error\nmean {mean:.2f}°, hit/miss wrong {mismatch.sum()} px",
                                     fontsize=9)
            if row == 0 and col == 4:
                fig.colorbar(im, ax=axes[row, col], fraction=0.046, label="degrees")
    for ax in axes.flat:
        ax.set_xticks([])
        ax.set_yticks([])
    fig.suptitle("Ply tangents (colour = direction) and their error against explicit helix plies; "
                 "cyan = hit/miss disagrees", fontsize=11)
    fig.tight_layout()
    fig.savefig(out / "implicit-plies-tangents.png", dpi=80)
    plt.close(fig)


def draw_accuracy(table: pathlib.Path, out: pathlib.Path):
    rows = list(csv.DictReader(open(table)))
    fig, axes = plt.subplots(1, 3, figsize=(15, 4))
    styles = {"elliptical": ("C0", "-"), "circular": ("C3", ":")}
    for method, (colour, dash) in styles.items():
        for bend, marker in (("0", "o"), ("2", "s")):
            sel = [r for r in rows if r["method"] == method and r["bend"] == bend]
            views = sorted({float(r["view"]) for r in sel})
            agree = [np.mean([float(r["agreement"]) for r in sel if float(r["view"]) == v]) for v in views]
            tang = [np.mean([float(r["tangent_mean"]) for r in sel if float(r["view"]) == v]) for v in views]
            evals = [np.mean([float(r["evals_mean"]) for r in sel if float(r["view"]) == v]) for v in views]
            label = f"{method}, {'straight' if bend == '0' else 'bend 2R'}"
            axes[0].plot(views, agree, color=colour, linestyle=dash, marker=marker, label=label)
            axes[1].semilogy(views, np.maximum(tang, 1e-4), color=colour, linestyle=dash, marker=marker, label=label)
            if method != "circular":
                axes[2].plot(views, evals, color=colour, linestyle=dash, marker=marker, label=label)
    axes[0].set_title("hit/miss agreement with explicit plies (mean over 2, 3, 5, 12 plies)")
    axes[0].axhline(0.99, color="grey", linewidth=0.8)
    axes[1].set_title("mean ply tangent error (degrees)")
    axes[2].set_title("curve evaluations of the busiest ply (mean over rays)")
    for ax in axes:
        ax.set_xlabel("view angle from the yarn normal (degrees)")
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out / "implicit-plies-accuracy.png", dpi=80)
    plt.close(fig)


def draw_fibers(work: pathlib.Path, out: pathlib.Path):
    centres = np.load(work / "fiber_centres.npy")
    maps = np.load(work / "fiber_maps.npy")
    ply = np.load(work / "ply_shadowing.npy")
    along = np.load(work / "migration.npy")
    variants, n, _ = maps.shape
    angles = np.degrees(np.linspace(0, 2 * np.pi, n, endpoint=False))
    fig = plt.figure(figsize=(15, 7))
    ax = fig.add_subplot(2, 3, 1)
    radius = 1 / np.sqrt(50)
    for v in range(variants):
        sel = centres[:, 0] == v
        for x, y in centres[sel, 1:]:
            ax.add_patch(plt.Circle((x, y), radius, fill=(v == 0), alpha=0.5 if v == 0 else 0.6,
                                    color=f"C{v}", linewidth=0.8))
    ax.add_patch(plt.Circle((0, 0), 1, fill=False, color="k", linestyle="--"))
    ax.set_xlim(-1.3, 1.3)
    ax.set_ylim(-1.3, 1.3)
    ax.set_aspect("equal")
    ax.set_title("ply cross-section: fibers of the 4 migration variants")
    titles = ["fiber normal angle (deg)", "visible fiber phase (deg)", "its distance (ply radii)", "G_f"]
    for k in range(4):
        ax = fig.add_subplot(2, 3, 2 + k) if k < 2 else fig.add_subplot(2, 3, 2 + k)
        for v in range(variants):
            y = np.degrees(maps[v, :, k]) if k < 2 else maps[v, :, k]
            ax.plot(angles, y, linewidth=0.8, label=f"variant {v}")
        ax.set_title(titles[k])
        ax.set_xlabel("angle around the ply (deg)")
        if k == 0:
            ax.legend(fontsize=7)
    ax = fig.add_subplot(2, 3, 6)
    ax.plot(np.degrees(np.linspace(0, 2 * np.pi, len(ply), endpoint=False)), ply, color="k", label="G_p (3 plies)")
    ax.plot(along[:, 0] * 30, along[:, 2], color="C1", linewidth=0.8, label="G_f at one angle, along the ply\n"
                                                                         "(x: cells x 30, migration blend)")
    ax.set_title("ply shadowing around the yarn; migration blend")
    ax.set_xlabel("azimuth around the yarn (deg)")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out / "fiber-maps.png", dpi=80)
    plt.close(fig)


def summarise(table: pathlib.Path):
    rows = list(csv.DictReader(open(table)))
    print("| method | bend | view | agreement (min over plies) | tangent error mean (deg) | evals/ply |")
    print("|---|---|---|---|---|---|")
    for method in ("elliptical", "circular"):
        for bend in ("0", "8", "4", "2"):
            for view in ("0", "30", "45", "60", "70", "80", "85"):
                sel = [r for r in rows if r["method"] == method and r["bend"] == bend and r["view"] == view]
                if not sel:
                    continue
                agree = min(float(r["agreement"]) for r in sel)
                tang = np.mean([float(r["tangent_mean"]) for r in sel])
                evals = np.mean([float(r["evals_mean"]) for r in sel])
                print(f"| {method} | {bend} | {view} | {agree:.4f} | {tang:.3f} | {evals:.1f} |")
    total = sum(int(r["rays"]) for r in rows if r["method"] == "elliptical")
    unconverged = sum(int(r["unconverged"]) for r in rows if r["method"] == "elliptical")
    nonfinite = sum(int(r["non_finite"]) for r in rows)
    print(f"elliptical: {total} rays, {unconverged} unconverged, {nonfinite} non-finite (all methods)")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--out", default=str(ROOT / "docs/images"))
    parser.add_argument("--work", default="/tmp/yarn_maps")
    parser.add_argument("--no-table", action="store_true", help="skip the accuracy sweep")
    args = parser.parse_args()
    work, out = pathlib.Path(args.work), pathlib.Path(args.out)
    work.mkdir(parents=True, exist_ok=True)
    out.mkdir(parents=True, exist_ok=True)
    exe = build(work)
    subprocess.run([str(exe), "images", str(work)], check=True)
    subprocess.run([str(exe), "fibers", str(work)], check=True)
    draw_tangents(work, out)
    draw_fibers(work, out)
    table = work / "accuracy.csv"
    if not args.no_table:
        subprocess.run([str(exe), "table", str(table)], check=True)
    if table.exists():
        draw_accuracy(table, out)
        summarise(table)


if __name__ == "__main__":
    main()
