"""The production tier's plan and report logic (bench/production.py, worker_requests.py, yarn_keys.py,
report.production_goals, where_time_goes.py) on tiny synthetic inputs; nothing here is timed."""
import io
import json
import pathlib
import sys
import textwrap

import numpy as np
import pytest

BENCH = pathlib.Path(__file__).resolve().parents[2] / "bench"
sys.path.insert(0, str(BENCH))
import production  # noqa: E402
import report  # noqa: E402
import run  # noqa: E402
import where_time_goes  # noqa: E402
import worker_requests  # noqa: E402
import yarn_keys  # noqa: E402


def test_schedule_interleaves_methods_render_by_render_and_alternates_their_order():
    methods = ["a", "b", "trace"]
    steps = production.schedule(methods, [1, 4], rounds=3, reference_spp=8)
    series = [(m, r["spp"], r["seed"]) for m, r in steps if r["kind"] == "series"]
    assert series[:6] == [("a", 1, 101), ("b", 1, 101), ("trace", 1, 101), ("a", 4, 101), ("b", 4, 101),
                          ("trace", 4, 101)]
    assert [m for m, _, _ in series[6:9]] == ["trace", "b", "a"]  # second round runs backwards
    for m in methods:  # every method renders every sample count once per round, with the round's seed
        assert sorted((spp, seed) for n, spp, seed in series if n == m) == [
            (1, 101), (1, 118), (1, 135), (4, 101), (4, 118), (4, 135)]
    references = [(m, r["spp"], r["name"]) for m, r in steps if r["kind"] == "reference"]
    assert references == [("a", 4, "reference_a"), ("a", 4, "reference_b"), ("b", 4, "reference_a"),
                          ("b", 4, "reference_b")]  # halves of 8; the trace baseline has none
    assert all(r["kind"] == "reference" for _, r in steps[len(series):])  # after all timed renders
    kept = [(m, r["name"]) for m, r in steps if r["kind"] == "series" and r["keep"]]
    assert len(kept) == len(set(kept)) == 6  # the first round's images are the ones kept


def test_record_keeps_the_layout_of_one_shot_workers_whatever_the_order():
    record = worker_requests.Record()
    requests = worker_requests.series_requests([1, 4], repeats=2, reference_spp=16)
    for i, request in enumerate(reversed(requests)):
        record.add(request, "image %s" % request["name"], {"i": i})
    assert sorted(record.images) == ["reference_a", "reference_b", "spp1", "spp4"]
    assert [e["spp"] for e in record.series] == [4, 1] and all(len(e["runs"]) == 2 for e in record.series)
    assert record.reference["spp"] == 16 and len(record.reference["runs"]) == 2
    assert record.first_stats() == record.series[0]["runs"][0]
    assert worker_requests.reference_requests(0) == []


FAKE_WORKER = textwrap.dedent("""
    import sys
    sys.path.insert(0, %r)
    import worker_requests
    print("Blender-style noise on stdout")
    if "--die" in sys.argv:
        sys.exit(3)
    worker_requests.serve(lambda r: {"samples": r["spp"] * 2}, {"setup_seconds": 0.5})
""")


def test_worker_talks_the_serve_protocol_and_reports_a_dead_worker(tmp_path):
    script = tmp_path / "fake_worker.py"
    script.write_text(FAKE_WORKER % str(BENCH))
    with open(tmp_path / "log", "w") as log:
        worker = production.Worker([sys.executable, str(script)], None, log, timeout=60)
        assert worker.ready == {"setup_seconds": 0.5, "ready": True}
        reply = worker.render(worker_requests.series_request(4, 0))
        assert reply == {"name": "spp4", "stats": {"samples": 8}}
        assert worker.finish() is None
        dead = production.Worker([sys.executable, str(script), "--die"], None, log, timeout=60)
        assert dead.ready is None and dead.problem.startswith("failed: worker ended (exit 3")
        assert dead.render(worker_requests.series_request(1, 0)) is None
        assert dead.finish().startswith("failed")


def test_run_scene_reports_methods_that_cannot_start_and_renders_the_rest(tmp_path):
    script = tmp_path / "fake_worker.py"
    script.write_text(FAKE_WORKER % str(BENCH))
    commands = {"ok": ([sys.executable, str(script)], None), "skipped": "skipped: no bpy venv"}
    with open(tmp_path / "log", "w") as log:
        outcomes = production.run_scene("scene.json", ["ok", "skipped"], [1, 2], 4, 2, commands.get, log, 60)
    assert outcomes == {"skipped": "skipped: no bpy venv", "ok": None}


def bspline_point(p, t):
    w = np.array([(1 - t) ** 3, 3 * t**3 - 6 * t**2 + 4, -3 * t**3 + 3 * t**2 + 3 * t + 1, t**3]) / 6
    return w @ p


