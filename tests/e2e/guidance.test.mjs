// Guidance and what is said is right: the first-visit hint, a new patch that is a visible solid, ξ
// kept within the model's scale, the probe, a volume slice's labels, imported meshes said to be
// smoothed and keeping their names, a failed script's drawing marked; undo in the Free-form mode
// and of the script text across opened examples.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { join } from 'node:path';
import { launch, open, settle, canvasBox, pick } from './harness.mjs';

const FIXTURES = new URL('../../crates/core/tests/fixtures/mesh/', import.meta.url).pathname;

let browser;
before(async () => { browser = await launch(); });
after(async () => { await browser?.close(); });

const model = (page) => page.evaluate(() => window.bezsolid.modeler.model_json());
const text = (page, id) => page.textContent(`#${id}`);

/** The page position of the control point `k` of the 2D view (from the view's own map). */
async function pointAt(page, k) {
  const box = await canvasBox(page);
  const [x0, y0] = await page.evaluate(() => [...window.bezsolid.modeler.probe(0, 0)]);
  const [x1, y1] = await page.evaluate(() => [...window.bezsolid.modeler.probe(100, 100)]);
  const p = JSON.parse(await model(page)).solid.points[k];
  return [box.x + (p[0] - x0) * (100 / (x1 - x0)), box.y + (p[1] - y0) * (100 / (y1 - y0))];
}

test('the first-visit hint goes once a point moves, and stays gone', async () => {
  const context = await browser.newContext({ viewport: { width: 1200, height: 760 } });
  const page = await context.newPage();
  const ready = async () => {
    await page.waitForSelector('body[data-ready="true"]', { timeout: 60_000 });
    await settle(page);
  };
  await page.goto(process.env.BEZSOLID_URL ?? 'http://127.0.0.1:8080/');
  await ready();
  assert.equal(await page.isVisible('#hint'), true);
  assert.match(await text(page, 'hint'), /drag a control point up or down/);
  // Dragging the middle point up.
  const [x, y] = await pointAt(page, 4);
  await page.mouse.move(x, y);
  await page.mouse.down();
  await page.mouse.move(x, y - 40, { steps: 5 });
  await page.mouse.up();
  await settle(page);
  await page.waitForFunction(() => document.getElementById('hint').hidden);
  // The probe under the still pointer reads the new model, not the one before the drag.
  const probed = await page.evaluate(([px, py]) => {
    const r = document.getElementById('view').getBoundingClientRect();
    return window.bezsolid.modeler.probe(px - r.left, py - r.top)[2];
  }, [x, y - 40]);
  await page.waitForFunction((f) => document.getElementById('probe').textContent.includes(`= ${f.toFixed(4)}`), probed);
  await page.reload();
  await ready();
  assert.equal(await page.isVisible('#hint'), false, 'not on the next visit');
  await context.close();
});

test('a new patch is a solid in the middle; ξ far past the model is refused and said', async () => {
  const { page, errors } = await open(browser);
  await page.fill('#grid-u', '5');
  await page.fill('#grid-v', '5');
  await page.click('#reset-grid');
  await settle(page);
  const centre = await page.evaluate(() => {
    const r = document.getElementById('view').getBoundingClientRect();
    return window.bezsolid.modeler.probe(r.width / 2, r.height / 2)[2];
  });
  assert.ok(centre > 0, `inside in the middle (f = ${centre})`);
  assert.match(await text(page, 'contour-info'), /Zero contour: 1 piece/);
  // Select the middle point and type a huge ξ: refused, said, the model kept.
  const before = await model(page);
  await page.locator('#view').focus();
  await page.keyboard.press('ArrowRight');
  await page.fill('#xi', '1e9');
  await page.locator('#xi').press('Enter');
  await page.waitForFunction(() => /too far from the model/.test(document.getElementById('status').textContent));
  assert.equal(await page.getAttribute('#xi', 'aria-invalid'), 'true');
  assert.equal(await model(page), before);
  // Typed key by key, a value past the bound puts the point back where it was, not at a prefix.
  await page.fill('#xi', '');
  await page.locator('#xi').pressSequentially('150');
  await page.waitForFunction(() => /too far from the model/.test(document.getElementById('status').textContent));
  await page.locator('#xi').press('Tab');
  await settle(page);
  assert.equal(await model(page), before);
  // A file whose ξ is far past the bound opens; its labels stay short, and keys bring ξ back.
  const points = JSON.parse(before).solid.points.map((p, k) => (k === 12 ? [p[0], p[1], 2e4] : p));
  await page.evaluate((m) => { window.bezsolid.modeler.load_model(m); window.bezsolid.redraw(); }, JSON.stringify({ ...JSON.parse(before), solid: { ...JSON.parse(before).solid, points } }));
  await settle(page);
  assert.match(await text(page, 'xi-max'), /^2\.00e\+4$/);
  assert.ok((await text(page, 'range-max')).length <= 9, await text(page, 'range-max'));
  await page.locator('#view').focus();
  await page.keyboard.press('Escape');
  await page.keyboard.press('ArrowRight');
  // The panel says the selection in the frame after the key.
  await settle(page);
  assert.match(await text(page, 'point-label'), /^P22 /);
  await page.keyboard.press('PageDown');
  await settle(page);
  assert.ok(Math.abs(JSON.parse(await model(page)).solid.points[12][2] - (2e4 - 0.1)) < 1e-6);
  assert.deepEqual(errors, []);
  await page.close();
});

