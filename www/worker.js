// The page's worker: long work off the main thread in the tools' wasm module, so that a fine
// resolution, a folded net or a large export never freezes the page. The jobs and their results
// are the Rust crate's (`jobs.rs`, `run_job`): this file carries them. One job at a time (work.js
// sends the next when this one answers); the page cancels a job by terminating the worker.
// Replies: { id, progress: [done, total] } on the way, then { id, data, ms, ... } (with
// `approximate`, `report` or `kept` where the job gives them) or { id, error }. A worker keeps its
// last mesh of a model of many solids (`kept`: the blocks it took from it): it is given the same
// share each time.
import init, { run_job } from './pkg/bezsolid_web.js';
import { WASM } from './pkg/assets.js';
import { decode } from './wire.js';

// The tools' module (not the page's), under its content-hashed name: the browser's cache keeps it
// across loads.
const ready = init({ module_or_path: WASM.bezsolid_web });

self.onmessage = async ({ data: { id, ...job } }) => {
  try {
    await ready;
    const t0 = performance.now();
    const progress = (done, total) => self.postMessage({ id, progress: [done, total] });
    const { data, ...extra } = decode(run_job(new TextEncoder().encode(JSON.stringify(job)), progress));
    self.postMessage({ id, data, ...extra, ms: performance.now() - t0 }, [data.buffer]);
  } catch (err) {
    // A trap (a bug, or memory exhausted) may leave the module broken: the page starts another.
    self.postMessage({ id, error: String(err?.message ?? err), fatal: err instanceof WebAssembly.RuntimeError });
  }
};
