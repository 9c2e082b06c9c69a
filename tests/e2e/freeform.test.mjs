// The Free-form mode in a real browser, on the backend under test: the default scene (the blob
// minus a torus) draws its result surface, the worker's fine surface arrives, the point mesh shows
// red points, a mesh file is imported by the picker and by a drop, the operation changes the
// result, the result exports as STL, OBJ and PLY that parse back, and a link reopens the scene.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { launch, open, settle, ARTIFACTS, pick, itemDisabled } from './harness.mjs';
import { decodePng } from './png.mjs';

let browser;
before(async () => { browser = await launch(); });
after(async () => { await browser?.close(); });

const FIXTURES = new URL('../../crates/core/tests/fixtures/mesh/', import.meta.url).pathname;

async function freeForm(page) {
  await page.check('input[name="workspace"][value="freeform"]');
  await page.waitForSelector('body[data-workspace="freeform"]');
  await settle(page);
}

const waitFine = (page, resolution = 64) => page.waitForFunction(
  (r) => (document.body.dataset.ffSurface ?? '').endsWith(`,${r}`), resolution, { timeout: 60_000 });

/** Counts of blue (result) and red (marked) pixels in the 3D view. */
async function colours(page, name) {
  await settle(page);
  const png = await page.locator('#view3d').screenshot();
  writeFileSync(join(ARTIFACTS, `${name}.png`), png);
  const img = decodePng(png);
  let blue = 0;
  let red = 0;
  for (let y = 0; y < img.height; y += 2) {
    for (let x = 0; x < img.width; x += 2) {
      const [r, g, b] = img.at(x, y);
      if (b > r + 30 && b > 90) blue += 1;
      if (r > 150 && g < 90 && b < 90) red += 1;
    }
  }
  return { blue, red, png };
}

/** Waits until `f()` holds (polling, up to 30 s). */
async function expect(f) {
  for (let k = 0; k < 300 && !f(); k++) await new Promise((r) => setTimeout(r, 100));
  assert.ok(f());
}

async function download(page, value) {
  const [file] = await Promise.all([page.waitForEvent('download'), pick(page, 'export', value)]);
  return readFileSync(await file.path());
}

test('the default free-form scene draws, meshes finely in the worker and shows the point mesh', async () => {
  const { page, errors } = await open(browser);
  await freeForm(page);
  assert.match(await page.textContent('#model-name'), /Free-form: A - B/);
  await waitFine(page);
  assert.match(await page.textContent('#ff-info'), /Result surface: [\d,]+ triangles at 64/);
  const result = await colours(page, 'freeform-result');
  assert.ok(result.blue > 2000, `the result is drawn (${result.blue} blue pixels)`);
  // The paper's intermediate picture: the points of A, red where B takes them away.
  await page.check('input[name="ff-display"][value="points"]');
  const points = await colours(page, 'freeform-points');
  assert.ok(points.red > 100, `red points are drawn (${points.red})`);
  assert.match(await page.textContent('#ff-info'), /Point mesh 25 × 25 × 25: [\d,]+ points, [\d,]+ red/);
  // Orbiting changes the picture and edits nothing.
  const before = await page.evaluate(() => window.bezsolid.ff.model_json());
  const box = await page.locator('#view3d').boundingBox();
  await page.mouse.move(box.x + box.width / 2, box.y + box.height / 2);
  await page.mouse.down();
  await page.mouse.move(box.x + box.width / 2 + 80, box.y + box.height / 2, { steps: 4 });
  await page.mouse.up();
  const orbited = await colours(page, 'freeform-orbited');
  assert.ok(!orbited.png.equals(points.png));
  assert.equal(await page.evaluate(() => window.bezsolid.ff.model_json()), before);
  assert.deepEqual(errors, []);
  await page.close();
});

