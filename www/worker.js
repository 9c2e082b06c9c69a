// The page's worker: long work off the main thread with the same wasm module, so that a fine
// resolution or a large export never freezes the page. One job at a time; the page cancels a job
// by terminating the worker and starting another.
import init, {
  headless_surface, headless_mesh, headless_esc_surface, headless_esc_mesh, headless_plasm,
  headless_plasm_mesh,
} from './pkg/bezsolid_web.js';

const ready = init();

const jobs = {
  surface: ({ model, resolution }) => headless_surface(model, resolution),
  mesh: ({ model, format, resolution }) => headless_mesh(model, format, resolution),
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
};

self.onmessage = async (event) => {
  const { id, kind } = event.data;
  try {
    await ready;
    const t0 = performance.now();
    const result = jobs[kind](event.data);
    const { data, ...extra } = ArrayBuffer.isView(result) ? { data: result } : result;
    self.postMessage({ id, data, ...extra, ms: performance.now() - t0 }, [data.buffer]);
  } catch (err) {
    self.postMessage({ id, error: String(err?.message ?? err) });
  }
};
