// The Script mode in a real browser, on the backend under test: each of the paper's examples runs
// in the worker and draws its figure (screenshots kept, run times written to script-times.json),
// an error is shown at its line with a way to it, endless work stops within the limits while the
// page stays responsive, a script travels through a link, a model file and the exports, and a
// drawn surface or solid opens in the Bézier mode as its Bézier patch or volume.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { launch, open, settle, ARTIFACTS, pick } from './harness.mjs';
import { decodePng, surfaceTones } from './png.mjs';

let browser;
before(async () => { browser = await launch(); });
after(async () => { await browser?.close(); });

async function scriptMode(page) {
  await page.check('input[name="workspace"][value="script"]');
  await page.waitForSelector('body[data-workspace="script"]');
  await finished(page);
}

/** Waits for the run under way to finish; returns its state (done or error). */
async function finished(page) {
  await page.waitForFunction(() => ['done', 'error', 'stopped'].includes(document.body.dataset.scriptState), null, { timeout: 60_000 });
  await settle(page);
  return page.evaluate(() => document.body.dataset.scriptState);
}

/** Pixels of the 3D view that are not the background, and the screenshot. */
async function drawn(page, name) {
  await settle(page);
  const png = await page.locator('#view3d').screenshot();
  writeFileSync(join(ARTIFACTS, `${name}.png`), png);
  const img = decodePng(png);
  let ink = 0;
  for (let y = 0; y < img.height; y += 2) {
    for (let x = 0; x < img.width; x += 2) {
      const [r, g, b] = img.at(x, y);
      if (Math.abs(r - 244) + Math.abs(g - 245) + Math.abs(b - 247) > 40) ink += 1;
    }
  }
  return { ink, png };
}

async function download(page, value) {
  const [file] = await Promise.all([page.waitForEvent('download'), pick(page, 'export', value)]);
  return readFileSync(await file.path());
}

const counts = (page) => page.evaluate(() => document.body.dataset.scriptCounts.split(',').map(Number));

test("each of the paper's examples runs and draws its figure", async () => {
  const { page, errors } = await open(browser);
  await scriptMode(page);
  // The default script is Fig. 1: the surface and its four curves.
  assert.equal(await page.evaluate(() => document.body.dataset.scriptState), 'done');
  assert.deepEqual(await counts(page), [800, 128, 0]);
  const expected = {
    3.1: [0, 30, 0], 3.3: [0, 20, 0], 4.1: [0, 32, 0], 4.4: [800, 128, 0],
    4.6: [392, 0, 0], 4.7: [392, 0, 0], 4.8: [384, 0, 0], '4.7-bezier-grid': [128, 0, 0],
  };
  const times = {};
  let previous = null;
  for (const [id, want] of Object.entries(expected)) {
    await pick(page, 'script-example', id);
    assert.equal(await finished(page), 'done', `${id}: ${await page.textContent('#script-message')}`);
    assert.deepEqual(await counts(page), want, id);
    times[id] = await page.evaluate(() => ({
      total: Number(document.body.dataset.scriptMs),
      worker: Number(document.body.dataset.scriptWorkerMs),
    }));
    const { ink, png } = await drawn(page, `script-${id}`);
    assert.ok(ink > 300, `${id} draws (${ink} pixels)`);
    assert.ok(!previous || !png.equals(previous), `${id} changes the picture`);
    previous = png;
    // The editor holds the example, and its values are listed.
    assert.match(await page.inputValue('#script'), new RegExp(`% Script ${id.replace('.', '\\.')} `));
    assert.ok((await page.locator('#script-values li').count()) >= 1);
  }
  writeFileSync(join(ARTIFACTS, 'script-times.json'), JSON.stringify(times, null, 2));
  console.log(`script run times in the page, ms (total: from the run to its drawing; worker: the run and drawing in the worker): ${JSON.stringify(times)}`);
  // The paper's damaged text is read and said: Script 4.4's point lists and Bernstein's `~`.
  await pick(page, 'script-example', '4.4');
  await finished(page);
  assert.match(await page.textContent('#script-message'), /Line 7, column 3 \(note\): `~` has no left operand/);
  assert.equal(await page.locator('#script-gutter .warn').count(), 5);
  // Orbiting changes the picture, not the script.
  const before = await drawn(page, 'script-4.4-again');
  const box = await page.locator('#view3d').boundingBox();
  await page.mouse.move(box.x + box.width / 2, box.y + box.height / 2);
  await page.mouse.down();
  await page.mouse.move(box.x + box.width / 2 + 90, box.y + box.height / 2 + 20, { steps: 4 });
  await page.mouse.up();
  const orbited = await drawn(page, 'script-4.4-orbited');
  assert.ok(!orbited.png.equals(before.png));
  assert.deepEqual(errors, []);
  await page.close();
});

