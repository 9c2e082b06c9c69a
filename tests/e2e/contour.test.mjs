// The contour view in a real browser, on the backend under test: loads cleanly, draws, and follows
// edits of a control point's ξ made through the UI, with the zero contour moving the right way.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { launch, open, canvasPixels, canvasBox, contourCrossings, settle, EXPECTED_BACKEND, ARTIFACTS } from './harness.mjs';
import { join } from 'node:path';

let browser;
before(async () => { browser = await launch(); });
after(async () => { await browser?.close(); });

// Rows of the scans: 24 CSS px below the centre, clear of the grid line and the control points.
const ROW = 24;

/** The contour's crossings of the scan row; both must exist (the line bounds the red solid). */
async function measure(page, scale, name) {
  const c = contourCrossings(await canvasPixels(page, name), ROW, scale);
  assert.ok(c.left !== null && c.right !== null, `the zero contour crosses the row on both sides: ${JSON.stringify(c)}`);
  return c;
}

/** The selected point as "i,j" once the panel has caught up with the last input. */
async function selected(page) {
  await settle(page);
  return page.getAttribute('body', 'data-selected');
}

test('the page loads without console errors on the expected backend', async () => {
  const { page, errors } = await open(browser);
  assert.equal(await page.textContent('#backend'), EXPECTED_BACKEND);
  assert.equal(await page.getAttribute('#backend', 'data-backend'), EXPECTED_BACKEND);
  assert.match(await page.textContent('#contour-info'), /1 piece/);
  assert.deepEqual(errors, []);
  await page.close();
});

test('?backend=webgl2 forces the fallback', async () => {
  const { page, errors } = await open(browser, '?backend=webgl2');
  assert.equal(await page.textContent('#backend'), 'WebGL2');
  const img = await canvasPixels(page, 'forced-webgl2');
  assert.ok(isDrawn(img), 'the WebGL2 canvas is drawn');
  assert.deepEqual(errors, []);
  await page.close();
});

test('?backend=webgpu uses WebGPU where it works and falls back to WebGL2 on a fresh canvas where not', async () => {
  const { page, errors } = await open(browser, '?backend=webgpu');
  assert.equal(await page.textContent('#backend'), EXPECTED_BACKEND);
  if (EXPECTED_BACKEND === 'WebGL2') {
    assert.match(await page.textContent('#status'), /WebGPU could not start/);
  }
  assert.ok(isDrawn(await canvasPixels(page, 'requested-webgpu')), 'the canvas is drawn');
  assert.deepEqual(errors, []);
  await page.close();
});

function isDrawn(img) {
  // The field is red in the middle and blue at the corners, with the dark contour between.
  const centre = img.at(img.width / 2 + 20, img.height / 2 + 30);
  const corner = img.at(6, 6);
  let dark = 0;
  for (let x = 0; x < img.width; x++) {
    const [r, g, b] = img.at(x, img.height / 2 + 30);
    if (r < 60 && g < 60 && b < 60) dark++;
  }
  return centre[0] > 150 && centre[0] - centre[2] > 40 && corner[2] - corner[0] > 40 && dark >= 2;
}

test('the canvas is not blank: field, contour and control points are drawn', async () => {
  const { page, errors } = await open(browser);
  const img = await canvasPixels(page, 'initial');
  const colours = new Set();
  for (let y = 0; y < img.height; y += 7) {
    for (let x = 0; x < img.width; x += 7) colours.add(img.at(x, y).slice(0, 3).join(','));
  }
  assert.ok(colours.size > 50, `a picture, not a flat fill (${colours.size} colours)`);
  assert.ok(isDrawn(img), 'red inside, blue outside, a dark contour');
  assert.deepEqual(errors, []);
  await page.close();
});

test('dragging the centre point up grows the solid; typing a low ξ shrinks it', async () => {
  const { page, errors } = await open(browser);
  const box = await canvasBox(page);
  const scale = (await canvasPixels(page)).width / box.width;
  const before = await measure(page, scale);
  assert.ok(before.left > 10 && before.right > 10, `the contour around the centre: ${JSON.stringify(before)}`);

  // Press on the centre control point and drag it up 60 px (ξ + 0.5).
  const cx = box.x + box.width / 2;
  const cy = box.y + box.height / 2;
  await page.mouse.move(cx, cy);
  await page.mouse.down();
  await page.mouse.move(cx, cy - 30, { steps: 3 });
  await page.mouse.move(cx, cy - 60, { steps: 3 });
  await page.mouse.up();
  assert.equal(await selected(page), '1,1');
  assert.equal(Number(await page.inputValue('#xi')), 1.5);
  const grown = await measure(page, scale, 'after-drag');
  assert.ok(grown.left > before.left + 3 && grown.right > before.right + 3,
    `the contour moved outwards: ${JSON.stringify(before)} → ${JSON.stringify(grown)}`);

  // The number input: a low ξ pulls the contour inwards, past where it started.
  await page.fill('#xi', '0.6');
  await page.press('#xi', 'Enter');
  const shrunk = await measure(page, scale, 'after-input');
  assert.ok(shrunk.left < before.left - 3 && shrunk.right < before.right - 3,
    `the contour moved inwards: ${JSON.stringify(before)} → ${JSON.stringify(shrunk)}`);
  assert.deepEqual(errors, []);
  await page.close();
});

