// Real-browser end-to-end test of the review page: Debian's chromium driven by playwright-core.
// A participant answers three clips by keyboard only, reloads the page, resumes at clip 4,
// answers the rest, fills the follow-up and finishes; the stored answers are then checked with
// `wheelpose review export`. Saves a screenshot of the rating page.
// Usage: node review_e2e.mjs <wheelpose binary> <repo root> [screenshot.png]
import { startServer, launchBrowser } from './harness.mjs';
import { execFileSync } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import assert from 'node:assert/strict';

const [binary, repo, screenshot] = process.argv.slice(2);
assert.ok(binary && repo, 'usage: node review_e2e.mjs <wheelpose> <repo> [screenshot.png]');
const work = fs.mkdtempSync(path.join(os.tmpdir(), 'wheelpose-review-browser-'));
const run = (...args) => execFileSync(binary, args, { encoding: 'utf8' });

// Two groups of three library clips.
run('motion', 'library', '--out', path.join(work, 'lib'), '--exports', 'json');
const groups = { humanml: ['clap_hands', 'basketball_dribble', 'chore_wipe_table'],
                 text2motion: ['cook_chop_vegetables', 'chore_sweep_floor', 'clap_overhead_cheer'] };
for (const [g, names] of Object.entries(groups)) {
  fs.mkdirSync(path.join(work, g));
  for (const n of names) fs.copyFileSync(path.join(work, 'lib', n + '.json'), path.join(work, g, n + '.json'));
}
const db = path.join(work, 'review.sqlite');
const invite = run('review', 'invite', '--db', db, '--name', 'P1');
const token = /#token=([0-9a-f]{64})/.exec(invite)[1];

const { server, url } = await startServer(binary, ['review', 'serve', '--clips', path.join(work, 'humanml'),
  path.join(work, 'text2motion'), '--db', db, '--port', '0', '--web', path.join(repo, 'web', 'review')]);
