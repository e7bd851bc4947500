// The part of a Flamenco v3 Manager that job types talk to, in Node.js: loads a job compiler
// script the way the Manager does (its own globals only, no Node.js modules) and compiles a
// job with it, so a job type can be tested and previewed without a Manager.
//
//   node farm/flamenco/local_manager.js <script.js> job-type          -> the job type as JSON
//   node farm/flamenco/local_manager.js <script.js> compile <job.json> -> the compiled tasks as JSON
//
// job.json: {"name": ..., "settings": {...}} as the Flamenco add-on submits it. Compile errors
// (what the script throws) go to stderr with exit status 2.
//
// Implemented after Flamenco's documentation (flamenco.blender.org: job types, commands) and
// its job compiler: author.Task(name, type), author.Command(name, parameters),
// task.addCommand / task.addDependency, job.addTask (which stores a copy of the task as it is
// then), frameChunker(frames, chunkSize), path.basename / dirname / join / stem, print, alert,
// formatTimestampLocal. The job type's name is the script's file name with "_" -> "-".
"use strict";

const fs = require("fs");
const nodePath = require("path");
const vm = require("vm");

// A JSON round trip: what the Manager stores and sends to Workers.
function plain(value) {
    return JSON.parse(JSON.stringify(value));
}

function makeAuthor() {
    return {
        Task(name, type) {
            name = String(name === undefined ? "" : name).trim();
            type = String(type === undefined ? "" : type).trim();
            if (!name) throw new Error("author.Task(name, type): name is required");
            if (!type) throw new Error("author.Task(name, type): type is required");
            const task = { name, type, priority: 50, commands: [], dependencies: [] };
            task.addCommand = (command) => task.commands.push(plain(command));
            task.addDependency = (other) => task.dependencies.push(other.name);
            return task;
        },
        Command(name, parameters) {
            return { name, parameters: parameters || {} };
        },
    };
}

// "1-3,7,10..12" -> [1, 2, 3, 7, 10, 11, 12], sorted, without repeats.
function explodeFrames(frames) {
    const found = new Set();
    for (const part of frames.replace(/\.\./g, "-").split(",")) {
        const ends = part.split("-").map((text) => text.trim());
        const numbers = ends.map((text) => (/^[0-9]+$/.test(text) ? Number(text) : NaN));
        if (ends.length > 2 || numbers.some(Number.isNaN)) {
            throw new Error(`invalid range "${frames}": ${part}`);
        }
        const last = numbers.length === 2 ? numbers[1] : numbers[0];
        for (let frame = numbers[0]; frame <= last; frame++) found.add(frame);
    }
    return Array.from(found).sort((a, b) => a - b);
}

// [1, 2, 3, 5, 6, 9] -> "1-3,5,6,9": runs of three or more frames as "A-B".
function mergeFrames(frames) {
    const parts = [];
    let start = 0;
    for (let i = 1; i <= frames.length; i++) {
        if (i < frames.length && frames[i] === frames[i - 1] + 1) continue;
        const first = frames[start], last = frames[i - 1];
        if (last - first >= 2) parts.push(`${first}-${last}`);
        else for (let frame = first; frame <= last; frame++) parts.push(String(frame));
        start = i;
    }
    return parts.join(",");
}

function frameChunker(frames, chunkSize) {
    frames = String(frames === undefined ? "" : frames).trim();
    if (!frames) throw new Error(`invalid range "${frames}": empty range`);
    if (!(chunkSize >= 1)) throw new Error(`invalid chunk size, must be positive number: ${chunkSize}`);
    const all = explodeFrames(frames);
    if (all.length === 0) throw new Error(`invalid range "${frames}": empty range`);
    const chunks = [];
    for (let i = 0; i < all.length; i += chunkSize) chunks.push(mergeFrames(all.slice(i, i + chunkSize)));
    return chunks;
}

function formatTimestampLocal(date) {
    const two = (n) => String(n).padStart(2, "0");
    return `${date.getFullYear()}-${two(date.getMonth() + 1)}-${two(date.getDate())}_` +
        `${two(date.getHours())}${two(date.getMinutes())}${two(date.getSeconds())}`;
}

function log(...args) {
    process.stderr.write(args.map((a) => (typeof a === "string" ? a : JSON.stringify(a))).join(" ") + "\n");
}

// The script loaded with exactly the Manager's globals: { jobType, compile(submitted) }.
function loadJobType(scriptPath) {
    const source = fs.readFileSync(scriptPath, "utf8");
    const globals = {
        author: makeAuthor(),
        path: {
            basename: (p) => nodePath.posix.basename(p),
            dirname: (p) => nodePath.posix.dirname(p),
            join: (...parts) => nodePath.posix.join(...parts),
            stem: (p) => nodePath.posix.parse(p).name,
        },
        frameChunker,
        formatTimestampLocal,
        print: log,
        alert: log,
    };
    const context = vm.createContext(globals);
    vm.runInContext(source, context, { filename: scriptPath });
    const jobType = plain(vm.runInContext("JOB_TYPE", context));
    jobType.name = nodePath.basename(scriptPath, ".js").replace(/_/g, "-");
    const compileJob = vm.runInContext("compileJob", context);
    if (typeof compileJob !== "function") throw new Error(`${scriptPath} defines no compileJob(job)`);

    function compile(submitted) {
        const job = {
            name: submitted.name || "job",
            type: jobType.name,
            priority: submitted.priority || 50,
            created: new Date(submitted.created || Date.now()),
            settings: plain(submitted.settings || {}),
            metadata: plain(submitted.metadata || {}),
            tasks: [],
        };
        job.addTask = (task) => job.tasks.push(plain(task));
        compileJob(job);
        return { name: job.name, type: job.type, settings: job.settings, tasks: job.tasks };
    }
    return { jobType, compile, context };
}

function main(argv) {
    const [script, action, jobFile] = argv;
    if (!script || !["job-type", "compile"].includes(action) || (action === "compile" && !jobFile)) {
        process.stderr.write("usage: local_manager.js <script.js> job-type | compile <job.json>\n");
        return 2;
    }
    const loaded = loadJobType(script);
    if (action === "job-type") {
        process.stdout.write(JSON.stringify(loaded.jobType, null, 2) + "\n");
        return 0;
    }
    let compiled;
    try {
        compiled = loaded.compile(JSON.parse(fs.readFileSync(jobFile, "utf8")));
    } catch (error) {
        process.stderr.write(`${jobFile}: job compile error: ${error && error.message ? error.message : error}\n`);
        return 2;
    }
    process.stdout.write(JSON.stringify(compiled, null, 2) + "\n");
    return 0;
}

module.exports = { loadJobType, frameChunker };

if (require.main === module) process.exitCode = main(process.argv.slice(2));
