// Long work never blocks the page, on the backend under test: the contour stack of a folded volume
// and the exports of a folded net run in the worker while the page keeps drawing and answering
// clicks; the work list shows them with their time, progress and a Cancel that stops them; a newer
// edit supersedes the stack under way; and what the worker makes is what the page made before.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { launch, open, settle, ARTIFACTS, pick } from './harness.mjs';
import { random } from './random.mjs';

let browser;
before(async () => { browser = await launch(); });
after(async () => { await browser?.close(); });

const model = (solid) => JSON.stringify({ format: 'bezsolid', version: 1, solid });

/**
 * A net of `degree` whose control points are those of a regular grid over the unit square or cube
 * in shuffled order, with random ξ: folded everywhere, so an exact contour needs the inverse map
 * at every sample. The work of such a net is bounded (a contour at the default resolution within
 * about two seconds natively), so the test that watches the page while the work runs takes the
 * heaviest there is: the stack of the degree-(16, 16, 16) net, seventeen slices of shuffled 16×16
 * patches, which runs for seconds in the worker; the SVG of a shuffled 16×16 patch runs long enough
 * to be cancelled.
 */
function shuffledNet(degree, seed) {
  const rnd = random(seed);
  const sides = degree.map((d) => d + 1);
  const count = sides.reduce((a, b) => a * b, 1);
  const at = [];
  for (let k = 0; k < count; k++) {
    const index = [];
    let rest = k;
    for (let a = sides.length - 1; a >= 0; a--) {
      index[a] = rest % sides[a];
      rest = Math.floor(rest / sides[a]);
    }
    at.push(index.map((i, a) => i / degree[a]));
  }
  for (let k = count - 1; k > 0; k--) {
    const j = Math.floor(rnd() * (k + 1));
    [at[k], at[j]] = [at[j], at[k]];
  }
  const kind = degree.length === 2 ? 'patch' : 'volume';
  return model({ kind, degree, points: at.map((p) => [...p, rnd() * 2 - 1]) });
}

const working = (page) => page.evaluate(() => document.body.dataset.working ?? '');

/**
 * What the page does for `ms` while work runs: how late its thread ran a timer set every 10 ms at
 * worst (the longest it was held), the longest task on it (as the browser reports long tasks), the
 * animation frames it drew (their count and the largest gap between two), and how long a click in
 * the middle took to be handled.
 */
async function responsiveness(page, ms) {
  const watched = page.evaluate((span) => new Promise((resolve) => {
    const frames = [];
    const tasks = [];
    let beat = performance.now();
    let held = 0;
    const observer = new PerformanceObserver((list) => {
      for (const e of list.getEntries()) tasks.push(e.duration);
    });
    observer.observe({ type: 'longtask' });
    const t0 = performance.now();
    const tick = () => {
      const now = performance.now();
      held = Math.max(held, now - beat);
      beat = now;
      if (now - t0 < span) setTimeout(tick, 10);
    };
    setTimeout(tick, 10);
    const step = (t) => {
      frames.push(t);
      if (t - t0 < span) {
        requestAnimationFrame(step);
        return;
      }
      observer.disconnect();
      const gaps = frames.slice(1).map((x, k) => x - frames[k]);
      resolve({ held, task: Math.max(0, ...tasks), frames: frames.length, gap: Math.max(0, ...gaps) });
    };
    requestAnimationFrame(step);
  }), ms);
  await page.waitForTimeout(ms / 3);
  const t0 = Date.now();
  await page.click('#debug-toggle');
  await page.waitForSelector('#debug:not([hidden])', { timeout: 5_000 });
  const click = Date.now() - t0;
  await page.click('#debug-toggle');
  return { ...(await watched), click };
}

/** How long the page is watched while work runs, in milliseconds. */
const WINDOW = 2000;

