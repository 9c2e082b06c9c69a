// The patch editor in a real browser, on the backend under test: space-mapping drags with undo and
// redo, share links (round trip, damaged links), the autosave, exports parsed back, and imports.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { launch, open, canvasPixels, canvasBox, screenOf, settle, URL as BASE, ARTIFACTS, pick } from './harness.mjs';
import { decodePng } from './png.mjs';

let browser;
before(async () => { browser = await launch(); });
after(async () => { await browser?.close(); });

const model = (page) => page.evaluate(() => window.bezsolid.modeler.model_json());
const status = (page) => page.textContent('#status');

/**
 * The 2D view as a picture, without the focus ring laid over it (which a key press shows on the
 * focused view): focus leaves the view first (the shortcuts work anywhere).
 */
async function viewShot(page) {
  await page.evaluate(() => document.activeElement?.blur());
  await settle(page);
  return page.locator('#view').screenshot();
}

/** Drags from `from` to `to` (page pixels) with real mouse events, in `steps` moves. */
async function drag(page, from, to, steps = 8) {
  await page.mouse.move(...from);
  await page.mouse.down();
  await page.mouse.move(...to, { steps });
  await page.mouse.up();
  await settle(page);
}

/** The rightmost dark (outline or grid line) pixel of image row `y` left of `fromX`. */
function rightEdge(img, y, fromX) {
  for (let x = Math.min(fromX, img.width - 1); x >= 0; x--) {
    const [r, g, b] = img.at(x, y);
    if (r < 110 && g < 110 && b < 130 && Math.abs(b - r) < 60) return x;
  }
  return -1;
}

test('a space-mapping drag moves the domain outline; undo and redo restore each picture exactly', async () => {
  const { page, errors } = await open(browser);
  const box = await canvasBox(page);
  const corner = await screenOf(page, 1, 1);
  // Select the corner P22 with a click that does not move it (no undo step), then take the picture.
  await page.mouse.click(...corner);
  await settle(page);
  assert.equal(await page.getAttribute('body', 'data-selected'), '2,2');
  assert.equal(await page.isDisabled('#undo'), true, 'a click is no step');
  const beforeShot = await viewShot(page);
  const before = decodePng(beforeShot);
  const scale = before.width / box.width;
  // A row a quarter of the way down from the corner: the right edge of the domain there.
  const [, midY] = await screenOf(page, 1, 0.75);
  const row = Math.round((midY - box.y) * scale);
  const edgeBefore = rightEdge(before, row, before.width - 5);
  assert.ok(Math.abs(edgeBefore / scale - (corner[0] - box.x)) < 4, `the edge is at x = 1: ${edgeBefore / scale} vs ${corner[0] - box.x}`);

  // Space mode by the switch; drag the corner right and up.
  await page.check('input[name="mode"][value="space"]');
  await settle(page);
  assert.equal(await page.getAttribute('body', 'data-mode'), 'space');
  await drag(page, corner, [corner[0] + 40, corner[1] - 40]);
  const afterShot = await viewShot(page);
  writeFileSync(join(ARTIFACTS, 'space-drag.png'), afterShot);
  const after = decodePng(afterShot);
  const edgeAfter = rightEdge(after, row, after.width - 5);
  assert.ok(edgeAfter > edgeBefore + 10 * scale, `the outline moved right: ${edgeBefore} → ${edgeAfter}`);
  assert.match(await page.textContent('#model-name'), /space-mapped/);
  const p = JSON.parse(await model(page)).solid.points[8];
  assert.ok(p[0] > 1.03 && p[1] > 1.03 && p[2] === -1, `P22 moved in x, y only: ${p}`);

  // Undo (Ctrl+Z) gives back the first picture exactly; redo (Ctrl+Shift+Z, then Ctrl+Y) the second.
  await page.keyboard.press('Control+z');
  await settle(page);
  assert.ok(beforeShot.equals(await viewShot(page)), 'undo restores the picture');
  assert.doesNotMatch(await page.textContent('#model-name'), /space-mapped/);
  await page.keyboard.press('Control+Shift+z');
  await settle(page);
  assert.ok(afterShot.equals(await viewShot(page)), 'redo re-applies the drag');
  await page.click('#undo');
  await settle(page);
  await page.keyboard.press('Control+y');
  await settle(page);
  assert.ok(afterShot.equals(await viewShot(page)), 'Ctrl+Y redoes too');

  // Shift gives the other mode for one drag: here ξ, so the point stays where it is.
  const moved = await screenOf(page, p[0], p[1]);
  await page.keyboard.down('Shift');
  await drag(page, moved, [moved[0], moved[1] - 36]);
  await page.keyboard.up('Shift');
  const q = JSON.parse(await model(page)).solid.points[8];
  assert.deepEqual(q.slice(0, 2), p.slice(0, 2));
  assert.ok(Math.abs(q[2] - (-1 + 36 / 120)) < 0.02, `ξ rose: ${q[2]}`);
  assert.deepEqual(errors, []);
  await page.close();
});

