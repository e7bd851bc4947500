#!/usr/bin/env python3
"""Where a render's time goes, in instructions (valgrind's callgrind: repeatable on a loaded machine).

  python3 bench/where_time_goes.py profile SCENE.json --out DIR [--size 320x240] [--spp 1]
          [--crop 0.5] [--mode auto] [--ply-method M] [--model ply] [--build-dir build]
      renders the scene twice under callgrind with one thread, counting only inside
      Renderer::render_pixel (no scene loading, no BVH build): as it is (DIR/full.callgrind) and
      with render.max_depth 1 (DIR/camera.callgrind: camera rays and the work at their hits, no
      bounces); writes DIR/breakdown.json and prints the breakdown. --crop F renders only the
      centre F x F of the image at the same pixel scale (film and focal length scaled), which keeps
      yarns as wide in pixels as at the full size for 1/F^2 of the callgrind time.
  python3 bench/where_time_goes.py breakdown DIR
      the breakdown of a profile's callgrind files computed again (after this tool changed).
  python3 bench/where_time_goes.py table DIR [DIR ...]
      the breakdowns of several profiles side by side, as a Markdown table (docs/benchmarks.md).

Two views of the same instructions (docs/benchmarks.md, "Where the time goes"):
  stages      what render_pixel calls, split up by its calls: traversal of camera, bounce and
              pass-through rays; shading at hits (camera depth from the max_depth 1 run, bounces the
              rest); light samples (sampling the light, the tube exit towards it, the BYSDF eval and
              pdf, the shadow ray); BSDF sampling (next direction and its tube exit); emitters; the
              rest (camera rays, random numbers, the path loop). Pass-through: shade() calls that
              found no ply (shade calls minus light-sample calls, one per scattering), costed at the
              mean shade() call plus one more traversal each (an estimate: callgrind counts per
              function, not per outcome).
  components  the same total split by what the code does wherever it is called: lobes (BYSDF
              eval / sample / pdf, far table lookups), fiber maps, tube exits, traversal (Embree),
              the implicit ply search, multi-scale (footprint, virtual rays, mixture), explicit ply
              shading, lights, the rest; a function of none of them is shared among its callers'
              components by what their calls cost (gprof's assumption: every call costs the same).
"""
import argparse
import collections
import json
import pathlib
import re
import subprocess
import sys
import tempfile

