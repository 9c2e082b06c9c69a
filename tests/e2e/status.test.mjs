// The status bar, on the backend under test: a damaged link is said over the views, in sight at
// 1280×800, 800×600 and 390×844, and stays until dismissed; a success ("Link copied") fades; the
// views under the bar keep their pointer. Open… and the mesh imports are real buttons.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { launch, open, settle, ARTIFACTS, URL } from './harness.mjs';

let browser;
before(async () => { browser = await launch(); });
after(async () => { await browser?.close(); });

const inSight = async (page) => {
  const bar = await page.locator('#status-bar').boundingBox();
  const views = await page.locator('.views').boundingBox();
  const size = page.viewportSize();
  assert.ok(bar, 'the bar is shown');
  assert.ok(bar.y >= 0 && bar.y + bar.height <= size.height && bar.x >= 0 && bar.x + bar.width <= size.width,
    `the bar (${JSON.stringify(bar)}) is on the screen (${JSON.stringify(size)})`);
  assert.ok(bar.y >= views.y && bar.y < views.y + 60, 'at the top of the views');
};

test('a damaged link is said where the eye is and stays until dismissed; a success fades', async () => {
  const { page, errors } = await open(browser, '#v1.AAAA');
  await page.waitForSelector('#status-bar:not([hidden])');
  assert.match(await page.textContent('#status'), /link/i);
  assert.equal(await page.getAttribute('#status-bar', 'data-kind'), 'error');
  for (const [width, height] of [[1280, 800], [800, 600], [390, 844]]) {
    await page.setViewportSize({ width, height });
    await settle(page);
    await inSight(page);
    writeFileSync(join(ARTIFACTS, `status-${width}.png`), await page.screenshot());
  }
  await page.setViewportSize({ width: 1280, height: 800 });
  // An error stays (past the time a success stays), until dismissed.
  await page.waitForTimeout(5600);
  assert.equal(await page.isVisible('#status-bar'), true);
  await page.click('#status-close');
  assert.equal(await page.isVisible('#status-bar'), false);
  // A success is in sight, then fades by itself.
  await page.context().grantPermissions(['clipboard-read', 'clipboard-write']);
  await page.click('#copy-link');
  await page.waitForSelector('#status-bar:not([hidden])');
  assert.equal(await page.getAttribute('#status-bar', 'data-kind'), 'info');
  await inSight(page);
  await page.waitForSelector('#status-bar[hidden]', { state: 'attached', timeout: 8000 });
  assert.deepEqual(errors.filter((e) => !/link/i.test(e)), []);
  await page.close();
});

test('Open… and the mesh imports are buttons a keyboard reaches and presses', async () => {
  const { page, errors } = await open(browser);
  for (const [name, input] of [['Open…', 'open-file'], ['Import mesh as A…', 'ff-import-a'], ['Import mesh as B…', 'ff-import-b']]) {
    if (input !== 'open-file') {
      await page.check('input[name="workspace"][value="freeform"]');
      await page.waitForSelector('body[data-workspace="freeform"]');
      if (input === 'ff-import-b') {
        await page.selectOption('#ff-op', 'union');
        await page.waitForSelector('#ff-import-b', { state: 'attached' });
      }
    }
    const button = page.getByRole('button', { name, exact: true });
    assert.equal(await button.count(), 1, `${name} is a button in the accessibility tree`);
    // The press reaches the hidden input as a click (its default, the browser's file dialog, is
    // stopped here: headless Chromium opens one dialog at a time).
    await page.evaluate((id) => {
      window.picked = null;
      document.getElementById(id).addEventListener('click', (e) => {
        window.picked = id;
        e.preventDefault();
      }, { once: true });
    }, input);
    await button.focus();
    await page.keyboard.press('Enter');
    await page.waitForFunction((id) => window.picked === id, input, { timeout: 5000 });
  }
  assert.deepEqual(errors, []);
  await page.close();
});

test('a browser without WebAssembly SIMD is told why the modeler cannot start, before any module is fetched', async () => {
  const page = await browser.newPage({ viewport: { width: 1200, height: 760 } });
  // This browser as one without SIMD: a module with a SIMD instruction does not validate.
  await page.addInitScript(() => {
    const validate = WebAssembly.validate;
    WebAssembly.validate = (bytes) => {
      const b = new Uint8Array(bytes.buffer ?? bytes);
      for (let i = 0; i + 1 < b.length; i += 1) if (b[i] === 0xfd) return false;
      return validate(bytes);
    };
  });
  const fetched = [];
  page.on('request', (r) => { if (/\.wasm$/.test(r.url())) fetched.push(r.url()); });
  await page.goto(URL);
  await page.waitForFunction(() => /could not start/.test(document.getElementById('loading').textContent));
  await page.waitForSelector('#status-bar:not([hidden])');
  assert.match(await page.textContent('#status'), /The modeler could not start: this browser lacks WebAssembly SIMD.*Safari 16\.4/);
  assert.equal(await page.getAttribute('#status-bar', 'data-kind'), 'error');
  assert.equal(await page.textContent('#loading-3d'), 'The 3D view could not start.');
  assert.notEqual(await page.getAttribute('body', 'data-ready'), 'true');
  assert.deepEqual(fetched, [], 'no module is fetched');
  writeFileSync(join(ARTIFACTS, 'no-simd.png'), await page.screenshot());
  await page.close();
});
