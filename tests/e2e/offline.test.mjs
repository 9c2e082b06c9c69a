// Installable and offline: the page names a web app manifest, and after one visit its service
// worker has kept the page and its modules, so that with the network gone a reload opens the
// modeler, draws, edits and runs work in its workers; the Content-Security-Policy stays strict
// (no inline script; the manifest and the worker allowed from the page's own origin only).
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { launch, open, settle, ARTIFACTS, pick } from './harness.mjs';

let browser;
before(async () => { browser = await launch(); });
after(async () => { await browser?.close(); });

test('after one visit the page opens, draws and works with no network', async () => {
  const { page, errors } = await open(browser);
  // The manifest: linked, served as a manifest, naming the page and an icon.
  const manifest = await page.evaluate(async () => {
    const href = document.querySelector('link[rel="manifest"]').href;
    const res = await fetch(href);
    return { type: res.headers.get('content-type'), body: await res.json() };
  });
  assert.match(manifest.type, /^application\/manifest\+json/);
  assert.equal(manifest.body.short_name, 'bezsolid');
  assert.equal(manifest.body.start_url, './');
  assert.ok(manifest.body.icons.length > 0);
  // The service worker takes the page over and keeps every file of the build's list.
  await page.waitForFunction(() => navigator.serviceWorker.controller !== null, null, { timeout: 60_000 });
  const kept = await page.evaluate(async () => {
    const list = await (await fetch('pkg/offline.json')).json();
    const cache = await caches.open('bezsolid-offline-v1');
    const missing = [];
    for (const file of list.files) if (!(await cache.match(new URL(file, location.href).href))) missing.push(file);
    return { count: list.files.length, missing, wasm: list.files.filter((f) => f.endsWith('.wasm')).length };
  });
  assert.deepEqual(kept.missing, []);
  assert.equal(kept.wasm, 3, 'both page modules and the tools');

  // No network: the page reloads (with a query, as a link may carry), draws and edits.
  await page.context().setOffline(true);
  // A file never kept cannot be fetched: the network is really gone.
  assert.equal(await page.evaluate(() => fetch('never-kept.txt').then(() => 'online', () => 'offline')), 'offline');
  await page.goto(`${page.url().split('?')[0]}?offline=1`);
  await page.waitForSelector('body[data-ready="true"]', { timeout: 60_000 });
  await pick(page, 'preset', 'blob');
  await page.waitForSelector('body[data-kind="volume"]');
  await settle(page);
  // Work in the workers (their module from the kept copy): a measurement.
  await page.click('#measure');
  await page.waitForFunction(() => /^Volume [\d.]+/.test(document.getElementById('measure-out').textContent), null, { timeout: 60_000 });
  writeFileSync(join(ARTIFACTS, 'offline.png'), await page.screenshot());
  await page.context().setOffline(false);
  // The one failed load is the probe's above; every other file came from the kept copy.
  assert.deepEqual(errors.filter((e) => !/net::ERR_(FAILED|INTERNET_DISCONNECTED)/.test(e)), []);
  assert.ok(errors.length <= 1, JSON.stringify(errors));
  await page.close();
});
