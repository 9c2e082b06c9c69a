// Zoom and touch in a real browser, on the backend under test: the wheel zooms the 2D view about
// the pointer and edits ξ only over the selected point or with Alt; F fits back; on a phone-sized
// touch screen one finger drags a point, two fingers zoom and pan both views without editing, and
// a swipe that starts off the views scrolls the page.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { launch, open, settle, URL as BASE, EXPECTED_BACKEND, ARTIFACTS } from './harness.mjs';

let browser;
before(async () => { browser = await launch(); });
after(async () => { await browser?.close(); });

const model = (page) => page.evaluate(() => window.bezsolid.modeler.model_json());
const zoom = (page) => page.evaluate(() => window.bezsolid.modeler.zoom());
/** The world point under CSS pixel (x, y) of the 2D canvas. */
const probe = (page, x, y) => page.evaluate(([x, y]) => [...window.bezsolid.modeler.probe(x, y)].slice(0, 2), [x, y]);

/** The box of the element `sel` in page CSS pixels (scrolled away or not). */
const rect = (page, sel) => page.evaluate((sel) => {
  const r = document.querySelector(sel).getBoundingClientRect();
  return { x: r.x + scrollX, y: r.y + scrollY, width: r.width, height: r.height };
}, sel);

/** The page position of world point (x, y) in the 2D view (the view is isotropic: two probes). */
async function screenOf(page, x, y) {
  const box = await rect(page, '#view');
  const [x0, y0] = await probe(page, 0, 0);
  const [x1, y1] = await probe(page, 100, 100);
  return [box.x + (x - x0) * 100 / (x1 - x0), box.y + (y - y0) * 100 / (y1 - y0)];
}

const close = (a, b, tol, what) => assert.ok(Math.abs(a - b) <= tol, `${what}: ${a} vs ${b}`);

test('the wheel zooms about the pointer; over the selected point or with Alt it changes ξ; F fits back', async () => {
  const { page, errors } = await open(browser);
  const box = await rect(page, '#view');
  // Select the centre point with a click that does not move it (no undo step).
  await page.mouse.click(...await screenOf(page, 0.5, 0.5));
  await settle(page);
  assert.equal(await page.getAttribute('body', 'data-selected'), '1,1');
  const json = await model(page);

  // (a) Over empty space: a zoom about the pointer, no edit, no undo step.
  const [qx, qy] = [60, box.height - 50];
  const under = await probe(page, qx, qy);
  await page.mouse.move(box.x + qx, box.y + qy);
  for (let k = 0; k < 3; k++) await page.mouse.wheel(0, -100);
  await settle(page);
  assert.ok(await zoom(page) > 1.3, `wheel up zoomed in: ${await zoom(page)}`);
  const still = await probe(page, qx, qy);
  close(still[0], under[0], 1e-9, 'x under the pointer');
  close(still[1], under[1], 1e-9, 'y under the pointer');
  assert.equal(await model(page), json, 'the model is unchanged');
  assert.equal(await page.isDisabled('#undo'), true, 'a zoom is no undo step');
  writeFileSync(join(ARTIFACTS, 'zoomed.png'), await page.locator('#view').screenshot());

  // (b) Over the selected point (where the zoomed view draws it): ξ, and the view stays.
  const z = await zoom(page);
  const xi = Number(await page.inputValue('#xi'));
  await page.mouse.move(...await screenOf(page, 0.5, 0.5));
  await page.mouse.wheel(0, -100);
  await settle(page);
  close(Number(await page.inputValue('#xi')), xi + 0.1, 1e-9, 'ξ over the point');
  assert.equal(await zoom(page), z);
  // With Alt, anywhere: ξ again.
  await page.mouse.move(box.x + qx, box.y + qy);
  await page.keyboard.down('Alt');
  await page.mouse.wheel(0, -100);
  await page.keyboard.up('Alt');
  await settle(page);
  close(Number(await page.inputValue('#xi')), xi + 0.2, 1e-9, 'ξ with Alt');
  assert.equal(await zoom(page), z);
  assert.equal(await page.isDisabled('#undo'), false, 'the ξ turns are an undo step');

  // Zoomed far in and out, wild deltas: clamped, finite.
  await page.evaluate(() => {
    const m = window.bezsolid.modeler;
    for (const d of [-1e9, -1e9, -1e9, -1e9, -1e9, -1e9, 0, NaN]) m.wheel(10, 10, d, false);
  });
  close(await zoom(page), 200, 1e-6, 'the closest zoom');
  await page.evaluate(() => {
    const m = window.bezsolid.modeler;
    for (let k = 0; k < 10; k++) m.wheel(10, 10, 1e9, false);
    m.pinch(NaN, 0, 2, 0, 0);
    m.pinch(0, 0, 1e300, 1e300, -1e300);
  });
  const z2 = await zoom(page);
  assert.ok(z2 >= 0.05 - 1e-9 && z2 <= 200 + 1e-6, `clamped: ${z2}`);
  const p = await probe(page, 10, 10);
  assert.ok(p.every(Number.isFinite), `finite: ${p}`);

  // (c) F fits again.
  await page.focus('#view');
  await page.keyboard.press('f');
  await settle(page);
  close(await zoom(page), 1, 1e-12, 'fitted');
  const [cx, cy] = await probe(page, box.width / 2, box.height / 2);
  close(cx, 0.5, 1e-9, 'the domain centred (x)');
  close(cy, 0.5, 1e-9, 'the domain centred (y)');
  assert.deepEqual(errors, []);
  await page.close();
});

