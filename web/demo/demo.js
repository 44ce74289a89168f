// The demo page: the models (TF.js graph models served by `wheelpose demo`) on one image. The
// input is prepared like `wheelpose predict --size 256`: the image scaled so its longer side is
// 256, padded right and bottom to multiples of 32; MoveNet MultiPose's output (1×6×56: 17 ×
// (y, x, score), box ymin, xmin, ymax, xmax, score, fractions of the input) mapped back to image
// pixels. The right panel is the real-photo ensemble, fused like `predict --model
// movenet-multipose --model movenet-wheelchair-full --flip` (src/learn/model_ensemble.h). Every
// text shown is set as text (textContent), never parsed as HTML.
'use strict';

const LONGER_SIDE = 256;
const KEYPOINT_MIN_SCORE = 0.3;  // keypoints drawn
const EDGES = [[0, 1], [0, 2], [1, 3], [2, 4], [5, 6], [5, 7], [7, 9], [6, 8], [8, 10], [5, 11],
  [6, 12], [11, 12], [11, 13], [13, 15], [12, 14], [14, 16]];
// Left/right keypoint pairs of COCO-17, swapped when a mirrored view is mapped back.
const FLIP_PAIRS = [[1, 2], [3, 4], [5, 6], [7, 8], [9, 10], [11, 12], [13, 14], [15, 16]];
const PREDICT_MIN_SCORE = 0.05;  // predict's --min-score: each ensemble view keeps these
const COLOURS = ['#e6194b', '#3cb44b', '#4363d8', '#f58231', '#911eb4', '#42d4f4'];

// What the page did, for people and for the browser test.
window.demoState = { ready: false, busy: false, image: null, results: {}, error: null, backend: null, seconds: null };
const models = {};

const $ = (id) => document.getElementById(id);

function setStatus(text, isError = false) {
  const status = $('status');
  status.textContent = text;
  status.classList.toggle('error', isError);
  if (isError) window.demoState.error = text;
}

// The image's RGBA pixels at its own size.
function pixelsOf(image, w, h) {
  const canvas = document.createElement('canvas');
  canvas.width = w;
  canvas.height = h;
  const ctx = canvas.getContext('2d', { willReadFrequently: true });
  ctx.drawImage(image, 0, 0);
  return ctx.getImageData(0, 0, w, h).data;
}

// Shrinks by averaging each output pixel's footprint, weighted by coverage: OpenCV's INTER_AREA,
// which `predict` uses, so both see the same input (a canvas's own downscale does not).
function areaResize(rgba, sw, sh, dw, dh, out, outW) {
  const fx = sw / dw, fy = sh / dh;
  const spans = (n, f, limit) => Array.from({ length: n }, (_, d) => {
    const lo = d * f, hi = Math.min((d + 1) * f, limit), taps = [];
    for (let s = Math.floor(lo); s < hi; ++s) taps.push([s, Math.min(hi, s + 1) - Math.max(lo, s)]);
    return taps;
  });
  const xs = spans(dw, fx, sw), ys = spans(dh, fy, sh);
  for (let dy = 0; dy < dh; ++dy) {
    for (let dx = 0; dx < dw; ++dx) {
      let r = 0, g = 0, b = 0, total = 0;
      for (const [sy, wy] of ys[dy]) {
        for (const [sx, wx] of xs[dx]) {
          const w = wx * wy, i = (sy * sw + sx) * 4;
          r += rgba[i] * w;
          g += rgba[i + 1] * w;
          b += rgba[i + 2] * w;
          total += w;
        }
      }
      const o = (dy * outW + dx) * 3;
      out[o] = Math.round(r / total);
      out[o + 1] = Math.round(g / total);
      out[o + 2] = Math.round(b / total);
    }
  }
}

