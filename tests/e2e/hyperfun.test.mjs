// The HyperFun mode in a real browser, on the backend under test: a `.hf` file opens in it and is
// drawn (its solid in the 3D view, its field's section under the editor), an edit redraws it as
// it is typed, an error is shown at its line while the last drawing stays, the program travels in
// a link and a model file, its mesh exports parse back and it is measured; a program that is one
// of bezsolid's exports opens back in the Bézier mode as the model it came from.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { launch, open, settle, ARTIFACTS, pick } from './harness.mjs';
import { decodePng } from './png.mjs';

let browser;
before(async () => { browser = await launch(); });
after(async () => { await browser?.close(); });

// A program written for HyperFun, not by bezsolid: a ball with a torus blended around it.
const PROGRAM = `-- a ball and a ring, blended
my_model(x[3], a[1])
{
  array centre[3];
  centre = [0, 0, 0];
  ball = hfSphere(x, centre, 4);
  ring = hfTorusZ(x, centre, 6, 1.5);
  my_model = hfBlendUni(ball, ring, 1, 1, 1);
}
`;

/** Waits for the drawing under way to end; returns its state (done or error). */
async function drawnState(page) {
  await page.waitForFunction(() => ['done', 'error', 'stopped'].includes(document.body.dataset.hfState), null, { timeout: 60_000 });
  await settle(page);
  return page.evaluate(() => document.body.dataset.hfState);
}

/** Pixels of `selector` far from its background colour `[r, g, b]`, and the screenshot. */
async function ink(page, selector, name, background) {
  await settle(page);
  const png = await page.locator(selector).screenshot();
  writeFileSync(join(ARTIFACTS, `${name}.png`), png);
  const img = decodePng(png);
  let n = 0;
  let red = 0;
  for (let y = 0; y < img.height; y += 2) {
    for (let x = 0; x < img.width; x += 2) {
      const [r, g, b] = img.at(x, y);
      if (Math.abs(r - background[0]) + Math.abs(g - background[1]) + Math.abs(b - background[2]) > 40) n += 1;
      if (r > g + 40 && r > b + 40) red += 1;
    }
  }
  return { ink: n, red, png };
}

const triangles = (page) => page.evaluate(() => Number(document.body.dataset.hfTriangles));

/** Types `text` over the editor's, as a person pasting it (an input event, drawn live). */
async function replaceProgram(page, text) {
  await page.focus('#hf');
  await page.keyboard.press('Control+A');
  await page.keyboard.insertText(text);
}