def test_segment_keys_sample_each_segment_at_start_and_middle_and_close_each_curve():
    rng = np.random.default_rng(2)
    points = rng.uniform(-1, 1, (9, 3))
    radii = np.linspace(0.1, 0.9, 9)
    # Curve 0: a chain of 5 points (2 segments); curve 1: one separate 4-point segment.
    segments = np.array([0, 1, 5])
    keys, key_radii, counts = yarn_keys.segment_keys(points, radii, segments, np.array([0, 2, 3]))
    assert counts.tolist() == [5, 3]
    np.testing.assert_allclose(keys[0], bspline_point(points[0:4], 0.0))
    np.testing.assert_allclose(keys[1], bspline_point(points[0:4], 0.5))
    np.testing.assert_allclose(keys[2], bspline_point(points[1:5], 0.0))
    np.testing.assert_allclose(keys[4], bspline_point(points[1:5], 1.0))
    np.testing.assert_allclose(keys[7], bspline_point(points[5:9], 1.0))
    np.testing.assert_allclose(key_radii[6], bspline_point(radii[5:9], 0.5))


def test_shared_models_are_found_beside_any_folder_above_the_repository(tmp_path, monkeypatch):
    (tmp_path / "shared" / "data").mkdir(parents=True)
    (tmp_path / "shared" / "data" / "m.bcc").write_bytes(b"")
    monkeypatch.setattr(run, "ROOT", tmp_path / "worktrees" / "repo")
    missing = str(tmp_path / "worktrees" / "shared" / "data" / "m.bcc")
    assert run.shared_model(missing) == str(tmp_path / "shared" / "data" / "m.bcc")
    assert run.shared_model(str(tmp_path / "elsewhere" / "m.bcc")) == str(tmp_path / "elsewhere" / "m.bcc")


def result(us, to_target=None, vs_auto=None):
    return {"us_per_sample": us, "time_to_target": to_target, "time_vs_auto": vs_auto}


def test_production_goals_are_judged_per_scene_and_as_medians_of_the_close_ups():
    scenes = [
        {"scene": "close_a", "results": {
            "bysdf-near": result(4.0, 2.0), "bysdf-multi": result(5.0, 1.0), "bysdf-far": result(3.0, 3.0),
            "bysdf-auto": result(5.0, 1.05, 1.0), "ply": result(5.0, 4.0, 4.0), "placeholder": result(2.0),
            "cycles-ply": result(9.0, 8.0, 8.0)}},
        {"scene": "close_b", "results": {
            "bysdf-near": result(6.0, 2.0), "bysdf-auto": result(6.0, 3.0, 1.0), "ply": result(5.0, 6.0, 2.0),
            "placeholder": result(2.0), "cycles-ply": result(9.0, 12.0, 4.0)}},
        {"scene": "garment", "results": {"bysdf-auto": result(1.0, 1.0, 1.0), "ply": result(1.0, 9.0, 9.0)}},
    ]
    goals = {goal.split(" (")[0].split(" <=")[0].split(" >=")[0]: (text, met) for goal, text, met in
             report.production_goals(scenes, ["close_a", "close_b"])}
    assert goals["BYSDF near µs/sample"] == ("close_a 0.80, close_b 1.20", False)
    assert goals["equal-quality time ply / bysdf-auto"] == ("3.00 (close_a 4.00, close_b 2.00)", True)
    assert goals["equal-quality time fiber / bysdf-auto"][1] is None  # not measured is not judged
    assert goals["equal-quality time cycles-ply / bysdf-auto"][1] is True  # median 6 >= 5
    assert goals["µs/sample bysdf-auto / placeholder on the same tubes"] == (
        "close_a 2.50, close_b 3.00, garment –", False)
    text, met = goals["equal-quality time bysdf-auto / fastest of near, multi, far"]
    assert text == "close_a 1.05, close_b 1.50, garment –" and met is False
    # Far converges soonest on close_a, but to another look: left out when only modes that keep
    # near's look count.
    scenes[0]["results"]["bysdf-far"]["time_to_target"] = 0.5
    scenes[0]["results"]["bysdf-far"]["flip_vs_near"] = 0.2
    scenes[0]["results"]["bysdf-multi"]["flip_vs_near"] = 0.005
    goals = [(goal, text) for goal, text, _ in report.production_goals(scenes, ["close_a", "close_b"])]
    assert goals[-2][1].startswith("close_a 2.10")  # against far
    assert "of those within FLIP 0.01" in goals[-1][0] and goals[-1][1].startswith("close_a 1.05")  # multi