/** A phone-sized touch page and a touch screen driven through CDP (real pointer events). */
async function openPhone() {
  const context = await browser.newContext({ viewport: { width: 390, height: 844 }, hasTouch: true, isMobile: true });
  const page = await context.newPage();
  const errors = [];
  page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
  page.on('pageerror', (e) => errors.push(String(e)));
  await page.goto(BASE);
  await page.waitForSelector('body[data-ready="true"]', { timeout: 60_000 });
  const cdp = await context.newCDPSession(page);
  /** The fingers down now, as page CSS pixels in the layout viewport: touchStart, touchMove, touchEnd. */
  const touch = async (type, points) => {
    const scroll = await page.evaluate(() => [scrollX, scrollY]);
    await cdp.send('Input.dispatchTouchEvent', {
      type,
      touchPoints: points.map(([x, y], id) => ({ x: x - scroll[0], y: y - scroll[1], id })),
    });
  };
  /** Fingers from `from` to `to` (arrays of page points), in `steps` moves, then lifted. */
  const gesture = async (from, to, steps = 8) => {
    await touch('touchStart', from);
    for (let k = 1; k <= steps; k++) {
      await touch('touchMove', from.map(([x, y], i) => [x + (to[i][0] - x) * k / steps, y + (to[i][1] - y) * k / steps]));
    }
    await touch('touchEnd', []);
    await settle(page);
  };
  return { context, page, errors, touch, gesture };
}

test('on a phone: one finger drags a point, two fingers zoom and pan both views, a second finger cancels a drag', async () => {
  const { context, page, errors, touch, gesture } = await openPhone();
  assert.equal(await page.textContent('#backend'), EXPECTED_BACKEND);
  const touches = await page.evaluate(() => {
    window.__touches = [];
    document.querySelector('#view').addEventListener('pointerdown', (e) => window.__touches.push(e.pointerType));
    return navigator.maxTouchPoints;
  });
  assert.ok(touches > 0, 'a touch screen');

  // One finger on the centre point drags it up: ξ rises (mode ξ), one undo step.
  const json = await model(page);
  const start = await screenOf(page, 0.5, 0.5);
  await gesture([start], [[start[0], start[1] - 48]]);
  assert.deepEqual(await page.evaluate(() => window.__touches), ['touch'], 'real pointer events of touch');
  assert.equal(await page.getAttribute('body', 'data-selected'), '1,1');
  const dragged = await model(page);
  assert.notEqual(dragged, json, 'the finger edited the model');
  const xi = JSON.parse(dragged).solid.points[4][2];
  assert.ok(Math.abs(xi - (JSON.parse(json).solid.points[4][2] + 48 / 120)) < 0.02, `ξ rose: ${xi}`);
  assert.equal(await page.isDisabled('#undo'), false);

  // Two fingers pinching apart on the 2D view: a zoom about their midpoint, no edit.
  const v = await rect(page, '#view');
  const mid = [v.x + v.width * 0.3, v.y + v.height * 0.75];
  const local = [mid[0] - v.x, mid[1] - v.y];
  const under = await probe(page, ...local);
  await gesture([[mid[0] - 30, mid[1]], [mid[0] + 30, mid[1]]], [[mid[0] - 60, mid[1]], [mid[0] + 60, mid[1]]]);
  const z = await zoom(page);
  close(z, 2, 0.05, 'fingers twice as far apart: twice the zoom');
  const still = await probe(page, ...local);
  close(still[0], under[0], 2e-3, 'x between the fingers');
  close(still[1], under[1], 2e-3, 'y between the fingers');
  assert.equal(await model(page), dragged, 'a pinch does not edit');
  // Two fingers moving together pan.
  await gesture([[mid[0] - 30, mid[1]], [mid[0] + 30, mid[1]]], [[mid[0] - 10, mid[1] - 40], [mid[0] + 50, mid[1] - 40]]);
  const panned = await probe(page, local[0] + 20, local[1] - 40);
  const now = await probe(page, ...local);
  assert.ok(Math.hypot(now[0] - still[0], now[1] - still[1]) > 1e-3, 'the picture moved');
  close(panned[0], still[0], 2e-3, 'the picture follows the fingers (x)');
  close(panned[1], still[1], 2e-3, 'the picture follows the fingers (y)');
  close(await zoom(page), z, 1e-6, 'a pan keeps the zoom');
  assert.equal(await model(page), dragged);

  // A drag under way when a second finger comes down is put back: the model as before the drag.
  const at = await screenOf(page, 0.5, 0.5);
  await touch('touchStart', [at]);
  for (let k = 1; k <= 4; k++) await touch('touchMove', [[at[0], at[1] - 10 * k]]);
  await settle(page);
  assert.notEqual(await model(page), dragged, 'the drag moves the point');
  await touch('touchStart', [[at[0], at[1] - 40], [at[0] + 80, at[1] + 20]]);
  await touch('touchMove', [[at[0], at[1] - 50], [at[0] + 110, at[1] + 30]]);
  await touch('touchEnd', []);
  await settle(page);
  assert.equal(await model(page), dragged, 'the second finger cancelled the drag');
  await page.click('#undo');
  await settle(page);
  assert.equal(await model(page), json, 'one undo step: the first drag only');
  assert.equal(await page.isDisabled('#undo'), true, 'the cancelled drag recorded no step');

  // Two fingers on the 3D view zoom the camera: the spheres spread out; the model is unchanged.
  const r3 = await rect(page, '#view3d');
  await page.evaluate((y) => scrollTo(0, y), r3.y - 100);
  const spread = () => page.evaluate(() => {
    const m = window.bezsolid.modeler;
    const [a, b] = [m.sphere_screen_3d(0), m.sphere_screen_3d(8)];
    return Math.hypot(a[0] - b[0], a[1] - b[1]);
  });
  const s0 = await spread();
  const shot0 = await page.locator('#view3d').screenshot();
  const c3 = [r3.x + r3.width / 2, r3.y + r3.height * 0.85];
  await gesture([[c3[0] - 25, c3[1]], [c3[0] + 25, c3[1]]], [[c3[0] - 75, c3[1]], [c3[0] + 75, c3[1]]]);
  const s1 = await spread();
  assert.ok(s1 > s0 * 2, `fingers three times as far apart bring the camera closer: ${s0} → ${s1}`);
  assert.ok(!shot0.equals(await page.locator('#view3d').screenshot()), 'the 3D picture changed');
  assert.equal(await model(page), json, 'the 3D pinch does not edit');
  writeFileSync(join(ARTIFACTS, 'phone-pinched.png'), await page.screenshot());

  // The Free-form mode's camera pinches too.
  await page.evaluate(() => scrollTo(0, 0));
  await page.check('input[name="workspace"][value="freeform"]');
  await settle(page);
  const r3f = await rect(page, '#view3d');
  await page.evaluate((y) => scrollTo(0, y), r3f.y - 100);
  await settle(page);
  const f0 = await page.locator('#view3d').screenshot();
  const cf = [r3f.x + r3f.width / 2, r3f.y + r3f.height / 2];
  await gesture([[cf[0] - 25, cf[1]], [cf[0] + 25, cf[1]]], [[cf[0] - 70, cf[1]], [cf[0] + 70, cf[1]]]);
  assert.ok(!f0.equals(await page.locator('#view3d').screenshot()), 'the free-form view zoomed');
  assert.deepEqual(errors, []);
  await context.close();
});

