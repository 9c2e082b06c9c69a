// The tools' wasm module (www/pkg, as `cargo xtask test` builds it) loaded in node, with no page
// and no GPU: a model file or a share link in, the model, the link and mesh files out, parsed back.
// The page's module (its WebGPU build) loads in node too: its Free-form view edits with no GPU.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { fileURLToPath } from 'node:url';
import { createRequire } from 'node:module';
import { MODEL, points } from './blob.mjs';

// The Khronos glTF validator (npm gltf-validator, in the tests' lockfile).
const validator = createRequire(import.meta.url)('gltf-validator');

const pkg = new URL('../../www/pkg/', import.meta.url);
const glue = await import(new URL('bezsolid_web.js', pkg));
await glue.default({ module_or_path: readFileSync(fileURLToPath(new URL('bezsolid_web_bg.wasm', pkg))) });
const { headless_model, headless_link, headless_mesh, headless_svg, headless_surface, headless_approximate, headless_measure } = glue;
const page = await import(new URL('bezsolid_page.js', pkg));
await page.default({ module_or_path: readFileSync(fileURLToPath(new URL('bezsolid_page_bg.wasm', pkg))) });

test('a model file and its link give the same model back', () => {
  const model = JSON.parse(headless_model(MODEL));
  assert.deepEqual(model.solid.points, points);
  const link = headless_link(MODEL);
  assert.match(link, /^#v1\.[A-Za-z0-9_-]+$/);
  assert.deepEqual(JSON.parse(headless_model(`https://example.invalid/${link}`)), model);
  assert.equal(headless_link(link), link);
});

test('STL, OBJ and PLY of a volume from a link parse back with one triangle count', () => {
  const link = headless_link(MODEL);
  const stl = Buffer.from(headless_mesh(link, 'stl', 24));
  const count = stl.readUInt32LE(80);
  assert.ok(count > 200, `${count} triangles`);
  assert.equal(stl.length, 84 + 50 * count);
  // Every facet's corners lie in the net's box.
  for (let t = 0; t < count; t++) {
    for (let c = 0; c < 3; c++) {
      for (let a = 0; a < 3; a++) {
        const x = stl.readFloatLE(84 + 50 * t + 12 + 12 * c + 4 * a);
        assert.ok(x >= -1.0001 && x <= 1.0001, `${x}`);
      }
    }
  }
  const obj = Buffer.from(headless_mesh(MODEL, 'obj', 24)).toString();
  assert.equal(obj.split('\n').filter((l) => l.startsWith('f ')).length, count);
  const ply = Buffer.from(headless_mesh(MODEL, 'ply', 24));
  assert.match(ply.subarray(0, 400).toString('latin1'), new RegExp(`element face ${count}\\b`));
});

test('measurements of a volume, from its link: the volume and area of the STL the same link gives', () => {
  const link = headless_link(MODEL);
  const m = JSON.parse(headless_measure(link, 24));
  assert.equal(m.dimension, 3);
  assert.equal(m.resolution, 24);
  // The STL's facets, read back: the divergence theorem and the triangles' areas.
  const stl = Buffer.from(headless_mesh(link, 'stl', 24));
  const count = stl.readUInt32LE(80);
  assert.equal(m.triangles, count);
  let volume = 0;
  let area = 0;
  const lo = [Infinity, Infinity, Infinity];
  const hi = [-Infinity, -Infinity, -Infinity];
  for (let t = 0; t < count; t++) {
    const p = [0, 1, 2].map((c) => [0, 1, 2].map((a) => stl.readFloatLE(84 + 50 * t + 12 + 12 * c + 4 * a)));
    const [a, b, c] = p;
    volume += (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0])) / 6;
    const u = [0, 1, 2].map((k) => b[k] - a[k]);
    const v = [0, 1, 2].map((k) => c[k] - a[k]);
    area += Math.hypot(u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]) / 2;
    for (const q of p) for (let k = 0; k < 3; k++) { lo[k] = Math.min(lo[k], q[k]); hi[k] = Math.max(hi[k], q[k]); }
  }
  assert.ok(m.volume > 0 && Math.abs(m.volume - volume) < 1e-4 * m.volume, `${m.volume} against ${volume}`);
  assert.ok(Math.abs(m.area - area) < 1e-4 * m.area, `${m.area} against ${area}`);
  for (let k = 0; k < 3; k++) {
    assert.ok(Math.abs(m.bbox[k] - lo[k]) < 1e-5 && Math.abs(m.bbox[k + 3] - hi[k]) < 1e-5, `${m.bbox}`);
  }
  assert.throws(() => headless_measure(link, 1), /resolution/);
});

