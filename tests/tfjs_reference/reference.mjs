#!/usr/bin/env node
// Runs the MoveNet TF.js graph models with the real TF.js runtime (wasm or cpu
// backend) on PNG inputs and writes a JSON fixture that the C++ importer test
// compares against.  See README.md in this folder.
//
// usage: node reference.mjs --models DIR --inputs MANIFEST.json --out FIXTURE.json
//          [--backend wasm|cpu] [--threads N] [--time-runs N] [--with-heads]
//          [--nodes a,b,c]

import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import crypto from 'node:crypto';
import { createRequire } from 'node:module';

// Everything TF.js is loaded through CommonJS so that core, converter and the
// backends share one tfjs-core instance.
const require = createRequire(import.meta.url);

class UserError extends Error {}

const USAGE =
  'usage: node reference.mjs --models DIR --inputs MANIFEST.json --out FIXTURE.json ' +
  '[--backend wasm|cpu] [--threads N] [--time-runs N] [--with-heads] [--nodes a,b,c]';

// Input size rules per model: a fixed H×W, or any multiple of `multiple`.
const MODELS = {
  'movenet-multipose': { multiple: 32 },
  'movenet-lightning': { size: [192, 192] },
  'movenet-thunder': { size: [256, 256] },
};

function parseArgs(argv) {
  const o = { backend: 'wasm', threads: null, timeRuns: 10, withHeads: false, nodes: [] };
  const need = (i) => {
    if (i + 1 >= argv.length) throw new UserError(`missing value for ${argv[i]} (see --help)`);
    return argv[i + 1];
  };
  const int = (flag, v, min) => {
    if (!/^\d+$/.test(v) || Number(v) < min) throw new UserError(`${flag} needs an integer >= ${min}, got '${v}'`);
    return Number(v);
  };
  for (let i = 0; i < argv.length; i++) {
    const a = argv[i];
    switch (a) {
      case '--models': o.models = need(i); i++; break;
      case '--inputs': o.inputs = need(i); i++; break;
      case '--out': o.out = need(i); i++; break;
      case '--backend': o.backend = need(i); i++; break;
      case '--threads': o.threads = int(a, need(i), 1); i++; break;
      case '--time-runs': o.timeRuns = int(a, need(i), 0); i++; break;
      case '--with-heads': o.withHeads = true; break;
      case '--nodes': o.nodes = need(i).split(',').map((s) => s.trim()).filter(Boolean); i++; break;
      case '-h': case '--help': process.stdout.write(USAGE + '\n'); process.exit(0); break;
      default: throw new UserError(`unknown argument '${a}' (see --help)`);
    }
  }
  for (const k of ['models', 'inputs', 'out']) {
    if (!o[k]) throw new UserError(`--${k} is required (see --help)`);
  }
  if (o.backend !== 'wasm' && o.backend !== 'cpu') throw new UserError(`--backend must be wasm or cpu, got '${o.backend}'`);
  if (o.threads != null && o.backend !== 'wasm') throw new UserError('--threads only applies to --backend wasm');
  return o;
}

function readFileOrFail(p, what) {
  try {
    return fs.readFileSync(p);
  } catch (e) {
    throw new UserError(`cannot read ${what} '${p}': ${e.code || e.message}`);
  }
}

// ---------------------------------------------------------------- backend ---

// In Node the wasm backend hard-codes "no multithread support" (tfjs issue
// #3830): Emscripten's pthread workers are handed blob: URLs (the worker
// script and the main script), which Node's worker_threads cannot load. For
// --threads N > 1 we force the flag on and turn those blobs into temp files:
//  - the worker script: URL.createObjectURL writes it to a .cjs file;
//  - the main script (posted to each worker as a Blob): written to a file when
//    the Blob is built, with a prelude defining the bundle-scope names the
//    factory's source refers to, and the worker script is patched to load that
//    file instead of the Blob.
// This relies on @tensorflow/tfjs-backend-wasm 4.22.0 internals; if they
// change, the patch points are not found and we fail with a clear message.
function enableNodeWasmThreads(tf) {
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'tfjs-wasm-'));
  process.on('exit', () => fs.rmSync(dir, { recursive: true, force: true }));
  const MAIN_MARK = 'var WasmBackendModuleThreadedSimd = ';
  const WORKER_MARK = 'typeof e.data.urlOrBlob=="string"';
  const mainFile = path.join(dir, 'threaded-simd-main.cjs');
  const PRELUDE = 'var require$$0=require("fs"),require$$1=require("path"),require$$3=require("perf_hooks"),' +
    'require$$4=require("os"),commonjsGlobal=globalThis,_scriptDir=location.href;\n';
  const NativeBlob = globalThis.Blob;
  const sources = new WeakMap();
  globalThis.Blob = class RecordingBlob extends NativeBlob {
    constructor(parts = [], opts) {
      super(parts, opts);
      if (parts.every((x) => typeof x === 'string')) {
        const text = parts.join('');
        sources.set(this, text);
        if (text.startsWith(MAIN_MARK)) fs.writeFileSync(mainFile, PRELUDE + text);
      }
    }
  };
  let n = 0;
  const nativeCreate = URL.createObjectURL;
  const nativeRevoke = URL.revokeObjectURL;
  URL.createObjectURL = (blob) => {
    const text = sources.get(blob);
    if (text === undefined) return nativeCreate(blob);
    if (!text.includes(WORKER_MARK)) throw new Error('--threads: unexpected tfjs-backend-wasm worker script (version changed?)');
    const f = path.join(dir, `worker${n++}.cjs`);
    fs.writeFileSync(f, text.replace(WORKER_MARK, `((e.data.urlOrBlob=${JSON.stringify(mainFile)}),true)`));
    return f;
  };
  URL.revokeObjectURL = (u) => (typeof u === 'string' && u.startsWith(dir) ? undefined : nativeRevoke(u));
  tf.env().set('WASM_HAS_MULTITHREAD_SUPPORT', true);
}

