// SPDX-License-Identifier: GPL-3.0-or-later
//
// "Purl Render": a Flamenco v3 job type that renders frames of a Blend file with Purl, the
// yarn-level cloth renderer, one task per chunk of frames.
//
// Install: copy this file into the `scripts/` folder next to the flamenco-manager executable
// (create it if needed) and restart the Manager; "Purl Render" then appears among the job types
// in the Flamenco add-on (press the refresh button there). Workers need Blender with the Purl
// add-on installed; enabling it in their preferences is not needed: every task enables it
// with --addons (docs/farm.md).
//
// Each task runs
//   {blender} {blenderArgs} --addons <module> [--threads N] <blendfile>
//       --scene <scene> --python-exit-code 1 --python-expr <Purl settings of this job>
//       --engine PURL --render-output <path> --render-format <format> --render-frame <chunk>
// The Purl settings are read from the .blend when the job is submitted and written back into
// the scene before rendering, so a job edited in the Manager's web interface (more samples, a
// new seed) renders what it shows. A worker without the add-on fails the task with a message
// instead of rendering empty frames.
//
// Runs in the Manager's JavaScript engine (goja, ES6): no Node.js modules, only the Manager's
// globals (author, path, frameChunker, print).

const JOB_TYPE = {
    label: "Purl Render",
    description: "Render frames of a Blend file with Purl (yarn-level cloth), in chunks of frames",
    settings: [
        // Chosen by the artist at submission.
        {
            key: "frames", type: "string", required: true,
            eval: "f'{C.scene.frame_start}-{C.scene.frame_end}'",
            evalInfo: { showLinkButton: true, description: "Scene frame range" },
            description: "Frames to render, e.g. '1-250', '1-30,40', '7'",
        },
        {
            key: "chunk_size", type: "int32", default: 4, propargs: { min: 1, max: 1000 },
            description: "Frames per task: each task starts Blender and loads the scene once",
        },
        {
            key: "render_output_root", type: "string", subtype: "dir_path", required: true,
            visible: "submission",
            description: "Folder on the shared storage for the frames; the job name is added to it",
        },
        {
            key: "render_output_path", type: "string", subtype: "file_path", editable: false,
            eval: "str(Path(abspath(settings.render_output_root), jobname, '######'))",
            description: "Where the frames are saved; '#' is replaced by the frame number",
        },
        {
            key: "addon_module", type: "string", required: true,
            eval: "next((a.module for a in C.preferences.addons if a.module.rsplit('.', 1)[-1] == 'purl'), 'purl')",
            visible: "submission",
            description: "Python module of the Purl add-on on the workers: 'purl' for the legacy add-on " +
                "(Blender 3.x), 'bl_ext.<repository>.purl' for the extension (Blender 4.2+)",
        },
        {
            key: "threads", type: "int32", default: 0, propargs: { min: 0, max: 1024 },
            visible: "submission",
            description: "Render threads per task, 0 for all of the worker's cores " +
                "(the image is the same for any count)",
        },

        // Purl's render settings, read from the scene at submission; editable in the web interface.
        { key: "samples", type: "int32", eval: "C.scene.purl.samples", visible: "web",
          description: "Samples per pixel" },
        { key: "seed", type: "int32", eval: "C.scene.purl.seed", visible: "web",
          description: "Random seed: the image is a function of scene, seed and samples" },
        { key: "animated_seed", type: "bool", eval: "C.scene.purl.use_animated_seed", visible: "web",
          description: "Add the frame number to the seed" },
        { key: "max_bounces", type: "int32", eval: "C.scene.purl.max_depth", visible: "web",
          description: "Path length limit" },
        { key: "clamp", type: "float", eval: "C.scene.purl.clamp", visible: "web",
          description: "Clamp sample radiance (0: off)" },
        { key: "scale", type: "string", eval: "C.scene.purl.multiscale_mode", visible: "web",
          description: "Multi-scale shading of camera hits: AUTO, NEAR, MULTI or FAR" },
        { key: "ply_search", type: "string", eval: "C.scene.purl.ply_method", visible: "web",
          description: "How yarns find the ply under a hit: ELLIPTICAL, LOCAL or CIRCULAR" },

        // Filled in by the Flamenco add-on.
        { key: "blendfile", type: "string", required: true, visible: "web",
          description: "Blend file to render" },
        { key: "scene", type: "string", required: true, eval: "C.scene.name", visible: "web",
          description: "Scene to render" },
        { key: "format", type: "string", required: true, eval: "C.scene.render.image_settings.file_format",
          visible: "web", description: "Image format of the frames (Blender's file format name)" },
    ],
};

