// Measures drag-to-redraw latency in the page (cargo xtask serve, then: cd tests && node latency.mjs [webgl2|webgpu] [--load];
// `cargo xtask bench` runs it and writes its lines in BENCHMARKS.md).
// Per case, a drag two ways: one move a frame (the move, then the frame after it), and a continuous
// stream of moves sent as fast as the browser takes them (the page applies the newest once a frame).
// Prints the median and max time from a pointer move to the end of the first frame drawn after it
// (the page's own figure), and for the stream how many moves were applied in how many frames.
import { chromium } from 'playwright-core';
const backend = process.argv[2] ?? 'webgl2';
// `--load`: the first load alone (the page's module differs by backend: WebGPU alone, or with WebGL2).
const loadOnly = process.argv.includes('--load');
const args = ['--no-sandbox'];
if (backend === 'webgpu') args.push('--enable-unsafe-webgpu', '--enable-features=Vulkan', '--use-vulkan=swiftshader', '--use-angle=swiftshader');
const browser = await chromium.launch({ executablePath: '/usr/bin/chromium', headless: true, args });
const page = await browser.newPage({ viewport: { width: 1400, height: 800 } });
page.on('pageerror', (e) => console.log('pageerror', String(e)));
const base = process.env.BEZSOLID_URL ?? 'http://127.0.0.1:8080/';
// The browser is started first (its GPU process, the connection) on a small file of the same
// origin, so that the first load measures the page, with nothing of it cached.
await page.goto(new URL('favicon.svg', base).href);
await page.goto(`${base}?backend=${backend}`);
await page.waitForSelector('body[data-ready="true"]', { timeout: 60000 });
// The first load: from navigation to the first frame drawn, and what was fetched before it (bodies
// as they travelled, compressed, and as decoded); then a reload, where the cache holds the module.
const firstLoad = async (label) => {
  const f = await page.evaluate(() => {
    const first = Number(document.body.dataset.firstFrameMs);
    const all = [...performance.getEntriesByType('navigation'), ...performance.getEntriesByType('resource')];
    const before = all.filter((e) => e.responseEnd <= first);
    const sum = (list, k) => list.reduce((a, e) => a + (e[k] || 0), 0);
    const wasm = before.filter((e) => e.name.endsWith('.wasm'));
    const mark = (name) => performance.getEntriesByName(name, 'mark')[0]?.startTime ?? NaN;
    const module = performance.getEntriesByType('mark').find((m) => m.name.startsWith('bezsolid:init '));
    const steps = { start: mark('bezsolid:start'), module: module?.startTime ?? NaN, modeler: mark('bezsolid:modeler'), viewer: mark('bezsolid:viewer') };
    return { steps, first, files: before.length, transfer: sum(before, 'transferSize'), encoded: sum(before, 'encodedBodySize'),
      decoded: sum(before, 'decodedBodySize'), wasm: sum(wasm, 'encodedBodySize'), wasmDecoded: sum(wasm, 'decodedBodySize') };
  });
  const kb = (b) => `${(b / 1000).toFixed(0)} KB`;
  console.log(`${backend}, ${label}: first frame drawn ${f.first.toFixed(0)} ms after navigation; ${f.files} files before it, ${kb(f.transfer)} over the network `
    + `(bodies ${kb(f.encoded)} as sent, ${kb(f.decoded)} decoded; the module ${kb(f.wasm)} as sent, ${kb(f.wasmDecoded)} decoded); `
    + `the page's script ran at ${f.steps.start.toFixed(0)} ms, its module was compiled at ${f.steps.module.toFixed(0)}, the 2D view's GPU up at ${f.steps.modeler.toFixed(0)}, the 3D view's at ${f.steps.viewer.toFixed(0)}`);
};
await firstLoad('first load, empty cache');
await page.reload();
await page.waitForSelector('body[data-ready="true"]', { timeout: 60000 });
await firstLoad('second load, the module from the cache');
if (loadOnly) {
  await browser.close();
  process.exit(0);
}
await page.focus('#view'); await page.keyboard.press('d');
const frame = () => page.evaluate(() => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r))));
let released = 0; // when the last measured drag let go
async function measure(label, canvasSel, getPoint, dx, dy, n = 12) {
  const box = await page.locator(canvasSel).boundingBox();
  const [x, y] = await getPoint(box);
  const med = (a) => [...a].sort((p, q) => p - q)[Math.floor(a.length / 2)];
  // One move a frame.
  await page.mouse.move(x, y); await page.mouse.down();
  const lat = [], ren = [], ren3 = [];
  for (let k = 1; k <= n; k++) {
    await page.mouse.move(x + dx * k, y + dy * k);
    await frame();
    lat.push(Number(await page.getAttribute('body', 'data-latency-ms')));
    ren.push(Number(await page.getAttribute('body', 'data-render-ms')));
    ren3.push(Number(await page.getAttribute('body', 'data-render3-ms')));
  }
  // Then a stream: 4n moves back and forth, none waiting for a frame.
  const before = await page.evaluate(() => {
    window.bezsolid.stats.latencies.length = 0;
    return { ...window.bezsolid.stats };
  });
  for (let k = 1; k <= 4 * n; k++) {
    const j = n - (k % (2 * n) < n ? k % n : n - (k % n));
    await page.mouse.move(x + dx * j, y + dy * j);
  }
  await frame();
  const after = await page.evaluate(() => window.bezsolid.stats);
  const stream = after.latencies.length ? after.latencies : [NaN];
  await page.mouse.up(); released = Date.now(); await frame(); await frame();
  console.log(`${label}: input→drawn median ${med(lat).toFixed(1)} ms (max ${Math.max(...lat).toFixed(1)}); 2D frame ${med(ren).toFixed(1)} ms, 3D frame ${med(ren3).toFixed(1)} ms`
    + `; under a stream of ${after.moves - before.moves} moves: ${after.applied - before.applied} applied in ${after.frames - before.frames} frames, input→drawn median ${med(stream).toFixed(1)} ms (max ${Math.max(...stream).toFixed(1)})`);
}
const screen2d = async (box, wx, wy) => {
  const [x0, y0] = await page.evaluate(() => [...window.bezsolid.modeler.probe(0, 0)]);
  const [x1, y1] = await page.evaluate(() => [...window.bezsolid.modeler.probe(100, 100)]);
  return [box.x + (wx - x0) * 100 / (x1 - x0), box.y + (wy - y0) * 100 / (y1 - y0)];
};
for (const [n, label] of [[4, '4×4 patch'], [16, '16×16 patch']]) {
  await page.fill('#grid-u', String(n)); await page.fill('#grid-v', String(n)); await page.click('#reset-grid'); await frame();
  const t = (n - 1) / 2 / (n - 1);
  const wi = Math.floor((n - 1) / 2) / (n - 1);
  await page.check('input[name="mode"][value="function"]'); await frame();
  await measure(`${label}, ξ drag in 2D`, '#view', (b) => screen2d(b, wi, wi), 0, -4);
  await page.check('input[name="mode"][value="space"]'); await frame();
  await measure(`${label}, space drag in 2D`, '#view', (b) => screen2d(b, wi, wi), 1.5, 1);
  await page.check('input[name="mode"][value="function"]'); await frame();
  const idx = Math.floor((n - 1) / 2) * n + Math.floor((n - 1) / 2);
  await measure(`${label}, ξ drag in 3D`, '#view3d', async (b) => { const [x, y] = await page.evaluate((i) => [...window.bezsolid.modeler.sphere_screen_3d(i)], idx); return [b.x + x, b.y + y]; }, 0, -3);
}
// 5×5×5 volume: a ball.
const pts = [];
for (let i = 0; i < 5; i++) for (let j = 0; j < 5; j++) for (let k = 0; k < 5; k++) {
  const r = Math.hypot(i - 2, j - 2, k - 2);
  pts.push([i / 4, j / 4, k / 4, 1 - r * 0.6]);
}
await page.evaluate((t) => { window.bezsolid.modeler.load_model(t); window.bezsolid.redraw(); }, JSON.stringify({ format: 'bezsolid', version: 1, solid: { kind: 'volume', degree: [4, 4, 4], points: pts } }));
await frame(); await frame();
const idx = (2 * 5 + 2) * 5 + 4;
await measure('5×5×5 volume, ξ drag in 3D (coarse 24 while moving)', '#view3d', async (b) => { const [x, y] = await page.evaluate((i) => [...window.bezsolid.modeler.sphere_screen_3d(i)], idx); return [b.x + x, b.y + y]; }, 0, 3);
const t0 = Date.now();
await page.waitForFunction(() => JSON.parse(window.bezsolid.modeler.panel()).surface?.[1] === 64);
await frame(); await frame();
const dbg = await page.textContent('#debug');
console.log(`5×5×5 volume, fine surface at rest (64, in the worker): ${dbg.match(/worker mesh: ([\d.]+)/)[1]} ms in the worker, ${await page.evaluate(() => JSON.parse(window.bezsolid.modeler.panel()).surface[0])} triangles; 3D frame then ${await page.getAttribute('body', 'data-render3-ms')} ms`);
await page.check('input[name="mode"][value="space"]'); await frame();
await measure('5×5×5 volume, space drag in 3D (coarse 24 while moving)', '#view3d', async (b) => { const [x, y] = await page.evaluate((i) => [...window.bezsolid.modeler.sphere_screen_3d(i)], idx); return [b.x + x, b.y + y]; }, 2, 0);

