// The Flamenco job type farm/flamenco/purl_render.js, compiled by the Manager stand-in
// farm/flamenco/local_manager.js: the tasks and the blender-render commands it produces.
// Run: node --test tests/farm/   (tests/farm/test_farm.py runs the commands in Blender)
"use strict";

const assert = require("node:assert/strict");
const path = require("node:path");
const test = require("node:test");

const { loadJobType, frameChunker } = require("../../farm/flamenco/local_manager.js");

const SCRIPT = path.join(__dirname, "..", "..", "farm", "flamenco", "purl_render.js");
const jobTypeScript = loadJobType(SCRIPT);

// Settings as the Flamenco add-on submits them for a three-frame Purl scene.
function settings(overrides) {
    return Object.assign({
        frames: "1-3", chunk_size: 2, render_output_root: "/render",
        render_output_path: "/render/knit/######", addon_module: "purl", threads: 0,
        samples: 16, seed: 7, animated_seed: true, max_bounces: 8, clamp: 0.5,
        scale: "AUTO", ply_search: "LOCAL",
        blendfile: "/shared/jobs/knit/knit.blend", scene: "Scene", format: "PNG",
    }, overrides);
}

function compile(overrides) {
    return jobTypeScript.compile({ name: "knit", settings: settings(overrides) });
}

function argAfter(args, flag) {
    const index = args.indexOf(flag);
    assert.notEqual(index, -1, `${flag} missing from ${JSON.stringify(args)}`);
    return args[index + 1];
}

test("the job type is named after its file and declares well-formed settings", () => {
    const jobType = jobTypeScript.jobType;
    assert.equal(jobType.name, "purl-render");
    assert.equal(jobType.label, "Purl Render");
    const keys = jobType.settings.map((s) => s.key);
    assert.equal(new Set(keys).size, keys.length, "setting keys repeat");
    for (const setting of jobType.settings) {
        assert.ok(["string", "int32", "float", "bool"].includes(setting.type), setting.key);
        assert.ok(setting.description, `${setting.key} has no description`);
        if ("visible" in setting) assert.ok(["submission", "web", "hidden"].includes(setting.visible), setting.key);
    }
    for (const key of ["frames", "chunk_size", "render_output_root", "blendfile", "scene", "format"]) {
        assert.ok(keys.includes(key), key);
    }
});

test("frames are split into chunks, one blender-render task each", () => {
    const job = compile({ frames: "1-3", chunk_size: 2 });
    assert.deepEqual(job.tasks.map((t) => t.name), ["render-1,2", "render-3"]);
    for (const task of job.tasks) {
        assert.equal(task.type, "blender");
        assert.equal(task.commands.length, 1);
        assert.equal(task.commands[0].name, "blender-render");
    }
    const frames = job.tasks.map((t) => argAfter(t.commands[0].parameters.args, "--render-frame"));
    assert.deepEqual(frames, ["1,2", "3"]);
});

test("chunks use Blender's frame notation", () => {
    const frames = (spec, size) => compile({ frames: spec, chunk_size: size })
        .tasks.map((t) => argAfter(t.commands[0].parameters.args, "--render-frame"));
    assert.deepEqual(frames("1-10", 4), ["1..4", "5..8", "9,10"]);
    assert.deepEqual(frames("1-3,7,20..22", 10), ["1..3,7,20..22"]);
    assert.deepEqual(frames("5", 1), ["5"]);
    assert.deepEqual(frames("3,1,2,2", 1), ["1", "2", "3"]);
});

