// A model of many solids built in a real browser by clicks alone, on the backend under test: a
// volume, a sphere, a box and a torus added beside it, a point of the volume dragged in space in the
// 3D view (the volume becomes space-mapped), a blend put around the sphere and its a0 slid, one
// undo; then the model shared by link and opened in a fresh page, and the whole model's surface
// drawn with the selection framed.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { launch, open, settle, canvasBox, screenOf, ARTIFACTS } from './harness.mjs';
import { surfaceTones } from './png.mjs';

let browser;
before(async () => { browser = await launch(); });
after(async () => { await browser?.close(); });

const outline = (page) => page.evaluate(() => JSON.parse(window.bezsolid.modeler.outline() ?? 'null'));
const labels = async (page) => (await outline(page)).rows.map((r) => r.label);
const surfaceAt = (page, resolution) => page.waitForFunction((r) => {
  const p = JSON.parse(window.bezsolid.modeler.panel());
  return p.surface?.[1] === r && p.surface_current;
}, resolution, { timeout: 60_000 });


test('a model of six parts is built by clicks, edited, undone, shared and opened again', async () => {
  const { page, errors } = await open(browser);
  // A volume to start from: one solid, no parts yet.
  await page.click('#new-volume');
  await page.waitForSelector('body[data-kind="volume"]');
  assert.equal(await outline(page), null, 'a model of one solid');
  assert.equal(await page.isVisible('#outline-hint'), true);

  // Parts added beside it join one union; each is selected as it comes.
  await page.click('[data-add="sphere"]');
  await page.click('[data-add="box"]');
  await page.click('[data-add="torus"]');
  await settle(page);
  let o = await outline(page);
  assert.deepEqual(o.rows.map((r) => r.depth), [0, 1, 1, 1, 1]);
  assert.equal(o.rows[0].label, 'Union');
  assert.match(o.rows[1].label, /^Bézier volume 4 × 4 × 3/);
  assert.match(o.rows[2].label, /^Sphere/);
  assert.deepEqual(o.selected, [3]);
  assert.equal(o.open, null, 'a torus is no Bézier part');
  assert.equal(await page.isVisible('#no-part'), true, 'the 2D view says how to edit points');
  assert.equal(await page.locator('#outline-tree [role="treeitem"]').count(), 5);
  assert.match(await page.textContent('#model-name'), /Many solids, 5 nodes/);
  // A second Bézier volume joins them, open in the editors at once.
  await page.click('[data-add="bezier"]');
  await page.waitForSelector('body[data-kind="volume"]');
  o = await outline(page);
  assert.equal(o.rows.length, 6);
  assert.match(o.rows[5].label, /^Bézier volume 4 × 4 × 4/);
  assert.deepEqual(o.open, [4]);
  assert.equal(await page.isVisible('#no-part'), false);

  // The volume opens in the editors; a sphere of it dragged in space in the 3D view.
  await page.click('#outline-tree [data-path="0"]');
  await page.waitForSelector('body[data-kind="volume"]');
  o = await outline(page);
  assert.deepEqual(o.open, [0]);
  assert.equal(await page.isVisible('#no-part'), false);
  await page.check('input[name="mode"][value="space"]');
  await surfaceAt(page, 64);
  const box = await page.locator('#view3d').boundingBox();
  const [x, y] = await page.evaluate(() => [...window.bezsolid.modeler.sphere_screen_3d(47)]);
  await page.mouse.move(box.x + x, box.y + y);
  await page.mouse.down();
  await page.mouse.move(box.x + x + 40, box.y + y + 30, { steps: 6 });
  await page.mouse.up();
  await settle(page);
  assert.equal(JSON.parse(await page.evaluate(() => window.bezsolid.modeler.panel())).space_mapped, true);
  const dragged = await page.evaluate(() => window.bezsolid.modeler.model_json());

  // A blended union around the sphere (with a second, small sphere), its a0 slid in steps: one
  // undo step for the slide.
  await page.click('#outline-tree [data-path="1"]');
  await page.click('[data-wrap="blend_union"]');
  await settle(page);
  o = await outline(page);
  assert.match(o.rows[2].label, /^Blended union a0 = 0.1/);
  assert.equal(o.rows.filter((r) => !r.label.match(/union|Union/)).length, 6, 'six parts');
  const slider = page.locator('[data-slider="a0"]');
  for (const v of ['0.2', '0.3', '0.45']) {
    await slider.fill(v);
    await settle(page);
  }
  assert.match((await labels(page))[2], /a0 = 0.45/);
  await page.click('#undo');
  await settle(page);
  assert.match((await labels(page))[2], /a0 = 0.1$/, 'the slide was one step');
  await page.click('#redo');
  await settle(page);
  assert.match((await labels(page))[2], /a0 = 0.45/);

  // The box moved by its handle in the 3D view: a transform comes around it, and the drag is one
  // undo step; then turned about its centre by the turn handle.
  await page.click('#outline-tree [data-path="2"]');
  await settle(page);
  assert.match((await labels(page))[5], /^Box/);
  const handle = async (which) => page.evaluate((k) => [...(window.bezsolid.modeler.handle_screen_3d(k) ?? [])], which);
  const dragBy = async ([hx, hy], dx, dy) => {
    await page.mouse.move(box.x + hx, box.y + hy);
    await page.mouse.down();
    await page.mouse.move(box.x + hx + dx, box.y + hy + dy, { steps: 5 });
    await page.mouse.up();
    await settle(page);
  };
  await dragBy(await handle(0), 50, -20);
  o = await outline(page);
  assert.equal(o.rows[5].label, 'Transform');
  assert.match(o.rows[6].label, /^Box/);
  const moved = o.fields.find((f) => f.name === 'translate[0]').value ** 2 + o.fields.find((f) => f.name === 'translate[2]').value ** 2;
  assert.ok(moved > 1e-4, 'the drag moved the box');
  await page.click('#undo');
  await settle(page);
  assert.match((await labels(page))[5], /^Box/, 'one undo step took the move and its transform');
  await page.click('#redo');
  await settle(page);
  await page.click('#fit-3d');
  await settle(page);
  const turn = await handle(1);
  assert.ok(turn[0] > 0 && turn[0] < box.width && turn[1] > 0 && turn[1] < box.height, `the turn handle is in sight at ${turn}`);
  await dragBy(turn, 60, 0);
  o = await outline(page);
  assert.ok(Math.abs(o.fields.find((f) => f.name === 'rotate[2]').value - 30) < 1e-9, `half a degree a pixel: ${JSON.stringify(o.fields)} ${JSON.stringify(o.selected)} ${await handle(1)} ${await handle(0)}`);

  // The volume named: a part around it, still open in the editors.
  await page.click('#outline-tree [data-path="0"]');
  await page.fill('#part-name', 'body');
  await page.press('#part-name', 'Enter');
  await settle(page);
  o = await outline(page);
  assert.equal(o.rows[1].label, '“body”');
  assert.match(o.rows[2].label, /^Bézier volume/);
  assert.deepEqual(o.open, [0, 0]);

  // The whole model's surface, the volume's points placed in it; the selection framed.
  await surfaceAt(page, 64);
  await settle(page);
  const shot = await page.locator('#view3d').screenshot();
  writeFileSync(join(ARTIFACTS, 'parts-3d.png'), shot);
  writeFileSync(join(ARTIFACTS, 'parts-page.png'), await page.screenshot());
  assert.ok(surfaceTones(shot) > 40, 'the shaded surface of the whole model is drawn');

  // Shared by link, opened in a fresh page: the same model.
  const model = await page.evaluate(() => window.bezsolid.modeler.model_json());
  assert.notEqual(model, dragged);
  await page.click('#copy-link');
  await page.waitForFunction(() => document.getElementById('share-url').value.includes('#v1.'));
  const link = await page.inputValue('#share-url');
  const fresh = await open(browser, link.slice(link.indexOf('#')));
  await settle(fresh.page);
  assert.equal(await fresh.page.evaluate(() => window.bezsolid.modeler.model_json()), model);
  assert.equal(await fresh.page.locator('#outline-tree [role="treeitem"]').count(), 10);
  assert.match(await fresh.page.textContent('#outline-tree [data-path="0"]'), /“body”$/);
  // The tree folds and opens by keys: ← on the root folds it away, → opens it again.
  await fresh.page.click('#outline-tree [data-path=""]');
  await settle(fresh.page);
  await fresh.page.focus('#outline-tree [aria-selected="true"]');
  await fresh.page.keyboard.press('ArrowLeft');
  assert.equal(await fresh.page.locator('#outline-tree [role="treeitem"]').count(), 1);
  assert.equal(await fresh.page.getAttribute('#outline-tree [data-path=""]', 'aria-expanded'), 'false');
  await fresh.page.keyboard.press('ArrowRight');
  assert.equal(await fresh.page.locator('#outline-tree [role="treeitem"]').count(), 10);
  await surfaceAt(fresh.page, 64);
  await settle(fresh.page);
  assert.ok(surfaceTones(await fresh.page.locator('#view3d').screenshot()) > 40);
  assert.deepEqual(fresh.errors, []);
  await fresh.page.close();
  assert.deepEqual(errors, []);
  await page.close();
});