test('errors show at their line, endless work stops, and the page stays responsive', async () => {
  const { page, errors } = await open(browser);
  await scriptMode(page);
  const type = async (text) => {
    await page.fill('#script', text);
    await page.focus('#script');
    await page.keyboard.press('Control+Enter');
    return finished(page);
  };
  // What comes before the error is drawn; the error is at line 3, column 7, with a way to it.
  assert.equal(await type('DEF SQR = ID * ID;\nMAP:(CONS:< S1, SQR ~ S1 >):(Domain:8);\n<1, 2> + 1;\n'), 'error');
  assert.match(await page.textContent('#script-message'), /Line 3, column 8: `\+` takes numbers or functions, but got a sequence of 2/);
  assert.equal(await page.textContent('#script-gutter .error'), '3');
  assert.deepEqual(await counts(page), [0, 8, 0]);
  await page.click('#script-message button');
  const caret = await page.evaluate(() => document.getElementById('script').selectionStart);
  assert.equal(caret, 'DEF SQR = ID * ID;\nMAP:(CONS:< S1, SQR ~ S1 >):(Domain:8);\n<1, 2> '.length);
  // Columns count characters; the editor counts UTF-16 units: Go to lands on the place.
  assert.equal(await type('% 😀 % 1 +;'), 'error');
  assert.match(await page.textContent('#script-message'), /Line 1, column 9: expected `;` after the expression, found `\+`/);
  await page.click('#script-message button');
  assert.equal(await page.evaluate(() => document.getElementById('script').selectionStart), '% 😀 % 1 '.length);
  // Unbalanced brackets, unknown names, wrong types, endless recursion, a MAP of 10⁸ cells.
  for (const [script, words] of [
    ['MAP:(CONS:<S1, S1>:(Domain:4);', /Line 1, column 30: expected `\)` closing the `\(` of line 1, column 5/],
    ['MAP:(CONS:alhpa ~ S1):(Domain:4);', /unknown name `alhpa`/],
    ['DEF f (n::IsNat) = n;\nf:(-1);', /Line 2, column 1: f: parameter `n` = -1 does not satisfy IsNat/],
    ['DEF f (n::IsReal) = f:(n + 1);\nf:0;', /nested more than 200 deep/],
    ['MAP:(CONS:<S1, S2>):(Domain:10000 * Domain:10000);', /200000000 cells, past the limit/],
  ]) {
    const shown = await drawn(page, 'script-kept');
    assert.equal(await type(script), 'error', script);
    assert.match(await page.textContent('#script-message'), words);
    // A run that stops before drawing keeps the last drawing.
    assert.ok((await drawn(page, 'script-kept')).png.equals(shown.png), script);
  }
  // Work that would take long: the step limit stops it, and the page answers meanwhile.
  const big = 'DEF big = #:1000000:1;\nDEF f (x::IsReal) = AA:ID:big;\nAA:f:big;';
  await page.fill('#script', big);
  await page.click('#script-run');
  // While the worker runs it, the page draws frames and orbits the view: the run is off this thread.
  const during = await page.evaluate(() => new Promise((resolve) => {
    const t0 = performance.now();
    let frames = 0;
    const tick = () => {
      frames += 1;
      if (frames < 10) requestAnimationFrame(tick);
      else resolve({ state: document.body.dataset.scriptState, ms: performance.now() - t0 });
    };
    requestAnimationFrame(tick);
  }));
  assert.equal(during.state, 'running', 'ten frames came while the script was still running');
  assert.ok(during.ms < 1000, `ten frames in ${during.ms} ms`);
  assert.equal(await finished(page), 'error');
  assert.match(await page.textContent('#script-message'), /stopped after 20000000 steps/);
  // Stop cancels a run under way.
  await page.click('#script-run');
  await page.click('#script-stop');
  assert.equal(await finished(page), 'stopped');
  assert.deepEqual(errors, []);
  await page.close();
});

