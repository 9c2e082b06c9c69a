// The Bézier mode: the 2D contour view's input, the side panel (the selected point, the model, a
// volume's slice and surface), the model's controls, and the work that follows a volume (its fine
// surface and contour stack, made in workers while the view draws a coarse one).
import { $, fmt, say, messageOf, setupMenu, enableItems, forgetStale } from './ui.js';
import { follower, lazyRunner } from './work.js';
import { KEYS, storage } from './storage.js';
import { pointers } from './touch.js';

/** Sets up the mode on `app` (see main.js); returns what the page asks of it. */
export function setupBezier(app) {
  const { modeler, canvas, VIEW2, VIEW3 } = app;
  const inputs = { x: $('px'), y: $('py'), xi: $('xi') };

  // The volume's fine surface and contour stack, each following the model in a worker.
  const mesher = app.runners.surface && follower({
    list: app.work,
    worker: () => app.runners.surface,
    request: () => modeler.surface_request(),
    // The model's revision with the cut's changes: a surface asked for before either is stale.
    revision: () => modeler.surface_revision(),
    // What the view shows: a model of many solids less its hidden parts.
    job: ([, resolution]) => ({ kind: 'surface', model: modeler.view_json() ?? modeler.model_json(), resolution }),
    accept: ([revision, resolution], { data, shares, kept }) => {
      const taken = modeler.set_surface(revision, resolution, data);
      // In how many workers' shares the surface drawn was made, and for a model of many solids
      // how many of its blocks were kept from the mesh before (tests read them; the panel says).
      if (taken) {
        document.body.dataset.surfaceShares = String(shares ?? 1);
        document.body.dataset.surfaceKept = kept ? kept.join(',') : '';
      }
      return taken;
    },
    onAccepted: () => app.redraw(VIEW3),
    label: ([, resolution]) => `Meshing the surface at ${resolution}`,
    failed: 'The surface could not be meshed',
  });
  const stacker = app.runners.surface && follower({
    list: app.work,
    worker: lazyRunner(true, app.workers),
    request: () => modeler.stack_request(),
    revision: () => modeler.revision(),
    job: ([, axis]) => ({ kind: 'stack', model: modeler.model_json(), axis }),
    accept: ([revision, axis], { data, shares }) => {
      const taken = modeler.set_stack(revision, axis, data);
      if (taken) document.body.dataset.stackShares = String(shares ?? 1);
      return taken;
    },
    onAccepted: () => app.redraw(VIEW3),
    label: ([, axis]) => `Contour stack across ${'uvw'[axis]}`,
    unit: 'slices',
    failed: 'The contour stack could not be made',
  });

  // The 2D view: select and drag points; the wheel zooms about the pointer (over the selected
  // point, or with Alt, it changes ξ); two fingers, the middle button or Space + drag zoom and pan;
  // the keys change ξ; f under the pointer.
  const local = (e) => {
    const rect = canvas.getBoundingClientRect();
    return [e.clientX - rect.left, e.clientY - rect.top];
  };
  const down = pointers();
  // Two fingers came down: zoom and pan until every finger is up (one left does nothing).
  let pinching = false;
  // A pan with the middle button or Space held: its pointer and last position.
  let panning = null;
  let pressRevision = -1; // the model's revision when the last drag began
  let space = false;
  const capture = (id) => {
    try {
      canvas.setPointerCapture(id);
    } catch {
      // The pointer is gone already.
    }
  };
  const release = (id) => {
    if (canvas.hasPointerCapture(id)) canvas.releasePointerCapture(id);
  };
  canvas.addEventListener('pointerdown', (e) => {
    const [x, y] = local(e);
    // A new press of a pointer still counted (a mouse released off the canvas) ends the old one.
    down.remove(e.pointerId);
    if (!panning && !pinching && down.count() === 0 && (e.button === 1 || (e.button === 0 && space))) {
      panning = { id: e.pointerId, at: [x, y] };
      capture(e.pointerId);
      e.preventDefault();
      return;
    }
    if (e.button !== 0 || panning) return;
    // Fingers and pens make a pinch; a mouse is one pointer whatever it missed.
    const n = e.pointerType === 'mouse' ? 1 : down.add(e.pointerId, [x, y]);
    if (n === 2) {
      // A second finger: the gesture is a pinch, and the edit begun by the first is put back.
      app.dropInput('drag-2d');
      if (modeler.cancel_drag()) {
        canvas.classList.remove('dragging');
        app.changed();
      }
      pinching = true;
      capture(e.pointerId);
      e.preventDefault();
      return;
    }
    if (n > 2 || pinching) return;
    canvas.focus();
    pressRevision = modeler.revision();
    if (modeler.pointer_down(x, y, e.shiftKey)) {
      capture(e.pointerId);
      canvas.classList.add('dragging');
      e.preventDefault();
    }
    app.redraw();
  });
  // f under the pointer, read again when the model changes under a still pointer (after a drag,
  // an undo, a typed value).
  let probeAt = null;
  let probePending = false;
  let probeSeen = -1;
  const showProbe = () => {
    probeSeen = modeler.revision();
    if (!probeAt) return;
    const [px, py, f] = modeler.probe(...probeAt);
    $('probe').textContent = `f(${px.toFixed(3)}, ${py.toFixed(3)}) = ${f.toFixed(4)} (${f >= 0 ? 'inside' : 'outside'})`;
  };
  canvas.addEventListener('pointermove', (e) => {
    const [x, y] = local(e);
    if (panning) {
      if (e.pointerId !== panning.id) return;
      const [px, py] = panning.at;
      panning.at = [x, y];
      if (modeler.pinch(px, py, 1, x - px, y - py)) app.redraw(VIEW2);
      return;
    }
    const step = down.move(e.pointerId, [x, y]);
    if (pinching) {
      if (step && modeler.pinch(step.x, step.y, step.scale, step.dx, step.dy)) app.redraw(VIEW2);
      return;
    }
    probeAt = [x, y];
    if (modeler.dragging()) {
      app.coalesce('drag-2d', (since) => {
        if (modeler.dragging() && modeler.pointer_move(x, y)) {
          app.stats.lastEdit = since;
          app.redraw();
        }
      });
      return;
    }
    canvas.classList.toggle('over-point', modeler.hit(x, y));
    // f under the pointer, once a frame at most (a folded net's inverse map costs milliseconds).
    if (!probePending) {
      probePending = true;
      requestAnimationFrame(() => {
        probePending = false;
        showProbe();
      });
    }
  });
  const endDrag = (e) => {
    if (panning) {
      if (e.pointerId !== panning.id) return;
      panning = null;
      release(e.pointerId);
      return;
    }
    down.remove(e.pointerId);
    if (pinching) {
      if (down.count() === 0) pinching = false;
      release(e.pointerId);
      return;
    }
    if (!modeler.dragging()) return;
    app.flushInput(); // the last move counts
    modeler.pointer_up();
    canvas.classList.remove('dragging');
    release(e.pointerId);
    if (modeler.revision() !== pressRevision) pointMoved();
    app.changed();
  };
  canvas.addEventListener('pointerup', endDrag);
  canvas.addEventListener('pointercancel', endDrag);
  canvas.addEventListener('lostpointercapture', endDrag);
  canvas.addEventListener('wheel', (e) => {
    e.preventDefault();
    const [x, y] = local(e);
    // deltaMode 1 counts lines: about 33 pixels each.
    const dy = e.deltaMode === 1 ? e.deltaY * 33 : e.deltaY;
    // With Ctrl the wheel is a trackpad's pinch: it zooms, wherever the pointer is.
    if (e.ctrlKey) {
      if (modeler.zoom_at(x, y, dy)) {
        probeSeen = -1;
        app.redraw(VIEW2);
      }
    } else if (modeler.wheel(x, y, dy, e.altKey)) {
      pointMoved();
      app.stats.lastEdit = performance.now();
      app.changed();
    } else {
      probeSeen = -1; // the view moved under the pointer: f is read again
      app.redraw(VIEW2);
    }
  }, { passive: false });
  canvas.addEventListener('keyup', (e) => {
    if (e.key === ' ') space = false;
  });
  canvas.addEventListener('blur', () => { space = false; });
  canvas.addEventListener('keydown', (e) => {
    if (e.ctrlKey || e.metaKey || e.altKey) return;
    if (e.key === ' ') {
      // Space held: a drag pans (and the page does not scroll).
      space = true;
      e.preventDefault();
      return;
    }
    if (e.key === 'd' || e.key === 'D') {
      app.toggleDebug();
      e.preventDefault();
      return;
    }
    const wasDragging = modeler.dragging();
    const before = modeler.revision();
    if (e.key === 'Escape') app.dropInput('drag-2d');
    if (modeler.key(e.key, e.shiftKey)) {
      e.preventDefault();
      if (modeler.revision() !== before) pointMoved();
      if (wasDragging && !modeler.dragging()) canvas.classList.remove('dragging');
      app.changed();
    }
  });

  // The unclipped contour of S_ξ beside the solid's, as the paper's Figs. 3 and 5 show it.
  $('unclipped').addEventListener('change', (e) => {
    modeler.set_unclipped(e.target.checked);
    app.redraw();
  });

  for (const radio of document.querySelectorAll('input[name="mode"]')) {
    radio.addEventListener('change', () => {
      if (radio.checked) {
        modeler.set_mode(radio.value);
        app.redraw();
      }
    });
  }

  // Numeric entry for the selected point: ξ, and x and y (space mapping).
  // What the point was when a field took focus: a typed value that is refused (1e9, keyed in
  // digit by digit) puts the point back there rather than keep a prefix of it (1).
  let atFocus = null;
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
        const { point } = app.panel();
        if (!point) return;
        modeler.set_selected_xy(which === 'x' ? value : point[0], which === 'y' ? value : point[1]);
      }
      input.removeAttribute('aria-invalid');
      pointMoved();
      app.changed();
    } catch (err) {
      input.setAttribute('aria-invalid', 'true');
      say(messageOf(err), 'error');
      const back = atFocus?.point;
      if (back && atFocus.which === which) {
        try {
          if (which === 'xi') modeler.set_selected_xi(back[2]);
          else modeler.set_selected_xy(back[0], back[1]);
          app.changed();
        } catch {
          // The point as it was is the model as it was.
        }
      }
    }
  };
  for (const which of Object.keys(inputs)) {
    inputs[which].addEventListener('focus', () => { atFocus = { which, point: app.panel().point }; });
    inputs[which].addEventListener('input', () => applyInput(which));
    inputs[which].addEventListener('change', () => {
      applyInput(which);
      update();
    });
  }

  // The model: presets, a new grid, elevation.
  setupMenu($('preset'), (name) => {
    if (name) app.attempt('Preset', () => modeler.load_preset(name)) && say('Opened the preset; Undo brings back the previous model.');
  });
  $('reset-grid').addEventListener('click', () => {
    app.attempt('New grid', () => modeler.reset_grid($('grid-u').valueAsNumber, $('grid-v').valueAsNumber));
  });
  for (const [id, axis] of [['elevate-u', 0], ['elevate-v', 1], ['elevate-w', 2]]) {
    $(id).addEventListener('click', () => app.attempt('Elevate', () => modeler.elevate(axis)));
  }
  for (const [axis, name] of ['u', 'v', 'w'].entries()) {
    $(`cell-add-${name}`).addEventListener('click', () => {
      if (app.attempt('Add a cell', () => modeler.add_cell(axis))) say(`Added a cell along ${name}: the last cells mirrored; drag a point on the shared face to move both cells.`);
    });
    $(`cell-remove-${name}`).addEventListener('click', () => {
      if (app.attempt('Remove a cell', () => modeler.remove_cell(axis))) say(`Removed the last cell along ${name}.`);
    });
  }
  $('new-volume').addEventListener('click', () => {
    app.attempt('New volume', () => modeler.new_volume($('grid-u').valueAsNumber, $('grid-v').valueAsNumber, $('grid-w').valueAsNumber));
  });

  // A volume: the slice in the 2D view, and the surface's resolution.
  for (const radio of document.querySelectorAll('input[name="slice-axis"]')) {
    radio.addEventListener('change', () => {
      if (!radio.checked) return;
      const axis = Number(radio.value);
      const vd = app.panel().volume_degree;
      if (!vd) return;
      app.attempt('Slice', () => modeler.set_slice(axis, Math.floor(vd[axis] / 2)));
    });
  }
  $('slice-index').addEventListener('input', (e) => {
    const s = app.panel().slice;
    if (s) app.attempt('Slice', () => modeler.set_slice(s[0], e.target.valueAsNumber));
  });
  // The true section of the volume by a plane across the slice's axis, live, instead of the slice.
  // The 3D surface can be cut at the plane, its cut face closed.
  // Across the parameters, the plane u, v or w = t of the parameter box: f at its points S(u).
  const applySection = () => {
    const on = $('section-on').checked;
    const across = $('section-params').checked;
    $('section-at').disabled = !on;
    $('section-params').disabled = !on;
    $('section-cap').disabled = !on || across;
    modeler.set_section(on, $('section-at').valueAsNumber / 100);
    modeler.set_section_parameters(across);
    modeler.set_section_cap(on && !across && $('section-cap').checked);
    app.redraw();
  };
  $('section-on').addEventListener('change', applySection);
  $('section-at').addEventListener('input', applySection);
  $('section-params').addEventListener('change', applySection);
  $('section-cap').addEventListener('change', applySection);
  $('resolution').addEventListener('change', (e) => {
    const v = e.target.valueAsNumber;
    if (!Number.isFinite(v)) return;
    e.target.value = String(modeler.set_resolution(v));
    app.redraw(VIEW3);
  });

  // What the views are called, for screen readers: what they show now.
  const ORBIT = 'drag elsewhere to orbit, right-drag or Shift-drag to pan, turn the wheel to zoom, F frames the model again';
  const nameViews = (volume, parts, slice, section, cap) => {
    const bezier = !parts || parts.open;
    const view2 = section && section[3]
      ? `2D view of the volume's section across its parameters, ${'uvw'[section[0]]} = ${fmt(section[1])}: f at the points S(u) of that parameter plane, over the parameter square drawn on the volume's box, and its zero contour (${fmt(100 * section[2])} % of the square inside); move it with the Section plane slider; the wheel zooms, F fits`
      : section
      ? `2D view of the ${parts ? 'whole model\'s' : 'volume\'s'} true section by the plane ${'xyz'[section[0]]} = ${fmt(section[1])}: f on the plane and its zero contour (area ${fmt(section[2])}); move the plane with the Section plane slider, turn the section off to edit the slice's points here; the wheel zooms, F fits`
      : !bezier
      ? '2D view of the model of many solids: its field and its contour. Select a Bézier part under Parts to edit its points here'
      : `2D contour view of ${slice ? `the ${'uvw'[slice[0]]} slice ${slice[1]} of the volume` : 'the patch solid'}: click a control point, or press Tab to walk the points (Esc then Tab leaves the view), then drag, press Page Up and Page Down, or turn the wheel over it to change its function value; the wheel elsewhere zooms about the pointer, F fits`;
    const view3 = parts
      ? `3D view of the model of many solids: the surface of the whole model${cap ? `, cut at ${'xyz'[cap[0]]} = ${fmt(cap[1])} (the solid below the plane, its cut face closed)` : ''}${section && !section[3] ? `, the section plane ${'xyz'[section[0]]} = ${fmt(section[1])} in violet (drag its frame to move it)` : ''}${parts.open ? ', the open part\'s control points as spheres' : ''}, the selection framed in orange with handles to move, turn and scale it; ${ORBIT}`
      : volume
        ? `3D view of the volume solid: its surface${cap ? `, cut at ${'xyz'[cap[0]]} = ${fmt(cap[1])} (the solid below the plane, its cut face closed)` : ''}${section && !section[3] ? `, the section plane ${'xyz'[section[0]]} = ${fmt(section[1])} in violet (drag its frame to move it)` : ''} and its control points as spheres coloured by ξ. Drag a sphere to change its ξ (or move it in space mode); ${ORBIT}`
        : `3D view of the patch: the surface (x, y, ξ) coloured by ξ, the plane ξ = 0 and the control points as spheres. Drag a sphere to change its ξ (or move it in x and y in space mode); ${ORBIT}`;
    if (canvas.getAttribute('aria-label') !== view2) canvas.setAttribute('aria-label', view2);
    if (app.canvas3.getAttribute('aria-label') !== view3) app.canvas3.setAttribute('aria-label', view3);
  };

  // The first-visit hint: until a point has moved (or it is dismissed), in this browser.
  let hinting = !storage.get(KEYS.hinted);
  const endHint = () => {
    hinting = false;
    $('hint').hidden = true;
    storage.set(KEYS.hinted, '1');
  };
  $('hint-close').addEventListener('click', endHint);
  /** A control point was moved (in either view, by any means): the hint has done its work. */
  function pointMoved() {
    if (hinting) endHint();
  }

  // The panel, from one snapshot of the editor, its last frame and its 3D view.
  // What the workers kept of the last surface of a model of many solids, for the panel.
  const keptNote = () => {
    const [kept, blocks] = (document.body.dataset.surfaceKept || '').split(',').map(Number);
    return kept > 0 ? `; ${kept.toLocaleString('en')} of its ${blocks.toLocaleString('en')} blocks reused from the workers' previous mesh` : '';
  };
  const update = () => {
    forgetStale('measure-out', modeler.revision());
    enableItems('#export-menu [data-script]', false);
    const p = app.panel();
    const sel = p.selected;
    const point = p.point;
    // A volume's slice across an axis is a patch over the two others, in increasing order: its
    // points are named by three indices, its plane's coordinates by those axes' names.
    const slice = p.volume_degree && !(app.outline.state() && !app.outline.state().open) ? p.slice : null;
    const others = slice ? [0, 1, 2].filter((a) => a !== slice[0]) : [0, 1];
    $('px-name').textContent = 'xyz'[others[0]];
    $('py-name').textContent = 'xyz'[others[1]];
    if (sel && point) {
      if (slice) {
        const ijk = [0, 0, 0];
        ijk[slice[0]] = slice[1];
        [ijk[others[0]], ijk[others[1]]] = sel;
        $('point-label').textContent = `P${ijk.join('')} (i = ${ijk[0]}, j = ${ijk[1]}, k = ${ijk[2]}) of the ${'uvw'[slice[0]]} slice ${slice[1]}`;
      } else {
        $('point-label').textContent = `P${sel[0]}${sel[1]} (i = ${sel[0]}, j = ${sel[1]})`;
      }
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
    const section = p.frame.section;
    // A section across the parameters names u, v, w and gives the part of the parameter square inside.
    const plane = section && `${(section[3] ? 'uvw' : 'xyz')[section[0]]} = ${fmt(section[1])}`;
    $('section-info').textContent = section ? plane : '–';
    $('contour-info').textContent = (!section ? ''
      : section[3] ? `Section across the parameters ${plane}: ${fmt(100 * section[2])} % of the parameter square inside; `
      : `True section ${plane}: area ${fmt(section[2])}; `)
      + `Zero contour: ${n} ${n === 1 ? 'piece' : 'pieces'}`
      + (p.frame.folded ? ' (the net folds over itself: the lines of every sheet are shown)' : '')
      + (p.frame.unclipped ? `; S_ξ = 0 unclipped: ${p.frame.unclipped} ${p.frame.unclipped === 1 ? 'piece' : 'pieces'}, dashed` : '');
    app.outline.update();
    const parts = app.outline.state();
    const [du, dv] = p.degree;
    const mapped = p.space_mapped;
    const vd = parts && !parts.open ? null : p.volume_degree;
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
      const [a, b] = [0, 1, 2].filter((k) => k !== axis);
      $('slice-info').textContent = `${name} slice ${index} of 0…${vd[axis]}: ${vd[a] + 1} × ${vd[b] + 1} points in the ${'xyz'[a]}${'xyz'[b]} plane`;
      const [t, resolution] = p.surface ?? [0, 0];
      const stack = p.stack;
      $('surface-info').textContent = parts
        ? `Surface of the whole model: ${t.toLocaleString('en')} triangles at ${resolution}${p.cap ? `, cut at ${'xyz'[p.cap[0]]} = ${fmt(p.cap[1])}` : ''}${p.surface_current ? keptNote() : ' (of the model before the last edit, until the new one comes)'}`
        : `Surface: ${t.toLocaleString('en')} triangles at ${resolution}${p.cap ? `, cut at ${'xyz'[p.cap[0]]} = ${fmt(p.cap[1])}` : ''}; `
        + (!stack ? 'contour stack: not made yet' : `contour stack: ${stack[0].toLocaleString('en')} segments${stack[1] ? '' : ' (of the model before the last edit, until the new one comes)'}`);
      document.body.dataset.stack = stack ? `${stack[0]},${stack[1] ? 1 : 0}` : '';
    } else {
      $('model-name').textContent = `Patch solid, ${du + 1} × ${dv + 1} points${mapped ? ', space-mapped' : ''}`;
      $('model-info').textContent = `Degree ${du} × ${dv}; ${mapped ? 'points moved: the inverse map finds (u, v)' : 'a regular grid: (u, v) by scaling'}.`;
    }
    if (parts) {
      const n = parts.rows.length;
      $('model-name').textContent = `Many solids, ${n} ${n === 1 ? 'node' : 'nodes'}`;
      $('model-name').title = parts.open ? `Editing a Bézier ${volume ? 'volume' : 'patch'}${mapped ? ', space-mapped' : ''}` : '';
    }
    if (p.cells) {
      const { count, degree } = p.cells;
      const dims = count.map((c, k) => c * degree[k] + 1);
      $('model-info').textContent = `Piecewise ${volume ? 'volume' : 'patch'}: ${count.join(' × ')} cells of degree ${degree.join(' × ')}, one net of ${dims.join(' × ')} points${mapped ? ', points moved' : ''}; a point on a face that cells share moves in each of them.`;
    }
    $('volume-controls').hidden = !volume;
    // A piecewise net's cells keep their degree: cells are added instead.
    $('elevate-u').disabled = $('elevate-v').disabled = Boolean(p.cells);
    $('elevate-w').disabled = !volume || Boolean(p.cells);
    const editing = !parts || Boolean(parts.open);
    for (const [axis, name] of ['u', 'v', 'w'].entries()) {
      const has = axis < 2 || volume;
      $(`cell-add-${name}`).disabled = !editing || !has;
      $(`cell-remove-${name}`).disabled = !editing || !has || !p.cells || p.cells.count[axis] < 2;
    }
    const solid3d = volume || parts?.dimension === 3;
    enableItems('#export-menu [data-volume]', solid3d);
    enableItems('#export-menu [data-bezier]', true);
    // The contours of a 3D model are its open part's slice's: none without one.
    enableItems('#export-menu [data-value="svg"]', !(parts && parts.dimension === 3 && !parts.open));
    document.body.dataset.kind = volume ? 'volume' : 'patch';
    nameViews(volume, parts, slice, p.frame.section, p.cap);
    if (!modeler.dragging() && !modeler.busy_3d() && probeSeen !== modeler.revision()) showProbe();
    $('hint').hidden = !hinting;
    $('undo').disabled = !p.can_undo;
    $('redo').disabled = !p.can_redo;
    const mode = p.mode;
    for (const r of document.querySelectorAll('input[name="mode"]')) r.checked = r.value === mode;
    canvas.classList.toggle('space', mode === 'space');
    document.body.dataset.selected = sel ? `${sel[0]},${sel[1]}` : '';
    document.body.dataset.mode = mode;
  };

  return {
    update,
    pointMoved,
    /** Undoes (`redo` false) or redoes a step; returns whether there was one. */
    history: (redo) => (redo ? modeler.redo() : modeler.undo()),
    /** Draws the 3D view. */
    render3d: (viewer) => modeler.render_3d(viewer),
    /** After a 3D frame: asks the workers for what the frame lacks; the ξ scale. */
    follow: () => {
      mesher?.check();
      stacker?.check();
      const xi = modeler.xi_extent();
      $('xi-min').textContent = fmt(-xi);
      $('xi-max').textContent = fmt(xi);
    },
    /** Cancels the work the model has moved past. */
    prune: () => {
      mesher?.prune();
      stacker?.prune();
    },
    /** The workers' last times, for the debug overlay. */
    timings: () => [['worker mesh', mesher], ['worker contour stack', stacker]],
  };
}