test('the wheel and the keyboard select points and change ξ', async () => {
  const { page, errors } = await open(browser);
  const box = await canvasBox(page);
  const scale = (await canvasPixels(page)).width / box.width;
  const before = await measure(page, scale);
  assert.ok(before.left > 10 && before.right > 10, `the contour around the centre: ${JSON.stringify(before)}`);

  // Keyboard: Tab selects the first point; arrows walk to the centre; Page Down lowers it.
  await page.focus('#view');
  await page.keyboard.press('Tab');
  assert.equal(await selected(page), '0,0');
  await page.keyboard.press('ArrowRight');
  await page.keyboard.press('ArrowUp');
  assert.equal(await selected(page), '1,1');
  await page.keyboard.press('PageDown');
  await page.keyboard.press('PageDown');
  await settle(page);
  assert.equal(Number(await page.inputValue('#xi')), 0.8);
  const lowered = await measure(page, scale, 'after-keys');
  assert.ok(lowered.left < before.left && lowered.right < before.right,
    `lowering the centre shrinks the solid: ${JSON.stringify(before)} → ${JSON.stringify(lowered)}`);

  // Wheel up over the selected point (the centre) raises it: 5 notches of 100 → ξ + 0.5.
  // (Elsewhere the wheel zooms the view: touch.test.mjs.)
  await page.mouse.move(box.x + box.width / 2, box.y + box.height / 2);
  for (let k = 0; k < 5; k++) await page.mouse.wheel(0, -100);
  await settle(page);
  assert.ok(Math.abs(Number(await page.inputValue('#xi')) - 1.3) < 1e-9);
  const raised = await measure(page, scale);
  assert.ok(raised.left > before.left + 2 && raised.right > before.right + 2,
    `raising the centre grows the solid: ${JSON.stringify(before)} → ${JSON.stringify(raised)}`);
  assert.deepEqual(errors, []);
  await page.close();
});

test('a screenshot of the modeler for the README', async () => {
  const { page, errors } = await open(browser);
  const box = await canvasBox(page);
  await page.mouse.click(box.x + box.width / 2, box.y + box.height / 2);
  await page.mouse.move(box.x + box.width * 0.62, box.y + box.height * 0.4);
  await settle(page);
  await page.screenshot({ path: join(ARTIFACTS, 'modeler.png') });
  assert.deepEqual(errors, []);
  await page.close();
});

test('the unclipped switch draws S_ξ = 0 dashed beside the solid, from the keyboard, and takes it away', async () => {
  const { page, errors } = await open(browser);
  // ξ positive along the right side: S_ξ > 0 runs on past the box, where the clipping cuts it.
  const points = [];
  for (let i = 0; i <= 2; i++) {
    for (let j = 0; j <= 2; j++) points.push([i / 2, j / 2, [-1, 0.2, 1][i]]);
  }
  const model = JSON.stringify({ format: 'bezsolid', version: 1, solid: { kind: 'patch', degree: [2, 2], points } });
  await page.evaluate((m) => { window.bezsolid.modeler.load_model(m); window.bezsolid.redraw(); }, model);
  await settle(page);
  const frame = async () => JSON.parse(await page.evaluate(() => window.bezsolid.modeler.panel())).frame;
  const before = await frame();
  assert.equal(before.unclipped, 0);
  const plain = await canvasPixels(page, 'unclipped-off');
  // Focused and switched by the keyboard alone.
  await page.focus('#unclipped');
  await page.keyboard.press('Space');
  await settle(page);
  const on = await frame();
  assert.ok(on.unclipped >= 1, `pieces of S_ξ = 0: ${on.unclipped}`);
  assert.equal(on.contours, before.contours, 'the solid\'s contour is unchanged');
  assert.match(await page.textContent('#contour-info'), /unclipped: \d+ piece/);
  const dashed = await canvasPixels(page, 'unclipped-on');
  // The dashes' violet shows where the plain picture has none.
  const violet = (img) => {
    let n = 0;
    for (let y = 0; y < img.height; y += 2) {
      for (let x = 0; x < img.width; x += 2) {
        const [r, g, b] = img.at(x, y);
        if (b > g + 40 && r > g + 15 && b > 70 && g < 90) n++;
      }
    }
    return n;
  };
  assert.ok(violet(dashed) > violet(plain) + 20, `violet pixels ${violet(plain)} → ${violet(dashed)}`);
  await page.keyboard.press('Space');
  await settle(page);
  assert.equal((await frame()).unclipped, 0);
  assert.deepEqual(errors, []);
  await page.close();
});
