// The volume editor in a real browser, on the backend under test: a volume preset draws its surface
// in 3D, the cross-section chooser changes the slice in the 2D view, a sphere dragged in 3D edits the
// volume (one undo step), and the mesh exports parse back with the mesh's triangle count.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { launch, open, settle, ARTIFACTS, pick } from './harness.mjs';
import { surfaceTones } from './png.mjs';
import { createRequire } from 'node:module';

// The Khronos glTF validator (npm gltf-validator, in the tests' lockfile).
const validator = createRequire(import.meta.url)('gltf-validator');

let browser;
before(async () => { browser = await launch(); });
after(async () => { await browser?.close(); });

const model = (page) => page.evaluate(() => window.bezsolid.modeler.model_json());

async function openFish(page) {
  await pick(page, 'preset', 'fish');
  await page.waitForSelector('body[data-kind="volume"]');
  await settle(page);
}

test('a volume preset draws its surface, and the cross-section chooser changes the 2D slice', async () => {
  const { page, errors } = await open(browser);
  await openFish(page);
  assert.match(await page.textContent('#model-name'), /Volume solid, 7 × 5 × 3 points/);
  // The fine surface comes from the worker (a coarse one is drawn meanwhile).
  await page.waitForFunction(() => JSON.parse(window.bezsolid.modeler.panel()).surface?.[1] === 64, null, { timeout: 30_000 });
  await settle(page);
  assert.match(await page.textContent('#surface-info'), /triangles at 64/);
  const shot = await page.locator('#view3d').screenshot();
  writeFileSync(join(ARTIFACTS, 'volume-3d.png'), shot);
  // The surface is drawn in its warm colour, shaded (more than a few tones of it).
  const tones = surfaceTones(shot);
  assert.ok(tones > 40, `the shaded surface is drawn (${tones} tones)`);
  assert.match(await page.textContent('#surface-info'), /Surface: [\d,]+ triangles/);

  const middle = await page.locator('#view').screenshot();
  await page.fill('#slice-index', '0');
  await page.dispatchEvent('#slice-index', 'input');
  await settle(page);
  assert.match(await page.textContent('#slice-info'), /w slice 0 of 0…2/);
  const bottom = await page.locator('#view').screenshot();
  assert.ok(!middle.equals(bottom), 'another slice, another picture');
  await page.check('input[name="slice-axis"][value="0"]');
  await settle(page);
  assert.match(await page.textContent('#slice-info'), /u slice 3 of 0…6: 5 × 3 points/);
  const across = await page.locator('#view').screenshot();
  writeFileSync(join(ARTIFACTS, 'volume-slice-u.png'), across);
  assert.ok(!across.equals(bottom));
  assert.equal(await page.isDisabled('#undo'), false, 'opening the preset is the one step');
  assert.deepEqual(errors, []);
  await page.close();
});