CALLGRIND = textwrap.dedent("""\
    version: 1
    creator: callgrind-3.19.0
    positions: line
    events: Ir
    summary: 1000

    fn=(1) purl::Renderer::render_pixel(int, int) const
    0 100
    cfn=(2) purl::EmbreeScene::intersect(purl::Ray const&, purl::SurfaceHit&) const
    calls=3 0
    0 200
    cfn=(3) purl::SurfaceShader::shade(purl::SurfaceHit const&) const
    calls=3 0
    0 500
    cfn=(4) purl::Lights::sample(purl::Vec3) const
    calls=2 0
    0 50
    cfn=(5) purl::ShadingPoint::eval(purl::Vec3) const
    calls=2 0
    0 150

    fn=(2)
    0 200

    fn=(3)
    0 100
    cfn=(6) purl::trace_yarn_hit(purl::CurveFrames const&) const
    calls=3 0
    0 400

    fn=(6)
    0 200
    cfn=(9) purl::(anonymous namespace)::shade(purl::PlyHit const&)
    calls=2 0
    0 200

    fn=(9)
    0 50
    cfn=(7) purl::FiberMaps::lookup(float) const
    calls=2 0
    0 150

    fn=(7)
    0 150

    fn=(4)
    0 50

    fn=(5)
    0 50
    cfn=(8) purl::BsdfEvalPdf purl::Bysdf::evaluate<false>(purl::Vec3) const
    calls=2 0
    0 100

    fn=(8)
    0 100
    """)


def test_callgrind_breakdown_splits_the_render_into_stages_and_components(tmp_path):
    path = tmp_path / "full.callgrind"
    path.write_text(CALLGRIND)
    profile = where_time_goes.Profile(path)
    assert profile.total() == 1000
    assert profile.calls_from(r"^purl::trace_yarn_hit", r"^purl::\(anonymous namespace\)::shade") == (200, 2)
    b = where_time_goes.breakdown(path, path, samples=10)
    stages = {r["name"]: r["instructions"] for r in b["stages"]}
    assert stages["traversal: camera, bounce and pass-through rays"] == 200
    assert stages["shading hits"] == 500 and stages["light samples"] == 200
    assert stages["camera rays, random numbers, path loop"] == 100
    assert sum(stages.values()) == 1000
    parts = {p["name"]: p["instructions"] for r in b["stages"] for p in r["parts"]}
    assert parts["light: BYSDF eval"] == 150 and parts["light: pick a point"] == 50
    assert parts["hit: implicit ply search, fiber maps (trace_yarn_hit)"] == 400
    assert all(r["camera_depth"] == r["instructions"] for r in b["stages"])  # the same file twice
    components = {r["name"]: r["instructions"] for r in b["components"]}
    assert components["lobes: BYSDF eval / sample / pdf"] == 100
    assert components["fiber maps"] == 150
    # trace_yarn_hit and the helper only it calls, without the fiber map lookups inside the helper.
    assert components["implicit ply search"] == 250
    assert components["the rest: camera, path loop, frames, film"] == 250  # render_pixel, shade, eval
    assert components["traversal (Embree)"] == 200
    assert sum(components.values()) == 1000
    assert b["pass_through"]["passes"] == 1  # 3 shade calls, 2 scatterings (light samples)
    assert b["pass_through"]["estimated_instructions"] == int(500 / 3 + 200 / 3)
    out = io.StringIO()
    where_time_goes.print_breakdown(b, out)
    assert "pass-through: 1 of 3 shade calls" in out.getvalue()
    (tmp_path / "camera.callgrind").write_text(CALLGRIND)
    (tmp_path / "breakdown.json").write_text(json.dumps({"samples": 10, "scene": "glove_close.json", "mode": "near"}))
    assert where_time_goes.reanalysed(tmp_path)["total"] == 1000  # keeps the profile's settings
    out = io.StringIO()
    where_time_goes.table([tmp_path], out)
    assert "| %s (near) |" % tmp_path.name in out.getvalue() and "| **total** | 100 |" in out.getvalue()
    assert "| shading hits | 50 (50.0 %), 100.0 % at camera depth |" in out.getvalue()


def test_production_suite_scenes_exist_and_fit_the_tier():
    suite = production.production_suite(run.ROOT)
    names = [s[0] for s in suite]
    assert set(production.CLOSE_UPS) < set(names) and len(names) >= 5
    for name, path, size, series, reference_spp, methods in suite:
        assert path.exists(), path
        assert size[0] * size[1] >= 320 * 240
        assert {"bysdf-near", "bysdf-multi", "bysdf-far", "bysdf-auto", "ply", "placeholder", "trace",
                "cycles-ply", "cycles-yarn"} <= set(methods)


@pytest.mark.parametrize("name", ["yarn_macro", "woven_close"])
def test_production_scenes_are_valid_json_with_a_bysdf_yarn(name):
    scene = json.loads((BENCH / "scenes" / "production" / (name + ".json")).read_text())
    assert scene["yarns"][0]["material"]["model"] == "bysdf"