test('a script travels in a link and a model file, and exports parse back', async () => {
  const { page, errors } = await open(browser);
  await scriptMode(page);
  await pick(page, 'script-example', '4.6');
  await finished(page);
  const script = await page.inputValue('#script');
  await page.click('#copy-link');
  await page.waitForFunction(() => document.body.dataset.link);
  const link = await page.evaluate(() => document.body.dataset.link);
  assert.ok(link.length < 1500, `${link.length} characters`);
  const obj = (await download(page, 'obj')).toString();
  assert.equal(obj.split('\n').filter((l) => l.startsWith('f ')).length, 392);
  assert.equal(obj.split('\n').filter((l) => l.startsWith('v ')).length, 225);
  const stl = await download(page, 'stl');
  assert.equal(stl.readUInt32LE(80), 392);
  const model = await download(page, 'model');
  assert.equal(JSON.parse(model.toString()).solid.kind, 'plasm');
  assert.equal((await download(page, 'psm')).toString(), script);

  // A new page, in the Bézier mode, opens the link into the Script mode and runs it.
  const other = await open(browser);
  await other.page.goto(link);
  await other.page.waitForSelector('body[data-ready="true"]');
  await other.page.waitForSelector('body[data-workspace="script"]');
  assert.equal(await finished(other.page), 'done');
  assert.equal(await other.page.inputValue('#script'), script);
  assert.deepEqual(await counts(other.page), [392, 0, 0]);
  // The model file opens too, from the Bézier mode.
  await other.page.fill('#script', 'MAP:(CONS:<S1, S1>):(Domain:2);');
  await other.page.check('input[name="workspace"][value="bezier"]');
  const path = join(ARTIFACTS, 'script.bsolid.json');
  writeFileSync(path, model);
  await other.page.setInputFiles('#open-file', path);
  await other.page.waitForSelector('body[data-workspace="script"]');
  assert.equal(await finished(other.page), 'done');
  assert.equal(await other.page.inputValue('#script'), script);
  // And the script survives a reload (autosave).
  await other.page.reload();
  await other.page.waitForSelector('body[data-ready="true"]');
  assert.equal(await finished(other.page), 'done');
  assert.equal(await other.page.inputValue('#script'), script);
  // Fig. 1's surface opens in the Bézier mode as its bicubic net, and Undo brings back the patch
  // that was there.
  await pick(other.page, 'script-example', '4.4');
  assert.equal(await finished(other.page), 'done');
  const previous = await other.page.evaluate(() => window.bezsolid.modeler.model_json());
  await other.page.click('#script-values li:first-child .edit-patch');
  await other.page.waitForSelector('body[data-workspace="bezier"]');
  await settle(other.page);
  assert.match(await other.page.textContent('#model-name'), /Patch solid, 4 × 4 points, space-mapped/);
  const net = JSON.parse(await other.page.evaluate(() => window.bezsolid.modeler.model_json()));
  assert.deepEqual(net.solid.degree, [3, 3]);
  assert.deepEqual(net.solid.points[0].map((x) => Math.round(x * 1e9) / 1e9), [0, 0, 0]);
  assert.deepEqual(net.solid.points[15].map((x) => Math.round(x * 1e9) / 1e9), [10, 6, -1]);
  await other.page.click('#undo');
  assert.equal(await other.page.evaluate(() => window.bezsolid.modeler.model_json()), previous);
  assert.deepEqual(other.errors, []);
  assert.deepEqual(errors, []);
  await other.page.close();
  await page.close();
});

