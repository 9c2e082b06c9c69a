// The HyperFun mode: a HyperFun program in an editor with line numbers, drawn as it is typed. Its
// solid is meshed in a worker of its own within the box (a newer edit or Stop cancels the mesh
// under way) and shown in the 3D view; its field's section in a plane across x, y or z is drawn
// under the editor, from a second worker, so that moving the plane never waits for a mesh. A
// program that is one of bezsolid's exports opens back as the model it came from.
import { tools } from './modules.js';
import { $, say, messageOf, enableItems, forgetStale } from './ui.js';
import { KEYS, storage } from './storage.js';
import { lazyRunner } from './work.js';
import { codeEditor } from './code.js';
import { decode } from './wire.js';

const DEFAULT_PROGRAM = `-- A ball blended onto a slab, a hole bored through both.
-- Edit it: the solid (where my_model >= 0) is drawn as you type.
my_model(x[3], a[1])
{
  array centre[3];
  array corner[3];
  centre = [0, 0, 1];
  corner = [-7, -7, -3];
  ball = hfSphere(x, centre, 5);
  slab = hfBlock(x, corner, 14, 14, 3);
  bore = hfCylinderZ(x, centre, 2);
  my_model = hfBlendUni(ball, slab, 1, 1, 1) \\ bore;
}
`;
const DEFAULT_BOX = [-10, -10, -10, 10, 10, 10];
/** Samples of the section along its longer side. */
const SECTION_SAMPLES = 160;
/** How long typing pauses before the program is drawn, in milliseconds. */
const LIVE_DELAY = 350;

/** Runs `job` in the tools' module on the page (no worker here): its result as a worker gives it. */
export async function runHere(job, onProgress = () => {}) {
  const bytes = (await tools()).run_job(new TextEncoder().encode(JSON.stringify(job)), onProgress);
  return decode(bytes);
}