ROOT_FUNCTION = "purl::Renderer::render_pixel"
STAGES = [  # (name, what render_pixel calls directly)
    ("traversal: camera, bounce and pass-through rays", r"^purl::EmbreeScene::intersect\("),
    ("shading hits", r"^purl::SurfaceShader::shade\("),
    ("light samples", r"^purl::(Lights::sample|ShadingPoint::(leave|eval|pdf)|EmbreeScene::occluded)\("),
    ("BSDF sampling: next direction and its exit", r"^purl::ShadingPoint::sample\("),
    ("emitters and background", r"^purl::Lights::(intersect_emitter|background|environment_hit|for_each)"),
]
SHADE = r"^purl::SurfaceShader::shade\("
STAGE_PARTS = {  # stage -> (caller, [(part, callee)]): what one stage's calls go to
    "shading hits": (SHADE, [
        ("hit: implicit ply search, fiber maps (trace_yarn_hit)", r"^purl::trace_yarn_hit\("),
        ("hit: multi-scale footprint, virtual rays, mixture", r"^purl::SurfaceShader::shade_multiscale\("),
        ("hit: far-field table", r"^purl::SurfaceShader::shade_far\("),
        ("hit: explicit ply / fiber shading", r"^purl::SurfaceShader::shade_(ply|fiber)\("),
    ]),
    "light samples": ("^" + re.escape(ROOT_FUNCTION) + r"\(", [
        ("light: pick a point", r"^purl::Lights::sample\("),
        ("light: tube exit", r"^purl::ShadingPoint::leave\("),
        ("light: BYSDF eval", r"^purl::ShadingPoint::eval\("),
        ("light: BYSDF pdf", r"^purl::ShadingPoint::pdf\("),
        ("light: shadow ray", r"^purl::EmbreeScene::occluded\("),
    ]),
}
COMPONENTS = [  # counted in this order, each outside the ones before
    ("lobes: BYSDF eval / sample / pdf", r"^(purl::BsdfEvalPdf )?purl::(Bysdf|FarFieldBsdf|PlaceholderYarnBsdf|"
                                         r"FiberBcsdf)::(?!Bysdf\(|pass_fraction)"),
    ("fiber maps", r"^purl::FiberMaps::(lookup|ply_shadowing|sample|sample_pair|unpack|variant_of)\("),
    ("tube exits", r"^purl::(tube_exit|tube_chord_length|ExplicitPlies::tube_exit)\("),
    ("traversal (Embree)", r"^(rtc|purl::EmbreeScene::(intersect|occluded)\()"),
    ("implicit ply search", r"^purl::(trace_yarn_hit|trace_plies|trace_plies_local|shade_ply_hit)\("),
    ("multi-scale: footprint, virtual rays, mixture",
     r"^purl::(MultiscaleBysdf::|MultiscaleSelector::|yarn_footprint)"),
    ("explicit ply shading", r"^purl::SurfaceShader::shade_(ply|fiber)\("),
    ("lights", r"^purl::Lights::"),
]
NAME_TABLES = {"fn": "fn", "cfn": "fn", "fl": "fl", "fi": "fl", "fe": "fl", "cfi": "fl", "cfl": "fl", "ob": "ob",
               "cob": "ob"}


class Profile:
    """Self costs per function and inclusive costs and call counts per call arc (caller, callee) of
    one callgrind output file (first event, Ir)."""

    def __init__(self, path):
        self.self_cost = collections.Counter()
        self.arc_cost = collections.Counter()
        self.arc_calls = collections.Counter()
        names = {"fn": {}, "fl": {}, "ob": {}}
        fn = cfn = None
        pending_calls = None
        with open(path, encoding="utf-8", errors="replace") as f:
            for line in f:
                line = line.rstrip("\n")
                if not line or line[0] == "#":
                    continue
                key, eq, value = line.partition("=")
                if eq and key in NAME_TABLES:
                    name = self._name(names[NAME_TABLES[key]], value)
                    if key == "fn":
                        fn = name
                    elif key == "cfn":
                        cfn = name
                    continue
                if eq and key == "calls":
                    pending_calls = int(value.split()[0])
                    continue
                if not (line[0].isdigit() or line[0] in "+-*"):
                    continue  # header lines (events:, totals:, ...) and jump lines
                parts = line.split()
                cost = int(parts[1]) if len(parts) > 1 else 0
                if pending_calls is not None:
                    self.arc_cost[(fn, cfn)] += cost
                    self.arc_calls[(fn, cfn)] += pending_calls
                    pending_calls = None
                else:
                    self.self_cost[fn] += cost

    @staticmethod
    def _name(table, value):
        """Callgrind's name compression: '(id) name' defines an id, '(id)' refers to it."""
        match = re.match(r"\((\d+)\)(?: (.*))?$", value)
        if not match:
            return value
        if match.group(2) is not None:
            table[match.group(1)] = match.group(2)
        return table.get(match.group(1), value)

    def total(self):
        return sum(self.self_cost.values())

    def functions(self):
        return set(self.self_cost) | {f for arc in self.arc_cost for f in arc}

    def matching(self, pattern):
        regex = re.compile(pattern)
        return {f for f in self.functions() if f and regex.search(base_name(f))}

    def calls_from(self, caller_pattern, callee_pattern):
        callers, callees = self.matching(caller_pattern), self.matching(callee_pattern)
        cost = sum(c for (a, b), c in self.arc_cost.items() if a in callers and b in callees)
        calls = sum(n for (a, b), n in self.arc_calls.items() if a in callers and b in callees)
        return cost, calls