// The letterboxed input and that of the mirror image (the resize is symmetric, so mirroring the
// resized rows is mirroring the image): {tensor, mirrored, scale, inputW, inputH, w, h}.
function letterbox(image) {
  const w = image.naturalWidth || image.width, h = image.naturalHeight || image.height;
  const scale = LONGER_SIDE / Math.max(w, h);
  const rw = Math.min(LONGER_SIDE, Math.max(1, Math.round(w * scale)));
  const rh = Math.min(LONGER_SIDE, Math.max(1, Math.round(h * scale)));
  const inputW = Math.ceil(rw / 32) * 32, inputH = Math.ceil(rh / 32) * 32;
  const rgb = new Int32Array(inputW * inputH * 3);  // black padding
  if (rw < w) {
    areaResize(pixelsOf(image, w, h), w, h, rw, rh, rgb, inputW);
  } else {  // enlarging: the canvas's bilinear filter
    const canvas = document.createElement('canvas');
    canvas.width = rw;
    canvas.height = rh;
    const ctx = canvas.getContext('2d', { willReadFrequently: true });
    ctx.drawImage(image, 0, 0, rw, rh);
    const rgba = ctx.getImageData(0, 0, rw, rh).data;
    for (let y = 0; y < rh; ++y) {
      for (let x = 0; x < rw; ++x) {
        const i = (y * rw + x) * 4, o = (y * inputW + x) * 3;
        rgb[o] = rgba[i];
        rgb[o + 1] = rgba[i + 1];
        rgb[o + 2] = rgba[i + 2];
      }
    }
  }
  const mirror = new Int32Array(inputW * inputH * 3);
  for (let y = 0; y < rh; ++y) {
    for (let x = 0; x < rw; ++x) {
      const i = (y * inputW + x) * 3, o = (y * inputW + rw - 1 - x) * 3;
      mirror[o] = rgb[i];
      mirror[o + 1] = rgb[i + 1];
      mirror[o + 2] = rgb[i + 2];
    }
  }
  return {
    tensor: tf.tensor4d(rgb, [1, inputH, inputW, 3], 'int32'),
    mirrored: tf.tensor4d(mirror, [1, inputH, inputW, 3], 'int32'),
    scale, inputW, inputH, w, h,
  };
}

// A person found in the mirror image, in the image's own coordinates (x → w − x, sides swapped).
function unmirror(person, w) {
  const keypoints = person.keypoints.map(([x, y, s]) => [w - x, y, s]);
  for (const [a, b] of FLIP_PAIRS) [keypoints[a], keypoints[b]] = [keypoints[b], keypoints[a]];
  const [x, y, bw, bh] = person.bbox;
  return { score: person.score, keypoints, bbox: [w - x - bw, y, bw, bh] };
}

function iou(a, b) {
  const iw = Math.max(0, Math.min(a[0] + a[2], b[0] + b[2]) - Math.max(a[0], b[0]));
  const ih = Math.max(0, Math.min(a[1] + a[3], b[1] + b[3]) - Math.max(a[1], b[1]));
  const union = a[2] * a[3] + b[2] * b[3] - iw * ih;
  return union > 0 ? iw * ih / union : 0;
}

// Several views' people fused into one list, as `predict` does (weighted boxes fusion): highest
// score first, each joins the first group whose leader overlaps it by IoU >= 0.5 and holds no
// one of its view; a group's score is the mean over the views (a view without it adds 0), its
// box the score-weighted mean, its keypoints weighted by score × keypoint score.
function fuse(views) {
  const everyone = [];
  views.forEach((people, view) => people.forEach((person) => everyone.push({ view, person })));
  everyone.sort((a, b) => b.person.score - a.person.score);  // stable: earlier views first
  const groups = [];
  for (const member of everyone) {
    const group = groups.find((g) => !g.some((m) => m.view === member.view) &&
      iou(member.person.bbox, g[0].person.bbox) >= 0.5);
    if (group) group.push(member); else groups.push([member]);
  }
  const share = 1 / views.length;
  const fused = groups.map((group) => {
    const people = group.map((m) => m.person);
    const lead = people[0];
    const boxWeight = people.reduce((t, p) => t + p.score, 0);
    const bbox = [0, 1, 2, 3].map((i) => boxWeight > 0
      ? people.reduce((t, p) => t + p.score * p.bbox[i], 0) / boxWeight : lead.bbox[i]);
    const keypoints = lead.keypoints.map((_, k) => {
      let x = 0, y = 0, weight = 0, score = 0;
      for (const p of people) {
        const w = p.score * p.keypoints[k][2];
        x += w * p.keypoints[k][0];
        y += w * p.keypoints[k][1];
        weight += w;
        score += share * p.keypoints[k][2];
      }
      return weight > 0 ? [x / weight, y / weight, score] : [lead.keypoints[k][0], lead.keypoints[k][1], score];
    });
    return { score: people.reduce((t, p) => t + share * p.score, 0), keypoints, bbox };
  });
  return fused.sort((a, b) => b.score - a.score);
}