/** Sets up the mode on `app` (see main.js); returns what the page asks of it. */
export function setupHyperfun(app) {
  const { hv, VIEW3 } = app;
  const { hyperfun_model_json, hyperfun_carries_model } = app.glue;
  let ran = false; // whether the editor's program was drawn since it was opened
  let revision = 0; // counts edits of the program, its box and its resolution
  const code = codeEditor(app, {
    ids: { editor: 'hf', gutter: 'hf-gutter' },
    key: KEYS.hyperfun,
    what: 'program',
    exportName: 'HyperFun (.hf)',
    mode: 'hyperfun',
    onRun: () => run(),
    onInput: () => edited(),
  });
  const { editor } = code;
  editor.value = storage.get(KEYS.hyperfun) ?? DEFAULT_PROGRAM;
  code.renderGutter(true);

  // The box: six numbers, kept in this browser; a box that is not one is marked and not used.
  const boxInput = $('hf-box');
  const parseBox = (text) => {
    const v = text.split(/[\s,;]+/).filter(Boolean).map(Number);
    if (v.length !== 6 || !v.every(Number.isFinite)) return null;
    return v[0] < v[3] && v[1] < v[4] && v[2] < v[5] ? v : null;
  };
  const showBox = (box) => { boxInput.value = box.join(', '); };
  let box = parseBox(storage.get(KEYS.hyperfunBox) ?? '') ?? DEFAULT_BOX;
  showBox(box);
  boxInput.addEventListener('input', () => {
    const b = parseBox(boxInput.value);
    boxInput.setAttribute('aria-invalid', String(!b));
    if (!b) return;
    box = b;
    storage.set(KEYS.hyperfunBox, box.join(','));
    edited();
  });
  boxInput.addEventListener('change', () => {
    if (parseBox(boxInput.value)) return;
    say('The box is six numbers x0, y0, z0, x1, y1, z1 with x0 < x1, y0 < y1 and z0 < z1; the last good box is kept.', 'warn');
    showBox(box);
    boxInput.setAttribute('aria-invalid', 'false');
  });
  const resolution = () => Number($('hf-resolution').value) || 48;
  $('hf-resolution').addEventListener('change', () => edited(0));
  const modelJson = () => hyperfun_model_json(editor.value, new Float64Array(box));

  // The workers: one meshes, one cuts sections (each started at the first use).
  const mesher = lazyRunner(!!app.runners.surface);
  const cutter = lazyRunner(!!app.runners.surface);
  const inWorker = async (worker, job, task, { cancel = true } = {}) => {
    const w = worker();
    if (w) {
      if (cancel) w.cancelAll();
      return w.run(job, { onStart: () => task?.started(), onProgress: (done, total) => task?.progress(done, total) });
    }
    task?.started();
    return runHere(job);
  };

  const message = $('hf-message');
  const showError = (error) => {
    message.replaceChildren();
    message.dataset.kind = error ? 'error' : '';
    code.mark(error ? new Map([[error.line, 'error']]) : new Map());
    if (!error) return;
    const p = document.createElement('p');
    p.className = 'error';
    p.textContent = error.line ? `Line ${error.line}, position ${error.column}: ${error.message}` : error.message;
    if (error.line) {
      const go = document.createElement('button');
      go.type = 'button';
      go.textContent = 'Go to';
      go.addEventListener('click', () => code.goTo(error.line, error.column));
      p.append(go);
    }
    message.append(p);
  };

  let runSeq = 0;
  let drew = false; // whether the drawing shown is of a program that drew something
  let runTask = null;
  const stop = () => {
    clearTimeout(liveTimer);
    runSeq += 1;
    mesher()?.cancelAll();
    runTask?.end();
    runTask = null;
    $('hf-stop').disabled = true;
    document.body.dataset.hfState = 'stopped';
    $('hf-info').textContent = 'Stopped; the drawing is from the last program drawn.';
  };
  const run = async ({ refit = false } = {}) => {
    clearTimeout(liveTimer);
    const seq = ++runSeq;
    ran = true;
    $('hf-edit').hidden = !hyperfun_carries_model(editor.value);
    let model;
    try {
      model = modelJson();
    } catch (err) {
      say(`The program cannot be drawn: ${messageOf(err)}`, 'error');
      return;
    }
    section({ restart: true, model });
    $('hf-stop').disabled = false;
    document.body.dataset.hfState = 'running';
    runTask?.end();
    const task = app.work.start('hyperfun', 'Drawing the HyperFun program', stop);
    runTask = task;
    const t0 = performance.now();
    let result;
    try {
      result = await inWorker(mesher, { kind: 'hyperfun-draw', model, resolution: resolution() }, task);
    } catch (err) {
      if (err.cancelled || seq !== runSeq) return;
      result = null;
      say(`The program could not be drawn: ${messageOf(err)}`, 'error');
      document.body.dataset.hfState = 'error';
    }
    if (seq !== runSeq) return;
    $('hf-stop').disabled = true;
    runTask?.end();
    runTask = null;
    if (!result) return;
    const report = JSON.parse(result.report);
    showError(report.error);
    if (!report.error) {
      hv.set_drawing(result.data, refit);
      drew = result.data.length > 0;
    }
    $('hf-stale').hidden = !(report.error && drew);
    const ms = performance.now() - t0;
    $('hf-info').textContent = report.error
      ? (report.error.at ? `Stopped at the point (${report.error.at.map((v) => Number(v.toPrecision(4))).join(', ')}).` : 'Not drawn: the program has an error.')
      : report.triangles
        ? `${report.triangles.toLocaleString('en')} triangles at ${report.cells} cells along the longest side, drawn in ${ms.toFixed(0)} ms.`
          + (report.dimension === 2 ? ' A program of x[2]: its plane solid is drawn through the box along z.' : '')
        : 'Nothing inside the box: no point of the grid has a value above 0.';
    document.body.dataset.hfState = report.error ? 'error' : 'done';
    document.body.dataset.hfTriangles = String(report.error ? 0 : report.triangles);
    app.redraw(VIEW3);
  };
  let liveTimer = 0;
  const edited = (delay = LIVE_DELAY) => {
    revision += 1;
    ran = false;
    if (app.workspace() !== 'hyperfun') return;
    // A drawing under way is of the text before: its result is dropped, the new one follows.
    runSeq += 1;
    runTask?.end();
    runTask = null;
    document.body.dataset.hfState = 'pending';
    clearTimeout(liveTimer);
    liveTimer = setTimeout(() => run(), delay);
  };

  // The section: the field's sign and size in the plane, the zero contour over it.
  const canvas = $('hf-section');
  const axisValue = () => Number(document.querySelector('input[name="hf-axis"]:checked')?.value ?? 2);
  const at = () => {
    const k = axisValue();
    return box[k] + (box[k + 3] - box[k]) * Number($('hf-at').value) / 1000;
  };
  // One section at a time: moving the plane asks again once the one under way is done (its
  // worker is not torn down every frame); a new program restarts it.
  let sectionSeq = 0;
  let sectionBusy = false;
  let sectionAgain = false;
  let lastSection = null;
  const section = async ({ restart = false, model: given } = {}) => {
    const axis = axisValue();
    const place = at();
    const label = `${'xyz'[axis]} = ${Number(place.toPrecision(4))}`;
    $('hf-section-label').textContent = label;
    $('hf-at').setAttribute('aria-valuetext', label);
    if (restart) sectionBusy = false;
    if (sectionBusy) {
      sectionAgain = true;
      return;
    }
    let model = given;
    try {
      model ??= modelJson();
    } catch {
      return;
    }
    const seq = ++sectionSeq;
    sectionBusy = true;
    sectionAgain = false;
    let result;
    try {
      result = await inWorker(cutter, { kind: 'hyperfun-section', model, axis, at: place, samples: SECTION_SAMPLES }, null, { cancel: restart });
    } catch (err) {
      if (err.cancelled || seq !== sectionSeq) return;
      lastSection = null;
      drawSection();
      return;
    } finally {
      if (seq === sectionSeq) {
        sectionBusy = false;
        if (sectionAgain) requestAnimationFrame(() => section());
      }
    }
    if (seq !== sectionSeq) return;
    const report = JSON.parse(result.report);
    if (report.error) return; // the program's error is shown by its drawing
    lastSection = { ...report, data: result.data };
    document.body.dataset.hfSection = `${report.segments}`;
    drawSection();
  };
  const drawSection = () => {
    const rect = canvas.getBoundingClientRect();
    const ratio = window.devicePixelRatio || 1;
    const w = Math.max(1, Math.round(rect.width * ratio));
    const h = Math.max(1, Math.round(rect.height * ratio));
    if (canvas.width !== w) canvas.width = w;
    if (canvas.height !== h) canvas.height = h;
    const g = canvas.getContext('2d');
    g.setTransform(1, 0, 0, 1, 0, 0);
    g.fillStyle = '#fff';
    g.fillRect(0, 0, w, h);
    const s = lastSection;
    if (!s) return;
    const { nx, ny, lo, hi, data } = s;
    // The plane's rectangle fitted to the canvas, y up.
    const scale = Math.min((w - 16) / (hi[0] - lo[0]), (h - 16) / (hi[1] - lo[1]));
    const ox = (w - (hi[0] - lo[0]) * scale) / 2;
    const oy = (h + (hi[1] - lo[1]) * scale) / 2;
    const px = (u) => ox + (u - lo[0]) * scale;
    const py = (v) => oy - (v - lo[1]) * scale;
    // The field: inside red, outside blue, deeper for larger |f| (scaled by the largest).
    let peak = 0;
    for (let i = 0; i < nx * ny; i++) peak = Math.max(peak, Math.abs(data[i]));
    const image = new ImageData(nx, ny);
    for (let j = 0; j < ny; j++) {
      for (let i = 0; i < nx; i++) {
        const v = data[j * nx + i];
        const t = peak > 0 ? Math.min(1, Math.sqrt(Math.abs(v) / peak)) : 0;
        const o = ((ny - 1 - j) * nx + i) * 4;
        const [r, gr, b] = v > 0 ? [252 - 40 * t, 190 - 120 * t, 180 - 120 * t] : [225 - 120 * t, 235 - 90 * t, 250 - 40 * t];
        image.data.set([r, gr, b, 255], o);
      }
    }
    const tile = new OffscreenCanvas(nx, ny);
    tile.getContext('2d').putImageData(image, 0, 0);
    g.imageSmoothingEnabled = true;
    g.drawImage(tile, px(lo[0]), py(hi[1]), (hi[0] - lo[0]) * scale, (hi[1] - lo[1]) * scale);
    g.strokeStyle = '#1d1f24';
    g.lineWidth = 1.6 * ratio;
    g.beginPath();
    for (let k = nx * ny; k + 3 < data.length; k += 4) {
      g.moveTo(px(data[k]), py(data[k + 1]));
      g.lineTo(px(data[k + 2]), py(data[k + 3]));
    }
    g.stroke();
    g.strokeStyle = '#9aa1ad';
    g.lineWidth = ratio;
    g.strokeRect(px(lo[0]), py(hi[1]), (hi[0] - lo[0]) * scale, (hi[1] - lo[1]) * scale);
  };
  new ResizeObserver(() => drawSection()).observe(canvas);
  let sectionFrame = 0;
  const sectionSoon = () => {
    cancelAnimationFrame(sectionFrame);
    sectionFrame = requestAnimationFrame(section);
  };
  $('hf-at').addEventListener('input', sectionSoon);
  for (const radio of document.querySelectorAll('input[name="hf-axis"]')) radio.addEventListener('change', sectionSoon);

  $('hf-run').addEventListener('click', () => run());
  $('hf-stop').addEventListener('click', stop);
  // A program that carries its model (one of bezsolid's exports) opens as that model, exactly.
  $('hf-edit').addEventListener('click', () => {
    try {
      app.modeler.load_model(editor.value);
    } catch (err) {
      say(`This program does not open as a Bézier solid: ${messageOf(err)}`, 'error');
      return;
    }
    app.setWorkspace('bezier');
    app.resize();
    app.resize3();
    say('Opened the model this program was exported from; Undo brings back the previous model.');
    app.changed();
  });

  // A part of the Bézier mode's model opened here: Put back replaces it, Keep apart forgets it.
  const partNote = $('hf-part');
  let partOrigin = null; // the part's program as it was opened
  const detach = () => {
    partNote.hidden = true;
    partOrigin = null;
  };
  $('hf-detach').addEventListener('click', () => {
    detach();
    say('The program is on its own now; the part stays as it was.');
  });
  $('hf-put-back').addEventListener('click', () => {
    // The part selected in the model must still be the one opened (a selection or an undo since
    // may have changed it).
    const selected = app.modeler.outline_hyperfun();
    if (selected === undefined || JSON.parse(selected).program !== partOrigin) {
      say('The part opened here is no longer the one selected in the Bézier mode: select it under Parts, or Keep apart.', 'error');
      return;
    }
    try {
      app.modeler.outline_set_hyperfun(editor.value, new Float64Array(box));
    } catch (err) {
      say(`The part was kept as it was: ${messageOf(err)}`, 'error');
      return;
    }
    detach();
    app.setWorkspace('bezier');
    app.resize();
    app.resize3();
    say('Put the program back in its part; Undo brings back the part as it was.');
    app.changed();
  });

  /** Puts `program` (and `newBox`, if given) in the editor, kept in this browser, not drawn yet. */
  const load = (program, newBox) => {
    detach();
    if (newBox) {
      box = [...newBox];
      showBox(box);
      storage.set(KEYS.hyperfunBox, box.join(','));
    }
    code.load(program);
    clearTimeout(liveTimer);
    revision += 1;
    ran = false;
  };

  return {
    text: () => editor.value,
    box: () => box,
    modelJson,
    resolution,
    revision: () => revision,
    load,
    /** Opens `program` (in `newBox`, if given) in the mode, says `note`, and draws it. */
    open: (program, newBox, note) => {
      app.setWorkspace('hyperfun');
      load(program, newBox);
      app.resize();
      app.resize3();
      say(note);
      run({ refit: true });
    },
    run,
    /** Opens a part of the Bézier mode's model (`{ program, box }`) here, to put back. */
    editPart: ({ program, box: partBox }) => {
      app.setWorkspace('hyperfun');
      load(program, partBox);
      partNote.hidden = false;
      partOrigin = program;
      app.resize();
      app.resize3();
      say('Opened the part\'s program: edit it, then Put back.');
      run({ refit: true });
    },
    /** Draws the program once the mode shows, if it was not drawn since it was opened. */
    runIfNew: () => {
      if (!ran) run({ refit: true });
      else drawSection();
    },
    update: () => {
      $('model-name').textContent = 'HyperFun program';
      app.canvas3.setAttribute('aria-label', 'Drawing of the HyperFun program: its solid within the box, shaded. Drag to orbit, right-drag or Shift-drag to pan, turn the wheel to zoom, F frames the drawing again');
      enableItems('#export-menu [data-bezier], #export-menu [data-script]', false);
      enableItems('#export-menu [data-volume], #export-menu [data-hyperfun]', true);
      forgetStale('hf-measure-out', revision);
    },
    render3d: (viewer) => hv.render(viewer),
    follow: () => {},
    prune: () => {},
    timings: () => [],
  };
}