def base_name(name):
    """Without callgrind's recursion suffix ('2) and the object file in brackets."""
    return re.sub(r"'\d+$", "", name)


def stages(profile):
    """Rows of what render_pixel's calls cost, each with the parts of STAGE_PARTS under it."""
    root = "^" + re.escape(ROOT_FUNCTION) + r"\("
    rows = []
    for name, pattern in STAGES:
        cost, calls = profile.calls_from(root, pattern)
        caller, parts = STAGE_PARTS.get(name, (None, []))
        rows.append({"name": name, "instructions": cost, "calls": calls, "parts": [
            dict(zip(("name", "instructions", "calls"), (n,) + profile.calls_from(caller, p))) for n, p in parts]})
    rows.append({"name": "camera rays, random numbers, path loop", "parts": [],
                 "instructions": profile.total() - sum(r["instructions"] for r in rows), "calls": None})
    return rows


def components(profile):
    """Every function's own instructions go to the component it belongs to, or, when it belongs to
    none, to its callers' components in proportion to what each call arc cost (as gprof shares a
    function among its callers): time in the fiber maps counts as fiber maps wherever they are
    called from, a helper counts where it is used."""
    patterns = [re.compile(p) for _, p in COMPONENTS]
    rest = len(COMPONENTS)
    incoming = collections.defaultdict(list)
    for (caller, callee), cost in profile.arc_cost.items():
        if caller != callee and cost > 0:
            incoming[callee].append((caller, cost))
    shares = {}

    def share_of(f, visiting):
        if f in shares:
            return shares[f]
        own = next((i for i, p in enumerate(patterns) if f and p.search(base_name(f))), None)
        callers = [(c, cost) for c, cost in incoming[f] if c not in visiting]
        if own is not None or not callers:
            result = {rest if own is None else own: 1.0}
        else:
            result = collections.Counter()
            weight = sum(cost for _, cost in callers)
            for caller, cost in callers:
                for component, fraction in share_of(caller, visiting | {f}).items():
                    result[component] += fraction * cost / weight
        shares[f] = result
        return result

    totals = collections.Counter()
    for f, cost in profile.self_cost.items():
        for component, fraction in share_of(f, frozenset()).items():
            totals[component] += cost * fraction
    names = [n for n, _ in COMPONENTS] + ["the rest: camera, path loop, frames, film"]
    return [{"name": n, "instructions": int(round(totals[i]))} for i, n in enumerate(names)]


def breakdown(full, camera=None, samples=None):
    """The breakdown of a full-depth profile, split by depth with a max_depth 1 profile of the same render."""
    a = Profile(full)
    stage_rows = stages(a)
    root = "^" + re.escape(ROOT_FUNCTION) + r"\("
    shade_cost, shade_calls = a.calls_from(root, SHADE)
    _, scatterings = a.calls_from(root, r"^purl::Lights::sample\(")
    trace_cost, trace_calls = a.calls_from(root, r"^purl::EmbreeScene::intersect\(")
    passes = shade_calls - scatterings
    result = {"total": a.total(), "samples": samples, "stages": stage_rows,
              "components": components(a),
              "pass_through": {"shade_calls": shade_calls, "passes": passes,
                               "estimated_instructions": int(passes * (shade_cost / max(shade_calls, 1) +
                                                                       trace_cost / max(trace_calls, 1)))}}
    if camera is not None:
        b = Profile(camera)
        for row, at_camera in zip(stage_rows, stages(b)):
            row["camera_depth"] = at_camera["instructions"]
            for part, part_at_camera in zip(row["parts"], at_camera["parts"]):
                part["camera_depth"] = part_at_camera["instructions"]
        _, camera_shade_calls = b.calls_from(root, SHADE)
        _, camera_scatterings = b.calls_from(root, r"^purl::Lights::sample\(")
        result["pass_through"]["camera_passes"] = camera_shade_calls - camera_scatterings
        result["camera_total"] = b.total()
    return result