test('a 16 × 16 grid drags in space live, and the view reports its frame time', async () => {
  const { page, errors } = await open(browser);
  await page.fill('#grid-u', '16');
  await page.fill('#grid-v', '16');
  await page.click('#reset-grid');
  await settle(page);
  assert.match(await page.textContent('#model-name'), /16 × 16 points/);
  await page.focus('#view');
  await page.keyboard.press('d');
  assert.equal(await page.getAttribute('#debug-toggle', 'aria-pressed'), 'true');
  await page.check('input[name="mode"][value="space"]');
  const [x, y] = await screenOf(page, 8 / 15, 8 / 15);
  const times = [];
  await page.mouse.move(x, y);
  await page.mouse.down();
  for (let k = 1; k <= 6; k++) {
    await page.mouse.move(x + 3 * k, y - 2 * k);
    await settle(page);
    times.push(Number(await page.getAttribute('body', 'data-render-ms')));
  }
  await page.mouse.up();
  await settle(page);
  assert.ok(times.every((t) => t > 0), `frame times are reported: ${times}`);
  console.log(`# 16x16 space drag, frame times (ms): ${times.map((t) => t.toFixed(1)).join(' ')}`);
  assert.match(await page.textContent('#debug'), /frame: [\d.]+ ms/);
  assert.match(await page.textContent('#model-name'), /space-mapped/);
  await page.screenshot({ path: join(ARTIFACTS, 'grid16.png') });
  assert.deepEqual(errors, []);
  await page.close();
});

/** Makes the model differ from the default: a space drag and a typed ξ. */
async function edit(page) {
  const centre = await screenOf(page, 0.5, 0.5);
  await page.check('input[name="mode"][value="space"]');
  await drag(page, centre, [centre[0] + 23, centre[1] + 11]);
  await page.fill('#xi', '0.8125');
  await page.press('#xi', 'Enter');
  await settle(page);
}

test('a copied link opens the identical model in a new page; damaged links keep the model', async () => {
  const { page, errors } = await open(browser);
  await edit(page);
  const original = await model(page);
  await page.click('#copy-link');
  await page.waitForFunction(() => document.querySelector('#share-url').value.includes('#v1.'));
  const link = await page.inputValue('#share-url');
  assert.ok(link.startsWith(BASE), link);
  assert.ok(link.length < 2000, `${link.length} characters`);

  const { page: other, errors: otherErrors } = await open(browser, link.slice(BASE.length));
  assert.equal(await model(other), original, 'the model file is identical');
  assert.match(await status(other), /Opened the model from the link/);
  assert.equal(new URL(other.url()).hash, '', 'the fragment is dropped once opened');

  // A cut link and a hostile one, pasted into the open page: a message, the model untouched.
  for (const bad of [link.slice(0, link.length - 25), `${BASE}#v1.${'A'.repeat(9000)}`, `${BASE}#v9.AAAA`, `${BASE}#v1.!!!!`]) {
    await other.evaluate((h) => { location.hash = h.slice(h.indexOf('#')); }, bad);
    await other.waitForFunction(() => document.querySelector('#status').dataset.kind === 'error');
    assert.match(await status(other), /could not be opened, so the current model was kept/);
    assert.equal(await model(other), original);
    await other.evaluate(() => { document.querySelector('#status').dataset.kind = ''; });
  }
  // Opened fresh with a bad link: the default model stays, and the page says why.
  const { page: third, errors: thirdErrors } = await open(browser, '#v1.thisisnotamodel');
  assert.match(await status(third), /could not be opened/);
  const { page: plain } = await open(browser);
  assert.equal(await model(third), await model(plain));
  for (const e of [errors, otherErrors, thirdErrors]) assert.deepEqual(e, []);
  await Promise.all([page.close(), other.close(), third.close(), plain.close()]);
});

