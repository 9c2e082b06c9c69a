// The outliner: the model as a tree of parts (primitives, Bézier patches and volumes, operations
// and moves), beside the views. Adding a part to a model of one solid makes it a model of many.
// Selecting a Bézier part opens its control points in the 2D and 3D editors; the 3D view shows the
// whole model, the selection framed. The selection's numbers are typed, or slid for blends and
// morphs (a slider's moves are one undo step). All of it is the modeler's (parts.rs); this module
// draws the rows and passes the clicks.
import { $ } from './ui.js';

// The numbers with sliders, and their ranges (typed numbers may go past them).
const SLIDERS = {
  a0: [0, 1, 0.01], a1: [0.05, 2, 0.01], a2: [0.05, 2, 0.01], t: [0, 1, 0.01],
};

// A field's name as people read it: `center[1]` → `center y`.
const fieldLabel = (name) => name.replace(/\[(\d)\]/, (_, i) => ` ${'xyz'[Number(i)]}`);

/** Sets up the outliner on `app` (see main.js); returns what the page asks of it. */
export function setupOutline(app) {
  const { modeler } = app;
  const list = $('outline-tree');
  const fields = $('outline-fields');
  let state = null; // the last `modeler.outline()`, parsed
  let fieldsOf = ''; // the selection and field names the inputs were made for
  const collapsed = new Set(); // path keys of the rows whose children are folded away
  let shape = ''; // the rows' paths: when they change (a node added, moved, removed), folds go

  const pathKey = (path) => path.join('.');
  const hasChildren = (rows, i) => i + 1 < rows.length && rows[i + 1].depth > rows[i].depth;
  // The rows shown: none under a folded one; the selection's ancestors are always open.
  const shownRows = () => {
    if (!state) return [];
    const sel = state.selected;
    for (let k = 0; k < sel.length; k++) collapsed.delete(pathKey(sel.slice(0, k)));
    const out = [];
    let foldedDepth = Infinity;
    for (const row of state.rows) {
      if (row.depth > foldedDepth) continue;
      foldedDepth = Infinity;
      out.push(row);
      if (collapsed.has(pathKey(row.path))) foldedDepth = row.depth;
    }
    return out;
  };
  const toggle = (row) => {
    const key = pathKey(row.path);
    if (collapsed.has(key)) collapsed.delete(key);
    else collapsed.add(key);
    makeRows();
    list.querySelector('[aria-selected="true"]')?.focus();
  };
  const select = (path) => app.attempt('Select', () => modeler.outline_select(Uint32Array.from(path)));

  for (const button of document.querySelectorAll('[data-add]')) {
    button.addEventListener('click', () => app.attempt('Add a part', () => modeler.outline_add(button.dataset.add)));
  }
  for (const button of document.querySelectorAll('[data-wrap]')) {
    button.addEventListener('click', () => app.attempt('Put an operation around the part', () => modeler.outline_wrap(button.dataset.wrap)));
  }
  $('part-up').addEventListener('click', () => app.attempt('Move the part', () => modeler.outline_reorder(-1)));
  $('part-down').addEventListener('click', () => app.attempt('Move the part', () => modeler.outline_reorder(1)));
  $('part-remove').addEventListener('click', () => app.attempt('Remove the part', () => modeler.outline_remove()));
  const hide = () => app.attempt('Hide the part', () => modeler.outline_hide());
  $('part-hide').addEventListener('click', hide);
  const nameInput = $('part-name');
  nameInput.addEventListener('change', () => {
    const ok = app.attempt('Name the part', () => modeler.outline_rename(nameInput.value));
    nameInput.setAttribute('aria-invalid', String(!ok));
  });
  nameInput.addEventListener('keydown', (e) => { if (e.key === 'Enter') nameInput.blur(); });

  // The tree's keys (the WAI-ARIA tree pattern): ↑ ↓ move the selection, → opens a row or goes to
  // its first child, ← folds it or goes to its parent, Home and End go to the ends, Delete
  // removes, Alt+↑ Alt+↓ reorder.
  list.addEventListener('keydown', (e) => {
    if (!state) return;
    const rows = shownRows();
    const at = rows.findIndex((r) => pathKey(r.path) === pathKey(state.selected));
    const row = rows[at];
    let to = null;
    if (e.key === 'ArrowRight' && row && hasChildren(state.rows, state.rows.indexOf(row))) {
      if (collapsed.has(pathKey(row.path))) toggle(row);
      else to = at + 1;
    } else if (e.key === 'ArrowLeft' && row) {
      if (hasChildren(state.rows, state.rows.indexOf(row)) && !collapsed.has(pathKey(row.path))) toggle(row);
      else if (row.path.length) to = rows.findIndex((r) => pathKey(r.path) === pathKey(row.path.slice(0, -1)));
    } else if (e.key === 'ArrowDown' && e.altKey) app.attempt('Move the part', () => modeler.outline_reorder(1));
    else if (e.key === 'ArrowUp' && e.altKey) app.attempt('Move the part', () => modeler.outline_reorder(-1));
    else if (e.key === 'ArrowDown') to = Math.min(rows.length - 1, at + 1);
    else if (e.key === 'ArrowUp') to = Math.max(0, at - 1);
    else if (e.key === 'Home') to = 0;
    else if (e.key === 'End') to = rows.length - 1;
    else if (e.key === 'Delete' || e.key === 'Backspace') app.attempt('Remove the part', () => modeler.outline_remove());
    else if (e.key === 'h' || e.key === 'H') hide();
    else if (e.key === 'F2') {
      nameInput.focus();
      nameInput.select();
    }
    else return;
    e.preventDefault();
    if (to !== null && to !== at) select(rows[to].path);
    requestAnimationFrame(() => list.querySelector('[aria-selected="true"]')?.focus());
  });

  const makeRows = () => {
    const all = state ? state.rows : [];
    list.replaceChildren(...shownRows().map((row) => {
      const li = document.createElement('li');
      if (hasChildren(all, all.indexOf(row))) {
        const open = !collapsed.has(pathKey(row.path));
        li.setAttribute('aria-expanded', String(open));
        const twist = document.createElement('span');
        twist.className = 'twist';
        twist.textContent = open ? '▾' : '▸';
        twist.setAttribute('aria-hidden', 'true');
        twist.title = open ? 'Fold its parts away' : 'Show its parts';
        twist.addEventListener('click', (e) => {
          e.stopPropagation();
          toggle(row);
        });
        li.append(twist);
      }
      const selected = state && pathKey(row.path) === pathKey(state.selected);
      li.setAttribute('role', 'treeitem');
      li.setAttribute('aria-level', String(row.depth + 1));
      li.setAttribute('aria-selected', String(selected));
      li.tabIndex = selected ? 0 : -1;
      li.dataset.path = pathKey(row.path);
      li.style.paddingLeft = `${1.5 + row.depth * 1.1}rem`;
      li.className = [row.bezier ? 'bezier' : '', row.hidden ? 'hidden-part' : ''].join(' ').trim();
      li.append(row.label);
      if (row.bezier) li.title = 'A Bézier part: select it to edit its control points in the 2D and 3D views';
      li.addEventListener('click', () => select(row.path));
      return li;
    }));
  };

  const makeFields = () => {
    fields.replaceChildren();
    if (!state) return;
    for (const { name, value } of state.fields) {
      const wrap = document.createElement('label');
      wrap.className = 'field';
      wrap.textContent = fieldLabel(name);
      const number = document.createElement('input');
      number.type = 'number';
      number.step = 'any';
      number.inputMode = 'decimal';
      number.dataset.field = name;
      number.value = String(Math.round(value * 1e6) / 1e6);
      number.addEventListener('change', () => {
        const v = number.valueAsNumber;
        const ok = Number.isFinite(v) && app.attempt(`Set ${fieldLabel(name)}`, () => modeler.outline_set(name, v));
        number.setAttribute('aria-invalid', String(!ok));
      });
      wrap.append(number);
      const range = SLIDERS[name];
      if (range) {
        const slider = document.createElement('input');
        slider.type = 'range';
        [slider.min, slider.max, slider.step] = range.map(String);
        slider.value = String(value);
        slider.dataset.slider = name;
        slider.setAttribute('aria-label', `${fieldLabel(name)} (slider)`);
        slider.addEventListener('input', () => {
          number.value = slider.value;
          app.attempt(`Set ${fieldLabel(name)}`, () => modeler.outline_set(name, slider.valueAsNumber));
        });
        wrap.append(slider);
      }
      fields.append(wrap);
    }
  };

  // A HyperFun part's program opens in the HyperFun mode, to be put back from there.
  $('part-hyperfun').addEventListener('click', () => {
    const part = modeler.outline_hyperfun();
    if (part !== undefined) app.hyperfun.editPart(JSON.parse(part));
  });

  /** Brings the outliner up to date with the model (each frame of the Bézier mode). */
  const update = () => {
    const text = modeler.outline();
    const next = text ? JSON.parse(text) : null;
    const changed = JSON.stringify(next) !== JSON.stringify(state);
    state = next;
    const nextShape = state ? state.rows.map((r) => `${pathKey(r.path)}:${r.label.split(' ')[0]}`).join(' ') : '';
    if (nextShape !== shape) {
      shape = nextShape;
      collapsed.clear();
    }
    document.body.dataset.parts = state ? String(state.rows.length) : '';
    $('part-tools').hidden = !state;
    $('outline-hint').hidden = !!state;
    $('no-part').hidden = !state || state.dimension !== 3 || state.open !== null;
    $('no-part-3d').hidden = !state || state.dimension !== 2 || state.open !== null;
    if (!changed) return;
    $('part-hyperfun').hidden = !state || modeler.outline_hyperfun() === undefined;
    if (state) {
      if (document.activeElement !== nameInput) nameInput.value = state.name;
      $('part-hide').setAttribute('aria-pressed', String(state.hidden));
      $('part-hide').textContent = state.hidden ? 'Show' : 'Hide';
    }
    const hadFocus = list.contains(document.activeElement);
    makeRows();
    if (hadFocus) list.querySelector('[aria-selected="true"]')?.focus();
    // The inputs are made again only for another selection or other fields: typing keeps its place.
    const key = state ? `${pathKey(state.selected)}|${state.fields.map((f) => f.name).join()}` : '';
    if (key !== fieldsOf) {
      fieldsOf = key;
      makeFields();
    } else if (state) {
      for (const { name, value } of state.fields) {
        const number = fields.querySelector(`[data-field="${name}"]`);
        if (number && document.activeElement !== number) number.value = String(Math.round(value * 1e6) / 1e6);
        const slider = fields.querySelector(`[data-slider="${name}"]`);
        if (slider && document.activeElement !== slider) slider.value = String(value);
      }
    }
    $('outline-info').textContent = state
      ? `${state.rows.length} ${state.rows.length === 1 ? 'node' : 'nodes'}, ${state.dimension}D; `
        + (state.open ? 'the selected Bézier part is in the editors.' : `selected: ${state.rows.find((r) => pathKey(r.path) === pathKey(state.selected))?.label ?? '–'}.`)
      : '';
  };

  return { update, state: () => state };
}