test('a bad value is refused with a message and the model stays; keys move through the parts', async () => {
  const { page, errors } = await open(browser);
  await page.click('#new-volume');
  await page.click('[data-add="sphere"]');
  await settle(page);
  const before = await page.evaluate(() => window.bezsolid.modeler.model_json());
  const radius = page.locator('[data-field="radius"]');
  await radius.fill('0');
  await radius.dispatchEvent('change');
  await settle(page);
  assert.match(await page.textContent('#status'), /radius/);
  assert.equal(await radius.getAttribute('aria-invalid'), 'true');
  assert.equal(await page.evaluate(() => window.bezsolid.modeler.model_json()), before);
  // Hidden by H in the tree: left out of what the views show, kept in the model; H shows it.
  await page.focus('#outline-tree [aria-selected="true"]');
  await page.keyboard.press('h');
  await settle(page);
  assert.match((await labels(page))[2], /^Unnamed part \(hidden\)$/);
  assert.equal(await page.getAttribute('#part-hide', 'aria-pressed'), 'true');
  const file = JSON.parse(await page.evaluate(() => window.bezsolid.modeler.model_json()));
  assert.equal(file.solid.of[1].kind, 'part');
  assert.equal(file.solid.of[1].hidden, true);
  const shown = JSON.parse(await page.evaluate(() => window.bezsolid.modeler.view_json()));
  assert.equal(shown.solid.kind, 'volume', 'the views show the volume alone');
  await page.keyboard.press('h');
  await settle(page);
  assert.match((await labels(page))[2], /^Sphere/, `shown again, the nameless part is gone: ${await labels(page)}`);

  // The tree by keyboard: ↑ selects the volume, Delete on the root is refused, Delete on the
  // sphere removes it (a union of one is its part).
  await page.focus('#outline-tree [aria-selected="true"]');
  await page.keyboard.press('ArrowUp');
  await settle(page);
  assert.deepEqual((await outline(page)).open, [0]);
  await page.keyboard.press('ArrowDown');
  await settle(page);
  await page.keyboard.press('Delete');
  await settle(page);
  const o = await outline(page);
  assert.equal(o.rows.length, 1);
  assert.match(o.rows[0].label, /^Bézier volume/);
  assert.deepEqual(errors, []);
  await page.close();
});

