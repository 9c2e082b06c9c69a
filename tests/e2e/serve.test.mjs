// The dev server that `cargo xtask serve` and the suite use: the module's MIME type, a
// Content-Security-Policy that allows WebAssembly compilation and nothing loose, and no way out of www/.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { request } from 'node:http';
import { URL as BASE } from './harness.mjs';

test('the module is served as application/wasm', async () => {
  const res = await fetch(new URL('pkg/bezsolid_web_bg.wasm', BASE));
  assert.equal(res.status, 200);
  assert.equal(res.headers.get('content-type'), 'application/wasm');
  const bytes = new Uint8Array(await res.arrayBuffer());
  assert.deepEqual([...bytes.slice(0, 4)], [0x00, 0x61, 0x73, 0x6d], 'the wasm magic number');
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
