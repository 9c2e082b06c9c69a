// The soak: many ordinary actions in one page, and what the page holds after them. Drags of the
// points of a 16 × 16 patch (pointer events on the 2D view, a frame each), share links opened one
// after another (patches, volumes, free-form scenes, scripts; the same ones in each half),
// switches between the three modes, and script runs. Run in two equal halves; the JS heap (after a
// garbage collection), the wasm memory and the GPU objects the renderers hold are sampled at the
// start, between the halves and at the end, each time in the same state (the Bézier mode, the
// 16 × 16 patch), so that the end can be compared with the middle: what leaks grows with the work,
// what is bounded levels off.
//
// Used by tests/e2e/soak.test.mjs (a shorter run in the suite) and tests/soak.mjs (the full one).

import { random } from './random.mjs';

/** The counts of the full soak. */
export const FULL = { drags: 2000, links: 200, switches: 50, runs: 50 };

const N = 16; // points per side of the dragged patch

/** The flat 16 × 16 patch over the unit square, ξ = 0.01: the whole square is inside, and a drag
 * of one point by a few tens of pixels opens a hole (a point's weight in `f` is at most 0.04). */
const PATCH = JSON.stringify({
  format: 'bezsolid',
  version: 1,
  solid: {
    kind: 'patch',
    degree: [N - 1, N - 1],
    points: Array.from({ length: N * N }, (_, k) => [Math.floor(k / N) / (N - 1), (k % N) / (N - 1), 0.01]),
  },
});

const frame = (page) => page.evaluate(() => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r))));

/** The links to open: `count` share links of models of every kind, made by the page's module. */
async function makeLinks(page, count, seed) {
  const rnd = random(seed);
  const specs = [];
  for (let k = 0; k < count; k++) {
    const r = rnd();
    if (r < 0.6) {
      // A patch of 2 to 16 points a side; a third of them space-mapped (points jittered).
      const [n, m] = [2 + Math.floor(rnd() * 15), 2 + Math.floor(rnd() * 15)];
      const jitter = rnd() < 0.33 ? 0.3 / Math.max(n, m) : 0;
      const points = [];
      for (let i = 0; i < n; i++) {
        for (let j = 0; j < m; j++) {
          points.push([i / (n - 1) + (rnd() - 0.5) * jitter, j / (m - 1) + (rnd() - 0.5) * jitter, rnd() * 2 - 0.8]);
        }
      }
      specs.push({ kind: 'model', model: { format: 'bezsolid', version: 1, solid: { kind: 'patch', degree: [n - 1, m - 1], points } } });
    } else if (r < 0.8) {
      // A volume of 3 to 5 points a side, a blob-like ξ; some space-mapped.
      const d = [3 + Math.floor(rnd() * 3), 3 + Math.floor(rnd() * 3), 3 + Math.floor(rnd() * 2)];
      const jitter = rnd() < 0.3 ? 0.08 : 0;
      const points = [];
      for (let i = 0; i < d[0]; i++) {
        for (let j = 0; j < d[1]; j++) {
          for (let l = 0; l < d[2]; l++) {
            const c = [i / (d[0] - 1), j / (d[1] - 1), l / (d[2] - 1)];
            const r2 = c.reduce((s, x) => s + (x - 0.5) ** 2, 0);
            points.push([...c.map((x) => x + (rnd() - 0.5) * jitter), 0.6 - 2.2 * r2 + (rnd() - 0.5) * 0.2]);
          }
        }
      }
      specs.push({ kind: 'model', model: { format: 'bezsolid', version: 1, solid: { kind: 'volume', degree: d.map((x) => x - 1), points } } });
    } else if (r < 0.9) {
      const examples = ['icosphere', 'torus', 'blob'];
      const pick = () => examples[Math.floor(rnd() * examples.length)];
      const ops = ['union', 'intersection', 'difference'];
      specs.push({ kind: 'model', model: { format: 'bezsolid', version: 1, solid: { kind: 'esc', operation: ops[Math.floor(rnd() * 3)], operands: [
        { example: pick(), offset: [0, 0, 0] },
        { example: pick(), offset: [rnd() - 0.5, rnd() - 0.5, rnd() - 0.5] },
      ] } } });
    } else {
      specs.push({ kind: 'script', index: Math.floor(rnd() * 7) });
    }
  }
  return page.evaluate(async (list) => {
    const m = await (await import(new URL('modules.js', location.href).href)).tools();
    const examples = JSON.parse(m.plasm_examples());
    return list.map((s) => {
      if (s.kind === 'script') return m.script_link(examples[s.index % examples.length].source);
      const text = JSON.stringify(s.model);
      if (s.model.solid.kind !== 'esc') return m.headless_link(text);
      const f = new m.FreeFormView();
      f.open(text);
      const link = f.link();
      f.free();
      return link;
    });
  }, specs);
}