test('a mesh imports by the picker and by a drop, bad ones keep the scene, and the result exports', async () => {
  const { page, errors } = await open(browser);
  await freeForm(page);
  await page.setInputFiles('#ff-import-b', join(FIXTURES, 'cube.obj'));
  await page.waitForFunction(() => /Imported cube\.obj as solid B/.test(document.getElementById('status').textContent));
  await settle(page);
  assert.equal(await page.inputValue('#ff-b'), 'imported');
  assert.match(await page.textContent('#ff-info'), /B: 12 triangles/);
  // The same cube as an ASCII PLY of six quads: the same 12 triangles.
  await page.setInputFiles('#ff-import-b', join(FIXTURES, 'cube.ply'));
  await page.waitForFunction(() => /Imported cube\.ply as solid B/.test(document.getElementById('status').textContent));
  await settle(page);
  assert.match(await page.textContent('#ff-info'), /B: 12 triangles/);
  // The cube into the blob, intersected.
  await page.selectOption('#ff-op', 'intersection');
  await page.waitForSelector('body[data-ff-operation="intersection"]');
  await waitFine(page);
  const inter = await colours(page, 'freeform-intersection');
  assert.ok(inter.blue > 500, `${inter.blue}`);
  const model = JSON.parse(await page.evaluate(() => window.bezsolid.ff.model_json()));
  assert.equal(model.solid.kind, 'esc');
  assert.equal(model.solid.operation, 'intersection');
  assert.equal(model.solid.operands[1].mesh.triangles.length, 12);

  // A broken mesh: its reason, and the scene is kept.
  await page.setInputFiles('#ff-import-a', join(FIXTURES, 'open.obj'));
  await page.waitForFunction(() => document.getElementById('status').dataset.kind === 'error');
  assert.match(await page.textContent('#status'), /open\.obj could not be imported.*4 open edges/);
  assert.deepEqual(JSON.parse(await page.evaluate(() => window.bezsolid.ff.model_json())), model);

  // A drop of a binary STL onto the page imports it as A.
  const stl = readFileSync(join(FIXTURES, 'tetra.stl'));
  await page.evaluate(async (bytes) => {
    const dt = new DataTransfer();
    dt.items.add(new File([new Uint8Array(bytes)], 'tetra.stl'));
    window.dispatchEvent(new DragEvent('drop', { dataTransfer: dt, bubbles: true, cancelable: true }));
  }, [...stl]);
  await page.waitForFunction(() => /Imported tetra\.stl as solid A/.test(document.getElementById('status').textContent));
  await settle(page);
  assert.match(await page.textContent('#ff-info'), /A: 4 triangles/);

  // Back to the blob minus a torus; the exports parse back.
  await page.selectOption('#ff-a', 'blob');
  await page.selectOption('#ff-b', 'torus');
  await page.selectOption('#ff-op', 'difference');
  await page.fill('#ff-resolution', '32');
  await page.dispatchEvent('#ff-resolution', 'change');
  await waitFine(page, 32);
  // The view draws the trimmed PN surfaces; the export is the closed mesh at the resolution, one
  // triangle count in every format, every edge shared by two faces.
  const bin = await download(page, 'stl');
  const triangles = bin.readUInt32LE(80);
  assert.ok(triangles > 1000, `${triangles}`);
  assert.equal(bin.length, 84 + 50 * triangles);
  const obj = (await download(page, 'obj')).toString();
  const faces = obj.split('\n').filter((l) => l.startsWith('f ')).map((l) => l.split(/\s+/).slice(1).map((v) => parseInt(v, 10)));
  assert.equal(faces.length, triangles);
  const edges = new Map();
  for (const f of faces) {
    for (let k = 0; k < 3; k++) {
      const [a, b] = [f[k], f[(k + 1) % 3]];
      const key = a < b ? `${a},${b}` : `${b},${a}`;
      edges.set(key, (edges.get(key) ?? 0) + 1);
    }
  }
  assert.ok([...edges.values()].every((n) => n === 2), 'the exported mesh is closed');
  const ply = (await download(page, 'ply')).toString('latin1');
  assert.match(ply, new RegExp(`element face ${triangles}\\b`));
  assert.ok(await itemDisabled(page, 'export', 'svg'));
  // Two exports asked for at once each get their own file.
  const both = [];
  page.on('download', (d) => both.push(d));
  await pick(page, 'export', 'stl');
  await pick(page, 'export', 'obj');
  await page.waitForFunction(() => !document.body.dataset.working, null, { timeout: 60_000 });
  await expect(() => both.length === 2);
  const byName = Object.fromEntries(await Promise.all(both.map(async (d) => [d.suggestedFilename(), readFileSync(await d.path())])));
  assert.equal(byName['bezsolid-result.stl'].readUInt32LE(80), triangles);
  const faces2 = byName['bezsolid-result.obj'].toString().split('\n').filter((l) => l.startsWith('f ')).length;
  assert.equal(faces2, triangles);
  assert.deepEqual(errors, []);
  await page.close();
});