test('GLB and 3MF of a volume: the GLB passes the Khronos glTF validator with no errors, the 3MF is an OPC zip', async () => {
  const link = headless_link(MODEL);
  const stl = Buffer.from(headless_mesh(link, 'stl', 24));
  const triangles = stl.readUInt32LE(80);
  const glb = new Uint8Array(headless_mesh(link, 'glb', 24));
  const report = await validator.validateBytes(glb, { uri: 'bezsolid.glb', format: 'glb', maxIssues: 100 });
  assert.equal(report.issues.numErrors, 0, JSON.stringify(report.issues.messages));
  assert.equal(report.issues.numWarnings, 0, JSON.stringify(report.issues.messages));
  assert.equal(report.info.totalTriangleCount, triangles);
  assert.match(report.info.generator, /^bezsolid /);
  const threeMf = Buffer.from(headless_mesh(link, '3mf', 24));
  assert.equal(threeMf.toString('latin1', 0, 4), 'PK\x03\x04');
  for (const name of ['[Content_Types].xml', '_rels/.rels', '3D/3dmodel.model']) {
    assert.ok(threeMf.includes(Buffer.from(name)), name);
  }
  assert.throws(() => headless_mesh(link, 'gltf', 24), /mesh format/);
});

test('the surface for the worker and the contour SVG of a patch', () => {
  const surface = headless_surface(MODEL, 24);
  assert.ok(surface instanceof Float32Array);
  const stl = Buffer.from(headless_mesh(MODEL, 'stl', 24));
  assert.equal(headless_approximate(), 0, 'a regular net is exact');
  assert.equal(surface.length, 18 * stl.readUInt32LE(80), 'six floats per vertex, three per triangle');
  const patch = JSON.stringify({ format: 'bezsolid', version: 1, solid: { kind: 'patch', degree: [2, 2], points: [
    [0, 0, -1], [0, 0.5, 0.25], [0, 1, -1], [0.5, 0, 0.25], [0.5, 0.5, 1], [0.5, 1, 0.25], [1, 0, -1], [1, 0.5, 0.25], [1, 1, -1]] } });
  const svg = headless_svg(patch);
  assert.match(svg, /<svg[^>]*viewBox/);
  assert.equal([...svg.matchAll(/<path /g)].length, 1);
  assert.throws(() => headless_svg(MODEL), /volume/);
});

test("the worker's contour stack of a volume: the slices reported as they are done", () => {
  const { headless_stack } = glue;
  const reports = [];
  const stack = headless_stack(MODEL, 2, (done, total) => reports.push([done, total]));
  assert.ok(stack instanceof Float64Array);
  assert.deepEqual(reports, [[1, 3], [2, 3], [3, 3]]);
  // Segments of six numbers: both ends on the slice's plane (w = 0, 1/2, 1 → z = -1, 0, 1 here,
  // the slice's mean z) and inside the net's box; the middle slice (ξ = 1 at its centre) has a
  // contour, the outer ones (ξ ≤ 0.25) may not.
  assert.ok(stack.length > 0 && stack.length % 6 === 0);
  const zs = new Set();
  for (let k = 0; k < stack.length; k += 3) {
    assert.ok([0, 1].every((a) => Math.abs(stack[k + a]) <= 1 + 1e-9));
    zs.add(stack[k + 2]);
  }
  assert.ok([...zs].every((z) => [-1, 0, 1].includes(z)), [...zs].join(' '));
  assert.ok(zs.has(0));
  // A progress report that throws changes nothing.
  assert.deepEqual(headless_stack(MODEL, 2, () => { throw new Error('ignored'); }), stack);
  // An axis is a `ParamAxis` (0, 1, 2): the glue refuses another number and the module lives on.
  assert.throws(() => headless_stack(MODEL, 3, () => {}), /invalid enum value/);
  assert.deepEqual(headless_stack(MODEL, glue.ParamAxis.W, () => {}), stack);
});

