// The page: brings up the modeler (Rust, wasm) on the canvas and forwards input to it. All state and
// logic are in Rust; this file only wires DOM events, sizes the canvas and fills the side panel.
import init, {
  start, start_3d, FreeFormView, is_free_form, headless_esc_mesh, headless_esc_surface,
  ScriptViewer, headless_plasm, headless_plasm_mesh, script_of, script_model_json, script_link,
  plasm_examples, script_patch_model, gpu_objects,
} from './pkg/bezsolid_web.js';
import { runner, workList } from './work.js';

const $ = (id) => document.getElementById(id);
const statusLine = $('status');
const xiInput = $('xi');

function say(message, kind = 'info') {
  statusLine.textContent = message;
  statusLine.dataset.kind = kind;
}

const fmt = (v) => (Math.abs(v) < 5e-4 ? '0' : v.toFixed(3));

// A canvas keeps its first context type: falling back to WebGL2 needs a fresh one.
function freshCanvas(old) {
  const canvas = old.cloneNode(false);
  old.replaceWith(canvas);
  return canvas;
}

async function bringUp(canvas, requested) {
  try {
    return { canvas, modeler: await start(canvas, requested) };
  } catch (err) {
    if (requested === 'webgl2') throw err;
    console.warn(`bezsolid: ${requested} failed (${err?.message ?? err}); falling back to WebGL2`);
    const fresh = freshCanvas(canvas);
    return { canvas: fresh, modeler: await start(fresh, 'webgl2'), fellBack: true };
  }
}

