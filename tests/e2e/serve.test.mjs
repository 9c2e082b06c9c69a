// The dev server that `cargo xtask serve` and the suite use: the module's MIME type, a
// Content-Security-Policy that allows WebAssembly compilation and nothing loose, no way out of www/,
// compressed transfer (brotli or gzip) and caching by content hash and ETag.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { request } from 'node:http';
import zlib from 'node:zlib';
import { URL as BASE } from './harness.mjs';

test('the modules are served as application/wasm', async () => {
  for (const module of ['bezsolid_page', 'bezsolid_page_gl', 'bezsolid_web']) {
    const res = await fetch(new URL(`pkg/${module}_bg.wasm`, BASE));
    assert.equal(res.status, 200);
    assert.equal(res.headers.get('content-type'), 'application/wasm');
    const bytes = new Uint8Array(await res.arrayBuffer());
    assert.deepEqual([...bytes.slice(0, 4)], [0x00, 0x61, 0x73, 0x6d], 'the wasm magic number');
  }
});

test('the page has a strict Content-Security-Policy', async () => {
  const res = await fetch(BASE);
  assert.equal(res.status, 200);
  assert.match(res.headers.get('content-type'), /^text\/html/);
  const csp = res.headers.get('content-security-policy');
  assert.ok(csp, 'a CSP header');
  const directives = Object.fromEntries(csp.split(';').map((d) => d.trim().split(/\s+/)).map(([k, ...v]) => [k, v]));
  assert.deepEqual(directives['default-src'], ["'none'"]);
  assert.deepEqual(directives['script-src'], ["'self'", "'wasm-unsafe-eval'"]);
  assert.ok(!csp.includes("'unsafe-eval'") && !csp.includes("'unsafe-inline'"), csp);
  assert.equal(res.headers.get('x-content-type-options'), 'nosniff');
});

test('requests cannot leave the served folder', async () => {
  // fetch() normalises "..", so send the raw request line.
  const status = (path) => new Promise((resolve, reject) => {
    const u = new URL(BASE);
    const req = request({ host: u.hostname, port: u.port, path, method: 'GET' }, (res) => {
      res.resume();
      resolve(res.statusCode);
    });
    req.on('error', reject);
    req.end();
  });
  assert.equal(await status('/../Cargo.toml'), 404);
  assert.equal(await status('/%2e%2e/Cargo.toml'), 404);
  assert.equal(await status('/pkg/../../xtask/src/main.rs'), 404);
  assert.equal(await status('/no-such-file.js'), 404);
});

/** A raw GET with `headers`: the status, the headers and the body as sent (not decoded). */
const get = (path, headers = {}) => new Promise((resolve, reject) => {
  const u = new URL(BASE);
  const req = request({ host: u.hostname, port: u.port, path, method: 'GET', headers }, (res) => {
    const chunks = [];
    res.on('data', (c) => chunks.push(c));
    res.on('end', () => resolve({ status: res.statusCode, headers: res.headers, body: Buffer.concat(chunks) }));
  });
  req.on('error', reject);
  req.end();
});

test('the modules travel compressed under content-hashed names that are cached for good', async () => {
  const assets = await get('/pkg/assets.js');
  assert.equal(assets.status, 200);
  assert.equal(assets.headers['cache-control'], 'no-cache', 'the names themselves are revalidated');
  const named = Object.fromEntries([...assets.body.toString().matchAll(/(\w+): new URL\('\.\/(\w+_bg\.[0-9a-f]{16}\.wasm)'/g)]
    .map(([, module, file]) => [module, file]));
  assert.deepEqual(Object.keys(named).sort(), ['bezsolid_page', 'bezsolid_page_gl', 'bezsolid_web'], `assets.js: ${assets.body}`);
  const sizes = {};
  for (const [module, name] of Object.entries(named)) {
    assert.ok(name.startsWith(`${module}_bg.`), name);
    const plain = await get(`/pkg/${module}_bg.wasm`);
    const br = await get(`/pkg/${name}`, { 'accept-encoding': 'gzip, deflate, br' });
    assert.equal(br.status, 200);
    assert.equal(br.headers['content-encoding'], 'br');
    assert.equal(br.headers['content-type'], 'application/wasm');
    assert.match(br.headers['cache-control'], /immutable/);
    assert.match(br.headers.vary, /Accept-Encoding/i);
    const fromBr = zlib.brotliDecompressSync(br.body);
    assert.ok(fromBr.equals(plain.body), `brotli decodes to ${module}`);
    assert.ok(br.body.length < plain.body.length / 2, `${br.body.length} of ${plain.body.length} bytes`);
    const gz = await get(`/pkg/${name}`, { 'accept-encoding': 'gzip' });
    assert.equal(gz.headers['content-encoding'], 'gzip');
    assert.ok(zlib.gunzipSync(gz.body).equals(plain.body), `gzip decodes to ${module}`);
    const none = await get(`/pkg/${name}`, { 'accept-encoding': 'identity' });
    assert.equal(none.headers['content-encoding'], undefined);
    assert.ok(none.body.equals(plain.body));
    sizes[module] = br.body.length;
  }
  // The split pays: the WebGPU page leaves out the WebGL2 path, and neither page module holds the
  // tools (meshing to files, free-form results, scripts).
  assert.ok(sizes.bezsolid_page < sizes.bezsolid_page_gl, JSON.stringify(sizes));
});

test('small files are compressed as they are sent and revalidated by their ETag', async () => {
  const first = await get('/main.js', { 'accept-encoding': 'br' });
  assert.equal(first.status, 200);
  assert.equal(first.headers['content-encoding'], 'br');
  assert.match(zlib.brotliDecompressSync(first.body).toString(), /pageModule/);
  const etag = first.headers.etag;
  assert.match(etag, /^"[0-9a-f]{16}"$/);
  const again = await get('/main.js', { 'accept-encoding': 'br', 'if-none-match': etag });
  assert.equal(again.status, 304);
  assert.equal(again.body.length, 0);
  const stale = await get('/main.js', { 'if-none-match': '"0000000000000000"' });
  assert.equal(stale.status, 200);
});