test('a volume slice names its points by three indices and its plane by its axes', async () => {
  const { page, errors } = await open(browser);
  await pick(page, 'preset', 'fish');
  await page.check('input[name="slice-axis"][value="0"]');
  await settle(page);
  assert.equal(await text(page, 'px-name'), 'y');
  assert.equal(await text(page, 'py-name'), 'z');
  assert.match(await text(page, 'slice-info'), /in the yz plane/);
  await page.locator('#view').focus();
  await page.keyboard.press('Tab');
  await settle(page);
  assert.match(await text(page, 'point-label'), /^P\d00 \(i = \d, j = 0, k = 0\) of the u slice \d/);
  await page.check('input[name="slice-axis"][value="1"]');
  await settle(page);
  assert.equal(await text(page, 'px-name'), 'x');
  assert.equal(await text(page, 'py-name'), 'z');
  assert.deepEqual(errors, []);
  await page.close();
});

test('Free-form: every change is undone and redone; an imported mesh is said to keep its sharp edges and keeps its name when moved', async () => {
  const { page, errors } = await open(browser);
  await page.check('input[name="workspace"][value="freeform"]');
  await page.waitForSelector('body[data-workspace="freeform"]');
  const scene = () => page.evaluate(() => window.bezsolid.ff.model_json());
  const start = await scene();
  assert.equal(await page.isDisabled('#undo'), true);
  await page.setInputFiles('#ff-import-b', join(FIXTURES, 'cube.obj'));
  await page.waitForFunction(() => /Imported cube\.obj as solid B\. .*edges sharper than the crease angle stay sharp/.test(document.getElementById('status').textContent));
  await settle(page);
  assert.match(await text(page, 'ff-info'), /B: 12 triangles/);
  await page.fill('#ff-x', '0.3');
  await page.locator('#ff-x').press('Enter');
  await settle(page);
  assert.match(await page.textContent('#ff-b option[value="imported"]'), /cube\.obj/, 'the moved mesh keeps its name');
  await page.selectOption('#ff-op', 'intersection');
  await page.waitForSelector('body[data-ff-operation="intersection"]');
  const last = await scene();
  // Ctrl+Z three times: the operation, the move, the import.
  await page.locator('#undo').focus();
  await page.keyboard.press('Control+z');
  await page.waitForSelector('body[data-ff-operation="difference"]');
  await page.keyboard.press('Control+z');
  await settle(page);
  assert.equal(await page.inputValue('#ff-x'), '0');
  await page.click('#undo');
  await settle(page);
  assert.equal(await scene(), start);
  assert.equal(await page.isDisabled('#undo'), true);
  await page.click('#redo');
  await page.keyboard.press('Control+y');
  await page.keyboard.press('Control+Shift+z');
  await page.waitForSelector('body[data-ff-operation="intersection"]');
  assert.equal(await scene(), last);
  assert.match(await page.textContent('#ff-b option[value="imported"]'), /cube\.obj/);
  assert.equal(await page.isDisabled('#redo'), true);
  assert.deepEqual(errors, []);
  await page.close();
});

test('Script: the text replaced by an example comes back by undo; a failed run marks the drawing as the last good one', async () => {
  const { page, errors } = await open(browser);
  await page.check('input[name="workspace"][value="script"]');
  await page.waitForSelector('body[data-workspace="script"]');
  const state = () => page.waitForFunction(() => ['done', 'error'].includes(document.body.dataset.scriptState), null, { timeout: 60_000 });
  await state();
  // The script the mode opens with (the paper's Script 4.4), as if typed with a definition more.
  const mine = `DEF mine = 1;\n${await page.inputValue('#script')}`;
  await page.fill('#script', mine);
  await page.click('#script-run');
  await state();
  await pick(page, 'script-example', '4.6');
  await state();
  assert.notEqual(await page.inputValue('#script'), mine);
  await page.locator('#script').focus();
  await page.keyboard.press('Control+z');
  assert.equal(await page.inputValue('#script'), mine, 'undo in the editor brings the text back');
  // A script that fails before drawing keeps the last drawing, marked.
  assert.equal(await page.isVisible('#script-stale'), false);
  await page.fill('#script', 'DEF broken = ;');
  await page.click('#script-run');
  await state();
  assert.equal(await page.evaluate(() => document.body.dataset.scriptState), 'error');
  assert.equal(await page.isVisible('#script-stale'), true);
  assert.match(await page.getAttribute('#script-message p.error', 'class'), /error/);
  await page.fill('#script', mine);
  await page.click('#script-run');
  await state();
  assert.equal(await page.isVisible('#script-stale'), false);
  assert.deepEqual(errors, []);
  await page.close();
});