test('dragging a sphere of the volume in 3D changes its ξ and the surface; undo restores it', async () => {
  const { page, errors } = await open(browser);
  await pick(page, 'preset', 'blob');
  await page.waitForSelector('body[data-kind="volume"]');
  const fine = () => page.waitForFunction(() => JSON.parse(window.bezsolid.modeler.panel()).surface?.[1] === 64, null, { timeout: 30_000 });
  await fine();
  const before = JSON.parse(await model(page));
  const triangles = await page.evaluate(() => JSON.parse(window.bezsolid.modeler.panel()).surface[0]);
  // The centre point of the blob (ξ = 1), index (1·3 + 1)·3 + 1 = 13.
  const box = await page.locator('#view3d').boundingBox();
  const [x, y] = await page.evaluate(() => [...window.bezsolid.modeler.sphere_screen_3d(13)]);
  await page.mouse.move(box.x + x, box.y + y);
  await page.mouse.down();
  await page.mouse.move(box.x + x, box.y + y + 90, { steps: 6 });
  await page.mouse.up();
  await settle(page);
  const after = JSON.parse(await model(page));
  assert.ok(after.solid.points[13][3] < before.solid.points[13][3] - 0.5, `ξ fell: ${after.solid.points[13][3]}`);
  assert.deepEqual(after.solid.points[13].slice(0, 3), before.solid.points[13].slice(0, 3));
  // The edited model's fine surface replaces the coarse one drawn during the drag; a lower centre
  // gives a smaller blob, so fewer triangles at the same resolution.
  await fine();
  const changed = await page.evaluate(() => JSON.parse(window.bezsolid.modeler.panel()).surface[0]);
  assert.ok(changed < triangles, `the surface was meshed again, smaller: ${triangles} → ${changed}`);
  await page.keyboard.press('Control+z');
  await settle(page);
  assert.deepEqual(JSON.parse(await model(page)), before);

  // A new flat volume, then one more point along w (elevation keeps the solid).
  await page.fill('#grid-u', '3');
  await page.fill('#grid-v', '3');
  await page.fill('#grid-w', '3');
  await page.click('#new-volume');
  await settle(page);
  assert.match(await page.textContent('#model-name'), /Volume solid, 3 × 3 × 3 points/);
  await page.click('#elevate-w');
  await settle(page);
  assert.match(await page.textContent('#model-name'), /Volume solid, 3 × 3 × 4 points/);
  // A new volume is a ball in the middle of its box: outside at the corners (elevation keeps them),
  // inside in the middle.
  const elevated = JSON.parse(await model(page)).solid.points;
  assert.equal(elevated[0][3], -0.5);
  assert.equal(elevated.at(-1)[3], -0.5);
  assert.ok(Math.max(...elevated.map((p) => p[3])) > 0.25);
  await page.click('#undo');
  await page.click('#undo');
  await settle(page);
  assert.deepEqual(JSON.parse(await model(page)), before);
  assert.deepEqual(errors, []);
  await page.close();
});

/** Chooses an export and returns the downloaded bytes. */
async function exported(page, kind) {
  const [download] = await Promise.all([page.waitForEvent('download'), pick(page, 'export', kind)]);
  const path = join(ARTIFACTS, `export-${download.suggestedFilename()}`);
  await download.saveAs(path);
  return readFileSync(path);
}

test('STL, OBJ, PLY, GLB and 3MF exports of a volume parse back with the mesh triangle count; links carry volumes', async () => {
  const { page, errors } = await open(browser);
  await openFish(page);
  await page.fill('#resolution', '40');
  await page.dispatchEvent('#resolution', 'change');
  // The triangles of the surface at that resolution, from the tools' module on the page.
  const count = await page.evaluate(async () => {
    const { modeler } = window.bezsolid;
    const stl = (await window.bezsolid.tools()).headless_mesh(modeler.model_json(), 'stl', modeler.resolution());
    return (stl.length - 84) / 50;
  });
  assert.ok(count > 100);
  const stl = await exported(page, 'stl');
  assert.equal(stl.readUInt32LE(80), count, 'STL triangle count');
  assert.equal(stl.length, 84 + 50 * count);
  for (let t = 0; t < count; t += 97) {
    for (let k = 0; k < 12; k++) assert.ok(Number.isFinite(stl.readFloatLE(84 + 50 * t + 4 * k)));
  }
  const obj = (await exported(page, 'obj')).toString();
  const faces = obj.split('\n').filter((l) => l.startsWith('f '));
  const verts = obj.split('\n').filter((l) => l.startsWith('v '));
  assert.equal(faces.length, count);
  assert.ok(faces.every((f) => f.trim().split(/\s+/).slice(1).every((i) => {
    const n = Number(i.split('/')[0]);
    return n >= 1 && n <= verts.length;
  })));
  const ply = await exported(page, 'ply');
  const header = ply.subarray(0, ply.indexOf('end_header') + 11).toString();
  assert.match(header, new RegExp(`element face ${count}\\b`));
  // GLB for viewers: the Khronos validator finds no error, the triangles are the mesh's.
  const glb = await exported(page, 'glb');
  const report = await validator.validateBytes(new Uint8Array(glb), { uri: 'bezsolid.glb', format: 'glb' });
  assert.equal(report.issues.numErrors, 0, JSON.stringify(report.issues.messages));
  assert.equal(report.info.totalTriangleCount, count);
  // 3MF for slicers: an OPC zip whose model part is there.
  const threeMf = await exported(page, '3mf');
  assert.equal(threeMf.toString('latin1', 0, 2), 'PK');
  assert.ok(threeMf.includes(Buffer.from('3D/3dmodel.model')));
  // The volume's link opens the same volume in a new page.
  await page.click('#copy-link');
  await page.waitForFunction(() => document.querySelector('#share-url').value.includes('#v1.'));
  const link = await page.inputValue('#share-url');
  const original = await model(page);
  const other = await browser.newPage();
  await other.goto(link);
  await other.waitForSelector('body[data-ready="true"]');
  assert.equal(await other.evaluate(() => window.bezsolid.modeler.model_json()), original);
  assert.equal(await other.getAttribute('body', 'data-kind'), 'volume');
  await other.close();
  assert.deepEqual(errors, []);
  await page.close();
});