test('a solid a script draws opens in the Bézier mode as its Bézier volume, whose 3D view draws; Undo brings back the model', async () => {
  const { page, errors } = await open(browser);
  const previous = await page.evaluate(() => window.bezsolid.modeler.model_json());
  await scriptMode(page);
  // Fig. 4's curves: grid1 (the plane quarter ring between c1 and c2) and the same grid at z = 1,
  // blended by Bezier:S3 into a slab.
  await pick(page, 'script-example', '4.8');
  assert.equal(await finished(page), 'done');
  const slab = 'DEF a1 = CubicHermite:S1:<<1,0,1>,<0,1,1>,<0,3,0>,<-3,0,0>>;\n'
    + 'DEF a2 = CubicHermite:S1:<<0.5,0,1>,<0,0.5,1>,<0,1,0>,<-1,0,0>>;\n'
    + 'DEF Slab = Bezier:S3:<grid1, CubicHermite:S2:<a1,a2,d,d>>;\n'
    + 'MAP:Slab:(Domain:8 * Domain:4 * Domain:2);\n';
  await page.fill('#script', `${await page.inputValue('#script')}${slab}`);
  await page.click('#script-run');
  assert.equal(await finished(page), 'done', await page.textContent('#script-message'));
  const { ink } = await drawn(page, 'script-slab');
  assert.ok(ink > 300, `the slab draws (${ink} pixels)`);
  // Only the solid (the fourth value) offers a volume; the plane grids offer neither net.
  assert.equal(await page.locator('#script-values li').count(), 4);
  assert.equal(await page.locator('#script-values .edit-volume').count(), 1);
  assert.equal(await page.locator('#script-values .edit-patch').count(), 0);
  assert.equal(await page.textContent('#script-values li:nth-child(4) .edit-volume'), 'Edit as a Bézier volume');
  await page.click('#script-values li:nth-child(4) .edit-volume');
  await page.waitForSelector('body[data-workspace="bezier"]');
  await page.waitForSelector('body[data-kind="volume"]');
  await settle(page);
  assert.match(await page.textContent('#model-name'), /Volume solid, 4 × 2 × 2 points, space-mapped/);
  assert.match(await page.textContent('#status'), /Opened the solid of line \d+ as a 4 × 2 × 2-point volume, its net found exactly from the map/);
  const net = JSON.parse(await page.evaluate(() => window.bezsolid.modeler.model_json()));
  assert.equal(net.solid.kind, 'volume');
  assert.deepEqual(net.solid.degree, [3, 1, 1]);
  const round = (p) => p.map((x) => Math.round(x * 1e9) / 1e9);
  // The corners are the map's: c1(0) at z = 0, and c2(1) at z = 1; ξ = 1/4 everywhere.
  assert.deepEqual(round(net.solid.points[0]), [1, 0, 0, 0.25]);
  assert.deepEqual(round(net.solid.points[15]), [0, 0.5, 1, 0.25]);
  assert.ok(net.solid.points.every((p) => p[3] === 0.25));
  // Its 3D view draws the slab's surface, shaded in the volume's warm colour.
  await page.waitForFunction(() => JSON.parse(window.bezsolid.modeler.panel()).surface?.[1] === 64, null, { timeout: 60_000 });
  await settle(page);
  assert.match(await page.textContent('#surface-info'), /Surface: [\d,]+ triangles at 64/);
  const shot = await page.locator('#view3d').screenshot();
  writeFileSync(join(ARTIFACTS, 'script-slab-volume-3d.png'), shot);
  const tones = surfaceTones(shot);
  assert.ok(tones > 20, `the shaded surface is drawn (${tones} tones)`);
  await page.click('#undo');
  assert.equal(await page.evaluate(() => window.bezsolid.modeler.model_json()), previous);
  // A surface in space has no volume: Fig. 1's surface offers a patch only.
  await page.check('input[name="workspace"][value="script"]');
  await pick(page, 'script-example', '4.4');
  assert.equal(await finished(page), 'done');
  assert.equal(await page.locator('#script-values .edit-volume').count(), 0);
  assert.equal(await page.locator('#script-values .edit-patch').count(), 1);
  assert.deepEqual(errors, []);
  await page.close();
});

test('the prelude: a script that only uses the paper\'s toolbox runs and draws; the panel lists it', async () => {
  const { page, errors } = await open(browser);
  await scriptMode(page);
  await page.fill('#script', 'DEF c = Bezier:S1:<<0,0,0>,<1,1,0>>;\nMAP:c:(Domain:8);');
  await page.click('#script-run');
  assert.equal(await finished(page), 'done');
  const [, segments] = (await page.evaluate(() => document.body.dataset.scriptCounts)).split(',').map(Number);
  assert.equal(segments, 8, 'the curve in eight segments');
  assert.match(await page.textContent('#prelude-names'), /Bezier.*CubicHermite/);
  await page.click('.prelude summary');
  assert.match(await page.textContent('#prelude-text'), /DEF Bezier/);
  assert.deepEqual(errors, []);
  await page.close();
});
