// The 3D view's input, shared by the modes: orbit (drag), pan (right drag or Shift), zoom (wheel),
// two fingers zoom and pan, fit (F or the button); in the Bézier mode a drag on a sphere moves that
// control point, one undo step as in 2D, with the volume's surface meshed coarsely while it moves
// and finely at rest; a second finger puts a drag begun by the first back.
import { $ } from './ui.js';
import { pointers } from './touch.js';

/** Sets up the input of the 3D view on `app` (see main.js). */
export function setupView3d(app) {
  const { modeler, ff, sv, hv, canvas3, VIEW2, VIEW3 } = app;
  const local = (e) => {
    const rect = canvas3.getBoundingClientRect();
    return [e.clientX - rect.left, e.clientY - rect.top];
  };
  // The free-form, script and HyperFun views only move their camera.
  const orbiter = () => ({ freeform: ff, script: sv, hyperfun: hv })[app.workspace()] ?? null;
  let orbiting = false;
  // A free-form solid being dragged (Alt-drag, or with Drag to move pressed).
  let movingSolid = false;
  let restTimer = 0;
  const down = pointers();
  // Two fingers came down: zoom and pan until every finger is up (one left does nothing).
  let pinching = false;
  const capture = (id) => {
    try {
      canvas3.setPointerCapture(id);
    } catch {
      // The pointer is gone already.
    }
  };
  canvas3.addEventListener('contextmenu', (e) => e.preventDefault());
  canvas3.addEventListener('pointerdown', (e) => {
    if (!app.viewer || (e.button !== 0 && e.button !== 2)) return;
    const [x, y] = local(e);
    // A new press of a pointer still counted (its release was missed) ends the old one.
    down.remove(e.pointerId);
    // Fingers and pens make a pinch; a mouse is one pointer whatever it missed.
    const n = e.pointerType === 'mouse' ? 1 : down.add(e.pointerId, [x, y]);
    if (n === 2) {
      // A second finger: the gesture is a pinch; a point's drag begun by the first is put back.
      const editing = !orbiter() && modeler.editing_3d();
      if (movingSolid) {
        // The move so far stays, one undo step; the fingers now pinch.
        ff.move_end();
        movingSolid = false;
        app.changed();
      }
      if (orbiter()) orbiter().pointer_up();
      else modeler.cancel_3d();
      orbiting = false;
      clearTimeout(restTimer);
      if (!orbiter()) modeler.set_coarse(false);
      pinching = true;
      app.dropInput('drag-3d');
      capture(e.pointerId);
      e.preventDefault();
      if (editing) app.changed();
      return;
    }
    if (n > 2 || pinching) return;
    canvas3.focus();
    let grabbed = false;
    if (app.workspace() === 'freeform' && app.freeform.movesSolid(e) && ff.move_start(app.freeform.slot(), x, y)) {
      movingSolid = true;
    } else if (orbiter()) {
      orbiter().pointer_down(x, y, e.button === 2 || e.shiftKey);
      orbiting = true;
    } else {
      grabbed = modeler.pointer_down_3d(x, y, e.button === 2, e.shiftKey);
    }
    capture(e.pointerId);
    canvas3.classList.add('dragging');
    e.preventDefault();
    if (!orbiting) app.redraw(grabbed ? VIEW2 | VIEW3 : VIEW3);
  });
  canvas3.addEventListener('pointermove', (e) => {
    if (!app.viewer) return;
    const [x, y] = local(e);
    const step = down.move(e.pointerId, [x, y]);
    if (pinching) {
      if (!step) return;
      const moved = orbiter()
        ? orbiter().pinch(step.scale, step.dx, step.dy)
        : modeler.pinch_3d(step.scale, step.dx, step.dy);
      if (moved) app.redraw(VIEW3);
      return;
    }
    if (movingSolid) {
      app.coalesce('drag-3d', (since) => {
        if (!movingSolid || !ff.move_to(x, y)) return;
        app.stats.lastEdit = since;
        app.redraw(VIEW3);
        app.freeform.update();
      });
      return;
    }
    if (orbiter()) {
      if (orbiting && orbiter().pointer_move(x, y)) app.redraw(VIEW3);
      return;
    }
    if (modeler.busy_3d()) {
      app.coalesce('drag-3d', (since) => {
        if (!modeler.busy_3d() || !modeler.pointer_move_3d(x, y)) return;
        const editing = modeler.editing_3d();
        // The true section's plane dragged: the slider and the 2D view follow.
        const plane = modeler.section_dragged_3d();
        if (plane) {
          const at = modeler.section_fraction();
          if (at !== undefined) document.getElementById('section-at').value = String(Math.round(at * 100));
        }
        if (editing) {
          app.stats.lastEdit = since;
          // A volume's surface is meshed coarsely while the point moves, finely when it rests.
          modeler.set_coarse(true);
          clearTimeout(restTimer);
          restTimer = setTimeout(() => { modeler.set_coarse(false); app.redraw(VIEW3); }, 250);
        }
        app.redraw(editing || plane ? VIEW2 | VIEW3 : VIEW3);
      });
      return;
    }
    canvas3.classList.toggle('over-point', modeler.hit_3d(x, y));
  });
  const release = (e) => {
    if (canvas3.hasPointerCapture(e.pointerId)) canvas3.releasePointerCapture(e.pointerId);
  };
  const endDrag = (e) => {
    down.remove(e.pointerId);
    if (pinching) {
      if (down.count() === 0) {
        pinching = false;
        canvas3.classList.remove('dragging');
      }
      release(e);
      return;
    }
    if (movingSolid) {
      app.flushInput(); // the last move counts
      movingSolid = false;
      ff.move_end();
      canvas3.classList.remove('dragging');
      release(e);
      app.changed();
      return;
    }
    if (app.viewer && orbiting) {
      orbiting = false;
      orbiter()?.pointer_up();
      canvas3.classList.remove('dragging');
      release(e);
      return;
    }
    if (!app.viewer || !modeler.busy_3d()) return;
    app.flushInput(); // the last move counts
    const editing = modeler.editing_3d();
    clearTimeout(restTimer);
    modeler.set_coarse(false);
    modeler.pointer_up_3d();
    canvas3.classList.remove('dragging');
    release(e);
    if (editing) app.bezier.pointMoved();
    if (editing) app.changed();
    else app.redraw(VIEW3);
  };
  canvas3.addEventListener('pointerup', endDrag);
  canvas3.addEventListener('pointercancel', endDrag);
  canvas3.addEventListener('lostpointercapture', endDrag);
  canvas3.addEventListener('wheel', (e) => {
    if (!app.viewer) return;
    e.preventDefault();
    // deltaMode 1 counts lines: about 33 pixels each.
    const dy = e.deltaMode === 1 ? e.deltaY * 33 : e.deltaY;
    if (orbiter()) orbiter().wheel(dy);
    else modeler.wheel_3d(dy);
    app.redraw(VIEW3);
  }, { passive: false });
  const fit = () => {
    if (orbiter()) orbiter().fit();
    else modeler.fit_3d();
    app.redraw(VIEW3);
  };
  $('fit-3d').addEventListener('click', fit);
  canvas3.addEventListener('keydown', (e) => {
    if (e.ctrlKey || e.metaKey || e.altKey) return;
    if (e.key === 'f' || e.key === 'F') {
      fit();
      e.preventDefault();
    }
  });
}
