// WheelPose review page: consent, questionnaire, one page per clip (four-view skeleton animation
// and three questions), optional follow-up questions. Every answer is sent as soon as it is given;
// reopening the link resumes at the first clip not fully answered. Text from the server is only
// ever inserted with textContent / value, never as HTML.
'use strict';

const token = new URLSearchParams(location.hash.slice(1)).get('token') || '';
const state = { session: null, clips: [], index: 0, clipCache: new Map(), paused: false,
  saving: Promise.resolve(), pending: 0 };
const $ = (id) => document.getElementById(id);

async function api(method, path, body) {
  const options = { method, headers: { Authorization: 'Bearer ' + token } };
  if (body !== undefined) {
    options.headers['Content-Type'] = 'application/json';
    options.body = JSON.stringify(body);
  }
  let response;
  try {
    response = await fetch(path, options);
  } catch (e) {
    throw new Error('The server cannot be reached. Your earlier answers are saved; please try again.');
  }
  const data = await response.json().catch(() => ({}));
  if (!response.ok) {
    if (response.status === 401) throw new Error('This link is not valid. Please use the personal link you were sent.');
    throw new Error(data.error || 'The server answered ' + response.status);
  }
  return data;
}

function showError(message) {
  const box = $('error');
  box.textContent = message;
  box.hidden = !message;
}

function show(sectionId) {
  for (const id of ['consent', 'questionnaire', 'rating', 'followup', 'done']) $(id).hidden = id !== sectionId;
  $('loading').hidden = true;
  $('progress-box').hidden = sectionId !== 'rating';
  if (sectionId !== 'rating') stopAnimation();
}

const complete = (r) => r && r.q1 != null && r.q2 != null && r.q3 != null;

function firstUnanswered() {
  const i = state.clips.findIndex((id) => !complete(state.session.ratings[id]));
  return i < 0 ? state.clips.length : i;
}

async function start() {
  if (!token) {
    $('loading').hidden = true;
    showError('This page needs your personal link (it ends with #token=…).');
    return;
  }
  try {
    state.session = await api('GET', '/api/session');
  } catch (e) {
    $('loading').hidden = true;
    showError(e.message);
    return;
  }
  state.clips = state.session.groups.flatMap((g) => g.clips);
  route();
}

function route() {
  const s = state.session;
  if (!s.consent) return show('consent');
  if (!s.questionnaire) return show('questionnaire');
  if (s.finished) return show('done');
  const i = firstUnanswered();
  if (i >= state.clips.length) return openFollowup();
  openClip(i);
}

// --- consent and questionnaire -------------------------------------------------------------

$('consent-form').addEventListener('submit', async (event) => {
  event.preventDefault();
  try {
    await api('POST', '/api/consent', { consent: true });
    state.session.consent = true;
    showError('');
    route();
    $('q-age').focus();
  } catch (e) { showError(e.message); }
});

$('questionnaire-form').addEventListener('submit', async (event) => {
  event.preventDefault();
  const form = event.target;
  const answers = {};
  for (const name of ['gender', 'occupation', 'condition', 'level', 'exercise', 'mobility']) {
    answers[name] = form.elements[name].value.trim();
  }
  const age = form.elements.age.value.trim();
  answers.age = age === '' ? null : Number(age);
  if (answers.age !== null && !(Number.isInteger(answers.age) && answers.age >= 18 && answers.age <= 120)) {
    showError('Please give your age as a whole number from 18 to 120, or leave it empty.');
    form.elements.age.focus();
    return;
  }
  try {
    await api('PUT', '/api/questionnaire', answers);
    state.session.questionnaire = answers;
    showError('');
    route();
  } catch (e) { showError(e.message); }
});

// --- rating pages ----------------------------------------------------------------------------

function buildScales() {
  for (const scale of document.querySelectorAll('.scale')) {
    const q = scale.dataset.q;
    const options = q === 'q3' ? [['yes', true], ['no', false]] : [1, 2, 3, 4, 5, 6, 7].map((v) => [String(v), v]);
    const descriptions = {
      q1: { 1: 'cannot perform at all', 7: 'without any difficulty' },
      q2: { 1: 'never', 7: 'every day' },
    };
    for (const [text, value] of options) {
      const label = document.createElement('label');
      const input = document.createElement('input');
      input.type = 'radio';
      input.name = q;
      input.value = JSON.stringify(value);
      input.id = q + '-' + text;
      const extra = descriptions[q] && descriptions[q][value];
      if (extra) input.setAttribute('aria-label', text + ', ' + extra);
      input.addEventListener('change', () => saveAnswer(q, value));
      label.append(input, document.createTextNode(text));
      scale.append(label);
    }
  }
}