/** The page in the state every sample is taken in: the Bézier mode with the 16 × 16 patch. */
async function home(page) {
  await page.check('input[name="workspace"][value="bezier"]');
  await page.evaluate((text) => {
    window.bezsolid.modeler.load_model(text);
    window.bezsolid.modeler.set_mode('function');
    window.bezsolid.redraw();
  }, PATCH);
  await frame(page);
}

/** What the page holds now: JS heap after a collection, wasm memory, GPU objects. */
async function sample(page, cdp) {
  await home(page);
  await cdp.send('HeapProfiler.collectGarbage');
  const { metrics } = await cdp.send('Performance.getMetrics');
  const heap = metrics.find((m) => m.name === 'JSHeapUsedSize').value;
  const [buffers, textures, made] = await page.evaluate(() => window.bezsolid.gpuObjects());
  const wasm = await page.evaluate(() => window.bezsolid.wasmMemory());
  return { heap, wasm, buffers, textures, made };
}

/**
 * `count` drags of random inner points of the 16 × 16 patch, up or down: pointer events on the
 * 2D view (down, two moves, up, in one task: the page draws the drag in the next frame), then one
 * frame. Fifty drags to a call into the page.
 */
async function drags(page, count, rnd) {
  const box = await page.locator('#view').boundingBox();
  const [x0, y0] = await page.evaluate(() => [...window.bezsolid.modeler.probe(0, 0)]);
  const [x1, y1] = await page.evaluate(() => [...window.bezsolid.modeler.probe(100, 100)]);
  const at = (wx, wy) => [(wx - x0) * 100 / (x1 - x0), (wy - y0) * 100 / (y1 - y0)];
  const all = [];
  for (let k = 0; k < count; k++) {
    const [i, j] = [1 + Math.floor(rnd() * (N - 2)), 1 + Math.floor(rnd() * (N - 2))];
    const dy = (rnd() < 0.5 ? -1 : 1) * (4 + Math.floor(rnd() * 30));
    all.push([...at(i / (N - 1), j / (N - 1)), dy]);
  }
  for (let k = 0; k < all.length; k += 50) {
    await page.evaluate(async ([list, left, top]) => {
      const view = document.getElementById('view');
      const send = (type, x, y, buttons) => view.dispatchEvent(new PointerEvent(type, {
        clientX: left + x, clientY: top + y, button: 0, buttons, pointerId: 1, pointerType: 'mouse', isPrimary: true, bubbles: true,
      }));
      for (const [x, y, dy] of list) {
        send('pointerdown', x, y, 1);
        send('pointermove', x, y + dy / 2, 1);
        send('pointermove', x, y + dy, 1);
        send('pointerup', x, y + dy, 0);
        await new Promise((r) => requestAnimationFrame(r));
      }
    }, [all.slice(k, k + 50), box.x, box.y]);
  }
}

/** Opens each link through the address, as a pasted link is opened. */
async function openLinks(page, links) {
  for (const link of links) {
    const opened = await page.evaluate((fragment) => new Promise((resolve) => {
      addEventListener('hashchange', () => requestAnimationFrame(() => resolve(true)), { once: true });
      setTimeout(() => resolve(false), 10_000);
      location.hash = fragment;
    }), link);
    if (!opened) throw new Error(`the link ${link.slice(0, 40)}… was not opened`);
  }
  await frame(page);
}

const WORKSPACES = ['freeform', 'script', 'bezier'];

