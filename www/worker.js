// The page's worker: meshes a volume's surface off the main thread with the same wasm module, so a
// fine resolution never freezes the page. One job at a time; the page sends only the newest.
import init, { headless_surface } from './pkg/bezsolid_web.js';

const ready = init();

self.onmessage = async (event) => {
  const { id, model, resolution } = event.data;
  try {
    await ready;
    const t0 = performance.now();
    const data = headless_surface(model, resolution);
    self.postMessage({ id, data, ms: performance.now() - t0 }, [data.buffer]);
  } catch (err) {
    self.postMessage({ id, error: String(err?.message ?? err) });
  }
};