test('a .hf file opens, is drawn, edited live, shared, exported and measured', async () => {
  const { page, errors } = await open(browser);
  const path = join(ARTIFACTS, 'ring.hf');
  writeFileSync(path, PROGRAM);
  await page.setInputFiles('#open-file', path);
  await page.waitForSelector('body[data-workspace="hyperfun"]');
  assert.equal(await drawnState(page), 'done', await page.textContent('#hf-message'));
  assert.equal(await page.inputValue('#hf'), PROGRAM);
  const first = await triangles(page);
  assert.ok(first > 1000, `${first} triangles`);
  const solid = await ink(page, '#view3d', 'hyperfun-ring', [244, 245, 247]);
  assert.ok(solid.ink > 2000, `the solid is drawn (${solid.ink} pixels)`);
  // A drag orbits the drawing and edits nothing; F frames it again.
  const bezier = await page.evaluate(() => window.bezsolid.modeler.model_json());
  const view = await page.locator('#view3d').boundingBox();
  await page.mouse.move(view.x + view.width / 2, view.y + view.height / 2);
  await page.mouse.down();
  await page.mouse.move(view.x + view.width / 2 + 90, view.y + view.height / 2 + 40, { steps: 6 });
  await page.mouse.up();
  const turned = await ink(page, '#view3d', 'hyperfun-turned', [244, 245, 247]);
  assert.ok(!turned.png.equals(solid.png), 'the drag turns the view');
  assert.equal(await page.evaluate(() => window.bezsolid.modeler.model_json()), bezier);
  await page.focus('#view3d');
  await page.keyboard.press('f');
  // The section z = 0 (the slider's middle) crosses the ball and the ring: inside is red.
  await page.waitForFunction(() => Number(document.body.dataset.hfSection) > 0);
  const cut = await ink(page, '#hf-section', 'hyperfun-section', [255, 255, 255]);
  assert.ok(cut.red > 500, `the section shows the inside (${cut.red} red pixels)`);
  // Across x, near the box's side: the plane misses the solid, nothing red.
  await page.check('input[name="hf-axis"][value="0"]');
  await page.fill('#hf-at', '990');
  await page.waitForFunction(() => document.querySelector('#hf-section-label').textContent.startsWith('x = 9.8'));
  await page.waitForFunction(() => document.body.dataset.hfSection === '0');
  const miss = await ink(page, '#hf-section', 'hyperfun-section-miss', [255, 255, 255]);
  assert.equal(miss.red, 0);

  // An edit redraws as it is typed: a larger ball.
  await replaceProgram(page, PROGRAM.replace('hfSphere(x, centre, 4)', 'hfSphere(x, centre, 6)'));
  await page.waitForFunction((n) => document.body.dataset.hfState === 'done' && Number(document.body.dataset.hfTriangles) !== n, first, { timeout: 60_000 });
  const larger = await ink(page, '#view3d', 'hyperfun-larger', [244, 245, 247]);
  assert.ok(!larger.png.equals(solid.png), 'the edit changes the drawing');

  // An error: HyperFun's message at its line, a way to it, the last drawing kept (marked).
  await replaceProgram(page, PROGRAM.replace('centre = [0, 0, 0];', 'centre = [0, 0, 0];\n  s = 1;'));
  assert.equal(await drawnState(page), 'error');
  const message = await page.textContent('#hf-message');
  assert.match(message, /Line 6, position \d+: Left bracket expected/);
  assert.equal(await page.locator('#hf-gutter .error').textContent(), '6');
  assert.equal(await page.locator('#hf-stale').isVisible(), true);
  await page.click('#hf-message button');
  assert.equal(await page.evaluate(() => document.activeElement.id), 'hf');

  // Back to the file's program; a box of its own.
  await replaceProgram(page, PROGRAM);
  await page.fill('#hf-box', '-8, -8, -3, 8, 8, 3');
  assert.equal(await drawnState(page), 'done');

  // Shared: the link opens the program, in its box, drawn, in a page that was in the Bézier mode.
  await page.click('#copy-link');
  await page.waitForFunction(() => document.body.dataset.link);
  const link = await page.evaluate(() => document.body.dataset.link);
  const other = await open(browser);
  await other.page.goto(link);
  await other.page.waitForSelector('body[data-workspace="hyperfun"]');
  assert.equal(await drawnState(other.page), 'done');
  assert.equal(await other.page.inputValue('#hf'), PROGRAM);
  assert.equal(await other.page.inputValue('#hf-box'), '-8, -8, -3, 8, 8, 3');
  assert.equal(await triangles(other.page), await triangles(page));
  assert.deepEqual(other.errors, []);
  await other.page.close();

  // The model file keeps the program and its box; the mesh exports parse back, closed.
  const model = JSON.parse(await download(page, 'model'));
  assert.equal(model.solid.kind, 'hyperfun');
  assert.equal(model.solid.program, PROGRAM);
  assert.deepEqual(model.solid.box, [[-8, -8, -3], [8, 8, 3]]);
  assert.equal((await download(page, 'hf')).toString(), PROGRAM);
  const obj = (await download(page, 'obj')).toString();
  const faces = obj.split('\n').filter((l) => l.startsWith('f ')).map((l) => l.slice(2).trim().split(/\s+/).map((v) => Number(v.split('/')[0])));
  assert.ok(faces.length > 1000, `${faces.length} faces`);
  const edges = new Map();
  for (const f of faces) {
    for (let k = 0; k < 3; k++) {
      const key = `${f[k]},${f[(k + 1) % 3]}`;
      edges.set(key, (edges.get(key) ?? 0) + 1);
    }
  }
  for (const [key, n] of edges) {
    const [a, b] = key.split(',');
    assert.equal(n, 1, `edge ${key} once`);
    assert.equal(edges.get(`${b},${a}`), 1, `edge ${key} has its twin: the mesh is closed`);
  }
  const stl = await download(page, 'stl');
  assert.equal(stl.readUInt32LE(80), faces.length);

  // Measured: the volume of the mesh, about the ball's and the ring's within the box.
  await page.click('#hf-measure');
  await page.waitForFunction(() => /Volume/.test(document.querySelector('#hf-measure-out').textContent), null, { timeout: 60_000 });
  const m = JSON.parse(await page.evaluate(() => document.body.dataset.measure));
  assert.ok(m.volume > 4 / 3 * Math.PI * 64 && m.volume < 16 * 16 * 6, `volume ${m.volume}`);
  assert.deepEqual(errors, []);
  await page.close();
});

