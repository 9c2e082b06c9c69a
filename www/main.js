// The page: brings up the modeler (Rust, wasm) and composes its parts. All state and logic are in
// Rust; the page's modules only wire DOM events, size the canvases and fill the panels:
//
//   ui.js        elements, the status line, downloads     storage.js  what this browser keeps
//   work.js      Web Workers, the work list, followers    view3d.js   the 3D view's input
//   bezier.js    the Bézier mode (2D view, panel)         freeform.js the Free-form mode
//   outline.js   the parts of a model of many solids
//   script.js    the Script mode (editor, runs)           files.js    links, files, exports
//   hyperfun.js  the HyperFun mode (program, section)     code.js     the modes' code editor
//   modules.js   which wasm module is fetched, and when
//
// Each part gets `app`, what they share: the page module's glue (`glue`), the wasm objects (`modeler`, `ff`, `sv`, `hv`, `viewer`), the
// canvases, the work list and workers, the mode (`workspace()`, `setWorkspace`), and the page's
// verbs (`redraw`, `changed`, `attempt`, `resize`, `resize3`, `panel`). A part's own face is set on
// `app` as it is made (`app.bezier`, `app.freeform`, `app.script`, `app.hyperfun`, `app.files`); parts call each
// other through `app` when events come, never while they are set up.
import { pageModule, tools, webglModule } from './modules.js';
import { $, say, messageOf, setupPickers, setupStatus } from './ui.js';
import { KEYS, storage } from './storage.js';
import { runner, team, workList } from './work.js';
import { setupBezier } from './bezier.js';
import { setupOutline } from './outline.js';
import { setupFreeForm } from './freeform.js';
import { setupScript } from './script.js';
import { setupHyperfun } from './hyperfun.js';
import { setupFiles } from './files.js';
import { setupView3d } from './view3d.js';

const WORKSPACES = ['bezier', 'freeform', 'script', 'hyperfun'];
// The modes whose views are programs' drawings (an editor where the 2D view is).
const PROGRAMS = ['script', 'hyperfun'];
const BACKENDS = ['auto', 'webgpu', 'webgl2'];

// A canvas keeps its first context type: falling back to WebGL2 needs a fresh one.
function freshCanvas(old) {
  const canvas = old.cloneNode(false);
  old.replaceWith(canvas);
  return canvas;
}

// The page's module is chosen for the backend before it is fetched; if WebGPU then fails to start,
// the WebGL2 build is fetched and the whole page uses it (objects of two modules never mix).
// The 3D view's GPU comes up beside the 2D view's (each view has its own device): its promise
// settles to `{ viewer }` or `{ err }`, so that a failure waits, handled, until it is read.
async function bringUp(canvas, canvas3, requested) {
  const module = await pageModule(requested);
  // The backend the 2D view comes up on: the WebGPU build draws with WebGPU alone, and the WebGL2
  // build is chosen where the browser gave no adapter.
  const backend = requested !== 'auto' ? requested : (module.name === 'bezsolid_page' ? 'webgpu' : 'webgl2');
  const view3 = (m, on) => m.glue.start_3d(canvas3, on).then((viewer) => {
    performance.mark('bezsolid:viewer');
    return { viewer };
  }, (err) => ({ err }));
  const three = view3(module, backend);
  try {
    return { module, canvas, canvas3, three, modeler: await module.glue.start(canvas, requested) };
  } catch (err) {
    if (requested === 'webgl2') throw err;
    console.warn(`bezsolid: ${requested} failed (${messageOf(err)}); falling back to WebGL2`);
    const gl = await webglModule();
    const fresh = freshCanvas(canvas);
    // The 3D view too, on a fresh canvas, from the WebGL2 build.
    (await three).viewer?.free();
    canvas3 = freshCanvas(canvas3);
    return {
      module: gl, canvas: fresh, canvas3, three: view3(gl, 'webgl2'),
      modeler: await gl.glue.start(fresh, 'webgl2'), fellBack: true,
    };
  }
}

/** Opens autosaved `text` with `open`; a stale or foreign value is dropped, quietly. */
function restore(what, text, open) {
  if (!text) return;
  try {
    open(text);
  } catch (err) {
    console.warn(`bezsolid: the autosaved ${what} could not be restored (${messageOf(err)})`);
  }
}