async function saveAnswer(q, value) {
  const clip = state.clips[state.index];
  const rating = Object.assign({ q1: null, q2: null, q3: null }, state.session.ratings[clip]);
  rating[q] = value;
  state.session.ratings[clip] = rating;
  $('saved').textContent = 'Saving…';
  // Send answers one after another: parallel requests could arrive out of order and leave an
  // older choice stored (arrow keys change a radio answer several times a second).
  const send = state.saving.then(() => api('PUT', '/api/rating', { clip, [q]: value }));
  state.saving = send.catch(() => {});
  ++state.pending;
  try {
    await send;
    showError('');
  } catch (e) {
    showError(e.message);
  } finally {
    --state.pending;
  }
  // "Saved" only once nothing is in flight, so it is true when it is announced.
  if (state.pending === 0 && state.clips[state.index] === clip && $('error').hidden) {
    $('saved').textContent = 'Answer saved.';
  }
}

function updateProgress() {
  const answered = state.clips.filter((id) => complete(state.session.ratings[id])).length;
  $('progress').max = state.clips.length;
  $('progress').value = answered;
  $('progress-label').textContent = `${answered} of ${state.clips.length} motions answered`;
}

function groupPosition(index) {
  let offset = 0;
  const groups = state.session.groups;
  for (let g = 0; g < groups.length; ++g) {
    if (index < offset + groups[g].clips.length) return { part: g + 1, parts: groups.length };
    offset += groups[g].clips.length;
  }
  return { part: groups.length, parts: groups.length };
}

async function openClip(index) {
  state.index = Math.max(0, Math.min(index, state.clips.length - 1));
  const clip = state.clips[state.index];
  show('rating');
  const { part, parts } = groupPosition(state.index);
  $('rating-title').textContent =
    `Motion ${state.index + 1} of ${state.clips.length}` + (parts > 1 ? ` (part ${part} of ${parts})` : '');
  const rating = state.session.ratings[clip] || {};
  for (const input of document.querySelectorAll('.scale input')) {
    input.checked = rating[input.name] != null && JSON.stringify(rating[input.name]) === input.value;
  }
  $('saved').textContent = '';
  $('prev').disabled = state.index === 0;
  updateProgress();
  $('rating-title').focus();
  try {
    let data = state.clipCache.get(clip);
    if (!data) {
      data = prepareClip(await api('GET', '/api/clip?id=' + encodeURIComponent(clip)));
      state.clipCache.set(clip, data);
    }
    if (state.clips[state.index] === clip) startAnimation(data);
  } catch (e) { showError(e.message); }
}

function next() {
  const clip = state.clips[state.index];
  if (!complete(state.session.ratings[clip])) {
    const missing = ['q1', 'q2', 'q3'].find((q) => (state.session.ratings[clip] || {})[q] == null);
    showError('Please answer all three questions before moving on.');
    document.querySelector(`#fs-${missing} input`).focus();
    return;
  }
  showError('');
  if (state.index + 1 >= state.clips.length) openFollowup();
  else openClip(state.index + 1);
}

function previous() {
  showError('');
  if (state.index > 0) openClip(state.index - 1);
}

$('rating-form').addEventListener('submit', (event) => event.preventDefault());
$('next').addEventListener('click', next);
$('prev').addEventListener('click', previous);
document.addEventListener('keydown', (event) => {
  if ($('rating').hidden || event.altKey || event.ctrlKey || event.metaKey) return;
  const tag = event.target.tagName;
  if (tag === 'INPUT' || tag === 'TEXTAREA') return;  // arrows choose answers there
  if (event.key === 'ArrowRight') { event.preventDefault(); next(); }
  if (event.key === 'ArrowLeft') { event.preventDefault(); previous(); }
});

$('pause').addEventListener('click', () => {
  state.paused = !state.paused;
  $('pause').setAttribute('aria-pressed', String(state.paused));
  $('pause').textContent = state.paused ? 'Play animation' : 'Pause animation';
});

// --- follow-up -------------------------------------------------------------------------------

function openFollowup() {
  show('followup');
  const f = state.session.free_text || {};
  for (const name of ['criteria', 'frequency', 'missing']) $('followup-form').elements[name].value = f[name] || '';
  $('followup-title').focus();
}