test('the true section of a volume: f on a plane, live as the plane moves and as a point is edited, by the keyboard', async () => {
  const { page, errors } = await open(browser);
  await openFish(page);
  const frame = async () => JSON.parse(await page.evaluate(() => window.bezsolid.modeler.panel())).frame;
  assert.equal((await frame()).section, null);
  // A point of the middle slice selected first (Tab in the 2D view), to edit with the section on.
  await page.focus('#view');
  await page.keyboard.press('Tab');
  await settle(page);
  assert.ok(await page.getAttribute('body', 'data-selected'), 'a point is selected');
  // Switched on from the keyboard: the plane z = 0 across w (the fish is −0.5 … 0.5 in z).
  await page.focus('#section-on');
  await page.keyboard.press('Space');
  await settle(page);
  let f = await frame();
  assert.ok(f.section, 'a section is drawn');
  const [axis, at, area] = f.section;
  assert.equal(axis, 2);
  assert.ok(Math.abs(at) < 1e-9, `z = ${at}`);
  assert.ok(area > 0.5 && f.contours >= 1, `the fish's middle section: area ${area}, ${f.contours} pieces`);
  assert.match(await page.textContent('#contour-info'), /True section z = 0: area/);
  writeFileSync(join(ARTIFACTS, 'section-z0.png'), await page.locator('#view').screenshot());
  // f under the pointer is the volume's on the plane: inside at the middle of the body.
  const inside = await page.evaluate(() => {
    const c = document.getElementById('view').getBoundingClientRect();
    for (let y = c.height * 0.3; y < c.height * 0.7; y += 4) {
      for (let x = c.width * 0.2; x < c.width * 0.8; x += 4) {
        const [, , value] = window.bezsolid.modeler.probe(x, y);
        if (value > 0) return true;
      }
    }
    return false;
  });
  assert.ok(inside, 'a point inside the section');
  // The selected point's ξ raised in the panel: the section follows at once.
  await page.fill('#xi', '6');
  await page.keyboard.press('Enter');
  await settle(page);
  const grown = (await frame()).section[2];
  assert.ok(grown > area, `area ${grown} after raising ξ, ${area} before`);
  await page.click('#undo');
  await settle(page);
  assert.ok(Math.abs((await frame()).section[2] - area) < 1e-9, 'undo gives the section back');
  // The plane moved up by the keyboard: the section shrinks towards the top of the body.
  await page.focus('#section-at');
  for (let k = 0; k < 30; k++) await page.keyboard.press('ArrowRight');
  await settle(page);
  f = await frame();
  assert.ok(f.section[1] > 0.25, `z = ${f.section[1]}`);
  assert.ok(f.section[2] < area, `area ${f.section[2]} above ${area}`);
  writeFileSync(join(ARTIFACTS, 'section-z03.png'), await page.locator('#view').screenshot());
  // Clicks in the view do not pick the slice's hidden points.
  const box = await page.locator('#view').boundingBox();
  const before = await page.evaluate(() => window.bezsolid.modeler.revision());
  await page.mouse.click(box.x + box.width / 2, box.y + box.height / 2);
  assert.equal(await page.evaluate(() => window.bezsolid.modeler.revision()), before);
  // Off again: the slice and its points come back.
  await page.focus('#section-on');
  await page.keyboard.press('Space');
  await settle(page);
  assert.equal((await frame()).section, null);
  assert.deepEqual(errors, []);
  await page.close();
});