test('an export opens back as its model; the section and editor at other sizes', async () => {
  const { page, errors } = await open(browser);
  // The Bézier model's export, put in the HyperFun mode's editor.
  const hf = await page.evaluate(async () => (await window.bezsolid.tools()).headless_hyperfun(window.bezsolid.modeler.model_json()));
  await page.check('input[name="workspace"][value="hyperfun"]');
  await page.waitForSelector('body[data-workspace="hyperfun"]');
  await replaceProgram(page, hf);
  await page.fill('#hf-box', '-1.5, -1.5, -1.5, 1.5, 1.5, 1.5');
  assert.equal(await drawnState(page), 'done', await page.textContent('#hf-message'));
  assert.equal(await page.locator('#hf-edit').isVisible(), true);
  const before = await page.evaluate(() => window.bezsolid.modeler.model_json());
  await page.click('#hf-edit');
  await page.waitForSelector('body[data-workspace="bezier"]');
  assert.equal(await page.evaluate(() => window.bezsolid.modeler.model_json()), before);
  // A program of no model offers no such edit.
  await page.check('input[name="workspace"][value="hyperfun"]');
  await replaceProgram(page, PROGRAM);
  await page.fill('#hf-box', '-8, -8, -3, 8, 8, 3');
  assert.equal(await drawnState(page), 'done');
  assert.equal(await page.locator('#hf-edit').isVisible(), false);
  for (const [name, size] of [['desktop', { width: 1200, height: 760 }], ['800x600', { width: 800, height: 600 }], ['phone', { width: 390, height: 844 }]]) {
    await page.setViewportSize(size);
    await settle(page);
    writeFileSync(join(ARTIFACTS, `hyperfun-${name}.png`), await page.screenshot({ fullPage: true }));
  }
  assert.deepEqual(errors, []);
  await page.close();
});

test('a model of many solids holds a HyperFun program as a part, drawn, linked and exported', async () => {
  const { page, errors } = await open(browser);
  const model = {
    format: 'bezsolid',
    version: 1,
    solid: {
      kind: 'difference',
      of: [
        { kind: 'hyperfun', program: PROGRAM, box: [[-8, -8, -3], [8, 8, 3]] },
        { kind: 'box', min: [-9, -9, 0], max: [9, 9, 4] },
      ],
    },
  };
  const path = join(ARTIFACTS, 'hyperfun-part.bsolid.json');
  writeFileSync(path, JSON.stringify(model));
  await page.setInputFiles('#open-file', path);
  await page.waitForFunction(() => document.getElementById('model-name').textContent.startsWith('Many solids'));
  assert.equal(await page.evaluate(() => document.body.dataset.workspace), 'bezier');
  const items = await page.locator('#outline-tree [role="treeitem"]').allTextContents();
  assert.ok(items.some((t) => /HyperFun program/.test(t)), items.join(' / '));
  await page.waitForFunction(() => !document.body.dataset.working, null, { timeout: 60_000 });
  const half = await ink(page, '#view3d', 'hyperfun-part', [244, 245, 247]);
  assert.ok(half.ink > 1000, `the part is drawn (${half.ink} pixels)`);
  // Its HyperFun export calls the program as a body of its own, and opens back as the model.
  const hf = (await download(page, 'hf')).toString();
  assert.match(hf, /^hf\d+_my_model\(x\[3\], a\[1\]\)/m);
  assert.match(hf, /hf\d+_my_model\(x, a\)/);
  // A link carries the part.
  await page.click('#copy-link');
  await page.waitForFunction(() => document.body.dataset.link);
  const other = await open(browser);
  await other.page.goto(await page.evaluate(() => document.body.dataset.link));
  await other.page.waitForFunction(() => document.getElementById('model-name').textContent.startsWith('Many solids'));
  assert.equal(await other.page.evaluate(() => window.bezsolid.modeler.model_json()), await page.evaluate(() => window.bezsolid.modeler.model_json()));
  await other.page.close();

  // The part's program is edited in the HyperFun mode and put back, one undo step.
  const row = page.locator('#outline-tree [role="treeitem"]', { hasText: 'HyperFun program' });
  await row.click();
  await page.waitForSelector('#part-hyperfun:not([hidden])');
  await page.click('#part-hyperfun');
  await page.waitForSelector('body[data-workspace="hyperfun"]');
  assert.equal(await page.inputValue('#hf'), PROGRAM);
  assert.equal(await page.inputValue('#hf-box'), '-8, -8, -3, 8, 8, 3');
  assert.equal(await page.locator('#hf-part').isVisible(), true);
  const edited = PROGRAM.replace('hfSphere(x, centre, 4)', 'hfSphere(x, centre, 5)');
  await replaceProgram(page, edited);
  assert.equal(await drawnState(page), 'done');
  await page.click('#hf-put-back');
  await page.waitForSelector('body[data-workspace="bezier"]');
  const put = JSON.parse(await page.evaluate(() => window.bezsolid.modeler.model_json()));
  assert.equal(put.solid.of[0].program, edited);
  await page.click('#undo');
  await page.waitForFunction((p) => JSON.parse(window.bezsolid.modeler.model_json()).solid.of[0].program === p, PROGRAM);
  // Add puts a new HyperFun part beside the selection.
  const before = await page.locator('#outline-tree [role="treeitem"]').count();
  await page.click('button[data-add="hyperfun"]');
  await page.waitForFunction((n) => document.querySelectorAll('#outline-tree [role="treeitem"]').length > n, before);
  await page.waitForSelector('#part-hyperfun:not([hidden])');
  assert.deepEqual(errors, []);
  await page.close();
});

async function download(page, value) {
  const [file] = await Promise.all([page.waitForEvent('download'), pick(page, 'export', value)]);
  return readFileSync(await file.path());
}
