// A short soak in the suite (tests/soak.mjs runs the full one): ordinary actions over and over in one
// page leave no error, the page still answers, and what it holds levels off (soak.mjs).
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { launch, open, settle, BACKEND, ARTIFACTS } from './harness.mjs';
import { soak, check } from './soak.mjs';

let browser;
before(async () => { browser = await launch(); });
after(async () => { await browser?.close(); });

// A tenth of the full drags and a fifth of the rest: under a minute on two cores (48 s measured;
// the full soak takes 7 to 8 minutes a backend). One backend is enough here: the renderers are the
// same code on both, and the full soak runs on either (tests/soak.mjs).
const COUNTS = { drags: 200, links: 40, switches: 12, runs: 10 };

test('a short soak leaves no error, and the page answers and holds what it held', { skip: BACKEND !== 'webgl2' && 'WebGL2 only' }, async () => {
  const { page, errors } = await open(browser);
  const result = await soak(page, COUNTS);
  writeFileSync(join(ARTIFACTS, 'soak.json'), JSON.stringify({ counts: COUNTS, ...result }, null, 2));
  await check(page, errors, result, assert);
  await settle(page);
  await page.close();
});
