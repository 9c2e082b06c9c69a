// The wasm modules and when each is fetched. The page's module holds what the first frame and
// editing need; it is built twice, drawing with WebGPU alone or with the WebGL2 fallback too, and
// the page picks one before it downloads either. The tools' module (the worker's jobs: fine
// meshes, contour stacks, exports, free-form results, scripts) is fetched by the workers, or here
// the first time the page has to run such work itself (no workers).
//
// Each module is fetched under its content-hashed name (assets.js, written by the build), which
// the browser keeps for good: a new build is a new name.
import { WASM } from './pkg/assets.js';

const loads = new Map();

// The smallest module with a WebAssembly SIMD instruction (`i32.const 0; i8x16.splat` in a
// function returning a v128): it validates only where the modules, built with SIMD, can run.
const SIMD_PROBE = new Uint8Array([
  0x00, 0x61, 0x73, 0x6d, 0x01, 0x00, 0x00, 0x00, // the magic and version 1
  0x01, 0x05, 0x01, 0x60, 0x00, 0x01, 0x7b, // types: () -> v128
  0x03, 0x02, 0x01, 0x00, // one function of that type
  0x0a, 0x08, 0x01, 0x06, 0x00, 0x41, 0x00, 0xfd, 0x0f, 0x0b, // its body
]);

/** Whether this browser runs WebAssembly SIMD (Chrome and Edge 91+, Firefox 89+, Safari 16.4+). */
export const hasSimd = () => typeof WebAssembly === 'object' && WebAssembly.validate(SIMD_PROBE);

/** The glue of module `name` (`bezsolid_page`, `bezsolid_page_gl`, `bezsolid_web`), initialised
 * once: `{ glue, wasm, name }` (`wasm`: its exports, with the memory). */
function load(name) {
  if (!loads.has(name)) {
    // The module is fetched and compiled while its glue loads.
    loads.set(name, (async () => {
      if (!hasSimd()) {
        throw new Error('this browser lacks WebAssembly SIMD, which the modeler is built with '
          + '(Chrome and Edge 91 or later, Firefox 89 or later, Safari 16.4 or later have it)');
      }
      const [glue, module] = await Promise.all([
        import(`./pkg/${name}.js`),
        WebAssembly.compileStreaming(fetch(WASM[name])),
      ]);
      const wasm = await glue.default({ module_or_path: module });
      performance.mark(`bezsolid:init ${name}`); // read by tests/latency.mjs
      return { glue, wasm, name };
    })());
  }
  return loads.get(name);
}

/** Whether this browser draws with WebGPU: it has `navigator.gpu` and gives an adapter. */
async function hasWebGpu() {
  if (!navigator.gpu) return false;
  try {
    return Boolean(await navigator.gpu.requestAdapter());
  } catch {
    return false;
  }
}

/** The page's module for the backend asked for (`auto`, `webgpu`, `webgl2`): WebGPU alone where
 * the browser has an adapter (or WebGPU is asked for), else the build with WebGL2. */
export async function pageModule(requested) {
  const gpu = requested === 'webgpu' || (requested === 'auto' && await hasWebGpu());
  return load(gpu ? 'bezsolid_page' : 'bezsolid_page_gl');
}

/** The page's module with WebGL2, for a fallback after WebGPU failed to start. */
export const webglModule = () => load('bezsolid_page_gl');

/** The tools' glue on this thread (for a page without workers), fetched once. */
export const tools = async () => (await load('bezsolid_web')).glue;
