// The Free-form mode: solids bounded by PN triangles over meshes (built-in or imported) and their
// Booleans, drawn in the 3D view; its panel, its controls, mesh import, and the result's fine
// surface made in a worker while the view draws a coarse one.
import { headless_esc_surface } from './pkg/bezsolid_web.js';
import { $, say, enableItems } from './ui.js';
import { follower, lazyRunner } from './work.js';

const OPERATION_NAMES = { none: 'A', union: 'A ∪ B', intersection: 'A ∩ B', difference: 'A − B' };

/** Sets up the mode on `app` (see main.js); returns what the page asks of it. */
export function setupFreeForm(app) {
  const { ff, VIEW3 } = app;
  let display = 'result';

  const mesher = app.runners.surface && follower({
    list: app.work,
    worker: lazyRunner(true),
    request: () => ff.surface_request(),
    revision: () => ff.revision(),
    job: ([, resolution]) => ({ kind: 'esc-surface', model: ff.model_json(), resolution }),
    accept: ([revision, resolution], { data }) => ff.set_surface(revision, resolution, data),
    onAccepted: () => app.redraw(VIEW3),
    label: ([, resolution]) => `Meshing the result at ${resolution}`,
    failed: 'The result could not be meshed',
  });

  // An OBJ, STL or PLY file becomes solid A (slot 0) or B (1).
  const importMesh = async (slot, file) => {
    if (!file) return;
    if (file.size > 128 * 1024 * 1024) {
      say(`${file.name} is too large (${file.size} bytes; a mesh file is at most 128 MiB).`, 'error');
      return;
    }
    const bytes = new Uint8Array(await file.arrayBuffer());
    // Reading, checking and indexing a large mesh takes a moment on this thread: say so first.
    say(`Importing ${file.name} (${bytes.length.toLocaleString('en')} bytes)…`);
    const task = app.work.start('import', `Importing ${file.name}`);
    task.started();
    await new Promise((r) => requestAnimationFrame(() => setTimeout(r, 0)));
    const imported = app.attempt(`${file.name} could not be imported, so the scene was kept`, () => ff.import_mesh(slot, file.name, bytes));
    task.end();
    if (imported) {
      app.setWorkspace('freeform');
      app.resize3();
      say(`Imported ${file.name} as solid ${slot === 0 ? 'A' : 'B'}, smoothed: each triangle becomes a curved PN patch through its corners, so sharp edges come out rounded.`);
    }
  };

  $('ff-b').innerHTML = $('ff-a').innerHTML; // one list of meshes for both solids
  $('ff-a').addEventListener('change', (e) => app.attempt('Solid A', () => ff.set_example(0, e.target.value)));
  $('ff-b').addEventListener('change', (e) => app.attempt('Solid B', () => ff.set_example(1, e.target.value)));
  $('ff-op').addEventListener('change', (e) => app.attempt('Operation', () => ff.set_operation(e.target.value)));
  $('ff-import-a').addEventListener('change', (e) => { importMesh(0, e.target.files?.[0]); e.target.value = ''; });
  $('ff-import-b').addEventListener('change', (e) => { importMesh(1, e.target.files?.[0]); e.target.value = ''; });
  const offsetIds = ['ff-bx', 'ff-by', 'ff-bz'];
  for (const id of offsetIds) {
    $(id).addEventListener('change', () => {
      const v = offsetIds.map((k) => $(k).valueAsNumber);
      if (!v.every(Number.isFinite)) {
        $(id).setAttribute('aria-invalid', 'true');
        return;
      }
      $(id).removeAttribute('aria-invalid');
      app.attempt('Move B', () => ff.set_offset(1, v[0], v[1], v[2]));
    });
  }
  for (const radio of document.querySelectorAll('input[name="ff-display"]')) {
    radio.addEventListener('change', () => {
      if (!radio.checked) return;
      display = radio.value;
      ff.set_display(display);
      app.redraw(VIEW3);
    });
  }
  $('ff-resolution').addEventListener('change', (e) => {
    const v = e.target.valueAsNumber;
    if (!Number.isFinite(v)) return;
    e.target.value = String(ff.set_resolution(v));
    app.redraw(VIEW3);
  });

  // The panel: the operation, the solids, B's offset and what the view shows.
  const update = () => {
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
      offsetIds.forEach((id, k) => {
        if (document.activeElement !== $(id)) $(id).value = String(Math.round(offset[k] * 1e6) / 1e6);
      });
    }
    const counts = ff.triangle_counts();
    const info = ff.surface_info();
    $('model-name').textContent = `Free-form: ${OPERATION_NAMES[op]}`;
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
    if ([0, 1].some((slot) => ff.operand_name(slot) && !ff.operand_is_example(slot))) {
      text += ' Imported meshes are smoothed by PN triangles: their sharp edges come out rounded.';
    }
    $('ff-info').textContent = text;
    document.body.dataset.ffSurface = info ? `${info[0]},${info[1]}` : '';
    enableItems('#export-menu [data-volume]', true);
    enableItems('#export-menu [data-bezier]', false);
    document.body.dataset.ffOperation = op;
    $('undo').disabled = !ff.can_undo();
    $('redo').disabled = !ff.can_redo();
    const shown = { result: `the surface of ${OPERATION_NAMES[op]}`, points: 'the point mesh of the chain', operands: 'the PN surfaces of A and B' }[display];
    app.canvas3.setAttribute('aria-label', `3D view of the free-form solids: ${shown}. Drag to orbit, right-drag or Shift-drag to pan, turn the wheel to zoom, F frames the solids again`);
  };

  return {
    update,
    importMesh,
    /** Undoes (`redo` false) or redoes a change of the scene; returns whether there was one. */
    history: (redo) => (redo ? ff.redo() : ff.undo()),
    /** Draws the 3D view. */
    render3d: (viewer) => ff.render(viewer),
    /** After a 3D frame: the fine surface from the worker (or, without one, here, once per change). */
    follow: () => {
      if (mesher) {
        mesher.check();
        return;
      }
      const request = ff.surface_request();
      if (request && ff.set_surface(request[0], request[1], headless_esc_surface(ff.model_json(), request[1]))) app.redraw(VIEW3);
    },
    /** Cancels the work the scene has moved past. */
    prune: () => mesher?.prune(),
    /** The worker's last time, for the debug overlay. */
    timings: () => [['worker free-form surface', mesher]],
  };
}