/**
 * The page answered while the work ran: its thread was never held long, it drew frames, and a
 * click was handled. The work measured here takes tens of seconds: on the page's thread it would
 * hold it for the whole window, with no frame and no click. The bounds are loose because the
 * suite runs on two cores with software rendering: with a worker busy, the browser's drawing (its
 * GPU process) starves, so frames came from every 16 ms (idle) down to 7 in 2 s, with tasks of up to
 * 900 ms waiting on the GPU process (none of it the page's code) and clicks of a second or two.
 */
function answered(r, when) {
  assert.ok(r.held < 1500, `the page's thread was held ${r.held.toFixed(0)} ms at most ${when}`);
  assert.ok(r.task < 1500, `the longest task on the page's thread ${when}: ${r.task.toFixed(0)} ms`);
  assert.ok(r.frames >= 3, `${r.frames} frames in ${WINDOW} ms ${when}`);
  assert.ok(r.click < 2500, `a click answered in ${r.click} ms ${when}`);
}

const measured = {};
/** Keeps what was measured, for the artifacts (work-frames.json). */
function record(what, r) {
  measured[what] = r;
  writeFileSync(join(ARTIFACTS, 'work-frames.json'), JSON.stringify(measured, null, 2));
}

/** The Cancel button of the work under way of `kind`. */
const cancelOf = (page, kind) => page.locator(`#work .task[data-kind="${kind}"] button`);

test('a folded volume: its contour stack runs in the worker, the page keeps drawing; Cancel, newer edits and another model stop it', async () => {
  const { page, errors } = await open(browser);
  await page.evaluate((text) => {
    window.bezsolid.modeler.load_model(text);
    window.bezsolid.redraw();
  }, shuffledNet([16, 16, 16], 1));
  const line = page.locator('#work .task[data-kind="stack"]');
  await page.waitForSelector('#work .task[data-kind="stack"][data-state="running"]', { timeout: 30_000 });
  assert.match(await line.textContent(), /Contour stack across w…/);
  assert.equal(await page.evaluate(() => JSON.parse(window.bezsolid.modeler.panel()).stack), null, 'no stack drawn yet');
  assert.match(await page.textContent('#surface-info'), /contour stack: not made yet/);
  await page.locator('#view3d').screenshot({ path: join(ARTIFACTS, 'work-stack.png') });
  await page.locator('#work').screenshot({ path: join(ARTIFACTS, 'work-list.png') });

  // Cancel: the job stops and is not asked for again until the model changes.
  await cancelOf(page, 'stack').click();
  await page.waitForFunction(() => !(document.body.dataset.working ?? '').includes('stack'));
  await page.waitForTimeout(500);
  await settle(page);
  assert.ok(!(await working(page)).includes('stack'), 'a cancelled stack is not started again');

  // An edit asks for the stack of the new model; a second edit supersedes it: one job under way.
  await page.focus('#view');
  await page.keyboard.press('Tab');
  await page.keyboard.press('PageUp');
  await page.waitForFunction(() => (document.body.dataset.working ?? '').includes('stack'));
  await page.keyboard.press('PageUp');
  await settle(page);
  await page.waitForTimeout(300);
  assert.equal(await page.locator('#work .task[data-kind="stack"]').count(), 1, 'the newer request replaced the older');
  // A mesh export of the folded volume is asked for beside it: the jobs under way leave the page a
  // core (on two cores the export waits for the stack); the page keeps drawing and answering while
  // they run. The export takes tens of seconds (every sample of the grid through the atlas, within
  // its work budget), the window two; it is cancelled after, and nothing is saved.
  let downloaded = false;
  page.on('download', () => { downloaded = true; });
  await pick(page, 'export', 'stl');
  await page.waitForSelector('#work .task[data-kind="export"]');
  await page.locator('#work').screenshot({ path: join(ARTIFACTS, 'work-list-two.png') });
  const during = await responsiveness(page, WINDOW);
  record('stack and STL export', during);
  const [running, cores, exporting] = await page.evaluate(() => [
    document.querySelectorAll('#work .task[data-state="running"]').length,
    Math.max(1, (navigator.hardwareConcurrency || 2) - 1),
    document.querySelectorAll('#work .task[data-kind="export"]').length,
  ]);
  assert.equal(exporting, 1, 'the export was still under way: the measure holds');
  answered(during, 'while a stack and an export are asked for');
  assert.ok(running >= 1 && running <= cores, `${running} jobs under way for ${cores} free cores`);
  await cancelOf(page, 'export').click();
  await page.waitForFunction(() => /Exporting STL was cancelled; nothing was saved/.test(document.getElementById('status').textContent));
  // Another model: any work on the folded one still under way is no longer wanted, and stops
  // without a Cancel.
  await pick(page, 'preset', 'fig9');
  await page.waitForFunction(() => !document.body.dataset.working);
  assert.equal(downloaded, false);
  assert.deepEqual(errors, []);
  await page.close();
});