test('a free-form link reopens the scene, and the model file opens back in the mode', async () => {
  const { page, errors } = await open(browser);
  await freeForm(page);
  await page.selectOption('#ff-a', 'icosphere');
  await page.fill('#ff-x', '0.6');
  await page.dispatchEvent('#ff-x', 'change');
  await page.selectOption('#ff-op', 'union');
  await page.click('#copy-link');
  await page.waitForFunction(() => document.body.dataset.link);
  const link = await page.evaluate(() => document.body.dataset.link);
  assert.ok(link.length < 200, link);
  const model = await page.evaluate(() => window.bezsolid.ff.model_json());
  const file = await download(page, 'model');
  assert.equal(file.toString(), model);

  // A new page, in the Bézier mode, opens the link into the Free-form mode.
  const other = await open(browser);
  await other.page.evaluate(() => window.bezsolid.setWorkspace('bezier'));
  await other.page.goto(link);
  await other.page.waitForSelector('body[data-ready="true"]');
  await other.page.waitForSelector('body[data-workspace="freeform"]');
  await settle(other.page);
  assert.equal(await other.page.evaluate(() => window.bezsolid.ff.model_json()), model);
  assert.equal(await other.page.inputValue('#ff-x'), '0.6');
  // The model file opens too (picker), after another edit, from the Bézier mode into this one.
  await other.page.selectOption('#ff-op', 'intersection');
  await other.page.check('input[name="workspace"][value="bezier"]');
  await other.page.waitForSelector('body[data-workspace="bezier"]');
  const path = join(ARTIFACTS, 'freeform.bsolid.json');
  writeFileSync(path, file);
  await other.page.setInputFiles('#open-file', path);
  await other.page.waitForFunction(() => /Opened freeform\.bsolid\.json/.test(document.getElementById('status').textContent));
  assert.equal(await other.page.evaluate(() => window.bezsolid.ff.model_json()), model);
  assert.deepEqual(other.errors, []);
  assert.deepEqual(errors, []);
  await other.page.close();
  await page.close();
});

test('a free-form export at resolution 160 shows how far it got; Cancel stops one, saving nothing', async () => {
  const { page, errors } = await open(browser);
  await freeForm(page);
  await page.fill('#ff-resolution', '160');
  await page.dispatchEvent('#ff-resolution', 'change');
  await waitFine(page, 160);
  // What the export lines of the work list say, as they change.
  await page.evaluate(() => {
    window.shares = [];
    new MutationObserver(() => {
      for (const how of document.querySelectorAll('#work .task[data-kind="export"] .how')) window.shares.push(how.textContent);
    }).observe(document.getElementById('work'), { subtree: true, childList: true, characterData: true });
  });
  const saved = [];
  page.on('download', (d) => saved.push(d.suggestedFilename()));
  const [stl] = await Promise.all([page.waitForEvent('download', { timeout: 120_000 }), pick(page, 'export', 'stl')]);
  assert.equal(stl.suggestedFilename(), 'bezsolid-result.stl');
  const shares = await page.evaluate(() => window.shares);
  assert.ok(shares.some((s) => /^\d+%, [\d.]+ s$/.test(s)), `the export said how far it got: ${shares.join(' | ')}`);
  // Two more: the second waits for the first; its Cancel stops it and nothing of it is saved.
  await pick(page, 'export', 'obj');
  await pick(page, 'export', 'ply');
  await page.locator('#work .task[data-kind="export"]:has-text("Exporting PLY") button').click();
  await page.waitForFunction(() => /Exporting PLY was cancelled; nothing was saved/.test(document.getElementById('status').textContent));
  await page.waitForFunction(() => !(document.body.dataset.working ?? '').includes('export'), null, { timeout: 120_000 });
  await settle(page);
  // The browser's download event may come a moment after the page has saved.
  await expect(() => saved.length >= 2);
  await settle(page);
  assert.deepEqual(saved, ['bezsolid-result.stl', 'bezsolid-result.obj']);
  assert.equal(await page.isDisabled('#undo'), true, 'exports are no undo steps');
  assert.deepEqual(errors, []);
  await page.close();
});