test('on a phone the views leave room to scroll: a swipe off them scrolls the page', async () => {
  const { context, page, errors, gesture } = await openPhone();
  const height = await page.evaluate(() => innerHeight);
  for (const sel of ['#view', '#view3d']) {
    const r = await rect(page, sel);
    assert.ok(r.height <= 0.6 * 844 + 1, `${sel} is ${r.height} px tall in a ${height} px window`);
  }
  // A point off the canvases in the first screen (the bar), off its controls and a finger's
  // width from the view (a touch that close is the view's).
  const v = await rect(page, '#view');
  const from = await page.evaluate((bottom) => {
    for (let y = bottom - 24; y > 0; y -= 6) {
      for (let x = 380; x > 10; x -= 10) {
        const e = document.elementFromPoint(x, y);
        if (e && !e.closest('canvas, button, input, select, label, a, textarea')) return [x, y];
      }
    }
    return null;
  }, v.y);
  assert.ok(from && from[1] > 120, `some of the first screen is not a view: ${from}`);
  await gesture([from], [[from[0], 10]], 12);
  await page.waitForFunction(() => scrollY > 50, null, { timeout: 5000 });
  // Once the fling has stopped: a swipe on the 2D view's empty space scrolls nothing (the view
  // keeps the finger).
  for (let y = -1, now = await page.evaluate(() => scrollY); now !== y; now = await page.evaluate(() => scrollY)) {
    y = now;
    await page.waitForTimeout(300);
  }
  const r = await rect(page, '#view');
  await page.evaluate((y) => scrollTo(0, y), r.y - 100);
  await settle(page);
  const y0 = await page.evaluate(() => scrollY);
  const empty = [r.x + 12, r.y + r.height - 12];
  assert.ok(empty[1] - y0 > 0 && empty[1] - y0 < height, 'the corner is in sight');
  await gesture([empty], [[empty[0], empty[1] - 200]], 10);
  await page.waitForTimeout(300);
  assert.equal(await page.evaluate(() => scrollY), y0, 'a finger on the view is the view\'s');
  assert.equal(await zoom(page), 1, 'and one finger on empty space neither zooms nor pans');
  assert.deepEqual(errors, []);
  await context.close();
});
