// The full soak (cargo xtask serve, then: cd tests && node soak.mjs [webgl2|webgpu] [fraction]):
// 2,000 drags on a 16 × 16 patch, 200 links opened one after another (100 models of every kind,
// twice), 50 switches between the modes and 50 script runs in one page (e2e/soak.mjs), then the
// checks of the suite's short soak.
// Prints the JS heap, the wasm memory and the GPU objects at the start, the middle and the end,
// and the time each kind of action took. `fraction` scales the counts.
import assert from 'node:assert/strict';
import { chromium } from 'playwright-core';
import { FULL, soak, check } from './e2e/soak.mjs';

const backend = process.argv[2] ?? 'webgl2';
const fraction = Number(process.argv[3] ?? 1);
const args = ['--no-sandbox'];
if (backend === 'webgpu') args.push('--enable-unsafe-webgpu', '--enable-features=Vulkan', '--use-vulkan=swiftshader', '--use-angle=swiftshader');
const browser = await chromium.launch({ executablePath: process.env.CHROMIUM ?? '/usr/bin/chromium', headless: true, args });
const page = await browser.newPage({ viewport: { width: 1200, height: 760 } });
const errors = [];
page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
page.on('pageerror', (e) => errors.push(String(e)));
await page.goto(`${process.env.BEZSOLID_URL ?? 'http://127.0.0.1:8080/'}?backend=${backend}`);
await page.waitForSelector('body[data-ready="true"]', { timeout: 60_000 });
const counts = Object.fromEntries(Object.entries(FULL).map(([k, n]) => [k, Math.max(2, Math.round(n * fraction))]));
console.log(`soak on ${backend}: ${JSON.stringify(counts)}`);
const mib = (b) => `${(b / 2 ** 20).toFixed(1)} MiB`;
const t0 = performance.now();
const result = await soak(page, counts, (when, s) => {
  console.log(`${when.padEnd(6)} JS heap ${mib(s.heap)}, wasm memory ${mib(s.wasm)}, GPU ${s.buffers} buffers + ${s.textures} textures live (${s.made} made)`
    + ` at ${((performance.now() - t0) / 1000).toFixed(0)} s`);
});
console.log(`seconds: ${Object.entries(result.time).map(([k, v]) => `${k} ${v.toFixed(1)}`).join(', ')}; in all ${((performance.now() - t0) / 1000).toFixed(0)}`);
await check(page, errors, result, assert);
console.log('ok: no error, the page answers, and every measure levelled off');
await browser.close();