def fmt_share(value, total):
    return "%.1f %%" % (100.0 * value / total) if total else "–"


def print_breakdown(result, out=sys.stdout):
    total, samples = result["total"], result.get("samples")
    per = (lambda v: "%8.0f" % (v / samples)) if samples else (lambda v: "%8s" % "–")
    out.write("%-50s %16s %8s %7s %s\n" % ("stage", "instructions", "/sample", "share",
                                          "at camera depth" if "camera_total" in result else ""))
    for row in [r for stage in result["stages"] for r in [stage] + [dict(p, name="  " + p["name"])
                                                                    for p in stage["parts"]]]:
        extra = fmt_share(row["camera_depth"], row["instructions"]) if "camera_depth" in row else ""
        out.write("%-50s %16d %s %7s %s\n" % (row["name"], row["instructions"], per(row["instructions"]),
                                              fmt_share(row["instructions"], total), extra))
    p = result["pass_through"]
    out.write("pass-through: %d of %d shade calls found no ply (%s); about %s of the render (estimated)\n" % (
        p["passes"], p["shade_calls"], fmt_share(p["passes"], p["shade_calls"]),
        fmt_share(p["estimated_instructions"], total)))
    out.write("\n%-50s %16s %8s %7s\n" % ("component", "instructions", "/sample", "share"))
    for row in result["components"]:
        out.write("%-50s %16d %s %7s\n" % (row["name"], row["instructions"], per(row["instructions"]),
                                           fmt_share(row["instructions"], total)))
    out.write("%-50s %16d %s\n" % ("total (render_pixel)", total, per(total)))


def profile(args):
    sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
    import run  # bench/run.py: the benchmark's scene preparation (film size, shared models)

    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    full_width, full_height = (int(v) for v in args.size.split("x"))
    width, height = round(full_width * args.crop), round(full_height * args.crop)
    scene_file = run.prepared_scene(pathlib.Path(args.scene), (width, height), out)
    scene = json.loads(scene_file.read_text(encoding="utf-8"))
    camera = scene["camera"]
    camera["lens"] = camera.get("lens", 50) * full_width / width  # the same angle per pixel
    purl = pathlib.Path(args.build_dir) / "purl"
    files = {}
    for label, depth in (("full", None), ("camera", 1)):
        if depth is not None:
            scene.setdefault("render", {})["max_depth"] = depth
        path = out / ("scene_%s.json" % label)
        path.write_text(json.dumps(scene, indent=1), encoding="utf-8")
        files[label] = out / ("%s.callgrind" % label)
        cmd = ["valgrind", "--tool=callgrind", "--collect-atstart=no", "--toggle-collect=%s*" % ROOT_FUNCTION,
               "--callgrind-out-file=%s" % files[label], str(purl), "render", str(path), "-o",
               str(pathlib.Path(tempfile.gettempdir()) / ("purl-where-%s.exr" % label)), "--spp", str(args.spp),
               "--threads", "1", "--stats"]
        if args.mode:
            cmd += ["--mode", args.mode]
        if args.ply_method:
            cmd += ["--ply-method", args.ply_method]
        if args.model:
            cmd += ["--model", args.model]
        print("where_time_goes: %s" % " ".join(cmd), file=sys.stderr, flush=True)
        p = subprocess.run(cmd, capture_output=True, text=True)
        (out / ("%s.log" % label)).write_text(p.stdout + p.stderr, encoding="utf-8")
        if p.returncode != 0:
            sys.exit("where_time_goes: the render failed (%s)" % (out / ("%s.log" % label)))
    result = breakdown(files["full"], files["camera"], samples=width * height * args.spp)
    mode = args.mode or scene.get("render", {}).get("multiscale", {}).get("mode", "auto")
    result.update({"scene": str(args.scene), "size": [full_width, full_height], "crop": [width, height],
                   "spp": args.spp, "mode": mode, "model": args.model or "bysdf",
                   "ply_method": args.ply_method, "far_table_built": "tabulating" in (out / "full.log").read_text()})
    (out / "breakdown.json").write_text(json.dumps(result, indent=1), encoding="utf-8")
    print_breakdown(result)