test('a 2D model of many solids: the 2D view draws the whole field and contour; it autosaves', async () => {
  const { page, errors } = await open(browser);
  const patch = JSON.parse(await page.evaluate(() => { window.bezsolid.modeler.load_preset('fig9'); return window.bezsolid.modeler.model_json(); })).solid;
  const model = JSON.stringify({
    format: 'bezsolid',
    version: 1,
    solid: {
      kind: 'union',
      of: [
        { kind: 'circle', center: [-1, 0.5], radius: 0.3 },
        { kind: 'part', name: 'paper', solid: patch },
        { kind: 'circle', center: [2, 0.5], radius: 0.3 },
      ],
    },
  });
  await page.evaluate((m) => { window.bezsolid.modeler.load_model(m); window.bezsolid.redraw(); }, model);
  await settle(page);
  await settle(page);
  const o = await outline(page);
  assert.equal(o.dimension, 2);
  assert.deepEqual(o.open, [1, 0], 'the patch opens in the editors');
  const panel = JSON.parse(await page.evaluate(() => window.bezsolid.modeler.panel()));
  assert.equal(panel.frame.contours, 3, 'two discs and the patch solid');
  // f under the pointer is the whole model's: inside the left disc.
  const view = await page.locator('#view').boundingBox();
  const inside = await page.evaluate(({ w, h }) => {
    for (let y = 0; y < h; y += 4) {
      for (let x = 0; x < w / 4; x += 4) {
        const [px, py, f] = window.bezsolid.modeler.probe(x, y);
        if (Math.hypot(px + 1, py - 0.5) < 0.1) return f;
      }
    }
    return null;
  }, { w: view.width, h: view.height });
  assert.ok(inside > 0, `inside the left disc f = ${inside}`);
  writeFileSync(join(ARTIFACTS, 'parts-2d.png'), await page.screenshot());
  // Autosaved, and restored as it was in a fresh page.
  await page.evaluate(() => window.bezsolid.saveNow());
  await page.reload();
  await page.waitForSelector('body[data-ready="true"]');
  assert.equal((await outline(page)).rows.length, 5);
  assert.equal(await page.isVisible('#no-part-3d'), false, 'the patch is open: the 3D view shows it');
  assert.deepEqual(errors, []);
  await page.close();
});