test('a section across the parameters: f at the points of the plane w = t, over the parameter square', async () => {
  const { page, errors } = await open(browser);
  await openFish(page);
  const frame = async () => JSON.parse(await page.evaluate(() => window.bezsolid.modeler.panel())).frame;
  assert.ok(await page.isDisabled('#section-params'), 'offered with the section only');
  await page.check('#section-on');
  await settle(page);
  const space = (await frame()).section;
  assert.equal(space[3], 0);
  // Across the parameters, by the keyboard.
  await page.focus('#section-params');
  await page.keyboard.press('Space');
  await settle(page);
  let f = await frame();
  const [axis, t, part, across] = f.section;
  assert.deepEqual([axis, t, across], [2, 0.5, 1]);
  assert.ok(part > 0.05 && part < 1 && f.contours >= 1, `${part} of the square inside, ${f.contours} pieces`);
  assert.match(await page.textContent('#contour-info'), /Section across the parameters w = 0\.50*: [\d.]+ % of the parameter square inside/);
  assert.match(await page.textContent('#section-info'), /^w = 0\.50*$/);
  // No cut in 3D: the plane is not one in space.
  assert.ok(await page.isDisabled('#section-cap'));
  assert.equal(JSON.parse(await page.evaluate(() => window.bezsolid.modeler.panel())).cap, null);
  writeFileSync(join(ARTIFACTS, 'section-params-fish.png'), await page.locator('#view').screenshot());
  // A space-mapped volume of the zoo: the vase's wall across its height, f through the inverse map.
  await pick(page, 'preset', 'vase');
  await page.waitForSelector('body[data-kind="volume"]');
  await settle(page);
  f = await frame();
  assert.ok(f.section && f.section[3] === 1, 'still across the parameters');
  assert.ok(f.contours >= 1, `${f.contours} pieces`);
  writeFileSync(join(ARTIFACTS, 'section-params-vase.png'), await page.locator('#view').screenshot());
  // Back across space.
  await page.uncheck('#section-params');
  await settle(page);
  assert.equal((await frame()).section[3], 0);
  assert.deepEqual(errors, []);
  await page.close();
});

