// Keyboard and assistive technology: an automated audit (axe-core) of each mode with no serious or
// critical violation, a walk by Tab alone that reaches every control of each mode, the menus that
// act only on Enter or a click, the canvases' focus ring, and the views' names in each mode.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { createRequire } from 'node:module';
import { writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { launch, open, settle, ARTIFACTS } from './harness.mjs';

const AXE = createRequire(import.meta.url).resolve('axe-core/axe.min.js');

let browser;
before(async () => { browser = await launch(); });
after(async () => { await browser?.close(); });

const setMode = async (page, mode) => {
  await page.check(`input[name="workspace"][value="${mode}"]`);
  await page.waitForFunction((m) => document.body.dataset.workspace === m, mode);
  await settle(page);
};

// The page in each of its modes (and a model of many solids, a volume, an open menu).
const STATES = {
  patch: async () => {},
  volume: async (page) => {
    await page.click('#preset');
    await page.click('#preset-menu [data-value="blob"]');
  },
  parts: async (page) => {
    await page.click('button[data-add="sphere"]');
  },
  'export menu': async (page) => {
    await page.click('#export');
  },
  'preset menu': async (page) => {
    await page.click('#preset');
  },
  freeform: (page) => setMode(page, 'freeform'),
  script: async (page) => {
    await setMode(page, 'script');
    await page.click('#script-run');
    await page.waitForFunction(() => !document.body.dataset.working, null, { timeout: 60_000 });
  },
  hyperfun: async (page) => {
    await setMode(page, 'hyperfun');
    await page.waitForFunction(() => document.body.dataset.hfState === 'done', null, { timeout: 60_000 });
  },
};

/** axe-core's serious and critical violations of the page as it is. */
async function audit(page) {
  await page.addScriptTag({ path: AXE });
  const results = await page.evaluate(() => window.axe.run(document, { resultTypes: ['violations'] }));
  return results.violations
    .filter((v) => v.impact === 'serious' || v.impact === 'critical')
    .map((v) => `${v.id} (${v.impact}): ${v.help} — ${v.nodes.map((n) => n.target.join(' ')).slice(0, 4).join(', ')}`);
}

for (const [name, reach] of Object.entries(STATES)) {
  test(`axe-core finds no serious or critical violation: ${name}`, async () => {
    // The page's Content-Security-Policy forbids the script the audit injects: bypassed here only.
    const { page, errors } = await open(browser, '', { bypassCSP: true });
    await reach(page);
    await settle(page);
    const violations = await audit(page);
    assert.deepEqual(violations, [], violations.join('\n'));
    assert.deepEqual(errors, []);
    await page.close();
  });
}

// What Tab must reach: every visible, enabled control (a radio group is one stop, as is the
// outliner's tree).
const controls = (page) => page.evaluate(() => {
  const seen = new Set();
  const out = [];
  for (const el of document.querySelectorAll('button, input, select, textarea, [tabindex]')) {
    if (el.tabIndex < 0 || el.disabled || !el.checkVisibility({ visibilityProperty: true })) continue;
    if (el.closest('[role="menu"]')) continue;
    const key = el.type === 'radio' ? `radio:${el.name}` : el.closest('[role="tree"]') ? 'tree' : el.id || el.outerHTML.slice(0, 80);
    if (!seen.has(key)) {
      seen.add(key);
      out.push(key);
    }
  }
  return out;
});

const focused = (page) => page.evaluate(() => {
  const el = document.activeElement;
  if (!el || el === document.body) return null;
  return el.type === 'radio' ? `radio:${el.name}` : el.closest('[role="tree"]') ? 'tree' : el.id || el.outerHTML.slice(0, 80);
});

/** Presses Tab until focus comes round again; Esc first where a widget keeps Tab (a view's points, the editor). */
async function walk(page) {
  const reached = [];
  for (let k = 0; k < 200; k++) {
    await page.keyboard.press('Tab');
    const at = await focused(page);
    if (at && at === reached[0]) return reached;
    assert.ok(!at || !reached.includes(at) || at === reached.at(-1), `Tab came back to ${at} before going round`);
    if (at && at !== reached.at(-1)) reached.push(at);
    if (at === 'view' || at === 'script' || at === 'hf') await page.keyboard.press('Escape');
  }
  assert.fail(`Tab did not come round in 200 presses: ${reached.join(', ')}`);
}

for (const mode of ['bezier', 'freeform', 'script', 'hyperfun']) {
  test(`Tab alone reaches every control of the ${mode} mode, and leaves the views`, async () => {
    const { page, errors } = await open(browser);
    if (mode !== 'bezier') await setMode(page, mode);
    // A model of many solids shows its outliner's tools.
    if (mode === 'bezier') {
      await page.click('button[data-add="box"]');
      // The panel shows the new model (its buttons enabled or not) on the frame after the edit.
      await page.waitForFunction(() => document.getElementById('model-name').textContent.startsWith('Many solids'));
    }
    await page.waitForFunction(() => !document.body.dataset.working, null, { timeout: 60_000 });
    await settle(page);
    await page.evaluate(() => document.activeElement?.blur());
    const all = await controls(page);
    const reached = await walk(page);
    const missed = all.filter((c) => !reached.includes(c));
    assert.deepEqual(missed, [], `not reached by Tab: ${missed.join(', ')}`);
    assert.ok(all.length > 10, `${all.length} controls`);
    assert.deepEqual(errors, []);
    await page.close();
  });
}

test('the 2D view lets Tab go after Esc, says so, and shows its focus ring over the drawing', async () => {
  const { page } = await open(browser);
  await page.locator('#view').focus();
  await page.keyboard.press('Tab');
  assert.equal(await focused(page), 'view', 'Tab walks the points first');
  await page.waitForFunction(() => /^P00 /.test(document.getElementById('point-label').textContent));
  await page.keyboard.press('Escape');
  await page.keyboard.press('Tab');
  assert.notEqual(await focused(page), 'view', 'after Esc, Tab leaves the view');
  await page.keyboard.press('Shift+Tab');
  assert.equal(await focused(page), 'view');
  await page.keyboard.press('Tab'); // a point again
  await page.keyboard.press('Escape');
  await page.keyboard.press('Shift+Tab');
  assert.notEqual(await focused(page), 'view', 'after Esc, Shift+Tab leaves it too');
  await page.keyboard.press('Tab');
  assert.match(await page.textContent('.bezier-only .keys'), /Esc.*Tab|leave/i);
  // The ring: the view's edge takes the focus colour when focused by keyboard.
  await page.keyboard.press('Shift+Tab');
  assert.equal(await focused(page), 'view');
  await settle(page);
  const shot = await page.locator('.viewport:has(> #view)').screenshot();
  writeFileSync(join(ARTIFACTS, 'focus-ring-2d.png'), shot);
  const edge = await page.evaluate(() => getComputedStyle(document.querySelector('.viewport:has(> #view)'), '::after').borderTopColor);
  assert.equal(edge, 'rgb(179, 89, 0)');
  await page.close();
});

test('Export and Preset are menus: arrows only move, Enter picks, Esc closes', async () => {
  const { page, errors } = await open(browser);
  const model = () => page.evaluate(() => window.bezsolid.modeler.model_json());
  let downloads = 0;
  page.on('download', () => { downloads += 1; });
  await page.locator('#export').focus();
  await page.keyboard.press('ArrowDown');
  assert.equal(await page.getAttribute('#export', 'aria-expanded'), 'true');
  await page.keyboard.press('ArrowDown');
  await page.keyboard.press('ArrowDown');
  await page.keyboard.press('Escape');
  assert.equal(await page.getAttribute('#export', 'aria-expanded'), 'false');
  assert.equal(await focused(page), 'export', 'Esc gives focus back to the button');
  await settle(page);
  assert.equal(downloads, 0, 'moving through the menu exports nothing');
  const [file] = await Promise.all([page.waitForEvent('download'), (async () => {
    await page.keyboard.press('Enter');
    await page.keyboard.press('Enter');
  })()]);
  assert.equal(file.suggestedFilename(), 'bezsolid.bsolid.json');

  const before = await model();
  await page.locator('#preset').focus();
  await page.keyboard.press('ArrowDown');
  await page.keyboard.press('ArrowDown');
  await page.keyboard.press('ArrowDown');
  await settle(page);
  assert.equal(await model(), before, 'moving through the presets changes nothing');
  await page.keyboard.press('Enter');
  await page.waitForFunction(() => /^Volume solid, 3 × 3 × 3/.test(document.getElementById('model-name').textContent));
  assert.notEqual(await model(), before);
  assert.deepEqual(errors, []);
  await page.close();
});

test('the 3D view is named for what it shows in each mode', async () => {
  const { page } = await open(browser);
  const name = () => page.getAttribute('#view3d', 'aria-label');
  assert.match(await name(), /patch/);
  await page.click('#preset');
  await page.click('#preset-menu [data-value="blob"]');
  await page.waitForFunction(() => /volume/.test(document.getElementById('view3d').getAttribute('aria-label')));
  assert.match(await page.getAttribute('#view', 'aria-label'), /w slice 1 of the volume/);
  await page.click('button[data-add="sphere"]');
  await page.waitForFunction(() => /many solids/.test(document.getElementById('view3d').getAttribute('aria-label')));
  await setMode(page, 'freeform');
  assert.match(await name(), /free-form/i);
  assert.doesNotMatch(await name(), /patch/);
  await setMode(page, 'script');
  assert.match(await name(), /script/i);
  assert.doesNotMatch(await name(), /patch/);
  await setMode(page, 'hyperfun');
  assert.match(await name(), /HyperFun program/);
  await page.close();
});