/** A piecewise net of `cells` cells of `degree` over the unit box scaled by `size`, ξ from `xi`. */
function piecewise(cells, degree, size, xi) {
  const dims = cells.map((c, a) => c * degree[a] + 1);
  const count = dims.reduce((a, b) => a * b, 1);
  const points = [];
  for (let k = 0; k < count; k++) {
    const at = [];
    let rest = k;
    for (let a = dims.length - 1; a >= 0; a--) {
      at[a] = rest % dims[a];
      rest = Math.floor(rest / dims[a]);
    }
    const t = at.map((i, a) => i / (dims[a] - 1));
    points.push([...t.map((x, a) => x * size[a]), xi(t)]);
  }
  return { kind: 'piecewise', cells, degree, points };
}

test('a piecewise solid opens from a file and a link: one solid in both views, no seam', async () => {
  let { page, errors } = await open(browser);
  // 2 × 2 quadratic cells: ξ positive in a band across every shared edge.
  const solid = piecewise([2, 2], [2, 2], [2, 2], (t) => 0.6 - 4 * ((t[0] - 0.5) ** 2 + (t[1] - 0.5) ** 2));
  const model = JSON.stringify({ format: 'bezsolid', version: 1, solid });
  await page.evaluate((m) => { window.bezsolid.modeler.load_model(m); window.bezsolid.redraw(); }, model);
  await settle(page);
  await settle(page);
  const o = await outline(page);
  assert.equal(o.dimension, 2);
  assert.match(o.rows[0].label, /^Piecewise patch: 2 × 2 cells of degree 2 × 2/);
  const panel = JSON.parse(await page.evaluate(() => window.bezsolid.modeler.panel()));
  assert.equal(panel.frame.contours, 1, 'one solid across the four cells');
  // f at the middle, where the four cells meet: inside, not clipped by any cell.
  const view = await page.locator('#view').boundingBox();
  const middle = await page.evaluate(({ w, h }) => {
    let best = null;
    for (let y = 0; y < h; y += 3) {
      for (let x = 0; x < w; x += 3) {
        const [px, py, f] = window.bezsolid.modeler.probe(x, y);
        const d = Math.hypot(px - 1, py - 1);
        if (best === null || d < best.d) best = { d, f };
      }
    }
    return best;
  }, { w: view.width, h: view.height });
  assert.ok(middle.d < 0.05 && middle.f > 0.1, `f at the shared corner: ${JSON.stringify(middle)}`);
  writeFileSync(join(ARTIFACTS, 'piecewise-2d.png'), await page.screenshot());

  // A piecewise volume by link: its whole surface drawn in the 3D view.
  const volume = piecewise([2, 1, 1], [2, 2, 2], [2, 1, 1], (t) => 1 - 3 * ((t[0] - 0.5) ** 2) - 2 * ((t[1] - 0.5) ** 2 + (t[2] - 0.5) ** 2));
  await page.evaluate((m) => window.bezsolid.modeler.load_model(m), JSON.stringify({ format: 'bezsolid', version: 1, solid: volume }));
  const link = await page.evaluate(() => window.bezsolid.modeler.link());
  assert.match(link, /^#v1\./);
  assert.deepEqual(errors, []);
  await page.close();
  ({ page, errors } = await open(browser, link));
  await settle(page);
  const o3 = await outline(page);
  assert.equal(o3.dimension, 3);
  assert.match(o3.rows[0].label, /^Piecewise volume: 2 × 1 × 1 cells/);
  await page.waitForFunction(() => {
    const p = JSON.parse(window.bezsolid.modeler.panel());
    return p.surface_current && p.surface?.[1] === 64;
  }, null, { timeout: 60_000 });
  const [triangles] = JSON.parse(await page.evaluate(() => window.bezsolid.modeler.panel())).surface;
  assert.ok(triangles > 1000, `the whole surface across both cells: ${triangles} triangles`);
  const shot = await page.locator('#view3d').screenshot();
  writeFileSync(join(ARTIFACTS, 'piecewise-3d.png'), shot);
  assert.ok(surfaceTones(shot) > 20, 'the surface is drawn, shaded');
  assert.deepEqual(errors, []);
  await page.close();
});

test('a piecewise net is edited like one net: a shared point moves every cell, cells are added and removed', async () => {
  const { page, errors } = await open(browser);
  const panel = async () => JSON.parse(await page.evaluate(() => window.bezsolid.modeler.panel()));
  const model = async () => JSON.parse(await page.evaluate(() => window.bezsolid.modeler.model_json())).solid;
  /** f at world point (x, y) of the 2D view. */
  const fAt = async (x, y) => {
    const box = await canvasBox(page);
    const [sx, sy] = await screenOf(page, x, y);
    return page.evaluate(([a, b]) => window.bezsolid.modeler.probe(a, b)[2], [sx - box.x, sy - box.y]);
  };
  // Two quadratic cells side by side over [0, 2] × [0, 1]: one net of 5 × 3 points.
  const solid = piecewise([2, 1], [2, 2], [2, 1], (t) => 0.5 - 2 * (t[0] - 0.5) ** 2 - 3 * (t[1] - 0.5) ** 2);
  await page.evaluate((m) => { window.bezsolid.modeler.load_model(m); window.bezsolid.redraw(); }, JSON.stringify({ format: 'bezsolid', version: 1, solid }));
  await settle(page);
  await settle(page);
  assert.deepEqual((await outline(page)).open, [], 'the piecewise part is open in the editor');
  let p = await panel();
  assert.deepEqual(p.cells, { count: [2, 1], degree: [2, 2] });
  assert.deepEqual(p.degree, [4, 2], 'the 2D view edits the global net');
  assert.match(await page.textContent('#model-info'), /Piecewise patch: 2 × 1 cells of degree 2 × 2, one net of 5 × 3 points/);

  // The point in the middle of the edge x = 1 the cells share, dragged in space: f changes on
  // both sides of the edge, the file keeps one net with the point moved once.
  const left0 = await fAt(0.85, 0.5);
  const right0 = await fAt(1.15, 0.5);
  await page.check('input[name="mode"][value="space"]');
  const from = await screenOf(page, 1, 0.5);
  const to = await screenOf(page, 1.25, 0.62);
  await page.mouse.move(...from);
  await page.mouse.down();
  await page.mouse.move(...to, { steps: 8 });
  await page.mouse.up();
  await settle(page);
  const moved = await model();
  assert.equal(moved.kind, 'piecewise');
  assert.deepEqual(moved.cells, [2, 1]);
  const shared = moved.points[2 * 3 + 1];
  assert.ok(Math.abs(shared[0] - 1.25) < 0.03 && Math.abs(shared[1] - 0.62) < 0.03, `the shared point: ${shared}`);
  assert.deepEqual(moved.points.filter((q, k) => k !== 7), solid.points.filter((q, k) => k !== 7), 'no other point moved');
  const [left1, right1] = [await fAt(0.85, 0.5), await fAt(1.15, 0.5)];
  assert.ok(Math.abs(left1 - left0) > 1e-3 && Math.abs(right1 - right0) > 1e-3, `both cells follow: ${left0} → ${left1}, ${right0} → ${right1}`);
  assert.equal((await panel()).space_mapped, true);
  // S_ξ = 0 unclipped beside the solid, across the cells; off the net's image the field is full blue.
  await page.check('#unclipped');
  await settle(page);
  assert.ok((await panel()).frame.unclipped >= 1, 'the unclipped curve is drawn');
  writeFileSync(join(ARTIFACTS, 'piecewise-edit-2d.png'), await page.screenshot());
  await page.uncheck('#unclipped');
  await page.click('#undo');
  await settle(page);
  assert.deepEqual((await model()).points, solid.points, 'one undo step for the drag');

  // Cells by the keyboard: a cell added along u, then removed; none to remove along v; no w.
  assert.equal(await page.isDisabled('#cell-remove-v'), true);
  assert.equal(await page.isDisabled('#cell-add-w'), true, 'a patch has no w');
  await page.focus('#cell-add-u');
  await page.keyboard.press('Enter');
  await settle(page);
  p = await panel();
  assert.deepEqual(p.cells.count, [3, 1]);
  assert.deepEqual(p.degree, [6, 2]);
  assert.match(await page.textContent('#model-info'), /3 × 1 cells/);
  assert.match(await page.textContent('#status'), /Added a cell along u/);
  // The new cell mirrors the last across x = 2: points 2·P₄ − P₃ and 2·P₄ − P₂ in the plane, ξ mirrored.
  const grown = (await model()).points;
  assert.equal(grown.length, 7 * 3);
  for (let j = 0; j < 3; j++) {
    for (const [i, mirror] of [[5, 3], [6, 2]]) {
      const [q, b, m] = [grown[i * 3 + j], grown[4 * 3 + j], grown[mirror * 3 + j]];
      assert.ok(Math.abs(q[0] - (2 * b[0] - m[0])) < 1e-12 && Math.abs(q[1] - (2 * b[1] - m[1])) < 1e-12 && q[2] === m[2], `P${i}${j} = ${q}`);
    }
  }
  await page.focus('#cell-remove-u');
  await page.keyboard.press('Enter');
  await settle(page);
  assert.deepEqual((await model()).points, solid.points, 'the cell removed: the net as it was');

  // A single volume becomes piecewise with a cell along w; a point of the face the cells share
  // dragged in the 3D view moves in both cells; the whole surface is drawn.
  await page.click('#new-volume');
  await page.waitForSelector('body[data-kind="volume"]');
  await page.click('#cell-add-w');
  await settle(page);
  const o = await outline(page);
  assert.match(o.rows[0].label, /^Piecewise volume: 1 × 1 × 2 cells of degree 3 × 3 × 2/);
  p = await panel();
  assert.deepEqual(p.volume_degree, [3, 3, 4]);
  const before = await model();
  // Point (1, 1, 2) of the 4 × 4 × 5 net: on the face w = 1/2.
  const index = (1 * 4 + 1) * 5 + 2;
  const box = await page.locator('#view3d').boundingBox();
  const [x, y] = await page.evaluate((k) => [...window.bezsolid.modeler.sphere_screen_3d(k)], index);
  await page.mouse.move(box.x + x, box.y + y);
  await page.mouse.down();
  await page.mouse.move(box.x + x + 30, box.y + y - 25, { steps: 6 });
  await page.mouse.up();
  await settle(page);
  const after = await model();
  assert.equal(after.kind, 'piecewise');
  const changed = after.points.flatMap((q, k) => (JSON.stringify(q) === JSON.stringify(before.points[k]) ? [] : [k]));
  assert.deepEqual(changed, [index], 'the one shared point moved');
  await surfaceAt(page, 64);
  const [triangles] = (await panel()).surface;
  assert.ok(triangles > 1000, `the whole surface: ${triangles} triangles`);
  const shot = await page.locator('#view3d').screenshot();
  writeFileSync(join(ARTIFACTS, 'piecewise-edit-3d.png'), shot);
  assert.ok(surfaceTones(shot) > 20, 'the surface is drawn, shaded');
  assert.deepEqual(errors, []);
  await page.close();
});

test('a model of many solids: the true section and the 3D cut are of the whole model', async () => {
  const { page, errors } = await open(browser);
  const panel = async () => JSON.parse(await page.evaluate(() => window.bezsolid.modeler.panel()));
  // A volume (a ball in [0, 1]³) and a sphere beside it; the volume open in the editors.
  await page.click('#new-volume');
  await page.waitForSelector('body[data-kind="volume"]');
  await page.click('[data-add="sphere"]');
  await page.click('#outline-tree [data-path="0"]');
  await page.waitForSelector('body[data-kind="volume"]');
  const sphere = JSON.parse(await page.evaluate(() => window.bezsolid.modeler.model_json())).solid.of[1];
  assert.equal(sphere.kind, 'sphere');
  await surfaceAt(page, 64);
  const whole = (await panel()).surface[0];
  // The section by the keyboard: across z in the whole model's box, through the sphere too.
  await page.focus('#section-on');
  await page.keyboard.press('Space');
  await settle(page);
  let p = await panel();
  const at = p.frame.section[1];
  assert.equal(p.frame.section[0], 2);
  assert.ok(Math.abs(at - sphere.center[2]) < sphere.radius, `z = ${at} cuts the sphere`);
  const box = await canvasBox(page);
  const [sx, sy] = await screenOf(page, sphere.center[0] + 0.3 * sphere.radius, sphere.center[1]);
  const [, , f] = await page.evaluate(([a, b]) => [...window.bezsolid.modeler.probe(a, b)], [sx - box.x, sy - box.y]);
  assert.ok(f > 0, `inside the sphere on the section: f = ${f}`);
  assert.match(await page.getAttribute('#view', 'aria-label'), /whole model's true section by the plane z = /);
  // The cut: the worker meshes the whole model intersected with the half-space below the plane.
  await page.focus('#section-cap');
  await page.keyboard.press('Space');
  await page.waitForFunction(() => /Surface of the whole model: [\d,]+ triangles at 64, cut at z = /.test(document.getElementById('surface-info').textContent));
  await surfaceAt(page, 64);
  p = await panel();
  assert.deepEqual(p.cap, [2, at]);
  assert.notEqual(p.surface[0], whole);
  const job = JSON.parse(await page.evaluate(() => window.bezsolid.modeler.view_json()));
  assert.equal(job.solid.kind, 'intersection');
  assert.equal(job.solid.of[0].kind, 'union');
  assert.deepEqual(job.solid.of[1], { kind: 'halfspace', normal: [0, 0, 1], offset: at });
  const shot = await page.locator('#view3d').screenshot();
  writeFileSync(join(ARTIFACTS, 'parts-section-cut.png'), shot);
  assert.ok(surfaceTones(shot) > 20, 'the cut surface is drawn, shaded');
  writeFileSync(join(ARTIFACTS, 'parts-section-2d.png'), await page.locator('#view').screenshot());
  // Off: the whole surface again.
  await page.focus('#section-cap');
  await page.keyboard.press('Space');
  await page.waitForFunction(() => !/cut at/.test(document.getElementById('surface-info').textContent));
  await surfaceAt(page, 64);
  assert.equal((await panel()).surface[0], whole);
  assert.deepEqual(errors, []);
  await page.close();
});

test('an edit of one part meshes the whole model again only near that part; the panel says how much was kept', async () => {
  const { page, errors } = await open(browser);
  await page.click('#new-volume');
  await page.waitForSelector('body[data-kind="volume"]');
  await page.click('[data-add="sphere"]');
  await settle(page);
  await page.click('#outline-tree [data-path="0"]');
  await page.waitForSelector('body[data-kind="volume"]');
  await surfaceAt(page, 64);
  const before = await page.evaluate(() => window.bezsolid.modeler.model_json());
  // A point of the volume raised by the keyboard: the workers mesh again the blocks near the
  // volume, and keep the sphere's.
  await page.focus('#view');
  await page.keyboard.press('Tab');
  await page.keyboard.press('PageUp');
  await settle(page);
  assert.notEqual(await page.evaluate(() => window.bezsolid.modeler.model_json()), before);
  await surfaceAt(page, 64);
  const [kept, blocks] = (await page.evaluate(() => document.body.dataset.surfaceKept)).split(',').map(Number);
  assert.ok(kept > 0 && kept < blocks, `${kept} of ${blocks} blocks kept`);
  // The panel's text follows the surface on the next drawing of the panel.
  const note = /Surface of the whole model: [\d,]+ triangles at 64; [\d,]+ of its [\d,]+ blocks reused from the workers' previous mesh$/;
  await page.waitForFunction((source) => new RegExp(source).test(document.getElementById('surface-info').textContent), note.source, { timeout: 10_000 })
    .catch(() => {});
  assert.match(await page.textContent('#surface-info'), note);
  writeFileSync(join(ARTIFACTS, 'parts-kept.png'), await page.screenshot());
  assert.deepEqual(errors, []);
  await page.close();
});