async function main() {
  setupStatus();
  setupPickers();
  let requested = new URLSearchParams(location.search).get('backend') ?? 'auto';
  if (!BACKENDS.includes(requested)) {
    say(`Unknown backend "${requested}" in the address; choosing automatically.`, 'warn');
    requested = 'auto';
  }
  // Marks for tests/latency.mjs: the script runs, the 2D view's GPU is up, the 3D view's.
  performance.mark('bezsolid:start');
  const { module, canvas, canvas3, three, modeler, fellBack } = await bringUp($('view'), $('view3d'), requested);
  performance.mark('bezsolid:modeler');
  const { glue, wasm } = module;
  const { FreeFormView, ScriptViewer, gpu_objects } = glue;
  const badge = $('backend');
  badge.textContent = modeler.backend();
  badge.dataset.backend = modeler.backend();
  badge.title = `Graphics backend: ${modeler.backend()} (${modeler.adapter() || 'adapter'})`;
  if (fellBack) say('WebGPU could not start here; drawing with WebGL2.', 'warn');

  // The autosaved models: the Bézier one (its history starts here), the Free-form scene.
  restore('model', storage.get(KEYS.model), (text) => modeler.load_model(text));
  modeler.forget_history();
  const ff = new FreeFormView();
  restore('free-form model', storage.get(KEYS.freeform), (text) => ff.open(text));
  ff.forget_history();
  let ffSavedRevision = ff.revision(); // the revision last autosaved (or restored)
  const sv = new ScriptViewer();
  const hv = new ScriptViewer();

  // The 3D view has its own device (a WebGL2 device draws on one canvas only); it is optional: the
  // 2D editor works on without it.
  let viewer = null;
  const { viewer: started, err } = await three;
  if (started) {
    viewer = started;
    $('loading-3d').hidden = true;
  } else {
    $('loading-3d').textContent = `The 3D view could not start: ${messageOf(err)}`;
    console.warn(`bezsolid: no 3D view (${messageOf(err)})`);
  }

  // Long work runs in Web Workers (work.js): the fine surfaces and contour stacks that follow the
  // models, exports, scripts. Without workers it runs on the page.
  // The surfaces are made by a team of workers in shares: one worker a core the page may use (one
  // core is left to the page), at most 8; `?workers=N` (1 to 8) in the address asks for N.
  const runners = { surface: null, export: null };
  const asked = new URLSearchParams(location.search).get('workers');
  let workers = Math.min(8, Math.max(1, (navigator.hardwareConcurrency || 2) - 1));
  if (asked !== null) {
    if (/^[1-8]$/.test(asked)) workers = Number(asked);
    else say(`"workers=${asked}" in the address is not 1 to 8; using ${workers}.`, 'warn');
  }
  try {
    runners.surface = team(workers);
    runners.export = runner();
    modeler.set_external_surface(true);
  } catch (err) {
    console.warn(`bezsolid: no Web Worker (${messageOf(err)}); long work runs on the page`);
  }

  let workspace = 'bezier';
  const VIEW2 = 1;
  const VIEW3 = 2;
  const app = {
    glue, wasm, modeler, ff, sv, hv, viewer, workers, canvas, canvas3, runners, VIEW2, VIEW3,
    work: workList($('work')),
    // `latency`: from an edit (`lastEdit`) to the end of the first frame drawn after it.
    // `moves`, `applied`, `frames`: pointer moves coalesced, applied, and frames drawn;
    // `latencies`: the last input → drawn figures.
    stats: { lastRender: 0, lastRender3: 0, lastEdit: 0, drawnEdit: 0, latency: 0, latencies: [], moves: 0, applied: 0, frames: 0 },
    workspace: () => workspace,
    /** The Bézier panel's snapshot of the editor, its last frame and its 3D view. */
    panel: () => JSON.parse(modeler.panel()),
  };
  const part = () => ({ bezier: app.bezier, freeform: app.freeform, script: app.script, hyperfun: app.hyperfun })[workspace];

  app.setWorkspace = (name) => {
    workspace = WORKSPACES.includes(name) ? name : 'bezier';
    document.body.dataset.workspace = workspace;
    for (const r of document.querySelectorAll('input[name="workspace"]')) r.checked = r.value === workspace;
    storage.set(KEYS.workspace, workspace);
  };

  // Input coalesced to one step a frame: of a stream of pointer moves for one gesture (`key`),
  // only the newest is applied, just before the frame is drawn; the others are dropped, never
  // queued. `apply(since)` gets when the oldest move it stands for came (for the input → drawn
  // figure). `flushInput()` applies what waits now (before a gesture ends).
  const INPUT = 4;
  const waiting = new Map(); // key → { apply, since }
  app.coalesce = (key, apply) => {
    const since = waiting.get(key)?.since ?? performance.now();
    waiting.set(key, { apply, since });
    app.stats.moves += 1;
    app.redraw(INPUT);
  };
  /** Drops the move waiting for gesture `key` (the gesture was cancelled). */
  app.dropInput = (key) => waiting.delete(key);
  app.flushInput = () => {
    for (const [key, { apply, since }] of [...waiting]) {
      waiting.delete(key);
      app.stats.applied += 1;
      apply(since);
    }
  };

  // Frames: `redraw(VIEW2 | VIEW3)` asks for the views on the next animation frame (once however
  // often it is asked); the frame then brings the panel up to date.
  let pending = 0;
  app.redraw = (which = VIEW2 | VIEW3) => {
    if (pending) {
      pending |= which;
      return;
    }
    pending = which;
    requestAnimationFrame(() => {
      app.flushInput(); // may ask for views: they join this frame
      const todo = pending;
      pending = 0;
      if (todo & VIEW2 && workspace === 'bezier') {
        const t0 = performance.now();
        modeler.render();
        app.stats.lastRender = performance.now() - t0;
      }
      if (todo & VIEW3 && viewer) {
        const t0 = performance.now();
        part().render3d(viewer);
        app.stats.lastRender3 = performance.now() - t0;
        part().follow();
      }
      const { stats } = app;
      if (todo & (VIEW2 | VIEW3)) stats.frames += 1;
      if (stats.lastEdit > stats.drawnEdit) {
        stats.latency = performance.now() - stats.lastEdit;
        stats.drawnEdit = stats.lastEdit;
        stats.latencies.push(stats.latency);
        if (stats.latencies.length > 240) stats.latencies.shift();
      }
      for (const p of [app.bezier, app.freeform, app.script, app.hyperfun]) p.prune();
      part().update();
      updateDebug();
    });
  };

  // Autosave a moment after the last change, and at once when the page is hidden or closed.
  let saveTimer = 0;
  const saveNow = () => {
    clearTimeout(saveTimer);
    saveTimer = 0;
    // The free-form scene only when it changed (with an imported mesh it is megabytes); if the
    // browser refuses it, the stale copy is dropped rather than restored on the next visit.
    if (ff.revision() !== ffSavedRevision) {
      if (storage.set(KEYS.freeform, ff.model_json())) {
        ffSavedRevision = ff.revision();
      } else {
        storage.remove(KEYS.freeform);
        say('The free-form scene is too large to keep in this browser; use Export → Model file.', 'warn');
      }
    }
    if (!storage.set(KEYS.model, modeler.model_json())) {
      say('The model could not be saved in this browser (storage is full or blocked); use Export → Model file.', 'warn');
    }
  };
  app.changed = () => {
    app.redraw();
    clearTimeout(saveTimer);
    saveTimer = setTimeout(saveNow, 300);
  };
  addEventListener('pagehide', () => { if (saveTimer) saveNow(); });
  document.addEventListener('visibilitychange', () => { if (document.hidden && saveTimer) saveNow(); });

  // An edit through a model: redraw and autosave, or say why not (the panel shows the model as it
  // stayed). Returns whether it was made.
  app.attempt = (what, f) => {
    try {
      f();
      app.changed();
      return true;
    } catch (err) {
      say(`${what}: ${messageOf(err)}`, 'error');
      part().update();
      return false;
    }
  };

  // The debug overlay (D in the 2D view, or its button): frame times, the workers', GPU objects.
  const debug = $('debug');
  const updateDebug = () => {
    if (debug.hidden) return;
    const { lastRender, lastRender3, lastEdit, latency } = app.stats;
    const gpu = gpu_objects();
    const workers = [app.bezier, app.freeform].flatMap((p) => p.timings())
      .map(([name, f]) => `${name}: ${f ? f.lastMs().toFixed(1) : '–'} ms\n`).join('');
    debug.textContent = `2D frame: ${lastRender.toFixed(1)} ms (evaluate, contour, draw)\n`
      + `3D frame: ${lastRender3.toFixed(1)} ms (surface, spheres, draw)\n`
      + workers
      + `input → drawn: ${lastEdit ? latency.toFixed(1) : '–'} ms (the last edit to the frame after it)\n`
      + `GPU: ${gpu[0]} buffers, ${gpu[1]} textures (${gpu[2]} made); wasm memory ${(wasm.memory.buffer.byteLength / 2 ** 20).toFixed(1)} MiB`;
    document.body.dataset.renderMs = lastRender.toFixed(2);
    if (lastEdit) document.body.dataset.latencyMs = latency.toFixed(2);
    document.body.dataset.render3Ms = lastRender3.toFixed(2);
  };
  app.toggleDebug = () => {
    debug.hidden = !debug.hidden;
    $('debug-toggle').setAttribute('aria-pressed', String(!debug.hidden));
    app.redraw();
  };
  $('debug-toggle').addEventListener('click', app.toggleDebug);

  // The canvases follow their boxes and the device pixel ratio.
  const ratio = () => window.devicePixelRatio || 1;
  app.resize = () => {
    const rect = canvas.getBoundingClientRect();
    const [w, h] = modeler.resize(rect.width, rect.height, ratio());
    if (canvas.width !== w) canvas.width = w;
    if (canvas.height !== h) canvas.height = h;
    app.redraw();
  };
  app.resize3 = () => {
    if (!viewer) return;
    const rect = canvas3.getBoundingClientRect();
    const [w, h] = modeler.resize_3d(viewer, rect.width, rect.height, ratio());
    ff.resize(viewer, rect.width, rect.height, ratio());
    sv.resize(viewer, rect.width, rect.height, ratio());
    hv.resize(viewer, rect.width, rect.height, ratio());
    if (canvas3.width !== w) canvas3.width = w;
    if (canvas3.height !== h) canvas3.height = h;
    app.redraw(VIEW3);
  };

  // Undo and redo in the Bézier and Free-form modes: the buttons, and the shortcuts anywhere but
  // in a text field (which keeps its own, as the script editor does).
  const history = (redo) => {
    if (part().history?.(redo)) app.changed();
  };
  $('undo').addEventListener('click', () => history(false));
  $('redo').addEventListener('click', () => history(true));
  document.addEventListener('keydown', (e) => {
    if (!(e.ctrlKey || e.metaKey) || e.altKey || PROGRAMS.includes(workspace)) return;
    const tag = e.target?.tagName;
    if ((tag === 'INPUT' && e.target.type !== 'radio') || tag === 'TEXTAREA') return;
    const key = e.key.toLowerCase();
    if (key === 'z' || key === 'y') {
      e.preventDefault();
      history(key === 'y' || e.shiftKey);
    }
  });

  app.outline = setupOutline(app);
  app.bezier = setupBezier(app);
  app.freeform = setupFreeForm(app);
  app.script = setupScript(app);
  app.hyperfun = setupHyperfun(app);
  app.files = setupFiles(app);
  setupView3d(app);

  // The mode last used, then a link in the address over it.
  app.setWorkspace(storage.get(KEYS.workspace));
  app.files.openFromAddress();
  for (const radio of document.querySelectorAll('input[name="workspace"]')) {
    radio.addEventListener('change', () => {
      if (!radio.checked) return;
      app.setWorkspace(radio.value);
      app.resize();
      app.resize3();
      if (PROGRAMS.includes(workspace)) app[workspace].runIfNew();
      app.redraw();
    });
  }

  new ResizeObserver(app.resize).observe(canvas);
  new ResizeObserver(app.resize3).observe(canvas3);
  // A media query matches one ratio: listen again at the new one after each change (zoom, new screen).
  const watchRatio = () => {
    matchMedia(`(resolution: ${ratio()}dppx)`).addEventListener('change', () => {
      app.resize();
      watchRatio();
    }, { once: true });
  };
  watchRatio();
  app.resize();
  app.resize3();

  // Hooks for tests and tools: the objects, and what the page holds (GPU objects the renderers
  // hold and made, `[buffers, textures, made]`; the wasm memory in bytes).
  window.bezsolid = {
    modeler, ff, sv, hv, canvas, canvas3, viewer, saveNow, stats: app.stats,
    redraw: app.redraw,
    setWorkspace: app.setWorkspace,
    runScript: app.script.run,
    drawHyperfun: app.hyperfun.run,
    gpuObjects: () => [...gpu_objects()],
    // The tools' module on the page (what writes the exports), fetched on first use.
    tools,
    wasmMemory: () => wasm.memory.buffer.byteLength,
  };
  $('loading').hidden = true;
  requestAnimationFrame(() => {
    modeler.render();
    if (viewer && !PROGRAMS.includes(workspace)) part().render3d(viewer);
    part().update();
    saveNow();
    if (PROGRAMS.includes(workspace)) app[workspace].runIfNew();
    // The first frame is drawn: how long after navigation (the benchmarks read it).
    document.body.dataset.firstFrameMs = performance.now().toFixed(1);
    document.body.dataset.ready = 'true';
    // Then the workers fetch the tools' module, in the background, ready for the first long job;
    // and the service worker keeps the page and its modules so that it opens offline next time.
    setTimeout(() => {
      runners.surface?.warm();
      runners.export?.warm();
      navigator.serviceWorker?.register('./sw.js').catch((err) => {
        console.warn(`bezsolid: no offline copy (${messageOf(err)})`);
      });
    }, 0);
  });
}

window.addEventListener('unhandledrejection', (e) => say(`Error: ${e.reason?.message ?? e.reason}`, 'error'));
main().catch((err) => {
  $('loading').textContent = 'The modeler could not start.';
  $('loading-3d').textContent = 'The 3D view could not start.';
  say(`The modeler could not start: ${messageOf(err)}`, 'error');
  console.error(err);
});
