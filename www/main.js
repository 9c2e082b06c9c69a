// The page: brings up the modeler (Rust, wasm) on the canvas and forwards input to it. All state and
// logic are in Rust; this file only wires DOM events, sizes the canvas and fills the side panel.
import init, { start } from './pkg/bezsolid_web.js';

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
  await init();
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

  let pending = false;
  const redraw = () => {
    if (pending) return;
    pending = true;
    requestAnimationFrame(() => {
      pending = false;
      modeler.render();
      updatePanel();
    });
  };

  const updatePanel = () => {
    const sel = modeler.selected();
    const xi = modeler.selected_xi();
    if (sel) {
      $('point-label').textContent = `P${sel[0]}${sel[1]} (i = ${sel[0]}, j = ${sel[1]})`;
      xiInput.disabled = false;
      if (document.activeElement !== xiInput) {
        xiInput.value = String(Math.round(xi * 1e6) / 1e6);
        xiInput.removeAttribute('aria-invalid');
      }
    } else {
      $('point-label').textContent = 'None selected: click a point or press Tab in the view.';
      xiInput.disabled = true;
      xiInput.value = '';
    }
    $('range-min').textContent = fmt(modeler.range_min());
    $('range-max').textContent = fmt(modeler.range_max());
    const n = modeler.contour_count();
    $('contour-info').textContent = `Zero contour: ${n} ${n === 1 ? 'piece' : 'pieces'}`;
    document.body.dataset.selected = sel ? `${sel[0]},${sel[1]}` : '';
  };

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

  const local = (e) => {
    const rect = canvas.getBoundingClientRect();
    return [e.clientX - rect.left, e.clientY - rect.top];
  };

  canvas.addEventListener('pointerdown', (e) => {
    if (e.button !== 0) return;
    canvas.focus();
    const [x, y] = local(e);
    if (modeler.pointer_down(x, y)) {
      canvas.setPointerCapture(e.pointerId);
      canvas.classList.add('dragging');
      e.preventDefault();
    }
    redraw();
  });
  canvas.addEventListener('pointermove', (e) => {
    const [x, y] = local(e);
    if (modeler.dragging()) {
      if (modeler.pointer_move(x, y)) redraw();
      return;
    }
    canvas.classList.toggle('over-point', modeler.hit(x, y));
    const [px, py, f] = modeler.probe(x, y);
    $('probe').textContent = `f(${px.toFixed(3)}, ${py.toFixed(3)}) = ${f.toFixed(4)} (${f >= 0 ? 'inside' : 'outside'})`;
  });
  const endDrag = (e) => {
    if (!modeler.dragging()) return;
    modeler.pointer_up();
    canvas.classList.remove('dragging');
    if (canvas.hasPointerCapture(e.pointerId)) canvas.releasePointerCapture(e.pointerId);
    redraw();
  };
  canvas.addEventListener('pointerup', endDrag);
  canvas.addEventListener('pointercancel', endDrag);
  canvas.addEventListener('lostpointercapture', endDrag);
  canvas.addEventListener('wheel', (e) => {
    // deltaMode 1 counts lines: about 33 pixels each.
    const dy = e.deltaMode === 1 ? e.deltaY * 33 : e.deltaY;
    if (modeler.wheel(dy)) {
      e.preventDefault();
      redraw();
    }
  }, { passive: false });
  canvas.addEventListener('keydown', (e) => {
    if (e.ctrlKey || e.metaKey || e.altKey) return;
    if (modeler.key(e.key, e.shiftKey)) {
      e.preventDefault();
      redraw();
    }
  });

  const applyInput = () => {
    const value = xiInput.valueAsNumber;
    if (!Number.isFinite(value)) {
      xiInput.setAttribute('aria-invalid', 'true');
      return;
    }
    try {
      modeler.set_selected_xi(value);
      xiInput.removeAttribute('aria-invalid');
      redraw();
    } catch (err) {
      xiInput.setAttribute('aria-invalid', 'true');
      say(err.message ?? String(err), 'error');
    }
  };
  xiInput.addEventListener('input', applyInput);
  xiInput.addEventListener('change', () => {
    applyInput();
    updatePanel();
  });

  window.bezsolid = { modeler, canvas };
  $('loading').hidden = true;
  requestAnimationFrame(() => {
    modeler.render();
    updatePanel();
    document.body.dataset.ready = 'true';
  });
}

window.addEventListener('unhandledrejection', (e) => say(`Error: ${e.reason?.message ?? e.reason}`, 'error'));
main().catch((err) => {
  $('loading').textContent = 'The modeler could not start.';
  say(`The modeler could not start: ${err?.message ?? err}`, 'error');
  console.error(err);
});