async function setupBackend(opts) {
  const tf = require('@tensorflow/tfjs-core');
  tf.env().set('PROD', true); // silences the "install tfjs-node" banner; no numeric effect
  require('@tensorflow/tfjs-backend-cpu');
  const info = { name: opts.backend };
  if (opts.backend === 'wasm') {
    const wasm = require('@tensorflow/tfjs-backend-wasm');
    // Load the .wasm binaries from node_modules, never from the network.
    const distDir = path.dirname(require.resolve('@tensorflow/tfjs-backend-wasm/dist/tfjs-backend-wasm.wasm'));
    wasm.setWasmPaths(distDir + path.sep);
    const threads = opts.threads ?? 1;
    const realCpus = os.cpus;
    if (threads > 1) {
      enableNodeWasmThreads(tf);
      wasm.setThreadsCount(threads);
      // The backend caps its thread pool at emscripten_num_logical_cores()/2
      // (it assumes 2 hyper-threads per core), i.e. os.cpus().length/2 in
      // Node: 1 on a 2-core machine. Report enough CPUs while it initialises.
      os.cpus = () => {
        const c = realCpus();
        while (c.length < 2 * threads) c.push(c[0]);
        return c;
      };
    }
    try {
      if (!(await tf.setBackend('wasm'))) throw new Error('could not initialise the wasm backend');
    } finally {
      os.cpus = realCpus;
    }
    const b = tf.backend();
    info.simd = await tf.env().getAsync('WASM_HAS_SIMD_SUPPORT');
    info.threads = b.wasm.tfjs.getThreadsCount();
    info.wasm_binary = info.threads > 1 ? 'tfjs-backend-wasm-threaded-simd.wasm'
      : info.simd ? 'tfjs-backend-wasm-simd.wasm' : 'tfjs-backend-wasm.wasm';
  } else {
    if (!(await tf.setBackend('cpu'))) throw new Error('could not initialise the cpu backend');
  }
  await tf.ready();
  return { tf, info };
}

// ------------------------------------------------------------------ model ---

function modelIOHandler(jsonPath) {
  const modelsDir = path.dirname(jsonPath);
  return {
    load: async () => {
      const j = JSON.parse(readFileOrFail(jsonPath, 'model topology').toString('utf8'));
      const weightSpecs = [];
      const shards = [];
      for (const group of j.weightsManifest || []) {
        weightSpecs.push(...group.weights);
        for (const p of group.paths) shards.push(readFileOrFail(path.join(modelsDir, p), 'weight shard'));
      }
      const all = Buffer.concat(shards);
      const weightData = all.buffer.slice(all.byteOffset, all.byteOffset + all.byteLength);
      return {
        modelTopology: j.modelTopology,
        weightSpecs,
        weightData,
        format: j.format,
        generatedBy: j.generatedBy,
        convertedBy: j.convertedBy,
        signature: j.signature,
        userDefinedMetadata: j.userDefinedMetadata,
        modelInitializer: j.modelInitializer,
      };
    },
  };
}

const CONV_OPS = new Set(['Conv2D', '_FusedConv2D', 'DepthwiseConv2dNative', 'FusedDepthwiseConv2dNative']);