test('a reload brings back the last model from the autosave', async () => {
  const { page, errors } = await open(browser);
  await edit(page);
  const edited = await model(page);
  await page.reload();
  await page.waitForSelector('body[data-ready="true"]');
  assert.equal(await model(page), edited);
  assert.equal(await page.isDisabled('#undo'), true, 'a restored model starts a fresh history');
  assert.deepEqual(errors, []);
  await page.close();
});

/** Chooses an export and returns the downloaded file's name and bytes. */
async function exported(page, kind) {
  const [download] = await Promise.all([
    page.waitForEvent('download'),
    pick(page, 'export', kind),
  ]);
  const path = join(ARTIFACTS, `export-${download.suggestedFilename()}`);
  await download.saveAs(path);
  return { name: download.suggestedFilename(), bytes: readFileSync(path) };
}

test('each export downloads a file that parses back; the model file opens again', async () => {
  const { page, errors } = await open(browser);
  const original = await model(page);

  const json = await exported(page, 'model');
  assert.equal(json.name, 'bezsolid.bsolid.json');
  const file = JSON.parse(json.bytes.toString());
  assert.equal(file.format, 'bezsolid');
  assert.equal(file.version, 1);
  assert.deepEqual(file.solid.degree, [2, 2]);
  assert.equal(file.solid.points.length, 9);

  // SVG: one closed path per contour piece, its points on the solid's boundary (f ≈ 0).
  const svg = (await exported(page, 'svg')).bytes.toString();
  const paths = [...svg.matchAll(/ d="([^"]+)"/g)].map((m) => m[1]);
  assert.equal(paths.length, 1, svg.slice(0, 400));
  const pts = [...paths[0].matchAll(/(-?[\d.e+-]+),(-?[\d.e+-]+)/g)].map((m) => [Number(m[1]), Number(m[2])]);
  assert.ok(pts.length > 50 && paths[0].trim().endsWith('Z'));
  const fs = await page.evaluate((ps) => {
    const m = window.bezsolid.modeler;
    const box = document.querySelector('#view').getBoundingClientRect();
    // probe takes CSS pixels: invert the view map from two probes.
    const [x0, y0] = m.probe(0, 0);
    const [x1, y1] = m.probe(100, 100);
    return ps.map(([x, y]) => m.probe((x - x0) / (x1 - x0) * 100, (y - y0) / (y1 - y0) * 100)[2]);
  }, pts.filter((_, k) => k % 10 === 0));
  assert.ok(fs.every((f) => Math.abs(f) < 1e-6), `SVG points on f = 0: ${fs.slice(0, 5)}`);

  // HyperFun: the model function with the explicit Bernstein sum.
  const hf = (await exported(page, 'hf')).bytes.toString();
  assert.match(hf, /my_model\(x\[3\], a\[1\]\)\s*\{/);
  assert.match(hf, /my_model = sxi & \(\(u\*us\) & \(v\*vs\)\);\s*\}/);

  // PNG of the view: the canvas's size, and a picture (red inside, blue outside).
  const png = decodePng((await exported(page, 'png')).bytes);
  const size = await page.evaluate(() => [window.bezsolid.canvas.width, window.bezsolid.canvas.height]);
  assert.deepEqual([png.width, png.height], size);
  const [r, , b] = png.at(png.width / 2 + 20, png.height / 2 + 30);
  const [r2, , b2] = png.at(4, 4);
  assert.ok(r > b + 40 && b2 > r2 + 40, `red middle ${[r, b]}, blue corner ${[r2, b2]}`);

  // A space-mapped model's HyperFun carries its inverse map, in HyperFun's own loops.
  await edit(page);
  const edited = await model(page);
  const mapped = (await exported(page, 'hf')).bytes.toString();
  assert.match(mapped, /-- solid: a space-mapped Bezier patch of degree \(\d+, \d+\)/);
  assert.match(mapped, /while \(m1go = 1\) loop/);
  assert.match(mapped, /my_model = n\d+;\s*\}\s*$/);
  assert.equal(await model(page), edited);
  // The HyperFun file carries its model: opened by the picker, it is the model it came from.
  await page.setInputFiles('#open-file', { name: 'm.bsolid.json', mimeType: 'application/json', buffer: json.bytes });
  await page.waitForFunction((o) => window.bezsolid.modeler.model_json() === o, original);
  await page.setInputFiles('#open-file', { name: 'edited.hf', mimeType: 'text/plain', buffer: Buffer.from(mapped) });
  await page.waitForFunction((o) => window.bezsolid.modeler.model_json() === o, edited);
  assert.match(await status(page), /Opened edited\.hf/);

  // Import: the exported model file by the picker (an undo step), and a broken one (kept).
  await page.setInputFiles('#open-file', { name: 'm.bsolid.json', mimeType: 'application/json', buffer: json.bytes });
  await page.waitForFunction((o) => window.bezsolid.modeler.model_json() === o, original);
  assert.match(await status(page), /Opened m\.bsolid\.json/);
  await page.click('#undo');
  assert.equal(await model(page), edited);
  await page.setInputFiles('#open-file', { name: 'bad.json', mimeType: 'application/json', buffer: Buffer.from('{"format": "bezsolid", "version": 1, "solid": {"kind": "patch", "degree": [2, 2], "points": [[0, 0, 1]]}}') });
  await page.waitForFunction(() => document.querySelector('#status').dataset.kind === 'error');
  assert.match(await status(page), /bad\.json could not be opened, so the current model was kept/);
  assert.equal(await model(page), edited);

  // Drag and drop of a file onto the page.
  await page.evaluate((text) => {
    const dt = new DataTransfer();
    dt.items.add(new File([text], 'dropped.bsolid.json', { type: 'application/json' }));
    window.dispatchEvent(new DragEvent('drop', { dataTransfer: dt, bubbles: true, cancelable: true }));
  }, json.bytes.toString());
  await page.waitForFunction((o) => window.bezsolid.modeler.model_json() === o, original);
  assert.match(await status(page), /Opened dropped\.bsolid\.json/);
  assert.deepEqual(errors, []);
  await page.close();
});