test('the stack from the worker is the stack the page made; the previous one stays drawn until it comes', async () => {
  const { page, errors } = await open(browser);
  await pick(page, 'preset', 'fish');
  await page.waitForSelector('body[data-kind="volume"]');
  await page.waitForFunction(() => document.body.dataset.stack?.endsWith(',1'), null, { timeout: 30_000 });
  const [segments] = await page.evaluate(() => JSON.parse(window.bezsolid.modeler.panel()).stack);
  // The same segments, made here by the function the page used to call on its own thread.
  const here = await page.evaluate(async () => {
    const m = await (await import(new URL('modules.js', location.href).href)).tools();
    return m.headless_stack(window.bezsolid.modeler.model_json(), 2, () => {}).length / 6;
  });
  assert.equal(segments, here);
  assert.ok(segments > 50, `${segments} segments`);
  assert.match(await page.textContent('#surface-info'), new RegExp(`contour stack: ${segments.toLocaleString('en')} segments$`));
  // An edit: the stack of the model before it is drawn (marked so) until the new one comes.
  await page.focus('#view');
  await page.keyboard.press('Tab');
  const info = await page.evaluate(() => {
    window.bezsolid.modeler.set_selected_xi(-2);
    const { stack } = JSON.parse(window.bezsolid.modeler.panel());
    window.bezsolid.redraw();
    return stack;
  });
  assert.deepEqual(info, [segments, false]);
  await page.waitForFunction(() => document.body.dataset.stack?.endsWith(',1'), null, { timeout: 30_000 });
  assert.deepEqual(errors, []);
  await page.close();
});

test('a volume drawn with its stack and surface from the worker is the picture the page drew making them itself', async () => {
  const shots = [];
  for (const worker of [true, false]) {
    const { page, errors } = await open(browser);
    if (!worker) await page.evaluate(() => window.bezsolid.modeler.set_external_surface(false));
    await pick(page, 'preset', 'ring');
    await page.waitForFunction(() => document.body.dataset.stack?.endsWith(',1') && JSON.parse(window.bezsolid.modeler.panel()).surface?.[1] === 64, null, { timeout: 30_000 });
    // Closer: the outer slices' contours show around the ring.
    await page.evaluate(() => {
      window.bezsolid.modeler.wheel_3d(-400);
      window.bezsolid.redraw();
    });
    await settle(page);
    const png = await page.locator('#view3d').screenshot({ mask: [page.locator('#fit-3d')] });
    writeFileSync(join(ARTIFACTS, `work-ring-${worker ? 'worker' : 'page'}.png`), png);
    shots.push(png);
    assert.deepEqual(errors, []);
    await page.close();
  }
  assert.ok(shots[0].equals(shots[1]), 'the same picture (work-ring-worker.png, work-ring-page.png)');
});