// Head outputs = conv nodes from which no further conv is reachable: the raw
// (pre-sigmoid) logits of every prediction head, where decoding starts.
function findHeadNodes(topology) {
  const nodes = topology.node;
  const consumers = new Map(nodes.map((n) => [n.name, []]));
  for (const n of nodes) {
    for (const inp of n.input || []) {
      const src = inp.replace(/^\^/, '').split(':')[0];
      if (consumers.has(src)) consumers.get(src).push(n.name);
    }
  }
  const byName = new Map(nodes.map((n) => [n.name, n]));
  const memo = new Map();
  const convDownstream = (name) => {
    if (memo.has(name)) return memo.get(name);
    memo.set(name, false);
    let r = false;
    for (const c of consumers.get(name)) {
      if (CONV_OPS.has(byName.get(c).op) || convDownstream(c)) { r = true; break; }
    }
    memo.set(name, r);
    return r;
  };
  return nodes.filter((n) => CONV_OPS.has(n.op) && !convDownstream(n.name)).map((n) => n.name);
}

// ------------------------------------------------------------------ input ---

function loadPng(file) {
  const { PNG } = require('pngjs');
  let png;
  try {
    png = PNG.sync.read(readFileOrFail(file, 'input image'));
  } catch (e) {
    if (e instanceof UserError) throw e;
    throw new UserError(`cannot decode PNG '${file}': ${e.message}`);
  }
  // Only 8-bit truecolour (RGB, colour type 2) or RGBA (type 6): pngjs would
  // silently expand grey/palette images and rescale 16-bit ones.
  if (png.depth !== 8 || (png.colorType !== 2 && png.colorType !== 6)) {
    throw new UserError(`${file}: PNG must be 8-bit RGB or RGBA (got bit depth ${png.depth}, colour type ${png.colorType})`);
  }
  const { width: w, height: h, data } = png; // pngjs yields RGBA8 here
  const rgb = new Uint8Array(w * h * 3);
  for (let i = 0, j = 0; i < w * h * 4; i += 4, j += 3) {
    rgb[j] = data[i];
    rgb[j + 1] = data[i + 1];
    rgb[j + 2] = data[i + 2];
  }
  return { h, w, rgb };
}

function checkSize(model, file, h, w) {
  const rule = MODELS[model];
  if (rule.size) {
    if (h !== rule.size[0] || w !== rule.size[1]) {
      throw new UserError(`${file}: image is ${w}x${h} but ${model} needs ${rule.size[1]}x${rule.size[0]}`);
    }
  } else if (h % rule.multiple || w % rule.multiple || !h || !w) {
    throw new UserError(`${file}: image is ${w}x${h} but ${model} needs width and height multiples of ${rule.multiple}`);
  }
}

// ----------------------------------------------------------------- output ---

function round7(x) {
  if (!Number.isFinite(x)) return null; // JSON has no NaN/Inf
  return x === 0 ? 0 : Number(x.toPrecision(7));
}

async function tensorToJson(t, op) {
  const data = Array.from(await t.data(), (v) => (typeof v === 'number' ? round7(v) : v));
  const o = { shape: t.shape, dtype: t.dtype, data };
  if (op) o.op = op;
  return o;
}

function writeAtomic(file, text) {
  const dir = path.dirname(path.resolve(file));
  if (!fs.existsSync(dir)) throw new UserError(`output folder '${dir}' does not exist`);
  const tmp = path.join(dir, `.${path.basename(file)}.${process.pid}.tmp`);
  try {
    fs.writeFileSync(tmp, text);
    fs.renameSync(tmp, file);
  } catch (e) {
    fs.rmSync(tmp, { force: true });
    throw e;
  }
}

// ------------------------------------------------------------------- main ---

