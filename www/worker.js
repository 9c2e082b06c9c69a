// The page's worker: long work off the main thread with the same wasm module, so that a fine
// resolution, a folded net or a large export never freezes the page. One job at a time (work.js
// sends the next when this one answers); the page cancels a job by terminating the worker.
// Replies: { id, progress: [done, total] } on the way, then { id, data, ms, ... } (with
// `approximate` for the Bézier models' jobs) or { id, error }.
import init, {
  headless_surface, headless_mesh, headless_esc_surface, headless_esc_mesh, headless_plasm,
  headless_plasm_mesh, headless_stack, headless_svg, script_patch_model, headless_approximate,
} from './pkg/bezsolid_web.js';

const ready = init();

// With what a job on a Bézier model made, how many of its evaluations ran out of their work
// budget (where the net folds over itself very many times: the result is approximate there).
const counted = (data) => ({ data, approximate: headless_approximate() });

const jobs = {
  surface: ({ model, resolution }) => counted(headless_surface(model, resolution)),
  mesh: ({ model, format, resolution }) => counted(headless_mesh(model, format, resolution)),
  // The zero contour of each slice of a volume, a progress report after each slice.
  stack: ({ model, axis }, progress) => counted(headless_stack(model, axis, progress)),
  svg: ({ model }) => counted(new TextEncoder().encode(headless_svg(model))),
  'esc-surface': ({ model, resolution }) => headless_esc_surface(model, resolution),
  'esc-mesh': ({ model, format, resolution }) => headless_esc_mesh(model, format, resolution),
  // A script's run: the drawing and its report (values, warnings, the error if any).
  plasm: ({ script }) => {
    const run = headless_plasm(script);
    const report = run.report();
    const data = run.take_floats();
    run.free();
    return { data, report };
  },
  'plasm-mesh': ({ model, format }) => headless_plasm_mesh(model, format),
  // The Bézier net of a script's surface (the script runs again): a patch model file.
  'plasm-patch': ({ script, index }) => new TextEncoder().encode(script_patch_model(script, index)),
};

self.onmessage = async (event) => {
  const { id, kind } = event.data;
  try {
    await ready;
    const t0 = performance.now();
    const progress = (done, total) => self.postMessage({ id, progress: [done, total] });
    const result = jobs[kind](event.data, progress);
    const { data, ...extra } = ArrayBuffer.isView(result) ? { data: result } : result;
    self.postMessage({ id, data, ...extra, ms: performance.now() - t0 }, [data.buffer]);
  } catch (err) {
    // A trap (a bug, or memory exhausted) may leave the module broken: the page starts another.
    self.postMessage({ id, error: String(err?.message ?? err), fatal: err instanceof WebAssembly.RuntimeError });
  }
};
