// Real-browser end-to-end test of the demo page (`wheelpose demo`): Debian's chromium loads the
// three models with TF.js, runs them on a bundled example picked by keyboard, and must draw the
// people `wheelpose predict --size 256` finds (the ensemble panel: `predict --model
// movenet-multipose --model movenet-wheelchair-full --flip`), keypoints within a pixel; a
// dropped non-image gets a message. Saves a screenshot.
// Usage: node demo_e2e.mjs <wheelpose binary> <repo root> [screenshot.png]
import { startServer, launchBrowser } from './harness.mjs';
import { execFileSync } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import assert from 'node:assert/strict';

const [binary, repo, screenshot] = process.argv.slice(2);
assert.ok(binary && repo, 'usage: node demo_e2e.mjs <wheelpose> <repo> [screenshot.png]');
const work = fs.mkdtempSync(path.join(os.tmpdir(), 'wheelpose-demo-browser-'));
const example = 'wheelchair-1.jpg';
const shipped = (name) => path.join(repo, 'share', 'models', name, 'model.json');

// What `predict` finds on the example with each model, at the page's input size.
fs.mkdirSync(path.join(work, 'images'));
fs.copyFileSync(path.join(repo, 'web', 'demo', 'examples', example), path.join(work, 'images', example));
const expected = {};
for (const [key, models] of [['pretrained', ['movenet-multipose']],
  ['wheelchair', [shipped('movenet-wheelchair')]],
  ['ensemble', ['movenet-multipose', shipped('movenet-wheelchair-full')]]]) {
  const out = path.join(work, key + '.json');
  const flip = key === 'ensemble' ? ['--flip'] : [];
  execFileSync(binary, ['-q', 'predict', ...models.flatMap((m) => ['--model', m]), ...flip,
    '--images', path.join(work, 'images'), '--size', '256', '--out', out]);
  expected[key] = JSON.parse(fs.readFileSync(out, 'utf8'));
}