test("the command is {blender} {blenderArgs} --addons <module> <blendfile> <render args>", () => {
    const parameters = compile({ chunk_size: 3 }).tasks[0].commands[0].parameters;
    assert.equal(parameters.exe, "{blender}");
    assert.equal(parameters.exeArgs, "{blenderArgs}");
    assert.deepEqual(parameters.argsBefore, ["--addons", "purl"]);
    assert.equal(parameters.blendfile, "/shared/jobs/knit/knit.blend");
    const args = parameters.args;
    assert.equal(argAfter(args, "--scene"), "Scene");
    assert.equal(argAfter(args, "--engine"), "PURL");
    assert.equal(argAfter(args, "--render-output"), "/render/knit/######");
    assert.equal(argAfter(args, "--render-format"), "PNG");
    assert.equal(argAfter(args, "--render-frame"), "1..3");
    // Blender reads its arguments in order: the settings script needs the exit-code switch before
    // it, and the frames are rendered last, once output and format are set.
    assert.ok(args.indexOf("--python-exit-code") < args.indexOf("--python-expr"));
    assert.equal(args[args.length - 2], "--render-frame");
    for (const flag of ["--engine", "--render-output", "--render-format", "--python-expr"]) {
        assert.ok(args.indexOf(flag) < args.indexOf("--render-frame"), flag);
    }
});

test("the extension's module name and a thread count reach the command line", () => {
    const parameters = compile({ addon_module: "bl_ext.user_default.purl", threads: 1 })
        .tasks[0].commands[0].parameters;
    assert.deepEqual(parameters.argsBefore, ["--addons", "bl_ext.user_default.purl", "--threads", "1"]);
});

test("the job's Purl settings are written into the scene before rendering", () => {
    const args = compile({ scene: "Shot \"A\"" }).tasks[0].commands[0].parameters.args;
    const script = argAfter(args, "--python-expr").split("\n");
    assert.equal(script[1], "scene = bpy.data.scenes[\"Shot \\\"A\\\"\"]");
    assert.match(script[3], /raise RuntimeError\(.*'purl' is not installed on this worker/);
    assert.equal(script[4], "missing = importlib.import_module(\"purl.scripting\").missing_input_files(scene)");
    assert.match(script[6], /raise RuntimeError\('Purl: files missing on this worker: '/);
    const assignments = script.slice(7);
    assert.deepEqual(assignments, [
        "scene.purl.samples = 16",
        "scene.purl.seed = 7",
        "scene.purl.use_animated_seed = True",
        "scene.purl.max_depth = 8",
        "scene.purl.clamp = 0.5",
        "scene.purl.multiscale_mode = \"AUTO\"",
        "scene.purl.ply_method = \"LOCAL\"",
    ]);
});

test("settings left out are not written", () => {
    const args = compile({ samples: undefined, clamp: null }).tasks[0].commands[0].parameters.args;
    const script = argAfter(args, "--python-expr");
    assert.doesNotMatch(script, /samples|clamp/);
    assert.match(script, /scene\.purl\.seed = 7/);
});

test("bad settings stop the job with a message naming the setting", () => {
    assert.throws(() => compile({ blendfile: "" }), /"blendfile" is required/);
    assert.throws(() => compile({ chunk_size: 0 }), /chunk_size must be at least 1/);
    assert.throws(() => compile({ addon_module: "purl; rm -rf /" }), /not a Python module name/);
    assert.throws(() => compile({ threads: -2 }), /threads must be 0/);
    assert.throws(() => compile({ frames: "1-x" }), /invalid range/);
});

test("frameChunker matches Flamenco's: runs of three or more as A-B, pairs as A,B", () => {
    assert.deepEqual(frameChunker("1-5", 2), ["1,2", "3,4", "5"]);
    assert.deepEqual(frameChunker("1..3, 10", 10), ["1-3,10"]);
    assert.throws(() => frameChunker("", 1), /empty range/);
    assert.throws(() => frameChunker("-3", 1), /invalid range/);
    assert.throws(() => frameChunker("1-3", 0), /invalid chunk size/);
});

test("the job type runs with the Manager's globals alone (no Node.js modules)", () => {
    for (const name of ["require", "process", "module", "console", "Buffer", "setTimeout"]) {
        assert.equal(typeof jobTypeScript.context[name], "undefined", name);
    }
    assert.equal(compile({}).tasks.length, 2);
});