def reanalysed(folder):
    """A profile folder's breakdown computed again from its callgrind files (after this tool changed)."""
    old = json.loads((folder / "breakdown.json").read_text(encoding="utf-8"))
    result = breakdown(folder / "full.callgrind", folder / "camera.callgrind", old["samples"])
    result.update({k: v for k, v in old.items() if k not in result})
    (folder / "breakdown.json").write_text(json.dumps(result, indent=1), encoding="utf-8")
    return result


def table(dirs, out=sys.stdout):
    """Markdown: one column per profile, instructions per sample and share."""
    results = [json.loads((pathlib.Path(d) / "breakdown.json").read_text(encoding="utf-8")) for d in dirs]
    heads = ["%s (%s)" % (pathlib.Path(d).name, r["mode"] if r.get("model", "bysdf") == "bysdf" else r["model"])
             for d, r in zip(dirs, results)]
    out.write("| instructions per sample (share) | %s |\n|---|%s\n" % (" | ".join(heads), "---|" * len(results)))

    def row(name, values):
        out.write("| %s | %s |\n" % (name, " | ".join(values)))

    def cell(value, r):
        return "%.0f (%s)" % (value / r["samples"], fmt_share(value, r["total"]))

    def staged(stage, r):
        depth = stage.get("camera_depth")
        text = cell(stage["instructions"], r)
        return text if depth is None else "%s, %s at camera depth" % (text, fmt_share(depth, stage["instructions"]))

    for i, stage in enumerate(results[0]["stages"]):
        row(stage["name"], [staged(r["stages"][i], r) for r in results])
        for j, part in enumerate(stage["parts"]):
            if any(r["stages"][i]["parts"][j]["instructions"] for r in results):
                row("&nbsp; " + part["name"], [staged(r["stages"][i]["parts"][j], r) for r in results])
    row("pass-through: shade calls finding no ply", ["%d of %d (%s)" % (
        r["pass_through"]["passes"], r["pass_through"]["shade_calls"],
        fmt_share(r["pass_through"]["passes"], r["pass_through"]["shade_calls"])) for r in results])
    row("pass-through: cost (estimated)", [cell(r["pass_through"]["estimated_instructions"], r) for r in results])
    row("**by component**", ["" for _ in results])
    for i, comp in enumerate(results[0]["components"]):
        if any(r["components"][i]["instructions"] for r in results):
            row(comp["name"], [cell(r["components"][i]["instructions"], r) for r in results])
    row("**total**", ["%.0f" % (r["total"] / r["samples"]) for r in results])


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = parser.add_subparsers(dest="command", required=True)
    p = sub.add_parser("profile")
    p.add_argument("scene")
    p.add_argument("--out", required=True)
    p.add_argument("--size", default="320x240")
    p.add_argument("--spp", type=int, default=1)
    p.add_argument("--crop", type=float, default=1.0, help="render the centre crop this fraction of each side")
    p.add_argument("--mode", choices=["near", "multi", "far", "auto"])
    p.add_argument("--ply-method")
    p.add_argument("--model", choices=["bysdf", "ply", "fiber"], help="yarn model (default bysdf)")
    p.add_argument("--build-dir", default=str(pathlib.Path(__file__).resolve().parents[1] / "build"))
    b = sub.add_parser("breakdown")
    b.add_argument("dir", help="a folder written by profile: re-reads its callgrind files")
    t = sub.add_parser("table")
    t.add_argument("dirs", nargs="+")
    args = parser.parse_args()
    if args.command == "profile":
        profile(args)
    elif args.command == "breakdown":
        print_breakdown(reanalysed(pathlib.Path(args.dir)))
    else:
        table(args.dirs)
    return 0


if __name__ == "__main__":
    sys.exit(main())
