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

/** Opens the page (query appended to the base URL) and waits for the first frame. */
export async function open(browser, query = '') {
  const page = await browser.newPage({ viewport: { width: 1200, height: 760 } });
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

const isRed = ([r, g, b]) => r - b > 40 && r > 120;

/**
 * Along the row `dy` CSS pixels below the canvas centre, how far the red (inside) region reaches to
 * the left and to the right of the centre, in image pixels. The scan starts a few pixels off the
 * centre to step over the vertical grid line there.
 */
export function redReach(img, dy, scale) {
  const cx = Math.round(img.width / 2);
  const y = Math.round(img.height / 2 + dy * scale);
  const start = Math.ceil(4 * scale);
  let left = start, right = start;
  if (!isRed(img.at(cx - start, y)) || !isRed(img.at(cx + start, y))) return { left: 0, right: 0 };
  while (cx - left - 1 >= 0 && isRed(img.at(cx - left - 1, y))) left++;
  while (cx + right + 1 < img.width && isRed(img.at(cx + right + 1, y))) right++;
  return { left, right };
}
