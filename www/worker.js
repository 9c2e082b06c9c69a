// The page's worker: long work off the main thread with the same wasm module, so that a fine
// resolution or a large export never freezes the page. One job at a time; the page cancels a job
// by terminating the worker and starting another.
import init, {
  headless_surface, headless_mesh, headless_esc_surface, headless_esc_mesh,
} from './pkg/bezsolid_web.js';

const ready = init();

const jobs = {
  surface: ({ model, resolution }) => headless_surface(model, resolution),
  mesh: ({ model, format, resolution }) => headless_mesh(model, format, resolution),
  'esc-surface': ({ model, resolution }) => headless_esc_surface(model, resolution),
  'esc-mesh': ({ model, format, resolution }) => headless_esc_mesh(model, format, resolution),
};

self.onmessage = async (event) => {
  const { id, kind } = event.data;
  try {
    await ready;
    const t0 = performance.now();
    const data = jobs[kind](event.data);
    self.postMessage({ id, data, ms: performance.now() - t0 }, [data.buffer]);
  } catch (err) {
    self.postMessage({ id, error: String(err?.message ?? err) });
  }
};
