// The 3D view in a real browser, on the backend under test: drawn, a sphere dragged with the mouse
// changes ξ (and the 2D contour with it) as one undo step, and the camera orbits without editing.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { launch, open, settle, ARTIFACTS } from './harness.mjs';
import { decodePng } from './png.mjs';

let browser;
before(async () => { browser = await launch(); });
after(async () => { await browser?.close(); });

const model = (page) => page.evaluate(() => window.bezsolid.modeler.model_json());

async function shot3(page, name) {
  await settle(page);
  // The Reset button over the canvas is masked: its anti-aliased corners vary by a unit between
  // compositions.
  const png = await page.locator('#view3d').screenshot({ mask: [page.locator('#fit-3d')] });
  if (name) writeFileSync(join(ARTIFACTS, `${name}.png`), png);
  return png;
}

/** The page position of control point `k`'s sphere. */
async function sphere(page, k) {
  const box = await page.locator('#view3d').boundingBox();
  const [x, y] = await page.evaluate((i) => [...window.bezsolid.modeler.sphere_screen_3d(i)], k);
  return [box.x + x, box.y + y];
}

test('the 3D view draws the surface, the plane and the spheres', async () => {
  const { page, errors } = await open(browser);
  assert.equal(await page.isHidden('#loading-3d'), true, 'the 3D view started');
  const img = decodePng(await shot3(page, 'view3d'));
  const colours = new Set();
  let reddish = 0;
  let bluish = 0;
  for (let y = 0; y < img.height; y += 5) {
    for (let x = 0; x < img.width; x += 5) {
      const [r, g, b] = img.at(x, y);
      colours.add(`${r >> 3},${g >> 3},${b >> 3}`);
      if (r > b + 60) reddish++;
      if (b > r + 60) bluish++;
    }
  }
  assert.ok(colours.size > 80, `a shaded picture (${colours.size} colours)`);
  assert.ok(reddish > 5 && bluish > 20, `red (ξ > 0) and blue (ξ < 0) parts: ${reddish}, ${bluish}`);
  // The centre sphere (ξ = 1, red) is drawn where the view says it is.
  const box = await page.locator('#view3d').boundingBox();
  const [cx, cy] = await sphere(page, 4);
  const scale = img.width / box.width;
  const [r, , b] = img.at((cx - box.x) * scale, (cy - box.y) * scale);
  assert.ok(r > b + 60, `the centre sphere is red: ${[r, b]}`);
  assert.deepEqual(errors, []);
  await page.close();
});

test('dragging a sphere up in 3D raises its ξ; the 2D contour follows; one undo step', async () => {
  const { page, errors } = await open(browser);
  const before = JSON.parse(await model(page));
  const [x, y] = await sphere(page, 4);
  // A click on the sphere selects it without a step; then the 2D picture to come back to.
  await page.mouse.click(x, y);
  await settle(page);
  assert.equal(await page.isDisabled('#undo'), true);
  const contour2d = await page.locator('#view').screenshot();
  await page.mouse.move(x, y);
  await page.mouse.down();
  await page.mouse.move(x, y - 40, { steps: 6 });
  await page.mouse.up();
  await settle(page);
  const after = JSON.parse(await model(page));
  const [p0, p1] = [before.solid.points[4], after.solid.points[4]];
  assert.deepEqual(p1.slice(0, 2), p0.slice(0, 2), 'x and y unchanged');
  assert.ok(p1[2] > p0[2] + 0.05, `ξ rose: ${p0[2]} → ${p1[2]}`);
  assert.equal(await page.getAttribute('body', 'data-selected'), '1,1');
  assert.ok(!contour2d.equals(await page.locator('#view').screenshot()), 'the 2D view changed');
  await shot3(page, 'view3d-dragged');
  await page.keyboard.press('Control+z');
  await settle(page);
  assert.deepEqual(JSON.parse(await model(page)), before);
  assert.ok(contour2d.equals(await page.locator('#view').screenshot()), 'undo restores the 2D picture');
  assert.deepEqual(errors, []);
  await page.close();
});

test('dragging empty space orbits the camera and edits nothing; Reset view frames it again', async () => {
  const { page, errors } = await open(browser);
  const before = await model(page);
  const box = await page.locator('#view3d').boundingBox();
  await page.click('#fit-3d');
  await page.mouse.move(box.x - 50, box.y + 50);
  const first = await shot3(page);
  await page.mouse.move(box.x + 20, box.y + box.height - 20);
  await page.mouse.down();
  await page.mouse.move(box.x + 120, box.y + box.height - 40, { steps: 5 });
  await page.mouse.up();
  const orbited = await shot3(page, 'view3d-orbited');
  assert.ok(!first.equals(orbited), 'the picture turned');
  assert.equal(await model(page), before);
  assert.equal(await page.isDisabled('#undo'), true);
  await page.mouse.move(box.x + box.width / 2, box.y + box.height / 2);
  await page.mouse.wheel(0, 300);
  assert.ok(!orbited.equals(await shot3(page)), 'the wheel zooms');
  await page.click('#fit-3d');
  await page.mouse.move(box.x - 50, box.y + 50);
  const reset = await shot3(page, 'view3d-reset');
  assert.ok(first.equals(reset), 'Reset view gives the first picture back');
  assert.deepEqual(errors, []);
  await page.close();
});