test('the SVG of a folded patch is made in the worker with a Cancel; a regular one is the SVG made before', async () => {
  const { page, errors } = await open(browser);
  // A regular patch: the worker's SVG is the one the tools' module makes on the page.
  const same = await page.evaluate(async () => (await window.bezsolid.tools()).headless_svg(window.bezsolid.modeler.patch_json()));
  const [download] = await Promise.all([page.waitForEvent('download'), pick(page, 'export', 'svg')]);
  const path = join(ARTIFACTS, 'work-contours.svg');
  await download.saveAs(path);
  assert.equal(readFileSync(path, 'utf8'), same);

  await page.evaluate((text) => {
    window.bezsolid.modeler.load_model(text);
    window.bezsolid.redraw();
  }, shuffledNet([16, 16], 1));
  await settle(page);
  let downloaded = false;
  page.on('download', () => { downloaded = true; });
  await pick(page, 'export', 'svg');
  await page.waitForSelector('#work .task[data-kind="export"][data-state="running"]');
  writeFileSync(join(ARTIFACTS, 'work-svg.png'), await page.screenshot());
  await cancelOf(page, 'export').click();
  await page.waitForFunction(() => /Exporting SVG was cancelled; nothing was saved/.test(document.getElementById('status').textContent));
  assert.equal(await working(page), '');
  assert.equal(downloaded, false);
  assert.deepEqual(errors, []);
  await page.close();
});

test('an export of a volume that folds over itself everywhere says it is approximate; a regular one does not', async () => {
  const { page, errors } = await open(browser);
  const exportStl = async () => {
    const [download] = await Promise.all([page.waitForEvent('download', { timeout: 120_000 }), pick(page, 'export', 'stl')]);
    await download.path();
    return page.evaluate(() => {
      const status = document.getElementById('status');
      return [status.textContent, status.dataset.kind];
    });
  };
  await pick(page, 'preset', 'fish');
  await page.waitForSelector('body[data-kind="volume"]');
  const [regular, regularKind] = await exportStl();
  assert.match(regular, /^Saved bezsolid\.stl\.$/);
  assert.notEqual(regularKind, 'warn');

  // The degree-16 net in shuffled order, meshed at 16 cells: within the work budget, many of its
  // evaluations cannot find every preimage, and the page says so where it says the file is saved.
  await page.evaluate((text) => {
    window.bezsolid.modeler.load_model(text);
    window.bezsolid.redraw();
  }, shuffledNet([16, 16, 16], 2));
  await page.fill('#resolution', '16');
  await page.dispatchEvent('#resolution', 'change');
  const [folded, foldedKind] = await exportStl();
  assert.match(folded, /^Saved bezsolid\.stl, approximate where the net folds over itself very many times: \d+ evaluations? ran out of their work budget\.$/);
  assert.equal(foldedKind, 'warn');
  await pick(page, 'preset', 'fig9');
  await page.waitForFunction(() => !document.body.dataset.working);
  assert.deepEqual(errors, []);
  await page.close();
});

test('with several workers a surface and a contour stack are made in shares, and are what one worker makes', async () => {
  const { page, errors } = await open(browser, '?workers=3');
  const fine = () => page.waitForFunction(() => {
    const p = JSON.parse(window.bezsolid.modeler.panel());
    return p.surface_current && p.surface?.[1] === 64;
  }, null, { timeout: 60_000 });
  // What one worker makes of what the view shows, here on the page's thread.
  const whole = () => page.evaluate(async () => {
    const m = await (await import(new URL('modules.js', location.href).href)).tools();
    const { modeler } = window.bezsolid;
    return m.headless_surface(modeler.view_json() ?? modeler.model_json(), 64).length / 18;
  });
  await pick(page, 'preset', 'fish');
  await page.waitForSelector('body[data-kind="volume"]');
  await fine();
  assert.equal(await page.getAttribute('body', 'data-surface-shares'), '3');
  const [triangles] = await page.evaluate(() => JSON.parse(window.bezsolid.modeler.panel()).surface);
  assert.ok(triangles > 500, `${triangles} triangles`);
  assert.equal(triangles, await whole());
  // Its contour stack, slices in shares: the stack one worker makes.
  await page.waitForFunction(() => document.body.dataset.stack?.endsWith(',1'), null, { timeout: 30_000 });
  assert.equal(await page.getAttribute('body', 'data-stack-shares'), '3');
  const [segments] = await page.evaluate(() => JSON.parse(window.bezsolid.modeler.panel()).stack);
  const here = await page.evaluate(async () => {
    const m = await (await import(new URL('modules.js', location.href).href)).tools();
    return m.headless_stack(window.bezsolid.modeler.model_json(), 2, () => {}).length / 6;
  });
  assert.ok(segments > 50, `${segments} segments`);
  assert.equal(segments, here);
  // A model of many solids: the volume with a sphere beside it.
  await page.click('[data-add="sphere"]');
  await fine();
  const [tree] = await page.evaluate(() => JSON.parse(window.bezsolid.modeler.panel()).surface);
  assert.ok(tree > 500 && tree !== triangles, `${tree} triangles with the sphere`);
  assert.equal(tree, await whole());
  assert.equal(await page.getAttribute('body', 'data-surface-shares'), '3');
  // An address asking for no workers, or too many, is told so and gets the default.
  const bad = await open(browser, '?workers=0');
  assert.match(await bad.page.textContent('#status'), /"workers=0" in the address is not 1 to 8/);
  await bad.page.close();
  assert.deepEqual(errors, []);
  await page.close();
});


