// Shared set-up of the browser suite: Debian chromium through playwright-core, on the backend that
// `cargo xtask test` asks for (BEZSOLID_BACKEND), with console errors collected.
import { mkdirSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { chromium } from 'playwright-core';
import { decodePng } from './png.mjs';

export const BACKEND = process.env.BEZSOLID_BACKEND ?? 'webgl2';
export const URL = process.env.BEZSOLID_URL ?? 'http://127.0.0.1:8080/';
export const EXPECTED_BACKEND = BACKEND === 'webgpu' ? 'WebGPU' : 'WebGL2';
export const ARTIFACTS = join(process.env.BEZSOLID_ARTIFACTS ?? '../target/e2e', BACKEND);
mkdirSync(ARTIFACTS, { recursive: true });

// TOOLCHAIN.md: the base flags, and for WebGPU the four that give an adapter that really draws.
const BASE_FLAGS = [
  '--no-sandbox', '--no-first-run', '--disable-background-networking', '--disable-component-update',
  '--disable-sync', '--disable-quic',
];
const WEBGPU_FLAGS = (process.env.BEZSOLID_WEBGPU_FLAGS
  ?? '--enable-unsafe-webgpu --enable-features=Vulkan --use-vulkan=swiftshader --use-angle=swiftshader')
  .split(' ');

export async function launch() {
  return chromium.launch({
    executablePath: process.env.CHROMIUM ?? '/usr/bin/chromium',
    headless: true,
    args: BACKEND === 'webgpu' ? [...BASE_FLAGS, ...WEBGPU_FLAGS] : BASE_FLAGS,
  });
}

/**
 * Opens the page (query appended to the base URL) and waits for the first frame; `options` are the
 * new page's (Playwright's `newPage`), over a 1200 × 760 window. The page opens as on a later
 * visit (the first-visit hint already used) unless `options.firstVisit`.
 */
export async function open(browser, query = '', options = {}) {
  const { firstVisit = false, ...pageOptions } = options;
  const page = await browser.newPage({ viewport: { width: 1200, height: 760 }, ...pageOptions });
  if (!firstVisit) await page.addInitScript(() => localStorage.setItem('bezsolid.hinted.v1', '1'));
  const errors = [];
  page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
  page.on('pageerror', (e) => errors.push(String(e)));
  await page.goto(URL + query);
  await page.waitForSelector('body[data-ready="true"]', { timeout: 60_000 });
  return { page, errors };
}

/** The canvas as decoded pixels (a screenshot: readback works after the frame is presented). */
export async function canvasPixels(page, name) {
  await settle(page);
  const png = await page.locator('#view').screenshot();
  if (name) writeFileSync(join(ARTIFACTS, `${name}.png`), png);
  return decodePng(png);
}

/** Waits for two animation frames, so that a redraw requested by an input has been presented. */
export async function settle(page) {
  await page.evaluate(() => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r))));
}

export async function canvasBox(page) {
  return page.locator('#view').boundingBox();
}

/** The viewport position (CSS pixels, what `page.mouse` takes) of world point (x, y) in the 2D view. */
export async function screenOf(page, x, y) {
  const box = await canvasBox(page);
  // probe() maps screen to world; the view is isotropic: find the map from two probes.
  const [x0, y0] = await page.evaluate(() => [...window.bezsolid.modeler.probe(0, 0)]);
  const [x1, y1] = await page.evaluate(() => [...window.bezsolid.modeler.probe(100, 100)]);
  return [box.x + (x - x0) * 100 / (x1 - x0), box.y + (y - y0) * 100 / (y1 - y0)];
}

const isRed = ([r, g, b]) => r - b > 40 && r > 120;
const isDark = ([r, g, b]) => r < 90 && g < 90 && b < 90;

/**
 * Where the zero contour crosses the row `dy` CSS pixels below the canvas centre, to the left and to
 * the right, as distances from the centre in image pixels: the middle of the first dark (contour
 * line) run met going outwards from a red (inside) centre. Checks that the field is reddish just
 * inside the line and bluish just outside it, so the line found is the boundary of the solid. The
 * scan starts a few pixels off the centre to step over the vertical grid line there. Returns null
 * for a side without such a crossing.
 */
export function contourCrossings(img, dy, scale) {
  const cx = Math.round(img.width / 2);
  const y = Math.round(img.height / 2 + dy * scale);
  const start = Math.ceil(4 * scale);
  const gap = Math.ceil(3 * scale);
  const side = (dir) => {
    if (!isRed(img.at(cx + dir * start, y))) return null;
    let first = start;
    while (first < img.width / 2 - gap - 2 && !isDark(img.at(cx + dir * first, y))) first++;
    if (!isDark(img.at(cx + dir * first, y))) return null;
    let last = first;
    while (isDark(img.at(cx + dir * (last + 1), y))) last++;
    const [ri, , bi] = img.at(cx + dir * (first - gap), y);
    const [ro, , bo] = img.at(cx + dir * (last + gap), y);
    if (!(ri > bi && bo > ro)) return null;
    return (first + last) / 2;
  };
  return { left: side(-1), right: side(1) };
}

/**
 * Picks `value` in the page's menu `id` (Export, Preset, the script examples) as a pointer does:
 * opens the menu with its button, clicks the item.
 */
export async function pick(page, id, value) {
  await page.click(`#${id}`);
  await page.click(`#${id}-menu [data-value="${value}"]`);
}

/** Whether the item `value` of the menu `id` is disabled. */
export async function itemDisabled(page, id, value) {
  return (await page.getAttribute(`#${id}-menu [data-value="${value}"]`, 'aria-disabled')) === 'true';
}