test('presets, a new grid and elevation change the model; elevation keeps the picture', async () => {
  const { page, errors } = await open(browser);
  const fig9 = await model(page);
  await pick(page, 'preset', 'flat');
  await settle(page);
  assert.match(await page.textContent('#model-name'), /4 × 4 points/);
  await pick(page, 'preset', 'fig9');
  await settle(page);
  assert.equal(await model(page), fig9);
  const shot = decodePng(await page.locator('#view').screenshot());
  await page.click('#elevate-u');
  await page.click('#elevate-v');
  await settle(page);
  assert.match(await page.textContent('#model-name'), /4 × 4 points/);
  // The same solid: the contour crosses the middle row at the same pixels (control points differ).
  const img = await canvasPixels(page, 'elevated');
  const y = Math.round(img.height / 2 + 40);
  const dark = (im) => {
    const xs = [];
    for (let x = 0; x < im.width; x++) {
      const [r, g, b] = im.at(x, y);
      if (r < 40 && g < 40 && b < 40) xs.push(x);
    }
    return xs;
  };
  const a = dark(shot);
  const b = dark(img);
  assert.ok(a.length > 0);
  assert.ok(Math.abs(a[0] - b[0]) <= 1 && Math.abs(a.at(-1) - b.at(-1)) <= 1, `${a} vs ${b}`);
  await page.fill('#grid-u', '1');
  await page.click('#reset-grid');
  assert.match(await status(page), /2 to 16 points per side/);
  assert.deepEqual(errors, []);
  await page.close();
});