async function main() {
  const wasm = await init();
  const params = new URLSearchParams(location.search);
  let requested = params.get('backend') ?? 'auto';
  if (!['auto', 'webgpu', 'webgl2'].includes(requested)) {
    say(`Unknown backend "${requested}" in the address; choosing automatically.`, 'warn');
    requested = 'auto';
  }
  const { canvas, modeler, fellBack } = await bringUp($('view'), requested);
  const badge = $('backend');
  badge.textContent = modeler.backend();
  badge.dataset.backend = modeler.backend();
  badge.title = `Graphics backend: ${modeler.backend()} (${modeler.adapter() || 'adapter'})`;
  if (fellBack) say('WebGPU could not start here; drawing with WebGL2.', 'warn');

  // Restore the autosaved model (quietly: a stale or foreign value is dropped), then open a link in
  // the address over it. The fragment is removed once opened: the model lives on in the autosave, so
  // a reload brings back the edits rather than the link's original.
  const saved = storage.get();
  if (saved) {
    try {
      modeler.load_model(saved);
    } catch (err) {
      console.warn(`bezsolid: the autosaved model could not be restored (${err?.message ?? err})`);
    }
    modeler.forget_history();
  }
  // The Free-form mode: solids over triangle meshes and their Booleans, drawn in the 3D
  // view; its model autosaves beside the Bézier one.
  const ff = new FreeFormView();
  const ffSaved = storage.get(FF_KEY);
  if (ffSaved) {
    try {
      ff.open(ffSaved);
    } catch (err) {
      console.warn(`bezsolid: the autosaved free-form model could not be restored (${err?.message ?? err})`);
    }
  }
  let ffSavedRevision = ff.revision(); // the revision last autosaved (or restored)
  const WORKSPACES = ['bezier', 'freeform', 'script'];
  let workspace = WORKSPACES.includes(storage.get(WORKSPACE_KEY)) ? storage.get(WORKSPACE_KEY) : 'bezier';
  const freeform = () => workspace === 'freeform';
  const scripting = () => workspace === 'script';
  // The Script mode: a PLaSM script in the editor, run in a worker, drawn in the 3D view.
  const sv = new ScriptViewer();
  const editor = $('script');
  const examples = JSON.parse(plasm_examples());
  editor.value = storage.get(SCRIPT_KEY) ?? examples.find((e) => e.id === '4.4').source;
  let scriptRan = false; // whether the editor's script was run since it was opened
  const openFromAddress = () => {
    if (!location.hash || location.hash === '#') return false;
    const script = script_of(location.href);
    const free = script === undefined && is_free_form(location.href);
    let opened = false;
    try {
      if (script !== undefined) {
        editor.value = script;
        storage.set(script, SCRIPT_KEY);
        scriptRan = false;
        setWorkspace('script');
        say('Opened the script from the link.');
        history.replaceState(null, '', location.pathname + location.search);
        return true;
      }
      if (free) ff.open(location.href);
      else modeler.open_link(location.href);
      setWorkspace(free ? 'freeform' : 'bezier');
      say(`Opened the ${free ? 'free-form ' : ''}model from the link.`);
      opened = true;
    } catch (err) {
      say(`This link could not be opened, so the current model was kept: ${err.message ?? err}`, 'error');
    }
    history.replaceState(null, '', location.pathname + location.search);
    return opened;
  };
  const setWorkspace = (name) => {
    workspace = WORKSPACES.includes(name) ? name : 'bezier';
    document.body.dataset.workspace = workspace;
    for (const r of document.querySelectorAll('input[name="workspace"]')) r.checked = r.value === workspace;
    storage.set(workspace, WORKSPACE_KEY);
  };
  setWorkspace(workspace);
  openFromAddress();

  // The 3D view has its own device (a WebGL2 device draws on one canvas only); it is optional: the
  // 2D editor works on without it.
  const canvas3 = $('view3d');
  let viewer = null;
  try {
    viewer = await start_3d(canvas3, modeler.backend() === 'WebGPU' ? 'webgpu' : 'webgl2');
    $('loading-3d').hidden = true;
  } catch (err) {
    $('loading-3d').textContent = `The 3D view could not start: ${err?.message ?? err}`;
    console.warn(`bezsolid: no 3D view (${err?.message ?? err})`);
  }

  // Long work runs in Web Workers (the same module, work.js): a volume's or free-form result's fine
  // surface and a volume's contour stack (the view draws a coarse surface and the previous stack
  // meanwhile; a newer request cancels the job under way), the exports of meshes and contours, and
  // scripts. Each shows in the work list with its time, its progress and a Cancel.
  const work = workList($('work'));
  let surfaceRunner = null;
  let exportRunner = null;
  try {
    surfaceRunner = runner();
    exportRunner = runner();
    modeler.set_external_surface(true);
  } catch (err) {
    console.warn(`bezsolid: no Web Worker (${err?.message ?? err}); long work runs on the page`);
  }
  // A worker made on first use (most visits never open a volume or a script).
  const lazyRunner = () => {
    let made;
    return () => {
      if (made === undefined) {
        try {
          made = surfaceRunner && runner();
        } catch {
          made = null;
        }
      }
      return made;
    };
  };
  // Work that follows the model: `request()` says what is wanted now (an array whose first entry
  // is the model's revision, or undefined), `job(request)` the worker's message for it, and
  // `accept(request, reply)` hands the result in (false when the model moved on). A newer request
  // cancels the job under way, and so does any change of the model (`revision()`: its result would
  // be dropped); one the user cancelled is not asked again until the model changes.
  const background = ({ work: worker, request, revision, job, accept, label, unit, failed }) => {
    let busy = ''; // the request in flight, as a key
    let busyRevision = null;
    let declined = '';
    let lastMs = 0;
    let inFlight = null;
    const send = async (wanted) => {
      const key = wanted.join(',');
      busy = key;
      busyRevision = wanted[0];
      inFlight?.cancel();
      const message = job(wanted);
      const task = work.start(message.kind, label(wanted), () => {
        declined = key;
        inFlight?.cancel();
      });
      const running = worker().run(message, {
        onProgress: (done, total) => task.progress(done, total, unit),
        onStart: () => task.started(),
      });
      inFlight = running;
      try {
        const reply = await running;
        if (accept(wanted, reply)) {
          lastMs = reply.ms;
          redraw(VIEW3);
        }
      } catch (err) {
        if (!err.cancelled) say(`${failed}: ${err.message}`, 'error');
      } finally {
        task.end();
        if (busy === key) busy = '';
        if (inFlight === running) {
          inFlight = null;
          busyRevision = null;
        }
      }
    };
    return {
      check() {
        const wanted = request();
        if (!wanted) return;
        const key = wanted.join(',');
        if (key === busy || key === declined) return;
        send(wanted);
      },
      /** Cancels the job under way if the model has changed since it was asked for. */
      prune() {
        if (inFlight && busyRevision !== revision()) inFlight.cancel();
      },
      lastMs: () => lastMs,
    };
  };
  const mesher = surfaceRunner && background({
    work: () => surfaceRunner,
    request: () => modeler.surface_request(),
    revision: () => modeler.revision(),
    job: ([, resolution]) => ({ kind: 'surface', model: modeler.model_json(), resolution }),
    accept: ([revision, resolution], { data }) => modeler.set_surface(revision, resolution, data),
    label: ([, resolution]) => `Meshing the surface at ${resolution}`,
    failed: 'The surface could not be meshed',
  });
  const stackRunner = lazyRunner();
  const stacker = surfaceRunner && background({
    work: stackRunner,
    request: () => modeler.stack_request(),
    revision: () => modeler.revision(),
    job: ([, axis]) => ({ kind: 'stack', model: modeler.model_json(), axis }),
    accept: ([revision, axis], { data }) => modeler.set_stack(revision, axis, data),
    label: ([, axis]) => `Contour stack across ${'uvw'[axis]}`,
    unit: 'slices',
    failed: 'The contour stack could not be made',
  });
  // The Free-form mode has its own worker for its result's surface (made on first use).
  const ffRunner = lazyRunner();
  const ffMesher = surfaceRunner && background({
    work: ffRunner,
    request: () => ff.surface_request(),
    revision: () => ff.revision(),
    job: ([, resolution]) => ({ kind: 'esc-surface', model: ff.model_json(), resolution }),
    accept: ([revision, resolution], { data }) => ff.set_surface(revision, resolution, data),
    label: ([, resolution]) => `Meshing the result at ${resolution}`,
    failed: 'The result could not be meshed',
  });

  let pending = 0;
  let lastRender = 0;
  let lastRender3 = 0;
  const VIEW2 = 1;
  const VIEW3 = 2;
  const redraw = (which = VIEW2 | VIEW3) => {
    if (pending) {
      pending |= which;
      return;
    }
    pending = which;
    requestAnimationFrame(() => {
      const todo = pending;
      pending = 0;
      if (todo & VIEW2 && workspace === 'bezier') {
        const t0 = performance.now();
        modeler.render();
        lastRender = performance.now() - t0;
      }
      if (todo & VIEW3 && viewer && scripting()) {
        const t0 = performance.now();
        sv.render(viewer);
        lastRender3 = performance.now() - t0;
      } else if (todo & VIEW3 && viewer && freeform()) {
        const t0 = performance.now();
        ff.render(viewer);
        lastRender3 = performance.now() - t0;
        if (ffMesher) {
          ffMesher.check();
        } else {
          // No worker: the fine surface on the page, once per change.
          const request = ff.surface_request();
          if (request && ff.set_surface(request[0], request[1], headless_esc_surface(ff.model_json(), request[1]))) redraw(VIEW3);
        }
      } else if (todo & VIEW3 && viewer) {
        const t0 = performance.now();
        modeler.render_3d(viewer);
        lastRender3 = performance.now() - t0;
        mesher?.check();
        stacker?.check();
        const xi = modeler.xi_extent();
        $('xi-min').textContent = fmt(-xi);
        $('xi-max').textContent = fmt(xi);
      }
      for (const b of [mesher, stacker, ffMesher]) b?.prune();
      updatePanel();
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
      if (storage.set(ff.model_json(), FF_KEY)) {
        ffSavedRevision = ff.revision();
      } else {
        storage.remove(FF_KEY);
        say('The free-form scene is too large to keep in this browser; use Export → Model file.', 'warn');
      }
    }
    if (!storage.set(modeler.model_json())) {
      say('The model could not be saved in this browser (storage is full or blocked); use Export → Model file.', 'warn');
    }
  };
  const changed = () => {
    redraw();
    clearTimeout(saveTimer);
    saveTimer = setTimeout(saveNow, 300);
  };
  addEventListener('pagehide', () => { if (saveTimer) saveNow(); });
  document.addEventListener('visibilitychange', () => { if (document.hidden && saveTimer) saveNow(); });

  const inputs = { x: $('px'), y: $('py'), xi: xiInput };
  const updateFreeForm = () => {
    const op = ff.operation();
    $('ff-op').value = op;
    $('ff-b-controls').disabled = op === 'none';
    for (const [slot, id] of [[0, 'ff-a'], [1, 'ff-b']]) {
      const select = $(id);
      const name = ff.operand_name(slot);
      const imported = select.querySelector('option[value="imported"]');
      if (name && !ff.operand_is_example(slot)) {
        imported.hidden = false;
        imported.textContent = `Imported: ${name}`;
        select.value = 'imported';
      } else if (name) {
        imported.hidden = true;
        select.value = name;
      }
    }
    const offset = ff.operand_offset(1);
    if (offset) {
      ['ff-bx', 'ff-by', 'ff-bz'].forEach((id, k) => {
        if (document.activeElement !== $(id)) $(id).value = String(Math.round(offset[k] * 1e6) / 1e6);
      });
    }
    const counts = ff.triangle_counts();
    const info = ff.surface_info();
    const opName = { none: 'A', union: 'A ∪ B', intersection: 'A ∩ B', difference: 'A − B' }[op];
    $('model-name').textContent = `Free-form: ${opName}`;
    let text = `A: ${counts[0].toLocaleString('en')} triangles`
      + (counts.length > 1 ? `, B: ${counts[1].toLocaleString('en')} triangles` : '') + '. ';
    const pointCounts = ff.point_counts();
    if (display === 'points' && pointCounts) {
      const [inside, marked] = pointCounts;
      text += `Point mesh 25 × 25 × 25: ${inside.toLocaleString('en')} points`
        + (marked ? `, ${marked.toLocaleString('en')} red (in the partial chain, removed by its last term)` : '');
    } else if (info) {
      text += `Result surface: ${info[0].toLocaleString('en')} triangles at ${info[1]}.`;
    }
    $('ff-info').textContent = text;
    document.body.dataset.ffSurface = info ? `${info[0]},${info[1]}` : '';
    for (const o of document.querySelectorAll('#export option[data-volume]')) o.disabled = false;
    for (const o of document.querySelectorAll('#export option[data-bezier]')) o.disabled = true;
    document.body.dataset.ffOperation = op;
  };
  let display = 'result';
  // What the Bézier panel shows, one snapshot of the editor, its last frame and its 3D view.
  const panel = () => JSON.parse(modeler.panel());
  const updatePanel = () => {
    if (freeform()) {
      updateFreeForm();
      return;
    }
    if (scripting()) {
      $('model-name').textContent = 'PLaSM script';
      for (const o of document.querySelectorAll('#export option[data-volume], #export option[data-script]')) o.disabled = false;
      for (const o of document.querySelectorAll('#export option[data-bezier]')) o.disabled = true;
      return;
    }
    for (const o of document.querySelectorAll('#export option[data-script]')) o.disabled = true;
    const p = panel();
    const sel = p.selected;
    const point = p.point;
    if (sel && point) {
      $('point-label').textContent = `P${sel[0]}${sel[1]} (i = ${sel[0]}, j = ${sel[1]})`;
      [inputs.x, inputs.y, inputs.xi].forEach((input, k) => {
        input.disabled = false;
        if (document.activeElement !== input) {
          input.value = String(Math.round(point[k] * 1e6) / 1e6);
          input.removeAttribute('aria-invalid');
        }
      });
    } else {
      $('point-label').textContent = 'None selected: click a point or press Tab in the view.';
      for (const input of Object.values(inputs)) {
        input.disabled = true;
        input.value = '';
      }
    }
    $('range-min').textContent = fmt(p.frame.range[0]);
    $('range-max').textContent = fmt(p.frame.range[1]);
    const n = p.frame.contours;
    $('contour-info').textContent = `Zero contour: ${n} ${n === 1 ? 'piece' : 'pieces'}`
      + (p.frame.folded ? ' (the net folds over itself: the lines of every sheet are shown)' : '');
    const [du, dv] = p.degree;
    const mapped = p.space_mapped;
    const vd = p.volume_degree;
    const volume = !!vd;
    if (volume) {
      const [axis, index] = p.slice;
      const name = ['u', 'v', 'w'][axis];
      $('model-name').textContent = `Volume solid, ${vd[0] + 1} × ${vd[1] + 1} × ${vd[2] + 1} points${mapped ? ', space-mapped' : ''}`;
      $('model-info').textContent = `Degree ${vd.join(' × ')}; ${mapped ? 'points moved: the inverse map finds (u, v, w)' : 'a regular grid'}. The 2D view edits one slice.`;
      for (const r of document.querySelectorAll('input[name="slice-axis"]')) r.checked = Number(r.value) === axis;
      const slider = $('slice-index');
      slider.max = String(vd[axis]);
      if (document.activeElement !== slider) slider.value = String(index);
      $('slice-info').textContent = `${name} slice ${index} of 0…${vd[axis]}: ${(vd[(axis + 1) % 3] + 1)} × ${(vd[(axis + 2) % 3] + 1)} points`;
      const [t, resolution] = p.surface ?? [0, 0];
      const stack = p.stack;
      $('surface-info').textContent = `Surface: ${t.toLocaleString('en')} triangles at ${resolution}; `
        + (!stack ? 'contour stack: not made yet' : `contour stack: ${stack[0].toLocaleString('en')} segments${stack[1] ? '' : ' (of the model before the last edit, until the new one comes)'}`);
      document.body.dataset.stack = stack ? `${stack[0]},${stack[1] ? 1 : 0}` : '';
    } else {
      $('model-name').textContent = `Patch solid, ${du + 1} × ${dv + 1} points${mapped ? ', space-mapped' : ''}`;
      $('model-info').textContent = `Degree ${du} × ${dv}; ${mapped ? 'points moved: the inverse map finds (u, v)' : 'a regular grid: (u, v) by scaling'}.`;
    }
    $('volume-controls').hidden = !volume;
    $('elevate-w').disabled = !volume;
    for (const o of document.querySelectorAll('#export option[data-volume]')) o.disabled = !volume;
    for (const o of document.querySelectorAll('#export option[data-bezier]')) o.disabled = false;
    document.body.dataset.kind = volume ? 'volume' : 'patch';
    $('undo').disabled = !p.can_undo;
    $('redo').disabled = !p.can_redo;
    const mode = p.mode;
    for (const r of document.querySelectorAll('input[name="mode"]')) r.checked = r.value === mode;
    canvas.classList.toggle('space', mode === 'space');
    document.body.dataset.selected = sel ? `${sel[0]},${sel[1]}` : '';
    document.body.dataset.mode = mode;
  };

  const debug = $('debug');
  let lastEdit = 0;
  const updateDebug = () => {
    if (debug.hidden) return;
    const gpu = gpu_objects();
    debug.textContent = `2D frame: ${lastRender.toFixed(1)} ms (evaluate, contour, draw)\n`
      + `3D frame: ${lastRender3.toFixed(1)} ms (surface, spheres, draw)\n`
      + `worker mesh: ${mesher ? mesher.lastMs().toFixed(1) : '–'} ms\n`
      + `worker contour stack: ${stacker ? stacker.lastMs().toFixed(1) : '–'} ms\n`
      + `worker free-form surface: ${ffMesher ? ffMesher.lastMs().toFixed(1) : '–'} ms\n`
      + `input → drawn: ${lastEdit ? (performance.now() - lastEdit).toFixed(1) : '–'} ms\n`
      + `GPU: ${gpu[0]} buffers, ${gpu[1]} textures (${gpu[2]} made); wasm memory ${(wasm.memory.buffer.byteLength / 2 ** 20).toFixed(1)} MiB`;
    document.body.dataset.renderMs = lastRender.toFixed(2);
    if (lastEdit) document.body.dataset.latencyMs = (performance.now() - lastEdit).toFixed(2);
    document.body.dataset.render3Ms = lastRender3.toFixed(2);
  };
  const toggleDebug = () => {
    debug.hidden = !debug.hidden;
    $('debug-toggle').setAttribute('aria-pressed', String(!debug.hidden));
    redraw();
  };
  $('debug-toggle').addEventListener('click', toggleDebug);

  const resize = () => {
    const rect = canvas.getBoundingClientRect();
    const [w, h] = modeler.resize(rect.width, rect.height, window.devicePixelRatio || 1);
    if (canvas.width !== w) canvas.width = w;
    if (canvas.height !== h) canvas.height = h;
    redraw();
  };
  new ResizeObserver(resize).observe(canvas);
  // A media query matches one ratio: listen again at the new one after each change (zoom, new screen).
  const watchRatio = () => {
    matchMedia(`(resolution: ${window.devicePixelRatio}dppx)`).addEventListener('change', () => {
      resize();
      watchRatio();
    }, { once: true });
  };
  watchRatio();
  resize();
  const resize3 = () => {
    if (!viewer) return;
    const rect = canvas3.getBoundingClientRect();
    const [w, h] = modeler.resize_3d(viewer, rect.width, rect.height, window.devicePixelRatio || 1);
    ff.resize(viewer, rect.width, rect.height, window.devicePixelRatio || 1);
    sv.resize(viewer, rect.width, rect.height, window.devicePixelRatio || 1);
    if (canvas3.width !== w) canvas3.width = w;
    if (canvas3.height !== h) canvas3.height = h;
    redraw(VIEW3);
  };
  new ResizeObserver(resize3).observe(canvas3);
  resize3();

  // The 3D view: orbit, pan, zoom, and drags of the spheres (one undo step each, as in 2D).
  const local3 = (e) => {
    const rect = canvas3.getBoundingClientRect();
    return [e.clientX - rect.left, e.clientY - rect.top];
  };
  canvas3.addEventListener('contextmenu', (e) => e.preventDefault());
  let ffDragging = false;
  // The free-form and script views only move their camera.
  const orbiter = () => (freeform() ? ff : scripting() ? sv : null);
  canvas3.addEventListener('pointerdown', (e) => {
    if (!viewer || (e.button !== 0 && e.button !== 2)) return;
    canvas3.focus();
    const [x, y] = local3(e);
    if (orbiter()) {
      orbiter().pointer_down(x, y, e.button === 2 || e.shiftKey);
      ffDragging = true;
      canvas3.setPointerCapture(e.pointerId);
      canvas3.classList.add('dragging');
      e.preventDefault();
      return;
    }
    const grabbed = modeler.pointer_down_3d(x, y, e.button === 2, e.shiftKey);
    canvas3.setPointerCapture(e.pointerId);
    canvas3.classList.add('dragging');
    e.preventDefault();
    redraw(grabbed ? VIEW2 | VIEW3 : VIEW3);
  });
  canvas3.addEventListener('pointermove', (e) => {
    if (!viewer) return;
    const [x, y] = local3(e);
    if (orbiter()) {
      if (ffDragging && orbiter().pointer_move(x, y)) redraw(VIEW3);
      return;
    }
    if (modeler.busy_3d()) {
      if (modeler.pointer_move_3d(x, y)) {
        const editing = modeler.editing_3d();
        if (editing) {
          lastEdit = performance.now();
          // A volume's surface is meshed coarsely while the point moves, finely when it rests.
          modeler.set_coarse(true);
          clearTimeout(restTimer);
          restTimer = setTimeout(() => { modeler.set_coarse(false); redraw(VIEW3); }, 250);
        }
        redraw(editing ? VIEW2 | VIEW3 : VIEW3);
      }
      return;
    }
    canvas3.classList.toggle('over-point', modeler.hit_3d(x, y));
  });
  let restTimer = 0;
  const endDrag3 = (e) => {
    if (viewer && ffDragging) {
      ffDragging = false;
      orbiter()?.pointer_up();
      canvas3.classList.remove('dragging');
      if (canvas3.hasPointerCapture(e.pointerId)) canvas3.releasePointerCapture(e.pointerId);
      return;
    }
    if (!viewer || !modeler.busy_3d()) return;
    const editing = modeler.editing_3d();
    clearTimeout(restTimer);
    modeler.set_coarse(false);
    modeler.pointer_up_3d();
    canvas3.classList.remove('dragging');
    if (canvas3.hasPointerCapture(e.pointerId)) canvas3.releasePointerCapture(e.pointerId);
    if (editing) changed();
    else redraw(VIEW3);
  };
  canvas3.addEventListener('pointerup', endDrag3);
  canvas3.addEventListener('pointercancel', endDrag3);
  canvas3.addEventListener('lostpointercapture', endDrag3);
  canvas3.addEventListener('wheel', (e) => {
    if (!viewer) return;
    e.preventDefault();
    if (orbiter()) orbiter().wheel(e.deltaMode === 1 ? e.deltaY * 33 : e.deltaY);
    else modeler.wheel_3d(e.deltaMode === 1 ? e.deltaY * 33 : e.deltaY);
    redraw(VIEW3);
  }, { passive: false });
  const fit3 = () => {
    if (orbiter()) orbiter().fit();
    else modeler.fit_3d();
    redraw(VIEW3);
  };
  $('fit-3d').addEventListener('click', fit3);
  canvas3.addEventListener('keydown', (e) => {
    if (e.ctrlKey || e.metaKey || e.altKey) return;
    if (e.key === 'f' || e.key === 'F') {
      fit3();
      e.preventDefault();
    }
  });

  const local = (e) => {
    const rect = canvas.getBoundingClientRect();
    return [e.clientX - rect.left, e.clientY - rect.top];
  };

  canvas.addEventListener('pointerdown', (e) => {
    if (e.button !== 0) return;
    canvas.focus();
    const [x, y] = local(e);
    if (modeler.pointer_down(x, y, e.shiftKey)) {
      canvas.setPointerCapture(e.pointerId);
      canvas.classList.add('dragging');
      e.preventDefault();
    }
    redraw();
  });
  let probeAt = [0, 0];
  let probePending = false;
  canvas.addEventListener('pointermove', (e) => {
    const [x, y] = local(e);
    if (modeler.dragging()) {
      if (modeler.pointer_move(x, y)) {
        lastEdit = performance.now();
        redraw();
      }
      return;
    }
    canvas.classList.toggle('over-point', modeler.hit(x, y));
    // f under the pointer, once a frame at most (a folded net's inverse map costs milliseconds).
    probeAt = [x, y];
    if (!probePending) {
      probePending = true;
      requestAnimationFrame(() => {
        probePending = false;
        const [px, py, f] = modeler.probe(...probeAt);
        $('probe').textContent = `f(${px.toFixed(3)}, ${py.toFixed(3)}) = ${f.toFixed(4)} (${f >= 0 ? 'inside' : 'outside'})`;
      });
    }
  });
  const endDrag = (e) => {
    if (!modeler.dragging()) return;
    modeler.pointer_up();
    canvas.classList.remove('dragging');
    if (canvas.hasPointerCapture(e.pointerId)) canvas.releasePointerCapture(e.pointerId);
    changed();
  };
  canvas.addEventListener('pointerup', endDrag);
  canvas.addEventListener('pointercancel', endDrag);
  canvas.addEventListener('lostpointercapture', endDrag);
  canvas.addEventListener('wheel', (e) => {
    // deltaMode 1 counts lines: about 33 pixels each.
    const dy = e.deltaMode === 1 ? e.deltaY * 33 : e.deltaY;
    if (modeler.wheel(dy)) {
      e.preventDefault();
      lastEdit = performance.now();
      changed();
    }
  }, { passive: false });
  canvas.addEventListener('keydown', (e) => {
    if (e.ctrlKey || e.metaKey || e.altKey) return;
    if (e.key === 'd' || e.key === 'D') {
      toggleDebug();
      e.preventDefault();
      return;
    }
    const wasDragging = modeler.dragging();
    if (modeler.key(e.key, e.shiftKey)) {
      e.preventDefault();
      if (wasDragging && !modeler.dragging()) canvas.classList.remove('dragging');
      changed();
    }
  });

  // Undo and redo: the buttons, and the shortcuts anywhere but in a text field (which keeps its own).
  const act = (f) => {
    if (f()) changed();
  };
  $('undo').addEventListener('click', () => act(() => modeler.undo()));
  $('redo').addEventListener('click', () => act(() => modeler.redo()));
  document.addEventListener('keydown', (e) => {
    if (!(e.ctrlKey || e.metaKey) || e.altKey || workspace !== 'bezier') return;
    const tag = e.target?.tagName;
    if ((tag === 'INPUT' && e.target.type !== 'radio') || tag === 'TEXTAREA') return;
    const key = e.key.toLowerCase();
    if (key === 'z' && !e.shiftKey) {
      e.preventDefault();
      act(() => modeler.undo());
    } else if ((key === 'z' && e.shiftKey) || key === 'y') {
      e.preventDefault();
      act(() => modeler.redo());
    }
  });

  for (const radio of document.querySelectorAll('input[name="mode"]')) {
    radio.addEventListener('change', () => {
      if (radio.checked) {
        modeler.set_mode(radio.value);
        redraw();
      }
    });
  }

  // Numeric entry for the selected point: ξ, and x and y (space mapping).
  const applyInput = (which) => {
    const input = inputs[which];
    const value = input.valueAsNumber;
    if (!Number.isFinite(value)) {
      input.setAttribute('aria-invalid', 'true');
      return;
    }
    try {
      if (which === 'xi') {
        modeler.set_selected_xi(value);
      } else {
        const { point } = panel();
        if (!point) return;
        modeler.set_selected_xy(which === 'x' ? value : point[0], which === 'y' ? value : point[1]);
      }
      input.removeAttribute('aria-invalid');
      changed();
    } catch (err) {
      input.setAttribute('aria-invalid', 'true');
      say(err.message ?? String(err), 'error');
    }
  };
  for (const which of Object.keys(inputs)) {
    inputs[which].addEventListener('input', () => applyInput(which));
    inputs[which].addEventListener('change', () => {
      applyInput(which);
      updatePanel();
    });
  }

  // The model: presets, a new grid, elevation.
  // An edit through the model: redraw and autosave, or say why not (the panel shows the model
  // as it stayed).
  const attempt = (what, f) => {
    try {
      f();
      changed();
      return true;
    } catch (err) {
      say(`${what}: ${err.message ?? err}`, 'error');
      updatePanel();
      return false;
    }
  };
  $('preset').addEventListener('change', (e) => {
    const name = e.target.value;
    e.target.value = '';
    if (name) attempt('Preset', () => modeler.load_preset(name)) && say(`Opened the preset; Undo brings back the previous model.`);
  });
  $('reset-grid').addEventListener('click', () => {
    attempt('New grid', () => modeler.reset_grid($('grid-u').valueAsNumber, $('grid-v').valueAsNumber));
  });
  $('elevate-u').addEventListener('click', () => attempt('Elevate', () => modeler.elevate(0)));
  $('elevate-v').addEventListener('click', () => attempt('Elevate', () => modeler.elevate(1)));
  $('elevate-w').addEventListener('click', () => attempt('Elevate', () => modeler.elevate(2)));
  $('new-volume').addEventListener('click', () => {
    attempt('New volume', () => modeler.new_volume($('grid-u').valueAsNumber, $('grid-v').valueAsNumber, $('grid-w').valueAsNumber));
  });

  // A volume: the slice in the 2D view, and the surface's resolution.
  for (const radio of document.querySelectorAll('input[name="slice-axis"]')) {
    radio.addEventListener('change', () => {
      if (!radio.checked) return;
      const axis = Number(radio.value);
      const vd = panel().volume_degree;
      if (!vd) return;
      attempt('Slice', () => modeler.set_slice(axis, Math.floor(vd[axis] / 2)));
    });
  }
  $('slice-index').addEventListener('input', (e) => {
    const s = panel().slice;
    if (s) attempt('Slice', () => modeler.set_slice(s[0], e.target.valueAsNumber));
  });
  $('resolution').addEventListener('change', (e) => {
    const v = e.target.valueAsNumber;
    if (!Number.isFinite(v)) return;
    e.target.value = String(modeler.set_resolution(v));
    redraw(VIEW3);
  });

  // Share: the link goes into the box (always) and the clipboard (where allowed).
  $('copy-link').addEventListener('click', async () => {
    let fragment;
    try {
      fragment = scripting() ? script_link(editor.value) : freeform() ? ff.link() : modeler.link();
    } catch (err) {
      say(`${err.message ?? err}`, 'error');
      return;
    }
    const url = location.origin + location.pathname + location.search + fragment;
    const box = $('share-url');
    box.value = url;
    document.body.dataset.link = url;
    try {
      await navigator.clipboard.writeText(url);
      say(`Link copied (${url.length} characters).`);
    } catch {
      box.focus();
      box.select();
      say('The browser did not allow copying: the link is selected in the box, copy it from there.', 'warn');
    }
  });
  addEventListener('hashchange', () => {
    if (openFromAddress()) {
      changed();
      if (scripting() && !scriptRan) runScript({ refit: true });
    }
  });

  // Files: open (picker or drop), save and export.
  const openFile = async (file) => {
    if (!file) return;
    if (file.size > 16 * 1024 * 1024 && !/\.(obj|stl|ply)$/i.test(file.name)) {
      say(`${file.name} is too large for a model file (${file.size} bytes).`, 'error');
      return;
    }
    if (/\.(obj|stl|ply)$/i.test(file.name)) {
      importMesh(0, file);
      return;
    }
    try {
      const text = await file.text();
      const script = /\.psm$/i.test(file.name) ? text : script_of(text);
      if (script !== undefined) {
        openScript(script, `Opened ${file.name}.`);
        return;
      }
      if (is_free_form(text)) {
        ff.open(text);
        setWorkspace('freeform');
        resize3();
        say(`Opened ${file.name}.`);
        changed();
        return;
      }
      modeler.load_model(text);
      setWorkspace('bezier');
      say(`Opened ${file.name}; Undo brings back the previous model.`);
      changed();
    } catch (err) {
      say(`${file.name} could not be opened, so the current model was kept: ${err.message ?? err}`, 'error');
    }
  };
  $('open-file').addEventListener('change', (e) => {
    openFile(e.target.files?.[0]);
    e.target.value = '';
  });
  const drop = $('drop');
  addEventListener('dragover', (e) => {
    if (![...(e.dataTransfer?.types ?? [])].includes('Files')) return;
    e.preventDefault();
    drop.hidden = false;
  });
  addEventListener('dragleave', (e) => { if (!e.relatedTarget) drop.hidden = true; });
  addEventListener('drop', (e) => {
    if (!e.dataTransfer?.files?.length) return;
    e.preventDefault();
    drop.hidden = true;
    const file = e.dataTransfer.files[0];
    if (/\.(obj|stl|ply)$/i.test(file.name)) importMesh(freeform() && e.shiftKey ? 1 : 0, file);
    else openFile(file);
  });

  const download = (name, blob) => {
    const a = document.createElement('a');
    a.href = URL.createObjectURL(blob);
    a.download = name;
    document.body.append(a);
    a.click();
    a.remove();
    setTimeout(() => URL.revokeObjectURL(a.href), 10_000);
    say(`Saved ${name}.`);
  };
  const exporters = {
    model: () => download('bezsolid.bsolid.json', new Blob([freeform() ? ff.model_json() : modeler.model_json()], { type: 'application/json' })),
    // The exact contour: on a folded net, the inverse map at every sample (seconds).
    svg: () => exportJob('bezsolid-contours.svg', 'image/svg+xml', 'Exporting SVG', { kind: 'svg', model: modeler.patch_json() }, () => modeler.svg()),
    hf: () => download('bezsolid.hf', new Blob([modeler.hyperfun()], { type: 'text/plain' })),
    stl: () => exportMesh('bezsolid.stl', 'mesh', 'stl', modeler.model_json(), modeler.resolution(), () => modeler.mesh_file('stl')),
    obj: () => exportMesh('bezsolid.obj', 'mesh', 'obj', modeler.model_json(), modeler.resolution(), () => modeler.mesh_file('obj')),
    ply: () => exportMesh('bezsolid.ply', 'mesh', 'ply', modeler.model_json(), modeler.resolution(), () => modeler.mesh_file('ply')),
    // The canvas is read in the same task as the frame is drawn, before the browser clears it.
    png: () => {
      modeler.render();
      canvas.toBlob((blob) => {
        if (blob) download('bezsolid-view.png', blob);
        else say('The view could not be captured as PNG.', 'error');
      }, 'image/png');
    },
  };
  // A file made in the export worker (in the work list while it runs, with a Cancel), or on the
  // page without one (`here`).
  const exportJob = async (name, type, label, message, here) => {
    if (!exportRunner) {
      download(name, new Blob([here()], { type }));
      return;
    }
    const running = exportRunner.run(message, {
      onProgress: (done, total) => task.progress(done, total),
      onStart: () => task.started(),
    });
    const task = work.start('export', label, () => running.cancel());
    try {
      const { data, approximate } = await running;
      download(name, new Blob([data], { type }));
      if (approximate) {
        say(`Saved ${name}, approximate where the net folds over itself very many times: `
          + `${approximate} ${approximate === 1 ? 'evaluation' : 'evaluations'} ran out of their work budget.`, 'warn');
      }
    } catch (err) {
      if (err.cancelled) say(`${label} was cancelled; nothing was saved.`);
      else say(`Export failed, nothing was changed: ${err.message ?? err}`, 'error');
    } finally {
      task.end();
    }
  };
  const MESH_TYPES = { stl: 'model/stl', obj: 'model/obj', ply: 'application/octet-stream' };
  const exportMesh = (name, kind, format, model, resolution, here) => exportJob(
    name, MESH_TYPES[format], `Exporting ${format.toUpperCase()}`, { kind, model, format, resolution }, here);
  // Free-form: the result's closed mesh at the chosen resolution.
  const exportResult = (format) => {
    const model = ff.model_json();
    const resolution = ff.resolution();
    exportMesh(`bezsolid-result.${format}`, 'esc-mesh', format, model, resolution, () => headless_esc_mesh(model, format, resolution));
  };
  $('export').addEventListener('change', (e) => {
    const kind = e.target.value;
    e.target.value = '';
    if (scripting()) {
      const script = editor.value;
      if (kind === 'model') download('bezsolid-script.bsolid.json', new Blob([script_model_json(script)], { type: 'application/json' }));
      else if (kind === 'psm') download('bezsolid.psm', new Blob([script], { type: 'text/plain' }));
      else if (['stl', 'obj', 'ply'].includes(kind)) exportMesh(`bezsolid-script.${kind}`, 'plasm-mesh', kind, script, 0, () => headless_plasm_mesh(script, kind));
      else if (kind === 'png' && viewer) {
        sv.render(viewer);
        canvas3.toBlob((blob) => {
          if (blob) download('bezsolid-script.png', blob);
          else say('The view could not be captured as PNG.', 'error');
        }, 'image/png');
      }
      return;
    }
    if (freeform() && ['stl', 'obj', 'ply'].includes(kind)) {
      exportResult(kind);
      return;
    }
    if (freeform() && kind === 'png') {
      ff.render(viewer);
      canvas3.toBlob((blob) => {
        if (blob) download('bezsolid-free-form.png', blob);
        else say('The view could not be captured as PNG.', 'error');
      }, 'image/png');
      return;
    }
    if (!exporters[kind]) return;
    try {
      exporters[kind]();
    } catch (err) {
      say(`Export failed, nothing was changed: ${err.message ?? err}`, 'error');
    }
  });

  // The Free-form controls.
  const importMesh = async (slot, file) => {
    if (!file) return;
    if (file.size > 128 * 1024 * 1024) {
      say(`${file.name} is too large (${file.size} bytes; a mesh file is at most 128 MiB).`, 'error');
      return;
    }
    const bytes = new Uint8Array(await file.arrayBuffer());
    // Reading, checking and indexing a large mesh takes a moment on this thread: say so first.
    say(`Importing ${file.name} (${bytes.length.toLocaleString('en')} bytes)…`);
    const task = work.start('import', `Importing ${file.name}`);
    task.started();
    await new Promise((r) => requestAnimationFrame(() => setTimeout(r, 0)));
    const imported = attempt(`${file.name} could not be imported, so the scene was kept`, () => ff.import_mesh(slot, file.name, bytes));
    task.end();
    if (imported) {
      setWorkspace('freeform');
      resize3();
      say(`Imported ${file.name} as solid ${slot === 0 ? 'A' : 'B'}.`);
    }
  };
  for (const radio of document.querySelectorAll('input[name="workspace"]')) {
    radio.addEventListener('change', () => {
      if (!radio.checked) return;
      setWorkspace(radio.value);
      resize();
      resize3();
      if (scripting() && !scriptRan) runScript({ refit: true });
      redraw();
    });
  }
  $('ff-b').innerHTML = $('ff-a').innerHTML; // one list of meshes for both solids
  $('ff-a').addEventListener('change', (e) => attempt('Solid A', () => ff.set_example(0, e.target.value)));
  $('ff-b').addEventListener('change', (e) => attempt('Solid B', () => ff.set_example(1, e.target.value)));
  $('ff-op').addEventListener('change', (e) => attempt('Operation', () => ff.set_operation(e.target.value)));
  $('ff-import-a').addEventListener('change', (e) => { importMesh(0, e.target.files?.[0]); e.target.value = ''; });
  $('ff-import-b').addEventListener('change', (e) => { importMesh(1, e.target.files?.[0]); e.target.value = ''; });
  for (const id of ['ff-bx', 'ff-by', 'ff-bz']) {
    $(id).addEventListener('change', () => {
      const v = ['ff-bx', 'ff-by', 'ff-bz'].map((k) => $(k).valueAsNumber);
      if (!v.every(Number.isFinite)) {
        $(id).setAttribute('aria-invalid', 'true');
        return;
      }
      $(id).removeAttribute('aria-invalid');
      attempt('Move B', () => ff.set_offset(1, v[0], v[1], v[2]));
    });
  }
  for (const radio of document.querySelectorAll('input[name="ff-display"]')) {
    radio.addEventListener('change', () => {
      if (!radio.checked) return;
      display = radio.value;
      ff.set_display(display);
      redraw(VIEW3);
    });
  }
  $('ff-resolution').addEventListener('change', (e) => {
    const v = e.target.valueAsNumber;
    if (!Number.isFinite(v)) return;
    e.target.value = String(ff.set_resolution(v));
    redraw(VIEW3);
  });

  // The script editor: line numbers, marks where the last run had errors or warnings, Ctrl+Enter
  // runs; runs go to a worker of their own, and a newer run (or Stop) cancels the one under way.
  const gutter = $('script-gutter');
  let marks = new Map(); // line → 'error' | 'warn'
  let gutterLines = 0;
  const renderGutter = (force = false) => {
    const n = editor.value.split('\n').length;
    if (!force && n === gutterLines) return;
    gutterLines = n;
    const out = [];
    for (let i = 1; i <= n; i++) {
      const mark = marks.get(i);
      out.push(mark ? `<span class="${mark}" title="${mark === 'error' ? 'error' : 'warning'}">${i}</span>` : String(i));
    }
    gutter.innerHTML = out.join('\n') + '\n\n';
    gutter.scrollTop = editor.scrollTop;
  };
  editor.addEventListener('scroll', () => { gutter.scrollTop = editor.scrollTop; });
  let scriptSaveTimer = 0;
  editor.addEventListener('input', () => {
    renderGutter();
    clearTimeout(scriptSaveTimer);
    scriptSaveTimer = setTimeout(() => {
      if (!storage.set(editor.value, SCRIPT_KEY)) say('The script could not be saved in this browser; use Export → Script.', 'warn');
    }, 300);
  });
  addEventListener('pagehide', () => storage.set(editor.value, SCRIPT_KEY));
  // The place (line, column from 1, in characters as the interpreter counts them) as an offset
  // in the editor's text (in UTF-16 units, as the text area counts them).
  const offsetOf = (line, column) => {
    const lines = editor.value.split('\n');
    let offset = 0;
    for (let i = 0; i < Math.min(line - 1, lines.length); i++) offset += lines[i].length + 1;
    const chars = Array.from(lines[line - 1] ?? '').slice(0, Math.max(column - 1, 0));
    return Math.min(offset + chars.join('').length, editor.value.length);
  };
  const goTo = (line, column) => {
    const at = offsetOf(line, column);
    editor.focus();
    editor.setSelectionRange(at, Math.min(at + 1, editor.value.length));
    const lineHeight = parseFloat(getComputedStyle(editor).lineHeight) || 19;
    editor.scrollTop = Math.max(0, (line - 4) * lineHeight);
  };
  const message = $('script-message');
  const showReport = (report, ms, workerMs) => {
    marks = new Map();
    message.replaceChildren();
    const place = (x) => `Line ${x.line}, column ${x.column}`;
    if (report.error) {
      const e = report.error;
      marks.set(e.line, 'error');
      const p = document.createElement('p');
      p.textContent = `${place(e)}: ${e.message}`;
      const go = document.createElement('button');
      go.type = 'button';
      go.textContent = 'Go to';
      go.addEventListener('click', () => goTo(e.line, e.column));
      p.append(go);
      message.append(p);
    }
    for (const w of report.warnings) {
      if (!marks.has(w.line)) marks.set(w.line, 'warn');
      const p = document.createElement('p');
      p.textContent = `${place(w)} (note): ${w.message}`;
      message.append(p);
    }
    message.dataset.kind = report.error ? 'error' : report.warnings.length ? 'warn' : '';
    renderGutter(true);
    const count = (n, one, many) => `${n.toLocaleString('en')} ${n === 1 ? one : many}`;
    const parts = [];
    if (report.triangles) parts.push(count(report.triangles, 'triangle', 'triangles'));
    if (report.segments) parts.push(count(report.segments, 'segment', 'segments'));
    if (report.points) parts.push(count(report.points, 'point', 'points'));
    $('script-info').textContent = (report.error ? 'Stopped at an error' : `Ran in ${ms.toFixed(0)} ms`)
      + ` (${count(report.steps, 'step', 'steps')}${workerMs !== undefined ? `, ${workerMs.toFixed(0)} ms in the worker` : ''}): `
      + (report.complexes ? `${count(report.complexes, 'result', 'results')} drawn, ${parts.join(', ')}.` : 'nothing to draw.')
      + (report.left_out ? ` Left out of the view: ${report.left_out}.` : '');
    const list = $('script-values');
    const ran = editor.value;
    list.replaceChildren(...report.values.map((v, index) => {
      const li = document.createElement('li');
      const line = document.createElement('span');
      line.className = 'line';
      line.textContent = `line ${v.line}`;
      li.append(line, v.text);
      if (v.patch) {
        // A surface of two parameters: its Bézier net, to edit point by point (ξ = z).
        const edit = document.createElement('button');
        edit.type = 'button';
        edit.className = 'edit-patch';
        edit.textContent = 'Edit as a Bézier patch';
        edit.title = 'Open this surface in the Bézier mode as a patch solid (x, y, ξ = z): its control net, found from the map';
        edit.addEventListener('click', async () => {
          // The script runs again to find the net: in the worker, cancellable.
          const worker = scriptWorker();
          let json;
          const task = worker && work.start('script', 'Finding the Bézier net', () => running.cancel());
          const running = worker?.run({ kind: 'plasm-patch', script: ran, index }, { onStart: () => task.started() });
          try {
            json = worker ? new TextDecoder().decode((await running).data) : script_patch_model(ran, index);
            modeler.load_model(json);
          } catch (err) {
            if (err.cancelled) say('Finding the Bézier net was cancelled; the model was kept.');
            else say(`This surface has no Bézier net: ${err.message ?? err}`, 'error');
            return;
          } finally {
            task?.end();
          }
          setWorkspace('bezier');
          resize();
          resize3();
          const [n, m] = panel().degree;
          say(`Opened the surface of line ${v.line} as a ${n + 1} × ${m + 1}-point patch (ξ = z); Undo brings back the previous model.`);
          changed();
        });
        li.append(edit);
      }
      return li;
    }));
    document.body.dataset.scriptState = report.error ? 'error' : 'done';
    document.body.dataset.scriptMs = ms.toFixed(1);
    document.body.dataset.scriptWorkerMs = workerMs === undefined ? '' : workerMs.toFixed(1);
    document.body.dataset.scriptCounts = `${report.triangles},${report.segments},${report.points}`;
  };
  // The script worker starts with the first run (most visits never open this mode).
  const scriptWorker = lazyRunner();
  let runSeq = 0;
  let scriptTask = null; // the run under way in the work list
  const stopScript = () => {
    runSeq += 1;
    scriptWorker()?.cancelAll();
    scriptTask?.end();
    scriptTask = null;
    $('script-stop').disabled = true;
    document.body.dataset.scriptState = 'stopped';
    $('script-info').textContent = 'Stopped; the drawing is from the last run.';
  };
  const runScript = async ({ refit = false } = {}) => {
    const script = editor.value;
    const seq = ++runSeq;
    scriptRan = true;
    $('script-stop').disabled = false;
    document.body.dataset.scriptState = 'running';
    scriptTask?.end();
    const task = work.start('script', 'Running the script', stopScript);
    scriptTask = task;
    const t0 = performance.now();
    let result;
    try {
      const worker = scriptWorker();
      if (worker) {
        worker.cancelAll();
        result = await worker.run({ kind: 'plasm', script }, { onStart: () => task.started() });
      } else {
        task.started();
        const run = headless_plasm(script);
        result = { report: run.report(), data: run.take_floats() };
        run.free();
      }
    } catch (err) {
      if (err.cancelled || seq !== runSeq) return; // a newer run or Stop took over
      result = null;
      say(`The script could not run: ${err.message ?? err}`, 'error');
      document.body.dataset.scriptState = 'error';
    }
    if (seq !== runSeq) return;
    $('script-stop').disabled = true;
    scriptTask?.end();
    scriptTask = null;
    if (!result) return;
    const report = JSON.parse(result.report);
    // A run that fails before drawing anything keeps the last drawing on screen.
    if (result.data.length || !report.error) sv.set_drawing(result.data, refit);
    showReport(report, performance.now() - t0, result.ms);
    redraw(VIEW3);
  };
  const openScript = (text, note) => {
    editor.value = text;
    storage.set(text, SCRIPT_KEY);
    setWorkspace('script');
    resize();
    resize3();
    renderGutter(true);
    say(note);
    runScript({ refit: true });
  };
  for (const e of examples) {
    const option = document.createElement('option');
    option.value = e.id;
    option.textContent = `Script ${e.id}: ${e.title}`;
    $('script-example').append(option);
  }
  $('script-example').addEventListener('change', (e) => {
    const example = examples.find((x) => x.id === e.target.value);
    e.target.value = '';
    if (example) openScript(example.source, `Opened the paper's Script ${example.id}.`);
  });
  $('script-run').addEventListener('click', () => runScript());
  $('script-stop').addEventListener('click', stopScript);
  // Tab indents; after Esc it leaves the editor (the usual way out of a code editor's Tab).
  let tabEscapes = false;
  editor.addEventListener('keydown', (e) => {
    if ((e.ctrlKey || e.metaKey) && e.key === 'Enter') {
      e.preventDefault();
      runScript();
      return;
    }
    if (e.key === 'Escape') {
      tabEscapes = true;
      return;
    }
    if (e.key === 'Tab' && !tabEscapes && !e.shiftKey && !e.ctrlKey && !e.altKey && !e.metaKey) {
      e.preventDefault();
      document.execCommand?.('insertText', false, '  ') || editor.setRangeText('  ', editor.selectionStart, editor.selectionEnd, 'end');
      return;
    }
    tabEscapes = false;
  });
  editor.addEventListener('focus', () => { tabEscapes = false; });
  renderGutter(true);

  // Hooks for tests and tools: the objects, and what the page holds (GPU objects the renderers
  // hold and made, `[buffers, textures, made]`; the wasm memory in bytes).
  window.bezsolid = {
    modeler, ff, sv, canvas, canvas3, viewer, redraw, saveNow, setWorkspace, runScript,
    gpuObjects: () => [...gpu_objects()],
    wasmMemory: () => wasm.memory.buffer.byteLength,
  };
  $('loading').hidden = true;
  requestAnimationFrame(() => {
    modeler.render();
    if (viewer) {
      if (freeform()) ff.render(viewer);
      else if (!scripting()) modeler.render_3d(viewer);
    }
    updatePanel();
    saveNow();
    if (scripting() && !scriptRan) runScript({ refit: true });
    document.body.dataset.ready = 'true';
  });
}

// localStorage can be missing or refuse (private modes, quota): the page works on without it.
const FF_KEY = 'bezsolid.freeform.v1';
const SCRIPT_KEY = 'bezsolid.script.v1';
const WORKSPACE_KEY = 'bezsolid.workspace.v1';
const storage = {
  key: 'bezsolid.model.v1',
  get(key = this.key) {
    try { return localStorage.getItem(key); } catch { return null; }
  },
  set(value, key = this.key) {
    try { localStorage.setItem(key, value); return true; } catch { return false; }
  },
  remove(key) {
    try { localStorage.removeItem(key); } catch { /* nothing kept, nothing to remove */ }
  },
};

window.addEventListener('unhandledrejection', (e) => say(`Error: ${e.reason?.message ?? e.reason}`, 'error'));
main().catch((err) => {
  $('loading').textContent = 'The modeler could not start.';
  say(`The modeler could not start: ${err?.message ?? err}`, 'error');
  console.error(err);
});