// A model of many solids built in the outliner: the first volume, a sphere, a box, a torus and a
// second volume; its surface is made in the worker (coarse while moving).
for (const [id, n] of [['#grid-u', 4], ['#grid-v', 4], ['#grid-w', 4]]) await page.fill(id, String(n));
await page.click('#new-volume');
for (const k of ['sphere', 'box', 'torus', 'bezier']) await page.click(`[data-add="${k}"]`);
await page.click('#outline-tree [data-path="0"]');
await page.click('#fit-3d');
await page.waitForFunction(() => JSON.parse(window.bezsolid.modeler.panel()).surface_current, null, { timeout: 60000 });
await page.check('input[name="mode"][value="function"]'); await frame();
await measure('5-part tree, a volume point dragged in 3D', '#view3d', async (b) => { const [x, y] = await page.evaluate(() => [...window.bezsolid.modeler.sphere_screen_3d(47)]); return [b.x + x, b.y + y]; }, 2, 1);
await page.waitForFunction(() => { const p = JSON.parse(window.bezsolid.modeler.panel()); return p.surface_current && p.surface?.[1] === 64; }, null, { timeout: 60000, polling: 10 });
console.log(`5-part tree: the whole model's fine surface (64) drawn ${Date.now() - released} ms after the release`);
await page.click('#outline-tree [data-path="2"]'); await frame();
await measure('5-part tree, the box moved by its handle in 3D', '#view3d', async (b) => { const [x, y] = await page.evaluate(() => [...window.bezsolid.modeler.handle_screen_3d(0)]); return [b.x + x, b.y + y]; }, 2, 1);

await browser.close();