test('Measure: the volume, area and box of the mesh the export makes, by keyboard, shown beside the button until the model changes; a patch its area and perimeter; a free-form result', async () => {
  const { page, errors } = await open(browser);
  // A patch: the area and perimeter of the contour the SVG export draws.
  await page.focus('#measure');
  await page.keyboard.press('Enter');
  await page.waitForFunction(() => /^Area [\d.]+, perimeter [\d.]+: measured on the contour at 256 cells per side/.test(document.getElementById('measure-out').textContent));
  const patch = JSON.parse(await page.evaluate(() => document.body.dataset.measure));
  assert.equal(patch.dimension, 2);
  assert.ok(patch.area > 0 && patch.perimeter > 0);

  // A volume: what the STL export writes, read back here, is what was measured.
  await pick(page, 'preset', 'blob');
  await page.waitForSelector('body[data-kind="volume"]');
  // A new model: the patch's measurement is gone.
  assert.equal(await page.textContent('#measure-out'), '');
  await page.click('#measure');
  await page.waitForFunction(() => /^Volume [\d.]+, surface area [\d.]+, bounding box/.test(document.getElementById('measure-out').textContent));
  const m = JSON.parse(await page.evaluate(() => document.body.dataset.measure));
  const [download] = await Promise.all([page.waitForEvent('download'), pick(page, 'export', 'stl')]);
  const stl = readFileSync(await download.path());
  const count = stl.readUInt32LE(80);
  assert.equal(m.triangles, count);
  let volume = 0;
  for (let t = 0; t < count; t++) {
    const [a, b, c] = [0, 1, 2].map((k) => [0, 1, 2].map((x) => stl.readFloatLE(84 + 50 * t + 12 + 12 * k + 4 * x)));
    volume += (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0])) / 6;
  }
  assert.ok(Math.abs(m.volume - volume) < 1e-4 * m.volume, `${m.volume} against ${volume}`);
  // The result stays while the model does (it does not fade as a passing note does).
  await page.waitForTimeout(5500);
  assert.match(await page.textContent('#measure-out'), /^Volume/);
  writeFileSync(join(ARTIFACTS, 'measure.png'), await page.screenshot());
  // A free-form result: its mesh measured with its own button.
  await page.check('input[name="workspace"][value="freeform"]');
  await page.waitForSelector('body[data-workspace="freeform"]');
  const before = await page.evaluate(() => document.body.dataset.measure);
  await page.click('#ff-measure');
  await page.waitForFunction((old) => document.body.dataset.measure !== old
    && /^Volume [\d.]+/.test(document.getElementById('ff-measure-out').textContent), before);
  const free = JSON.parse(await page.evaluate(() => document.body.dataset.measure));
  assert.ok(free.dimension === 3 && free.volume > 0 && free.triangles > 0);
  assert.deepEqual(errors, []);
  await page.close();
});
