// The package for node that `cargo xtask pack` writes to pkg/, as a user gets it: installed with npm
// into a fresh folder (as a copy of what its "files" list, offline: it has no dependencies), then the
// examples of its README run there with node, unchanged, so the README cannot drift from the package.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { existsSync, mkdtempSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { fileURLToPath } from 'node:url';
import { createRequire } from 'node:module';
import { MODEL } from './blob.mjs';

const pkg = fileURLToPath(new URL('../../pkg/', import.meta.url));

let dir;
let bezsolid;
let link;

before(() => {
  if (!existsSync(join(pkg, 'package.json'))) {
    throw new Error(`no package in ${pkg}: run \`cargo xtask pack\` first (\`cargo xtask test\` runs it before these tests)`);
  }
  dir = mkdtempSync(join(tmpdir(), 'bezsolid-package-'));
  writeFileSync(join(dir, 'package.json'), JSON.stringify({ name: 'bezsolid-user', private: true }));
  // --install-links: a copy of the packed files, as from a registry, not a link to the folder.
  execFileSync('npm', ['install', pkg, '--install-links', '--no-audit', '--no-fund', '--offline', '--loglevel=error'],
    { cwd: dir, stdio: ['ignore', 'ignore', 'inherit'] });
  bezsolid = createRequire(join(dir, 'package.json'))('bezsolid');
  link = `https://example.invalid/bezsolid/${bezsolid.headless_link(MODEL)}`;
});

after(() => {
  if (dir) rmSync(dir, { recursive: true, force: true });
});

/** The README's fenced `js` blocks. */
function examples() {
  const readme = readFileSync(join(dir, 'node_modules/bezsolid/README.md'), 'utf8');
  return [...readme.matchAll(/^```js\n([\s\S]*?)^```$/gm)].map((m) => m[1]);
}

/** Runs `node file args…` in the user's folder; returns its standard output. */
function node(file, ...args) {
  return execFileSync(process.execPath, [file, ...args], { cwd: dir, encoding: 'utf8', stdio: ['ignore', 'pipe', 'inherit'] });
}

/** The triangles of a binary STL, checked: 80-byte header, u32 count, 50 bytes a triangle, finite numbers. */
function stlTriangles(bytes) {
  assert.ok(bytes.length >= 84, `${bytes.length} bytes`);
  const count = bytes.readUInt32LE(80);
  assert.ok(count > 0, 'no triangles');
  assert.equal(bytes.length, 84 + 50 * count);
  for (let t = 0; t < count; t++) {
    for (let f = 0; f < 12; f++) {
      const x = bytes.readFloatLE(84 + 50 * t + 4 * f);
      assert.ok(Number.isFinite(x), `triangle ${t}, float ${f}: ${x}`);
    }
  }
  return count;
}

test("the installed package holds what its package.json names, with the TypeScript declarations", () => {
  const root = join(dir, 'node_modules/bezsolid');
  const manifest = JSON.parse(readFileSync(join(root, 'package.json'), 'utf8'));
  assert.equal(manifest.name, 'bezsolid');
  assert.deepEqual(manifest.dependencies ?? {}, {});
  for (const file of manifest.files) assert.ok(existsSync(join(root, file)), file);
  const types = readFileSync(join(root, manifest.exports['.'].types), 'utf8');
  assert.equal(manifest.types, manifest.exports['.'].types);
  assert.match(types, /export function headless_mesh\(text: string, format: MeshFormat, resolution: number\): Uint8Array;/);
  assert.match(types, /export type MeshFormat = "obj" \| "stl" \| "ply" \| "3mf" \| "glb";/);
  // The README names every function the package exports.
  const readme = readFileSync(join(root, 'README.md'), 'utf8');
  const functions = [...types.matchAll(/^export function (\w+)\(/gm)].map((m) => m[1]);
  assert.ok(functions.length > 10, functions.join(' '));
  for (const f of functions) assert.ok(readme.includes(`\`${f}(`), `the README does not list ${f}`);
});

test("the README's example turns a share link into an STL file", () => {
  const code = examples().find((c) => c.includes("require('bezsolid')"));
  assert.ok(code, "no example with require('bezsolid') in the README");
  writeFileSync(join(dir, 'stl.cjs'), code);
  const out = node('stl.cjs', link, 'model.stl');
  assert.match(out, /wrote model\.stl/);
  const stl = readFileSync(join(dir, 'model.stl'));
  stlTriangles(stl);
  // The same file as the module gives in this process, for the link's fragment alone.
  assert.ok(stl.equals(Buffer.from(bezsolid.headless_mesh(link.slice(link.indexOf('#')), 'stl', 48))));
});

test("the README's ES module example measures a model file and prints its link", () => {
  const code = examples().find((c) => c.includes("from 'bezsolid'"));
  assert.ok(code, "no example importing from 'bezsolid' in the README");
  writeFileSync(join(dir, 'measure.mjs'), code);
  writeFileSync(join(dir, 'model.bsolid.json'), MODEL);
  const [printed, measured] = node('measure.mjs', 'model.bsolid.json').trim().split('\n');
  assert.equal(`https://example.invalid/bezsolid/${printed}`, link);
  const m = /^volume (\S+), area (\S+), box (.+)$/.exec(measured);
  assert.ok(m, measured);
  assert.ok(Number(m[1]) > 0 && Number(m[2]) > 0, measured);
  assert.equal(m[3].split(' ').length, 6);
});

test("import { headless_mesh } from 'bezsolid' in an ES module gives the STL that require gives", () => {
  writeFileSync(join(dir, 'import.mjs'), [
    "import { writeFileSync } from 'node:fs';",
    "import { headless_mesh } from 'bezsolid';",
    "writeFileSync('imported.stl', headless_mesh(process.argv[2], 'stl', 24));",
  ].join('\n'));
  node('import.mjs', link);
  const stl = readFileSync(join(dir, 'imported.stl'));
  stlTriangles(stl);
  assert.ok(stl.equals(Buffer.from(bezsolid.headless_mesh(link, 'stl', 24))));
});

test('bad input throws an Error that says what is wrong', () => {
  const error = (pattern) => (e) => e instanceof Error && pattern.test(e.message);
  assert.throws(() => bezsolid.headless_mesh(link, 'stl', 1), error(/resolution 1/));
  assert.throws(() => bezsolid.headless_mesh(link, 'stl', 513), error(/resolution 513/));
  assert.throws(() => bezsolid.headless_mesh(link, 'gltf', 24), error(/mesh format/));
  assert.throws(() => bezsolid.headless_mesh('#v1.AAAA', 'stl', 24), Error);
  assert.throws(() => bezsolid.headless_model('not a model'), Error);
});