$('back-to-clips').addEventListener('click', () => openClip(state.clips.length - 1));
$('followup-form').addEventListener('submit', async (event) => {
  event.preventDefault();
  const form = event.target;
  const answers = {};
  for (const name of ['criteria', 'frequency', 'missing']) answers[name] = form.elements[name].value;
  try {
    await state.saving;  // every rating reaches the server before the study is marked finished
    await api('PUT', '/api/free-text', answers);
    await api('POST', '/api/finish');
    state.session.free_text = answers;
    state.session.finished = true;
    showError('');
    show('done');
    $('done-title').focus();
  } catch (e) { showError(e.message); }
});

// --- skeleton animation ----------------------------------------------------------------------
// Clip frame: metres, +Y up, the body faces +Z, the subject's left is +X.

const DEG = Math.PI / 180;
const VIEWS = {
  // Seen from in front, 45° to the subject's left and 45° above.
  'view-oblique': (p) => {
    const yaw = 45 * DEG, pitch = 45 * DEG;
    const x = p[0] * Math.cos(yaw) - p[2] * Math.sin(yaw);
    const z = p[0] * Math.sin(yaw) + p[2] * Math.cos(yaw);
    return [-x, p[1] * Math.cos(pitch) - z * Math.sin(pitch)];
  },
  'view-top': (p) => [-p[0], p[2]],   // from above, facing up the screen
  'view-side': (p) => [p[2], p[1]],   // from the subject's right, facing right
  'view-front': (p) => [-p[0], p[1]], // from in front: subject's left on the viewer's right
};

function prepareClip(data) {
  const n = data.joints.length;
  const side = data.joints.map((name) => (name.startsWith('left') ? 'left' : name.startsWith('right') ? 'right' : 'centre'));
  const views = {};
  for (const [id, project] of Object.entries(VIEWS)) {
    const frames = data.frames.map((flat) => {
      const out = [];
      for (let j = 0; j < n; ++j) out.push(project([flat[3 * j], flat[3 * j + 1], flat[3 * j + 2]]));
      return out;
    });
    let minX = Infinity, maxX = -Infinity, minY = Infinity, maxY = -Infinity;
    for (const f of frames) for (const [x, y] of f) {
      minX = Math.min(minX, x); maxX = Math.max(maxX, x); minY = Math.min(minY, y); maxY = Math.max(maxY, y);
    }
    views[id] = { frames, box: [minX, maxX, minY, maxY] };
  }
  return { fps: data.fps || 20, count: data.frames.length, parents: data.parents, side, views };
}

let animationHandle = 0;
let shownFrame = 0;
function stopAnimation() {
  cancelAnimationFrame(animationHandle);
  animationHandle = 0;
}

function startAnimation(clip) {
  stopAnimation();
  let last = performance.now();
  let time = 0;
  const tick = (now) => {
    // rAF timestamps can precede the performance.now() taken at start: never step backwards.
    if (!state.paused) time += Math.max(0, now - last) / 1000;
    last = now;
    shownFrame = Math.max(0, Math.floor(time * clip.fps)) % clip.count;
    for (const id of Object.keys(VIEWS)) drawView($(id), clip, clip.views[id], shownFrame);
    animationHandle = requestAnimationFrame(tick);
  };
  animationHandle = requestAnimationFrame(tick);
}

const COLOURS = { left: '#0072b2', right: '#d55e00', centre: '#333333' };
function drawView(canvas, clip, view, frame) {
  const ctx = canvas.getContext('2d');
  const w = canvas.width, h = canvas.height;
  ctx.fillStyle = '#f7f7f7';
  ctx.fillRect(0, 0, w, h);
  const [minX, maxX, minY, maxY] = view.box;
  const scale = 0.85 * Math.min(w / Math.max(maxX - minX, 0.2), h / Math.max(maxY - minY, 0.2));
  const cx = (minX + maxX) / 2, cy = (minY + maxY) / 2;
  const px = (p) => [w / 2 + (p[0] - cx) * scale, h / 2 - (p[1] - cy) * scale];
  const pts = view.frames[frame].map(px);
  ctx.lineCap = 'round';
  ctx.lineWidth = 5;
  for (let j = 0; j < pts.length; ++j) {
    const parent = clip.parents[j];
    if (parent < 0) continue;
    ctx.strokeStyle = COLOURS[clip.side[j]];
    ctx.beginPath();
    ctx.moveTo(pts[parent][0], pts[parent][1]);
    ctx.lineTo(pts[j][0], pts[j][1]);
    ctx.stroke();
  }
  for (let j = 0; j < pts.length; ++j) {
    ctx.fillStyle = COLOURS[clip.side[j]];
    ctx.beginPath();
    ctx.arc(pts[j][0], pts[j][1], 4, 0, 2 * Math.PI);
    ctx.fill();
  }
}

buildScales();
start();