test('a model of many solids: its model file, link, mesh and surface, from the file and its link', () => {
  const tree = JSON.stringify({
    format: 'bezsolid',
    version: 1,
    solid: {
      kind: 'difference',
      of: [
        { kind: 'sphere', center: [0, 0, 0], radius: 1 },
        { kind: 'transform', rotate: [0, 90, 0], solid: { kind: 'cylinder', center: [0, 0, 0], axis: 'z', radius: 0.4 } },
      ],
    },
  });
  const link = headless_link(tree);
  assert.match(link, /^#v1\./);
  assert.equal(headless_model(link), headless_model(tree));
  const stl = Buffer.from(headless_mesh(link, 'stl', 32));
  const triangles = stl.readUInt32LE(80);
  assert.ok(triangles > 500, `${triangles} triangles`);
  assert.equal(stl.length, 84 + 50 * triangles);
  // The sphere pierced along x: no vertex inside the hole (distance from the x axis below 0.4).
  for (let t = 0; t < triangles; t++) {
    for (let v = 0; v < 3; v++) {
      const at = 84 + 50 * t + 12 + 12 * v;
      const [y, z] = [stl.readFloatLE(at + 4), stl.readFloatLE(at + 8)];
      assert.ok(Math.hypot(y, z) > 0.39, `${y} ${z}`);
    }
  }
  assert.equal(headless_surface(tree, 32).length, 18 * triangles);
  assert.throws(() => headless_mesh(tree.replace('"radius":1', '"radius":0'), 'stl', 32), /solid\.of\[0\]\.radius/);
});

test('bad input throws a clear error and never kills the module', () => {
  assert.throws(() => headless_model('#v1.AAAA'), /damaged/);
  assert.throws(() => headless_model('{"format": "bezsolid"'), /not a bezsolid model file/);
  assert.throws(() => headless_mesh(MODEL, 'xyz', 24), /unknown mesh format/);
  assert.throws(() => headless_mesh(MODEL, 'stl', 100000), /outside/);
  const patch = JSON.stringify({ format: 'bezsolid', version: 1, solid: { kind: 'patch', degree: [1, 1], points: [[0, 0, 1], [0, 1, 1], [1, 0, 1], [1, 1, 1]] } });
  assert.throws(() => headless_mesh(patch, 'stl', 24), /patch/);
  // Still alive after the errors.
  assert.ok(headless_mesh(MODEL, 'stl', 8).length > 84);
});

test('a free-form model: its result surface and mesh files, from the file and its link', () => {
  const { headless_esc_surface, headless_esc_mesh, is_free_form } = glue;
  const { FreeFormView } = page;
  const file = JSON.stringify({
    format: 'bezsolid',
    version: 1,
    solid: {
      kind: 'esc',
      operation: 'difference',
      operands: [{ example: 'icosphere' }, { example: 'torus', offset: [0, 0, 0.5] }],
    },
  });
  assert.ok(is_free_form(file));
  assert.ok(!is_free_form(MODEL));
  const view = new FreeFormView();
  view.open(file);
  const link = view.link();
  assert.ok(is_free_form(link));
  const floats = headless_esc_surface(link, 24);
  assert.deepEqual(floats, headless_esc_surface(file, 24));
  const triangles = floats.length / 18;
  assert.ok(triangles > 500);
  // Every vertex is inside the unit sphere (the PN icosphere is within 1e-3 of it) and outside the
  // torus moved up by 0.5, to the surface's tolerance.
  for (let v = 0; v < floats.length; v += 6) {
    const [x, y, z] = [floats[v], floats[v + 1], floats[v + 2]];
    assert.ok(Math.hypot(x, y, z) < 1.01, `${x} ${y} ${z}`);
    const r = Math.hypot(x, y) - 1;
    assert.ok(Math.hypot(r, z - 0.5) > 0.39, `${x} ${y} ${z}`);
  }
  // The export is the closed mesh at the resolution: one triangle count in STL and OBJ.
  const stl = headless_esc_mesh(link, 'stl', 24);
  const obj = new TextDecoder().decode(headless_esc_mesh(link, 'obj', 24));
  const faces = obj.split('\n').filter((l) => l.startsWith('f ')).length;
  assert.ok(faces > 500);
  assert.equal(new DataView(stl.buffer, stl.byteOffset).getUint32(80, true), faces);
  assert.throws(() => headless_esc_mesh(link, 'gltf', 24), /unknown mesh format/);
  assert.throws(() => headless_esc_surface('#v1.AAAA', 24), /the link is damaged/);
  assert.throws(() => view.open('{"format":"bezsolid","version":1,"solid":{"kind":"esc","operands":[{"example":"teapot"}]}}'), /no example/);
  // The choices are typed (`Operation`, `FreeFormExample`, `FreeFormDisplay`): another name is a
  // clear error that changes nothing.
  assert.equal(view.operation(), 'difference');
  assert.throws(() => view.set_operation('xor'), /unknown operation: use "union"/);
  assert.throws(() => view.set_example(0, 'teapot'), /unknown example/);
  assert.throws(() => view.set_display('wireframe'), /unknown display/);
  assert.equal(view.link(), link);
  view.set_operation('none');
  assert.equal(view.operation(), 'none');
  view.set_example(0, 'torus');
  assert.equal(view.operand_name(0), 'torus');
  view.free();
});

test("PLaSM scripts: the paper's examples draw and export; endless recursion stops within wasm's stack", () => {
  const { headless_plasm, headless_plasm_mesh, plasm_examples, script_link, script_of } = glue;
  const examples = JSON.parse(plasm_examples());
  assert.deepEqual(examples.map((e) => e.id), ['3.1', '3.3', '4.1', '4.4', '4.6', '4.7', '4.8', '4.7-bezier-grid']);
  for (const e of examples) {
    const run = headless_plasm(e.source);
    const report = JSON.parse(run.report());
    const floats = run.take_floats();
    run.free();
    assert.equal(report.error, null, `${e.id}: ${JSON.stringify(report.error)}`);
    assert.ok(floats.length > 0 && floats.length % 30 === 0, e.id);
    // The script travels in a link.
    assert.equal(script_of(script_link(e.source)), e.source);
  }
  // Script 4.4's OBJ: the surface's 800 triangles on 441 vertices, and four curves of 32 segments.
  const fig1 = examples.find((e) => e.id === '4.4').source;
  const obj = Buffer.from(headless_plasm_mesh(fig1, 'obj')).toString();
  const lines = obj.split('\n');
  assert.equal(lines.filter((l) => l.startsWith('f ')).length, 800);
  assert.equal(lines.filter((l) => l.startsWith('l ')).length, 128);
  assert.equal(lines.filter((l) => l.startsWith('v ')).length, 441 + 4 * 33);
  // Recursion as deep as the limit allows, in the module's own (1 MiB) stack: an error, not a trap.
  for (const script of [
    'DEF f (n::IsReal) = f:(n + 1);\nf:0;',
    'DEF s (n::IsReal) = <<<<<<<<<<<<<<<<<<<<<<<<s:(n + 1)>>>>>>>>>>>>>>>>>>>>>>>>;\ns:0;',
    `DEF p (n::IsReal) = ${'1+('.repeat(200)}p:(n+1)${')'.repeat(200)};\np:0;`,
    'DEF Pred = C:-:1;\nDEF Choose (n,k::IsNat) = IF:<OR ~ [C:EQ:0 ~ S2, EQ], K:1, Choose ~ AA:Pred * / >:<n,k>;\nChoose:<1000, 999>;',
  ]) {
    const run = headless_plasm(script);
    const report = JSON.parse(run.report());
    run.free();
    assert.equal(report.error.kind, 'Limit', script);
  }
  assert.throws(() => headless_plasm_mesh('1 +;', 'obj'), /line 1, column 3/);
  // A solid blended from surfaces opens as its Bézier volume (ξ = 1/4: the solid is the map's image);
  // a surface does not.
  const { script_volume_model } = glue;
  const slab = `${fig1}DEF Body = Bezier:S3:<Surf1, <S1:Surf1, S2:Surf1, K:4 + S3:Surf1>>;\nMAP:Body:(Domain:4 * Domain:4 * Domain:2);\n`;
  const report = JSON.parse(headless_plasm(slab).report());
  const solidAt = report.values.findIndex((v) => v.volume);
  assert.equal(solidAt, 5, JSON.stringify(report.values));
  const volume = JSON.parse(script_volume_model(slab, solidAt)).solid;
  assert.equal(volume.kind, 'volume');
  assert.deepEqual(volume.degree, [3, 3, 1]);
  assert.ok(volume.points.every((p) => p.length === 4 && p[3] === 0.25));
  assert.deepEqual(volume.points[1].map((x) => Math.round(x * 1e9) / 1e9), [0, 0, 4, 0.25]);
  assert.throws(() => script_volume_model(slab, 0), /that value is a surface in 3 coordinates/);
  // The module still works after all of that.
  assert.ok(JSON.parse(headless_plasm(examples[0].source).report()).error === null);
});

test("the worker's protocol: a job as JSON in, one buffer out, as the worker decodes it", () => {
  const { run_job } = glue;
  const job = (message, progress = () => {}) => {
    const bytes = run_job(new TextEncoder().encode(JSON.stringify(message)), progress);
    const length = new DataView(bytes.buffer, bytes.byteOffset).getUint32(0, true);
    const header = JSON.parse(new TextDecoder().decode(bytes.subarray(4, 4 + length)));
    const start = bytes.byteOffset + Math.ceil((4 + length) / 8) * 8;
    const type = { bytes: Uint8Array, f32: Float32Array, f64: Float64Array }[header.payload];
    return { header, data: new type(bytes.buffer.slice(start, bytes.byteOffset + bytes.byteLength)) };
  };
  const surface = job({ kind: 'surface', model: MODEL, resolution: 16 });
  assert.equal(surface.header.approximate, 0);
  assert.deepEqual(surface.data, headless_surface(MODEL, 16));
  const reports = [];
  const stack = job({ kind: 'stack', model: MODEL, axis: 2 }, (done, total) => reports.push([done, total]));
  assert.ok(stack.data instanceof Float64Array && stack.data.length % 6 === 0 && stack.data.length > 0);
  assert.deepEqual(reports.at(-1), [3, 3]);
  const stl = job({ kind: 'mesh', model: MODEL, format: 'stl', resolution: 16 }).data;
  assert.deepEqual(stl, headless_mesh(MODEL, 'stl', 16));
  const plasm = job({ kind: 'plasm', script: 'MAP:(CONS:<S1, S1>):(Domain:4);' });
  assert.equal(JSON.parse(plasm.header.report).error, null);
  const volume = job({ kind: 'plasm-volume', script: 'MAP:<S1, S2, S3 + S1>:(Domain:2 * Domain:2 * Domain:2);', index: 0 });
  assert.equal(JSON.parse(new TextDecoder().decode(volume.data)).solid.kind, 'volume');
  assert.throws(() => job({ kind: 'format-disk' }), /not a job/);
  assert.throws(() => job({ kind: 'surface', model: '{', resolution: 16 }), /model/);
});