// MultiPose's output to people in image pixels, the model's order, those scoring minScore+.
function decode(values, box, minScore) {
  const people = [];
  for (let j = 0; j < 6; ++j) {
    const p = values.subarray(j * 56, j * 56 + 56);
    if (p[55] < minScore) continue;
    const keypoints = [];
    for (let k = 0; k < 17; ++k) {
      keypoints.push([p[3 * k + 1] * box.inputW / box.scale, p[3 * k] * box.inputH / box.scale,
        p[3 * k + 2]]);
    }
    const clampX = (v) => Math.min(Math.max(v, 0), box.w), clampY = (v) => Math.min(Math.max(v, 0), box.h);
    const x0 = clampX(p[52] * box.inputW / box.scale), y0 = clampY(p[51] * box.inputH / box.scale);
    const x1 = clampX(p[54] * box.inputW / box.scale), y1 = clampY(p[53] * box.inputH / box.scale);
    people.push({ score: p[55], keypoints, bbox: [x0, y0, Math.max(0, x1 - x0), Math.max(0, y1 - y0)] });
  }
  return people;
}

function draw(key, image, people) {
  const canvas = $('canvas-' + key);
  const w = image.naturalWidth || image.width, h = image.naturalHeight || image.height;
  canvas.width = w;
  canvas.height = h;
  const ctx = canvas.getContext('2d');
  ctx.drawImage(image, 0, 0);
  const line = Math.max(2, Math.round(Math.max(w, h) / 300));
  people.forEach((person, i) => {
    const colour = COLOURS[i % COLOURS.length];
    ctx.strokeStyle = colour;
    ctx.fillStyle = colour;
    ctx.lineWidth = line;
    ctx.strokeRect(...person.bbox);
    for (const [a, b] of EDGES) {
      const pa = person.keypoints[a], pb = person.keypoints[b];
      if (pa[2] < KEYPOINT_MIN_SCORE || pb[2] < KEYPOINT_MIN_SCORE) continue;
      ctx.beginPath();
      ctx.moveTo(pa[0], pa[1]);
      ctx.lineTo(pb[0], pb[1]);
      ctx.stroke();
    }
    for (const [x, y, s] of person.keypoints) {
      if (s < KEYPOINT_MIN_SCORE) continue;
      ctx.beginPath();
      ctx.arc(x, y, line * 1.5, 0, 2 * Math.PI);
      ctx.fill();
    }
    ctx.font = `${Math.max(12, line * 7)}px sans-serif`;
    ctx.fillText(`${i + 1}: ${person.score.toFixed(2)}`, person.bbox[0] + line, person.bbox[1] - line * 2);
  });
  const list = $('people-' + key);
  list.replaceChildren();
  for (const [i, person] of people.entries()) {
    const item = document.createElement('li');
    const seen = person.keypoints.filter((k) => k[2] >= KEYPOINT_MIN_SCORE).length;
    item.textContent = `Person ${i + 1}: score ${person.score.toFixed(2)}, ${seen} of 17 keypoints`;
    list.append(item);
  }
  if (people.length === 0) {
    const item = document.createElement('li');
    item.textContent = 'Nobody found at this score.';
    list.append(item);
  }
}

async function run(model, input) {
  const out = model.execute({ [model.inputs[0].name]: input }, 'Identity:0');
  const values = await out.data();
  out.dispose();
  return values;
}

