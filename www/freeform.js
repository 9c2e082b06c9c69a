// The Free-form mode: solids bounded by PN triangles over meshes (built-in or imported), each
// placed by an offset, a rotation and a scale, and a Boolean expression over them, drawn in the
// 3D view; its panel, its controls, mesh import, dragging a solid in the 3D view, and the result's
// fine surface made in a worker while the view draws a coarse one.
import { tools } from './modules.js';
import { $, say, enableItems, forgetStale } from './ui.js';
import { follower, lazyRunner } from './work.js';

// The solids' colours in the 3D view, in turn (as the Rust side draws them).
const COLORS = ['#2f6aad', '#a8570f', '#2e7434', '#6a4496', '#1f6e6e', '#a3303f'];
const PLACE_IDS = ['ff-x', 'ff-y', 'ff-z', 'ff-rx', 'ff-ry', 'ff-rz', 'ff-sx', 'ff-sy', 'ff-sz'];

/** Sets up the mode on `app` (see main.js); returns what the page asks of it. */
export function setupFreeForm(app) {
  const { ff, VIEW3 } = app;
  let display = 'result';
  // The solid the placement fields and a drag move: B when there is one, as before many solids.
  let slot = 1;

  // Without workers: the tools' module on this thread (a promise while it is fetched).
  let here = null;
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

  const letter = (k) => ff.letters()[k] ?? String.fromCharCode(65 + k);

  // An OBJ, STL or PLY file becomes solid `k` (one past the last: a new solid).
  const importMesh = async (k, file) => {
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
    const imported = app.attempt(`${file.name} could not be imported, so the scene was kept`, () => ff.import_mesh(k, file.name, bytes));
    task.end();
    if (imported) {
      app.setWorkspace('freeform');
      app.resize3();
      say(`Imported ${file.name} as solid ${letter(k)}. Its triangles become curved PN patches through their corners; edges sharper than the crease angle stay sharp.`);
    }
  };

  // A row per solid: its letter, mesh, import and remove. Rows are made again when the count or
  // the letters change; their controls keep ids by letter (#ff-a, #ff-import-a, …).
  const rows = $('ff-operands');
  let rowsKey = '';
  const buildRows = () => {
    const letters = ff.letters();
    const key = letters.join(',');
    if (key === rowsKey) return;
    rowsKey = key;
    rows.replaceChildren();
    letters.forEach((name, k) => {
      const row = $('ff-row').content.firstElementChild.cloneNode(true);
      const id = name.toLowerCase();
      const swatch = row.querySelector('.ff-letter');
      swatch.textContent = name;
      swatch.style.background = COLORS[k % COLORS.length];
      const select = row.querySelector('.ff-mesh');
      select.id = `ff-${id}`;
      select.setAttribute('aria-label', `Solid ${name}`);
      select.addEventListener('change', () => app.attempt(`Solid ${name}`, () => ff.set_example(k, select.value)));
      const file = row.querySelector('.ff-file');
      file.id = `ff-import-${id}`;
      file.addEventListener('change', (e) => { importMesh(k, e.target.files?.[0]); e.target.value = ''; });
      const pick = row.querySelector('.ff-import');
      pick.id = `ff-pick-${id}`;
      pick.setAttribute('aria-label', `Import mesh as ${name}…`);
      pick.addEventListener('click', () => file.click());
      const remove = row.querySelector('.ff-remove');
      remove.id = `ff-remove-${id}`;
      remove.setAttribute('aria-label', `Remove solid ${name}`);
      remove.disabled = letters.length === 1;
      remove.addEventListener('click', () => {
        if (app.attempt(`Remove ${name}`, () => ff.remove_operand(k))) {
          say(`Removed solid ${name}; the expression is now ${ff.expression()}.`);
        }
      });
      rows.append(row);
    });
    $('ff-slot').replaceChildren(...letters.map((name, k) => new Option(name, String(k))));
  };

  // The rows are there from the start, before the mode is first shown.
  buildRows();

  $('ff-add').addEventListener('click', () => {
    let added = -1;
    if (app.attempt('Add a solid', () => { added = ff.add_operand('icosphere'); })) {
      slot = added;
      say(`Added solid ${letter(added)} beside the scene: ${ff.expression()}. Change its mesh, place it, or edit the expression.`);
    }
  });
  $('ff-op').addEventListener('change', (e) => app.attempt('Operation', () => ff.set_operation(e.target.value)));
  const expr = $('ff-expr');
  const applyExpression = () => {
    if (expr.value.trim() === ff.expression()) {
      expr.removeAttribute('aria-invalid');
      return;
    }
    try {
      ff.set_expression(expr.value);
      expr.removeAttribute('aria-invalid');
      app.changed();
    } catch (err) {
      // The text stays as typed, marked, so that it can be mended; the scene is kept.
      expr.setAttribute('aria-invalid', 'true');
      say(`Expression: ${err?.message ?? err}`, 'error');
    }
  };
  expr.addEventListener('change', applyExpression);
  expr.addEventListener('keydown', (e) => {
    if (e.key === 'Enter') applyExpression();
    if (e.key === 'Escape') {
      expr.value = ff.expression();
      expr.removeAttribute('aria-invalid');
    }
  });
  $('ff-slot').addEventListener('change', (e) => { slot = Number(e.target.value); update(); });
  for (const id of PLACE_IDS) {
    $(id).addEventListener('change', () => {
      const v = PLACE_IDS.map((k) => $(k).valueAsNumber);
      if (!v.every(Number.isFinite)) {
        $(id).setAttribute('aria-invalid', 'true');
        return;
      }
      const ok = app.attempt(`Place ${letter(slot)}`, () => ff.set_placement(slot, ...v));
      if (ok) for (const k of PLACE_IDS) $(k).removeAttribute('aria-invalid');
      else $(id).setAttribute('aria-invalid', 'true');
    });
  }
  $('ff-crease').addEventListener('change', (e) => {
    const v = e.target.valueAsNumber;
    const ok = Number.isFinite(v) && app.attempt(`Crease angle of ${letter(slot)}`, () => ff.set_crease(slot, v));
    if (ok) e.target.removeAttribute('aria-invalid');
    else e.target.setAttribute('aria-invalid', 'true');
  });
  const drag = $('ff-drag');
  drag.addEventListener('click', () => {
    drag.setAttribute('aria-pressed', String(drag.getAttribute('aria-pressed') !== 'true'));
    update();
  });
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

  // The panel: the solids, the operation and expression, the placement and what the view shows.
  const update = () => {
    forgetStale('ff-measure-out', ff.revision());
    buildRows();
    const count = ff.operand_count();
    if (slot >= count) slot = count - 1;
    const op = ff.operation();
    $('ff-op').value = op;
    const text = ff.expression();
    if (document.activeElement !== expr || expr.getAttribute('aria-invalid') !== 'true') {
      if (document.activeElement !== expr) expr.value = text;
      if (expr.value === text) expr.removeAttribute('aria-invalid');
    }
    for (let k = 0; k < count; k++) {
      const select = $(`ff-${letter(k).toLowerCase()}`);
      if (!select) continue;
      const name = ff.operand_name(k);
      const imported = select.querySelector('option[value="imported"]');
      if (name && !ff.operand_is_example(k)) {
        imported.hidden = false;
        imported.textContent = `Imported: ${name}`;
        select.value = 'imported';
      } else if (name) {
        imported.hidden = true;
        select.value = name;
      }
    }
    $('ff-slot').value = String(slot);
    const placement = ff.placement(slot);
    if (placement) {
      PLACE_IDS.forEach((id, k) => {
        if (document.activeElement !== $(id)) $(id).value = String(Math.round(placement[k] * 1e6) / 1e6);
      });
    }
    if (document.activeElement !== $('ff-crease')) $('ff-crease').value = String(ff.crease(slot) ?? 50);
    drag.textContent = drag.getAttribute('aria-pressed') === 'true' ? `Dragging moves ${letter(slot)}` : 'Drag to move';
    const counts = ff.triangle_counts();
    const info = ff.surface_info();
    $('model-name').textContent = `Free-form: ${text}`;
    let line = Array.from(counts, (n) => n).map((n, k) => `${letter(k)}: ${n.toLocaleString('en')} triangles`).join(', ') + '. ';
    const pointCounts = ff.point_counts();
    if (display === 'points' && pointCounts) {
      const [inside, marked] = pointCounts;
      line += `Point mesh 25 × 25 × 25: ${inside.toLocaleString('en')} points`
        + (marked ? `, ${marked.toLocaleString('en')} red (in the partial chain, removed by its last term)` : '');
    } else if (info) {
      line += `Result surface: ${info[0].toLocaleString('en')} triangles at ${info[1]}.`;
    }
    $('ff-info').textContent = line;
    document.body.dataset.ffSurface = info ? `${info[0]},${info[1]}` : '';
    enableItems('#export-menu [data-volume]', true);
    enableItems('#export-menu [data-bezier], #export-menu [data-script]', false);
    document.body.dataset.ffOperation = op;
    document.body.dataset.ffExpression = text;
    $('undo').disabled = !ff.can_undo();
    $('redo').disabled = !ff.can_redo();
    const shown = { result: `the surface of ${text}`, points: 'the point mesh of the chain', operands: `the PN surfaces of the solids ${ff.letters().join(', ')}` }[display];
    app.canvas3.setAttribute('aria-label', `3D view of the free-form solids: ${shown}. Drag to orbit, right-drag or Shift-drag to pan, Alt-drag (or Drag to move) moves solid ${letter(slot)}, turn the wheel to zoom, F frames the solids again`);
  };

  return {
    update,
    importMesh,
    /** Whether a drag that begins with `event` moves the selected solid (rather than orbiting). */
    movesSolid: (event) => event.button === 0 && (event.altKey || drag.getAttribute('aria-pressed') === 'true'),
    /** The solid a drag moves. */
    slot: () => slot,
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
      // Without a worker: the tools' module is fetched once, then the surface is made here.
      if (!here) {
        here = tools();
        here.then((t) => { here = t; app.redraw(VIEW3); }, (err) => say(`No fine surface: ${err.message ?? err}`, 'error'));
      }
      if (here instanceof Promise) return;
      const request = ff.surface_request();
      if (request && ff.set_surface(request[0], request[1], here.headless_esc_surface(ff.model_json(), request[1]))) app.redraw(VIEW3);
    },
    /** Cancels the work the scene has moved past. */
    prune: () => mesher?.prune(),
    /** The worker's last time, for the debug overlay. */
    timings: () => [['worker free-form surface', mesher]],
  };
}