test('solids are added, combined by a typed expression, placed by numbers and by dragging, and a link carries it all', async () => {
  const { page, errors } = await open(browser);
  await freeForm(page);
  const ffExpr = () => page.evaluate(() => document.body.dataset.ffExpression);
  assert.equal(await ffExpr(), 'A - B');
  // A third solid joins the union, with its own row, letter and controls.
  await page.click('#ff-add');
  await page.waitForFunction(() => document.body.dataset.ffExpression === 'A - B | C');
  assert.equal(await page.locator('#ff-operands li').count(), 3);
  assert.equal(await page.inputValue('#ff-c'), 'icosphere');
  assert.equal(await page.inputValue('#ff-op'), 'expression');
  // A typed expression; a bad one is marked and said, and the scene is kept.
  await page.fill('#ff-expr', '!(A | C) & B');
  await page.press('#ff-expr', 'Enter');
  await page.waitForFunction(() => document.body.dataset.ffExpression === '!(A | C) & B');
  await page.fill('#ff-expr', 'A | D');
  await page.press('#ff-expr', 'Enter');
  await page.waitForFunction(() => /no solid is named "D" \(at character 5\)/.test(document.getElementById('status').textContent));
  assert.equal(await page.getAttribute('#ff-expr', 'aria-invalid'), 'true');
  assert.equal(await ffExpr(), '!(A | C) & B');
  await page.press('#ff-expr', 'Escape');
  assert.equal(await page.inputValue('#ff-expr'), '!(A | C) & B');
  await page.fill('#ff-expr', '(A | C) - B');
  await page.press('#ff-expr', 'Enter');
  await page.waitForFunction(() => document.body.dataset.ffExpression === 'A | C - B');
  await waitFine(page);
  // C is placed by typed numbers: turned, scaled, moved.
  await page.selectOption('#ff-slot', '2');
  for (const [id, v] of [['#ff-rz', '30'], ['#ff-sx', '0.5'], ['#ff-sz', '1.5'], ['#ff-y', '0.4']]) {
    await page.fill(id, v);
    await page.dispatchEvent(id, 'change');
  }
  const placed = JSON.parse(await page.evaluate(() => window.bezsolid.ff.model_json()));
  const c = placed.solid.operands[2];
  assert.deepEqual([c.rotate, c.scale, c.offset[1]], [[0, 0, 30], [0.5, 1, 1.5], 0.4]);
  assert.equal(placed.solid.expression, 'A | C - B');
  // A zero scale is refused, marked, and the model kept.
  await page.fill('#ff-sy', '0');
  await page.dispatchEvent('#ff-sy', 'change');
  await page.waitForFunction(() => /Place C: .*scale 0/.test(document.getElementById('status').textContent));
  assert.equal(await page.getAttribute('#ff-sy', 'aria-invalid'), 'true');
  assert.deepEqual(JSON.parse(await page.evaluate(() => window.bezsolid.ff.model_json())), placed);
  await page.fill('#ff-sy', '1');
  await page.dispatchEvent('#ff-sy', 'change');
  // Dragging in the 3D view with Drag to move pressed moves C in the plane facing the view: one
  // undo step gives the typed place back.
  await page.click('#ff-drag');
  assert.equal(await page.getAttribute('#ff-drag', 'aria-pressed'), 'true');
  const box = await page.locator('#view3d').boundingBox();
  const [x0, y0] = [box.x + box.width / 2, box.y + box.height / 2];
  await page.mouse.move(x0, y0);
  await page.mouse.down();
  for (let k = 1; k <= 10; k++) await page.mouse.move(x0 + 8 * k, y0 - 3 * k);
  await page.mouse.up();
  await settle(page);
  const dragged = JSON.parse(await page.evaluate(() => window.bezsolid.ff.model_json()));
  assert.notDeepEqual(dragged.solid.operands[2].offset, c.offset, 'the drag moved C');
  assert.deepEqual(dragged.solid.operands[1], placed.solid.operands[1], 'and nothing else');
  assert.notEqual(await page.inputValue('#ff-x'), String(c.offset[0]), 'the fields follow');
  await page.click('#undo');
  await settle(page);
  assert.deepEqual(JSON.parse(await page.evaluate(() => window.bezsolid.ff.model_json())), placed);
  await page.click('#ff-drag');
  // The link carries the expression and the placement; a new page opens the same model.
  await page.click('#copy-link');
  await page.waitForFunction(() => document.body.dataset.link);
  const link = await page.evaluate(() => document.body.dataset.link);
  const other = await open(browser);
  await other.page.goto(link);
  await other.page.waitForSelector('body[data-ready="true"]');
  await other.page.waitForSelector('body[data-workspace="freeform"]');
  await settle(other.page);
  assert.deepEqual(JSON.parse(await other.page.evaluate(() => window.bezsolid.ff.model_json())), placed);
  assert.equal(await other.page.inputValue('#ff-expr'), 'A | C - B');
  // Removing B drops it from the expression; complement takes A alone.
  await other.page.click('button[aria-label="Remove solid B"]');
  await other.page.waitForFunction(() => document.body.dataset.ffExpression === 'A | B');
  await other.page.selectOption('#ff-op', 'complement');
  await other.page.waitForFunction(() => document.body.dataset.ffExpression === '!A');
  assert.equal(await other.page.locator('#ff-operands li').count(), 1);
  assert.equal(await other.page.isDisabled('button[aria-label="Remove solid A"]'), true);
  await colours(other.page, 'freeform-complement');
  assert.deepEqual(other.errors, []);
  assert.deepEqual(errors, []);
  await other.page.close();
  await page.close();
});