async function runAll(image, name) {
  if (!window.demoState.ready) return;
  window.demoState.busy = true;
  setStatus(`Running the models on ${name}…`);
  const start = performance.now();
  const minScore = Math.min(1, Math.max(0, Number($('min-score').value) || 0));
  const box = letterbox(image);
  const results = {};
  try {
    const plain = {};
    for (const key of ['pretrained', 'wheelchair']) {
      plain[key] = await run(models[key], box.tensor);
      results[key] = decode(plain[key], box, minScore);
      draw(key, image, results[key]);
    }
    // The ensemble: the pretrained model and its partner, each on the image and on its mirror.
    const views = [decode(plain.pretrained, box, PREDICT_MIN_SCORE),
      decode(await run(models.pretrained, box.mirrored), box, PREDICT_MIN_SCORE).map((p) => unmirror(p, box.w)),
      decode(await run(models.ensemble, box.tensor), box, PREDICT_MIN_SCORE),
      decode(await run(models.ensemble, box.mirrored), box, PREDICT_MIN_SCORE).map((p) => unmirror(p, box.w))];
    results.ensemble = fuse(views).filter((p) => p.score >= minScore);
    draw('ensemble', image, results.ensemble);
  } finally {
    box.tensor.dispose();
    box.mirrored.dispose();
    window.demoState.busy = false;
  }
  const seconds = (performance.now() - start) / 1000;
  window.demoState.seconds = seconds;
  window.demoState.image = name;
  window.demoState.results = results;
  const count = (key) => results[key].length;
  setStatus(`${name}: pretrained found ${count('pretrained')}, wheelchair model ${count('wheelchair')}, ensemble ${count('ensemble')} (score ≥ ${minScore}); ${seconds.toFixed(1)} s (${window.demoState.backend}).`);
}

function loadImage(url, name) {
  const image = new Image();
  image.onload = () => runAll(image, name).catch((e) => setStatus(`Could not run the models: ${e.message}`, true));
  image.onerror = () => setStatus(`“${name}” could not be read as an image.`, true);
  image.src = url;
}

function openFile(file) {
  if (!file) return;
  if (!file.type.startsWith('image/')) {
    setStatus(`“${file.name}” is not an image (${file.type || 'unknown type'}); drop a JPEG or PNG photo.`, true);
    return;
  }
  loadImage(URL.createObjectURL(file), file.name);
}

// TF.js's WebAssembly backend (with SIMD where the browser has it), else the plain JavaScript
// one. One thread: TF.js 4.22's threaded build, tried with the page cross-origin isolated, never
// reported ready in chromium (no error, it hangs), and single-threaded SIMD answers in about a
// second.
async function chooseBackend() {
  try {
    tf.wasm.setWasmPaths('/tfjs/tfjs-backend-wasm/dist/');
    tf.env().set('WASM_HAS_MULTITHREAD_SUPPORT', false);
    if (await tf.setBackend('wasm')) {
      await tf.ready();
      return 'wasm';
    }
  } catch (e) {
    console.warn(`WebAssembly backend unavailable (${e.message}); using the JavaScript one`);
  }
  await tf.setBackend('cpu');
  await tf.ready();
  return 'cpu';
}

async function init() {
  const config = await (await fetch('/api/config')).json();
  const select = $('example');
  for (const name of config.examples) {
    const option = document.createElement('option');
    option.value = name;
    option.textContent = name;
    select.append(option);
  }
  for (const m of config.models) {
    $('title-' + m.key).textContent = `${$('title-' + m.key).textContent} (${m.name})`;
  }
  window.demoState.backend = await chooseBackend();
  for (const key of ['pretrained', 'wheelchair', 'ensemble']) {
    models[key] = await tf.loadGraphModel(`/models/${key}/model.json`);
  }
  window.demoState.ready = true;
  setStatus(`Models loaded (${window.demoState.backend === 'wasm' ? 'WebAssembly' : 'JavaScript'} backend). Choose or drop a photo, or show an example.`);
}

$('file').addEventListener('change', (e) => openFile(e.target.files[0]));
$('show-example').addEventListener('click', () => {
  const name = $('example').value;
  if (name) loadImage('/examples/' + encodeURIComponent(name), name);
});
document.addEventListener('dragover', (e) => {
  e.preventDefault();
  $('drop-hint').hidden = false;
});
document.addEventListener('dragleave', (e) => {
  if (e.relatedTarget === null) $('drop-hint').hidden = true;
});
document.addEventListener('drop', (e) => {
  e.preventDefault();
  $('drop-hint').hidden = true;
  openFile(e.dataTransfer.files[0]);
});
init().catch((e) => setStatus(`Could not load the models: ${e.message}`, true));