async function switches(page, count, start) {
  for (let k = 0; k < count; k++) {
    const name = WORKSPACES[(start + k) % 3];
    await page.check(`input[name="workspace"][value="${name}"]`);
    await page.waitForSelector(`body[data-workspace="${name}"]`);
    await frame(page);
  }
}

/** Runs the script in the editor `count` times, each to its end. */
async function runs(page, count) {
  await page.check('input[name="workspace"][value="script"]');
  const done = () => page.waitForFunction(() => ['done', 'error'].includes(document.body.dataset.scriptState), null, { timeout: 60_000 });
  await done();
  for (let k = 0; k < count; k++) {
    await page.evaluate(() => { document.body.dataset.scriptState = ''; });
    await page.click('#script-run');
    await done();
  }
}

/**
 * Runs the soak on an open page; returns the samples (start, middle, end) and the seconds each
 * kind of action took. `counts` are the totals over both halves.
 */
export async function soak(page, counts, log = () => {}) {
  const cdp = await page.context().newCDPSession(page);
  await cdp.send('Performance.enable');
  const rnd = random(20240611);
  // Both halves open the same links: what the page holds depends on the largest model it has met,
  // so the halves must meet the same ones for the end to be comparable with the middle.
  const links = await makeLinks(page, Math.ceil(counts.links / 2), 7);
  const time = { drags: 0, links: 0, switches: 0, runs: 0 };
  const timed = async (what, f) => {
    const t0 = performance.now();
    await f();
    time[what] += (performance.now() - t0) / 1000;
  };
  const samples = [await sample(page, cdp)];
  log('start', samples[0]);
  for (let half = 0; half < 2; half++) {
    const part = (n) => (half === 0 ? Math.floor(n / 2) : n - Math.floor(n / 2));
    await home(page);
    await timed('drags', () => drags(page, part(counts.drags), rnd));
    await timed('links', () => openLinks(page, links.slice(0, part(counts.links))));
    await timed('switches', () => switches(page, part(counts.switches), half));
    await timed('runs', () => runs(page, part(counts.runs)));
    samples.push(await sample(page, cdp));
    log(half === 0 ? 'middle' : 'end', samples.at(-1));
  }
  await cdp.detach();
  return { samples, time };
}

/** How far a measure may grow from the middle to the end: 1.5 × plus this slack. */
const SLACK = { heap: 2 << 20, wasm: 8 << 20, buffers: 1, textures: 1 };

/**
 * The soak's checks: no error anywhere, a drag still changes the contour, and each measure at the
 * end is at most 1.5 × its middle value plus a small slack (it levels off; a leak grows with the
 * work, and both halves do the same work).
 */
export async function check(page, errors, { samples }, assert) {
  const [, middle, end] = samples;
  for (const key of Object.keys(SLACK)) {
    assert.ok(end[key] <= 1.5 * middle[key] + SLACK[key], `${key} grew: ${samples.map((s) => s[key]).join(' → ')}`);
  }
  assert.deepEqual(errors, [], 'no console or page error');
  assert.notEqual(await page.getAttribute('#status', 'data-kind'), 'error', await page.textContent('#status'));
  // The page still answers: a drag of the middle point down changes the contour.
  await home(page);
  const before = await page.locator('#view').screenshot();
  const box = await page.locator('#view').boundingBox();
  const [x0, y0] = await page.evaluate(() => [...window.bezsolid.modeler.probe(0, 0)]);
  const [x1, y1] = await page.evaluate(() => [...window.bezsolid.modeler.probe(100, 100)]);
  const x = box.x + (7 / 15 - x0) * 100 / (x1 - x0);
  const y = box.y + (7 / 15 - y0) * 100 / (y1 - y0);
  const pieces = await page.evaluate(() => JSON.parse(window.bezsolid.modeler.panel()).frame.contours);
  await page.mouse.move(x, y);
  await page.mouse.down();
  await page.mouse.move(x, y + 80, { steps: 4 });
  await page.mouse.up();
  await frame(page);
  assert.ok(!before.equals(await page.locator('#view').screenshot()), 'the drag changed the picture');
  assert.ok(await page.evaluate(() => JSON.parse(window.bezsolid.modeler.panel()).frame.contours) > pieces, 'a hole opened in the solid');
}