test('the 3D surface cut at the section plane: the solid below it, its cut face closed, following the plane', async () => {
  const { page, errors } = await open(browser);
  await openFish(page);
  const panel = async () => JSON.parse(await page.evaluate(() => window.bezsolid.modeler.panel()));
  // The fine surface of the model as it is, at 64.
  const fine = () => page.waitForFunction(() => {
    const p = JSON.parse(window.bezsolid.modeler.panel());
    return p.surface_current && p.surface?.[1] === 64;
  });
  await fine();
  const whole = (await panel()).surface[0];
  const wholeShot = await page.locator('#view3d').screenshot();
  // The cut is offered with the section only; by the keyboard.
  assert.ok(await page.isDisabled('#section-cap'));
  await page.focus('#section-on');
  await page.keyboard.press('Space');
  await settle(page);
  assert.ok(!(await page.isDisabled('#section-cap')));
  await page.focus('#section-cap');
  await page.keyboard.press('Space');
  await page.waitForFunction(() => /triangles at 64, cut at z = 0;/.test(document.getElementById('surface-info').textContent));
  await fine();
  let p = await panel();
  assert.deepEqual(p.cap, [2, 0]);
  const cut = p.surface[0];
  assert.notEqual(cut, whole);
  // What the worker meshes: the fish intersected with the half-space z <= 0.
  const job = JSON.parse(await page.evaluate(() => window.bezsolid.modeler.view_json()));
  assert.equal(job.solid.kind, 'intersection');
  assert.deepEqual(job.solid.of[1], { kind: 'halfspace', normal: [0, 0, 1], offset: 0 });
  assert.match(await page.getAttribute('#view3d', 'aria-label'), /cut at z = 0 \(the solid below the plane, its cut face closed\)/);
  const cutShot = await page.locator('#view3d').screenshot();
  writeFileSync(join(ARTIFACTS, 'section-cut-z0.png'), cutShot);
  assert.ok(!cutShot.equals(wholeShot), 'the cut surface looks otherwise');
  assert.ok(surfaceTones(cutShot) > 20, 'the cut surface is drawn, shaded');
  // The plane moved: a new cut comes, lower in the body.
  await page.focus('#section-at');
  for (let k = 0; k < 20; k++) await page.keyboard.press('ArrowLeft');
  await page.waitForFunction(() => /cut at z = -0\.\d+;/.test(document.getElementById('surface-info').textContent));
  await fine();
  p = await panel();
  assert.ok(p.cap[1] < -0.1, `z = ${p.cap[1]}`);
  assert.ok(p.surface[0] !== cut, 'another cut');
  writeFileSync(join(ARTIFACTS, 'section-cut-low.png'), await page.locator('#view3d').screenshot());
  // The plane's frame dragged up in the 3D view (between the control points on the box's side):
  // the section, its slider and the cut follow; the model is not edited.
  const revision = await page.evaluate(() => window.bezsolid.modeler.revision());
  const [fx, fy] = await page.evaluate(() => window.bezsolid.modeler.section_screen_3d(0, 0.375));
  const view3 = await page.locator('#view3d').boundingBox();
  const low = p.frame.section[1];
  await page.mouse.move(view3.x + fx, view3.y + fy);
  await page.mouse.down();
  for (let k = 1; k <= 8; k++) await page.mouse.move(view3.x + fx, view3.y + fy - 4 * k);
  await page.mouse.up();
  await settle(page);
  p = await panel();
  assert.ok(p.frame.section[1] > low + 0.05, `z = ${p.frame.section[1]} after the drag, ${low} before`);
  assert.ok(Math.abs(p.cap[1] - p.frame.section[1]) < 1e-12, 'the cut is at the plane');
  const fraction = await page.evaluate(() => window.bezsolid.modeler.section_fraction());
  assert.equal(Number(await page.inputValue('#section-at')), Math.round(fraction * 100));
  assert.equal(await page.evaluate(() => window.bezsolid.modeler.revision()), revision);
  await fine();
  writeFileSync(join(ARTIFACTS, 'section-cut-dragged.png'), await page.locator('#view3d').screenshot());
  // Off: the whole surface again.
  await page.focus('#section-cap');
  await page.keyboard.press('Space');
  await page.waitForFunction(() => !/cut at/.test(document.getElementById('surface-info').textContent));
  await fine();
  assert.equal((await panel()).surface[0], whole);
  assert.deepEqual(errors, []);
  await page.close();
});

test('the Bézier zoo: each space-mapped preset opens from the menu and draws its shaded surface', async () => {
  const { page, errors } = await open(browser);
  const zoo = [
    ['chair', '7 × 7 × 7'], ['vase', '7 × 7 × 5'], ['knot', '7 × 7 × 3'],
    ['shell', '7 × 7 × 5'], ['koi', '7 × 5 × 5'], ['tooth', '5 × 3 × 7'],
  ];
  const shots = [];
  for (const [name, points] of zoo) {
    await pick(page, 'preset', name);
    // The panel names the new model on the frame after it opens (the one before was a volume too).
    const named = `Volume solid, ${points} points`;
    await page.waitForFunction((n) => document.getElementById('model-name').textContent.startsWith(n), named)
      .catch(async () => assert.fail(`${name}: the panel says ${await page.textContent('#model-name')}`));
    // The fine surface from the worker, forward from the parameter box (the map is injective).
    await page.waitForFunction(() => JSON.parse(window.bezsolid.modeler.panel()).surface?.[1] === 64, null, { timeout: 30_000 });
    await settle(page);
    const panel = JSON.parse(await page.evaluate(() => window.bezsolid.modeler.panel()));
    assert.ok(panel.space_mapped, `${name} is a space mapping`);
    assert.match(await page.textContent('#surface-info'), /Surface: [\d,]+ triangles at 64/, name);
    const shot = await page.locator('#view3d').screenshot();
    writeFileSync(join(ARTIFACTS, `zoo-${name}.png`), shot);
    const tones = surfaceTones(shot);
    assert.ok(tones > 40, `${name}: the shaded surface is drawn (${tones} tones)`);
    assert.ok(!shots.some((s) => s.equals(shot)), `${name} looks like none before it`);
    shots.push(shot);
  }
  assert.deepEqual(errors, []);
  await page.close();
});
