// Live under a stream of input: pointer moves that come faster than frames are coalesced, the newest
// applied once a frame and drawn, never queued; the release applies the last one.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { launch, open, settle } from './harness.mjs';

let browser;
before(async () => { browser = await launch(); });
after(async () => { await browser?.close(); });

const stats = (page) => page.evaluate(() => ({ ...window.bezsolid.stats, latencies: [] }));
const xiOf = (page, k) => page.evaluate((i) => JSON.parse(window.bezsolid.modeler.model_json()).solid.points[i][2], k);

/** Page position of point `k` of the 2D view. */
async function pointAt(page, k) {
  const box = await page.locator('#view').boundingBox();
  const [x0, y0] = await page.evaluate(() => [...window.bezsolid.modeler.probe(0, 0)]);
  const [x1, y1] = await page.evaluate(() => [...window.bezsolid.modeler.probe(100, 100)]);
  const p = JSON.parse(await page.evaluate(() => window.bezsolid.modeler.model_json())).solid.points[k];
  return [box.x + (p[0] - x0) * (100 / (x1 - x0)), box.y + (p[1] - y0) * (100 / (y1 - y0))];
}

/** `count` pointer moves of the mouse on `selector`, in one task (faster than any frame), ending at `to`. */
const stream = (page, selector, from, to, count) => page.evaluate(([sel, [x0, y0], [x1, y1], n]) => {
  const canvas = document.querySelector(sel);
  for (let k = 1; k <= n; k++) {
    const t = k / n;
    canvas.dispatchEvent(new PointerEvent('pointermove', {
      bubbles: true, pointerId: 1, pointerType: 'mouse', isPrimary: true, buttons: 1,
      clientX: x0 + (x1 - x0) * t, clientY: y0 + (y1 - y0) * t,
    }));
  }
}, [selector, from, to, count]);

test('a stream of moves over a 16 × 16 patch is applied and drawn once a frame, the newest winning', async () => {
  const { page, errors } = await open(browser);
  await page.fill('#grid-u', '16');
  await page.fill('#grid-v', '16');
  await page.click('#reset-grid');
  await settle(page);
  const k = 7 * 16 + 7;
  const [x, y] = await pointAt(page, k);
  await page.mouse.move(x, y);
  await page.mouse.down();
  await settle(page);
  const s0 = await stats(page);
  await stream(page, '#view', [x, y], [x, y - 60], 200);
  await settle(page);
  const s1 = await stats(page);
  assert.equal(s1.moves - s0.moves, 200);
  assert.ok(s1.applied - s0.applied <= 2, `${s1.applied - s0.applied} of 200 moves applied`);
  assert.ok(s1.frames - s0.frames <= 8, `${s1.frames - s0.frames} frames for one task of 200 moves`);
  assert.ok(s1.drawnEdit >= s1.lastEdit && s1.lastEdit > s0.lastEdit, 'the newest edit is drawn');
  const streamed = await xiOf(page, k);
  // The same drag in one move: the same ξ (the newest move won; none was lost or queued).
  await page.mouse.up();
  await page.keyboard.press('Control+z');
  await settle(page);
  await page.mouse.move(x, y);
  await page.mouse.down();
  await page.mouse.move(x, y - 60);
  await page.mouse.up();
  await settle(page);
  assert.ok(Math.abs((await xiOf(page, k)) - streamed) < 1e-6, `${streamed} vs ${await xiOf(page, k)}`);
  assert.deepEqual(errors, []);
  await page.close();
});

test('a stream of moves of a sphere in 3D is coalesced too, and the release keeps the last move', async () => {
  const { page, errors } = await open(browser);
  const box = await page.locator('#view3d').boundingBox();
  const [sx, sy] = await page.evaluate(() => [...window.bezsolid.modeler.sphere_screen_3d(4)]);
  const [x, y] = [box.x + sx, box.y + sy];
  await page.mouse.move(x, y);
  await page.mouse.down();
  await settle(page);
  const xi0 = await xiOf(page, 4);
  const s0 = await stats(page);
  await stream(page, '#view3d', [x, y], [x, y - 50], 100);
  // Released at once: the last move counts whether or not a frame came in between.
  await page.mouse.up();
  await settle(page);
  const s1 = await stats(page);
  assert.equal(s1.moves - s0.moves, 100);
  assert.ok(s1.applied - s0.applied <= 2, `${s1.applied - s0.applied} of 100 moves applied`);
  const xi1 = await xiOf(page, 4);
  assert.ok(xi1 > xi0 + 0.05, `ξ rose with the stream: ${xi0} → ${xi1}`);
  assert.equal(await page.isDisabled('#undo'), false, 'one undo step');
  await page.keyboard.press('Control+z');
  await settle(page);
  assert.equal(await xiOf(page, 4), xi0);
  assert.deepEqual(errors, []);
  await page.close();
});