async function main() {
  const opts = parseArgs(process.argv.slice(2));
  if (!fs.existsSync(opts.models) || !fs.statSync(opts.models).isDirectory()) {
    throw new UserError(`models folder '${opts.models}' not found`);
  }
  let manifest;
  try {
    manifest = JSON.parse(readFileOrFail(opts.inputs, 'manifest').toString('utf8'));
  } catch (e) {
    if (e instanceof UserError) throw e;
    throw new UserError(`manifest '${opts.inputs}' is not valid JSON: ${e.message}`);
  }
  if (!Array.isArray(manifest.inputs) || manifest.inputs.length === 0) {
    throw new UserError(`manifest '${opts.inputs}' has no "inputs" list`);
  }
  const manifestDir = path.dirname(opts.inputs);
  const outDir = path.dirname(path.resolve(opts.out));
  if (!fs.existsSync(outDir)) throw new UserError(`output folder '${outDir}' does not exist`);

  // Validate every entry and decode every image before starting TF.js.
  const jobs = manifest.inputs.map((e, i) => {
    if (!e || typeof e.file !== 'string' || typeof e.model !== 'string') {
      throw new UserError(`manifest entry ${i} needs "file" and "model" strings`);
    }
    if (!MODELS[e.model]) {
      throw new UserError(`manifest entry ${i}: unknown model '${e.model}' (known: ${Object.keys(MODELS).join(', ')})`);
    }
    if (e.topology !== undefined && typeof e.topology !== 'string') {
      throw new UserError(`manifest entry ${i}: "topology" must be a path string`);
    }
    // "topology": another model.json of the same kind (e.g. one `wheelpose model export` wrote).
    const topo = e.topology ? path.join(manifestDir, e.topology) : path.join(opts.models, `${e.model}.json`);
    if (!fs.existsSync(topo)) throw new UserError(`model file '${topo}' not found`);
    const file = path.join(manifestDir, e.file);
    const img = loadPng(file);
    checkSize(e.model, e.file, img.h, img.w);
    return { ...e, ...img, topo };
  });

  const { tf, info } = await setupBackend(opts);
  const tfjsVersion = require('@tensorflow/tfjs-core/package.json').version;
  const convVersion = require('@tensorflow/tfjs-converter/package.json').version;
  const { loadGraphModel } = require('@tensorflow/tfjs-converter');

  const models = new Map();
  const getModel = async (name, topoPath) => {
    if (!models.has(topoPath)) {
      const handler = modelIOHandler(topoPath);
      const model = await loadGraphModel(handler);
      const topo = model.artifacts.modelTopology;
      const opOf = new Map(topo.node.map((n) => [n.name, n.op]));
      const heads = findHeadNodes(topo);
      for (const n of opts.nodes) {
        if (!opOf.has(n.split(':')[0])) throw new UserError(`--nodes: '${n}' is not a node of ${name}`);
      }
      // Final outputs by their tensor names ("Identity:0"), as the signature lists them.
      const sigOut = model.artifacts.signature && model.artifacts.signature.outputs;
      const outputNames = sigOut ? Object.values(sigOut).map((o) => o.name) : model.outputs.map((o) => o.name);
      models.set(topoPath, { model, heads, opOf, inputName: model.inputs[0].name, outputNames });
    }
    return models.get(topoPath);
  };

  const entries = [];
  for (const job of jobs) {
    const m = await getModel(job.model, job.topo);
    const input = tf.tensor4d(Int32Array.from(job.rgb), [1, job.h, job.w, 3], 'int32');
    const feed = { [m.inputName]: input };
    const extra = [...(opts.withHeads ? m.heads : []), ...opts.nodes];
    const names = [...new Set([...m.outputNames, ...extra])];
    const outs = [].concat(m.model.execute(feed, names)); // one name -> a bare Tensor
    const outputs = {};
    for (let i = 0; i < names.length; i++) {
      outputs[names[i]] = await tensorToJson(outs[i], i < m.outputNames.length ? undefined : m.opOf.get(names[i].split(':')[0]));
    }
    tf.dispose(outs);

    let msPerRun = null;
    if (opts.timeRuns > 0) {
      const runOnce = () => {
        const t0 = performance.now();
        const o = [].concat(m.model.execute(feed, m.outputNames));
        o.forEach((t) => t.dataSync());
        const dt = performance.now() - t0;
        tf.dispose(o);
        return dt;
      };
      runOnce();
      runOnce();
      const times = Array.from({ length: opts.timeRuns }, runOnce).sort((a, b) => a - b);
      const k = times.length;
      msPerRun = Number((k % 2 ? times[(k - 1) / 2] : (times[k / 2 - 1] + times[k / 2]) / 2).toFixed(3));
    }
    input.dispose();

    const sha = crypto.createHash('sha256').update(job.rgb).digest('hex');
    entries.push({
      file: job.file,
      model: job.model,
      ...(job.topology ? { topology: job.topology } : {}),
      input_shape: [1, job.h, job.w, 3],
      input_sha256: sha,
      head_nodes: m.heads,
      outputs,
      ms_per_run: msPerRun,
    });
    process.stderr.write(`${job.file} [${job.model} ${job.w}x${job.h}] ` +
      `${msPerRun == null ? '' : msPerRun + ' ms/run'}\n`);
  }

  const backendDesc = info.name === 'wasm'
    ? `wasm (${info.wasm_binary}, threads=${info.threads})` : 'cpu';
  const fixture = {
    generator: `tests/tfjs_reference/reference.mjs: @tensorflow/tfjs-core ${tfjsVersion}, ` +
      `@tensorflow/tfjs-converter ${convVersion}, backend ${backendDesc}, node ${process.version}`,
    backend: info,
    time_runs: opts.timeRuns,
    entries,
  };
  writeAtomic(opts.out, JSON.stringify(fixture) + '\n');
}

main().then(
  () => process.exit(0),
  (e) => {
    const msg = e instanceof UserError ? e.message : (e && (e.stack || e.message)) || String(e);
    process.stderr.write(`reference.mjs: error: ${msg}\n`);
    process.exit(1);
  },
);