const { page, close } = await launchBrowser({ width: 1280, height: 900 });
let failed = false;
try {
  const errors = [];
  page.on('pageerror', (e) => errors.push(e.message));
  page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
  const key = (k, times = 1) => (async () => { for (let i = 0; i < times; ++i) await page.keyboard.press(k); })();
  const focusedId = () => page.evaluate(() => document.activeElement && document.activeElement.id);

  await page.goto(`${url}/#token=${token}`);
  // Consent and questionnaire, by keyboard.
  await page.locator('#consent').waitFor({ state: 'visible' });
  await key('Tab'); await key('Tab');  // skip link, checkbox
  while ((await focusedId()) !== 'consent-box') await key('Tab');
  await key('Space');
  await key('Tab'); await key('Enter');
  await page.locator('#questionnaire').waitFor({ state: 'visible' });
  assert.equal(await focusedId(), 'q-age');
  await page.keyboard.type('34');
  await key('Tab'); await page.keyboard.type('F');
  await key('Tab'); await page.keyboard.type('Teacher');
  await key('Tab'); await page.keyboard.type('Spinal cord injury');
  await key('Tab'); await page.keyboard.type('T-12');
  await key('Tab'); await page.keyboard.type('Swimming');
  await key('Tab'); await page.keyboard.type('Full');
  await key('Tab'); await key('Enter');

  // One clip by keyboard: Tab into each radio group, Space picks the first option, arrows move.
  const expected = [];
  async function answerClip(n, q1, q2, q3, shot) {
    await page.locator('#rating').waitFor({ state: 'visible' });
    assert.match(await page.locator('#rating-title').textContent(), new RegExp(`^Motion ${n} of 6`));
    assert.equal(await focusedId(), 'rating-title');
    await key('Tab');
    assert.equal(await focusedId(), 'pause');
    await key('Tab'); await key('Space'); await key('ArrowRight', q1 - 1);
    assert.equal(await focusedId(), `q1-${q1}`);
    await key('Tab'); await key('Space'); await key('ArrowRight', q2 - 1);
    await key('Tab'); await key('Space'); if (!q3) await key('ArrowRight');
    await page.locator('#saved').filter({ hasText: 'Answer saved.' }).waitFor();
    if (shot) {
      await page.waitForTimeout(400);  // let the animation draw a few frames
      await page.screenshot({ path: shot, fullPage: true });
    }
    while ((await focusedId()) !== 'next') await key('Tab');
    await key('Enter');
    expected.push({ q1, q2, q3 });
  }
  await answerClip(1, 5, 3, true, screenshot);
  await answerClip(2, 2, 6, false);
  // Arrow-key navigation back and forth keeps the answers.
  await page.locator('#rating-title').filter({ hasText: 'Motion 3 of 6' }).waitFor();
  await key('ArrowLeft');
  await page.locator('#rating-title').filter({ hasText: 'Motion 2 of 6' }).waitFor();
  assert.equal(await page.locator('#q1-2').isChecked(), true);
  assert.equal(await page.locator('#q3-no').isChecked(), true);
  await key('ArrowRight');
  await answerClip(3, 7, 7, true);

  // Reload: the page resumes at the first unanswered clip.
  await page.reload();
  await page.locator('#rating-title').filter({ hasText: 'Motion 4 of 6' }).waitFor();
  assert.equal(await page.locator('#progress').getAttribute('value'), '3');
  // The animation is drawn (not a blank canvas) and can be paused.
  const inked = await page.evaluate(() => {
    const c = document.getElementById('view-front');
    const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
    let n = 0;
    for (let i = 0; i < d.length; i += 4) n += d[i] < 120 || d[i + 2] < 120;
    return n;
  });
  assert.ok(inked > 100, 'front view canvas is empty');
  await page.locator('#pause').click();
  assert.equal(await page.locator('#pause').getAttribute('aria-pressed'), 'true');
  await page.locator('#pause').click();
  // At 640 px wide (1280 px at 200 % zoom) nothing scrolls sideways.
  await page.setViewportSize({ width: 640, height: 900 });
  assert.ok(await page.evaluate(() => document.documentElement.scrollWidth <= 640), 'horizontal scroll at 200% zoom');
  await page.setViewportSize({ width: 1280, height: 900 });
  await page.locator('#rating-title').focus();

  await answerClip(4, 1, 1, false);
  await answerClip(5, 4, 4, true);
  await answerClip(6, 3, 2, true);
  await page.locator('#followup').waitFor({ state: 'visible' });
  await page.locator('#f-criteria').fill('Balance <b>and</b> reach');
  await page.locator('#followup-form button[type=submit]').click();
  await page.locator('#done').waitFor({ state: 'visible' });
  assert.deepEqual(errors, []);

  // What the server stored, in the participant's (recorded, random) group order.
  const exported = JSON.parse(run('review', 'export', '--db', db, '--format', 'json'));
  const p = exported.participants[0];
  assert.equal(p.questionnaire.level, 'T-12');
  assert.equal(p.questionnaire.age, 34);
  assert.equal(p.free_text.criteria, 'Balance <b>and</b> reach');
  assert.notEqual(p.finished_at, '');
  const order = p.group_order.flatMap((g) => [...groups[g]].sort().map((n) => `${g}/${n}`));  // file-name order
  const byClip = Object.fromEntries(p.ratings.map((r) => [r.clip, r]));
  order.forEach((clip, i) => {
    assert.ok(byClip[clip], `no answer stored for ${clip}`);
    assert.deepEqual({ q1: byClip[clip].q1, q2: byClip[clip].q2, q3: byClip[clip].q3 }, expected[i], clip);
  });
  console.log(`browser e2e: 6 clips answered by keyboard, resumed after reload, order ${p.group_order.join(' then ')}`);
} catch (e) {
  failed = true;
  console.error(e);
} finally {
  await close();
  server.kill('SIGTERM');
  fs.rmSync(work, { recursive: true, force: true });
}
process.exit(failed ? 1 : 0);