const { server, url } = await startServer(binary, ['demo', '--port', '0']);
const { page, close } = await launchBrowser({ width: 1400, height: 900 });
let failed = false;
try {
  const errors = [];
  const outside = [];
  page.on('pageerror', (e) => errors.push(e.message));
  page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
  page.on('request', (r) => { if (!r.url().startsWith(url) && !r.url().startsWith('blob:') && !r.url().startsWith('data:')) outside.push(r.url()); });
  // Polls with evaluate: waitForFunction evaluates strings, which the page's CSP forbids.
  const waitFor = async (predicate, arg, what) => {
    for (const end = Date.now() + 120000; Date.now() < end;) {
      if (await page.evaluate(predicate, arg)) return;
      await new Promise((r) => setTimeout(r, 200));
    }
    throw new Error('timed out waiting for ' + what);
  };
  await page.goto(url + '/');
  await waitFor(() => window.demoState && (window.demoState.ready || window.demoState.error), null, 'the models');
  assert.equal(await page.evaluate(() => window.demoState.error), null);

  // Keyboard only: focus the example list, pick the example, Tab to the button, Enter.
  await page.focus('#example');
  await page.selectOption('#example', example);
  await page.keyboard.press('Tab');
  assert.equal(await page.evaluate(() => document.activeElement.id), 'show-example');
  await page.keyboard.press('Enter');
  await waitFor((name) => window.demoState.image === name && !window.demoState.busy, example,
    'the results');
  const results = await page.evaluate(() => window.demoState.results);
  const backend = await page.evaluate(() => window.demoState.backend);
  assert.equal(backend, 'wasm', 'the page must run on the WebAssembly backend');
  // The time a user waits for the three panels, cold (the first photo) and warm (the next).
  const cold = await page.evaluate(() => window.demoState.seconds);
  await page.evaluate(() => { window.demoState.seconds = null; });
  await page.click('#show-example');
  await waitFor(() => window.demoState.seconds !== null, null, 'the second run');
  const warm = await page.evaluate(() => window.demoState.seconds);
  const [width, height] = await page.evaluate(() => {
    const c = document.getElementById('canvas-pretrained');
    return [c.width, c.height];
  });
  console.log(`benchmark: demo three panels on ${example} (${width}x${height}), ${backend} backend: ` +
    `${cold.toFixed(2)} s cold, ${warm.toFixed(2)} s warm`);
  // The three panels line up: their pictures start at the same height whatever the titles do.
  const tops = await page.evaluate(() => ['pretrained', 'wheelchair', 'ensemble'].map(
    (k) => document.getElementById('canvas-' + k).getBoundingClientRect().top));
  assert.ok(Math.max(...tops) - Math.min(...tops) < 1, `the panels' pictures start at ${tops.join(', ')}`);

  // Every person the page draws (score >= 0.2) is one `predict` found: same score within 0.03,
  // confident keypoints within 1 px (the page resizes like OpenCV).
  for (const key of ['pretrained', 'wheelchair', 'ensemble']) {
    const page_people = results[key];
    const strong = expected[key].filter((p) => p.score >= 0.25);
    assert.ok(strong.length >= 1, `${key}: predict finds nobody on ${example}`);
    assert.ok(page_people.length >= strong.length, `${key}: page drew ${page_people.length}, predict has ${strong.length} scoring 0.25+`);
    for (const person of page_people) {
      const cx = person.bbox[0] + person.bbox[2] / 2, cy = person.bbox[1] + person.bbox[3] / 2;
      let best = null, bestDistance = Infinity;
      for (const p of expected[key]) {
        const d = Math.hypot(p.bbox[0] + p.bbox[2] / 2 - cx, p.bbox[1] + p.bbox[3] / 2 - cy);
        if (d < bestDistance) { bestDistance = d; best = p; }
      }
      assert.ok(best && Math.abs(best.score - person.score) < 0.03,
        `${key}: page person scoring ${person.score} has no match in predict's results`);
      let worst = 0;
      for (let k = 0; k < 17; ++k) {
        const [x, y, s] = person.keypoints[k];
        if (s < 0.3 || best.keypoints[3 * k + 2] < 0.3) continue;
        worst = Math.max(worst, Math.hypot(x - best.keypoints[3 * k], y - best.keypoints[3 * k + 1]));
      }
      assert.ok(worst <= 1, `${key}: a keypoint is ${worst.toFixed(1)} px from predict's`);
      console.log(`${key}: person ${person.score.toFixed(3)} matches predict (${best.score.toFixed(3)}), keypoints within ${worst.toFixed(2)} px`);
    }
    const items = await page.locator(`#people-${key} li`).allTextContents();
    assert.equal(items.length, page_people.length);
    assert.match(items[0], /^Person 1: score 0\.\d\d, \d+ of 17 keypoints$/);
  }
  if (screenshot) await page.screenshot({ path: screenshot, fullPage: true });

  // A dropped file that is not an image: one message, nothing run.
  const transfer = await page.evaluateHandle(() => {
    const dt = new DataTransfer();
    dt.items.add(new File(['<b>not</b> a photo'], 'notes<b>.txt', { type: 'text/plain' }));
    return dt;
  });
  await page.dispatchEvent('body', 'drop', { dataTransfer: transfer });
  const status = await page.textContent('#status');
  assert.match(status, /“notes<b>\.txt” is not an image \(text\/plain\)/);
  assert.equal(await page.locator('#status b').count(), 0, 'the file name must be shown as text');
  assert.equal(await page.evaluate(() => window.demoState.image), example);

  assert.deepEqual(outside, [], 'the page must load nothing from outside the server');
  assert.deepEqual(errors, []);
  console.log('demo_e2e: ok');
} catch (e) {
  failed = true;
  console.error(e);
} finally {
  await close();
  server.kill('SIGTERM');
  fs.rmSync(work, { recursive: true, force: true });
}
process.exit(failed ? 1 : 0);