// Job setting -> Purl scene property, written into the scene before rendering.
const PURL_SCENE_SETTINGS = [
    ["samples", "samples"],
    ["seed", "seed"],
    ["animated_seed", "use_animated_seed"],
    ["max_bounces", "max_depth"],
    ["clamp", "clamp"],
    ["scale", "multiscale_mode"],
    ["ply_search", "ply_method"],
];

function compileJob(job) {
    const settings = job.settings;
    checkSettings(settings);
    const chunks = frameChunker(settings.frames, settings.chunk_size);
    for (const chunk of chunks) {
        job.addTask(renderTask(settings, chunk));
    }
    print("Purl Render:", chunks.length, "tasks for frames", settings.frames);
}

function renderTask(settings, chunk) {
    const task = author.Task(`render-${chunk}`, "blender");
    const argsBefore = ["--addons", settings.addon_module];
    if (settings.threads > 0) {
        argsBefore.push("--threads", String(settings.threads));
    }
    task.addCommand(author.Command("blender-render", {
        exe: "{blender}",
        exeArgs: "{blenderArgs}",
        argsBefore: argsBefore,
        blendfile: settings.blendfile,
        args: [
            "--scene", settings.scene,
            "--python-exit-code", "1",
            "--python-expr", purlSettingsScript(settings),
            "--engine", "PURL",
            "--render-output", settings.render_output_path,
            "--render-format", settings.format,
            "--render-frame", blenderFrames(chunk),
        ],
    }));
    return task;
}

// Python run by Blender after loading the file: checks that Purl is enabled (a clear error
// instead of "engine not found") and that the files it reads outside the .blend are here (the
// render would only warn), then writes this job's Purl settings into the scene.
function purlSettingsScript(settings) {
    const lines = [
        "import bpy, importlib",
        `scene = bpy.data.scenes[${pythonLiteral(settings.scene)}]`,
        "if not hasattr(scene, 'purl'):",
        `    raise RuntimeError(${pythonLiteral(
            `Purl: the add-on '${settings.addon_module}' is not installed on this worker (docs/farm.md)`)})`,
        `missing = importlib.import_module(${pythonLiteral(settings.addon_module + ".scripting")})` +
            ".missing_input_files(scene)",
        "if missing:",
        "    raise RuntimeError('Purl: files missing on this worker: ' + ', '.join(missing))",
    ];
    for (const pair of PURL_SCENE_SETTINGS) {
        const value = settings[pair[0]];
        if (value !== undefined && value !== null) {
            lines.push(`scene.purl.${pair[1]} = ${pythonLiteral(value)}`);
        }
    }
    return lines.join("\n");
}

function pythonLiteral(value) {
    if (typeof value === "boolean") return value ? "True" : "False";
    // A JSON string or number is also a valid Python literal.
    return JSON.stringify(value);
}

// frameChunker's "1-3,7" -> Blender's "1..3,7".
function blenderFrames(chunk) {
    return chunk.split(",").map((part) => part.replace(/^(-?\d+)-(-?\d+)$/, "$1..$2")).join(",");
}

function checkSettings(settings) {
    for (const setting of JOB_TYPE.settings) {
        const value = settings[setting.key];
        if (setting.required && (value === undefined || value === null || value === "")) {
            throw `Purl Render: setting "${setting.key}" is required`;
        }
    }
    if (!(settings.chunk_size >= 1)) {
        throw `Purl Render: chunk_size must be at least 1, got ${settings.chunk_size}`;
    }
    if (!/^[A-Za-z_][A-Za-z0-9_]*(\.[A-Za-z_][A-Za-z0-9_]*)*$/.test(settings.addon_module)) {
        throw `Purl Render: addon_module "${settings.addon_module}" is not a Python module name`;
    }
    if (settings.threads !== undefined && !(settings.threads >= 0)) {
        throw `Purl Render: threads must be 0 (all cores) or more, got ${settings.threads}`;
    }
}
