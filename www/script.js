// The Script mode: a PLaSM script in an editor with line numbers and marks where the last run had
// errors or warnings; Ctrl+Enter runs it in a worker of its own (a newer run or Stop cancels the one
// under way) and the 3D view draws its results. A surface of two parameters opens in the Bézier
// mode as a patch, a solid of three parameters as a volume.
import { tools } from './modules.js';
import { $, say, messageOf, setupMenu, enableItems } from './ui.js';
import { KEYS, storage } from './storage.js';
import { lazyRunner } from './work.js';
import { codeEditor } from './code.js';

/** Sets up the mode on `app` (see main.js); returns what the page asks of it. */
export function setupScript(app) {
  const { sv, VIEW3 } = app;
  const { plasm_examples, plasm_prelude } = app.glue;
  const examples = JSON.parse(plasm_examples());
  const prelude = JSON.parse(plasm_prelude());
  $('prelude-names').replaceChildren(...prelude.names.flatMap((name, k) => {
    const code = document.createElement('code');
    code.textContent = name;
    return k ? [', ', code] : [code];
  }));
  $('prelude-text').textContent = prelude.text;
  const code = codeEditor(app, {
    ids: { editor: 'script', gutter: 'script-gutter' },
    key: KEYS.script,
    what: 'script',
    exportName: 'Script',
    mode: 'script',
    onRun: () => run(),
  });
  const { editor } = code;
  editor.value = storage.get(KEYS.script) ?? examples.find((e) => e.id === '4.4').source;
  code.renderGutter(true);
  let ran = false; // whether the editor's script was run since it was opened

  // The script worker starts with the first run (most visits never open this mode).
  const worker = lazyRunner(!!app.runners.surface);

  // A top-level value that is a surface of two parameters (a patch, ξ = z) or a solid of three (a
  // volume, ξ = 1/4 everywhere: the solid is the map's image): its Bézier net, to edit point by
  // point. The script runs again to find the net: in the worker, cancellable.
  const editAsNet = async (script, index, line, volume) => {
    const w = worker();
    let json;
    const what = volume ? 'solid' : 'surface';
    const task = w && app.work.start('script', 'Finding the Bézier net', () => running.cancel());
    const running = w?.run({ kind: volume ? 'plasm-volume' : 'plasm-patch', script, index }, { onStart: () => task.started() });
    try {
      json = w ? new TextDecoder().decode((await running).data) : (await tools())[volume ? 'script_volume_model' : 'script_patch_model'](script, index);
      app.modeler.load_model(json);
    } catch (err) {
      if (err.cancelled) say('Finding the Bézier net was cancelled; the model was kept.');
      else say(`This ${what} has no Bézier net: ${messageOf(err)}`, 'error');
      return;
    } finally {
      task?.end();
    }
    app.setWorkspace('bezier');
    app.resize();
    app.resize3();
    const panel = app.panel();
    if (volume) {
      const [n, m, l] = panel.volume_degree;
      say(`Opened the solid of line ${line} as a ${n + 1} × ${m + 1} × ${l + 1}-point volume, its net found exactly from the map (ξ = 1/4 everywhere: the solid is the map's image); Undo brings back the previous model.`);
    } else {
      const [n, m] = panel.degree;
      say(`Opened the surface of line ${line} as a ${n + 1} × ${m + 1}-point patch (ξ = z); Undo brings back the previous model.`);
    }
    app.changed();
  };

  const message = $('script-message');
  const showReport = (report, ms, workerMs) => {
    const marks = new Map();
    message.replaceChildren();
    const place = (x) => `Line ${x.line}, column ${x.column}`;
    if (report.error) {
      const e = report.error;
      marks.set(e.line, 'error');
      const p = document.createElement('p');
      p.className = 'error';
      p.textContent = `${place(e)}: ${e.message}`;
      const go = document.createElement('button');
      go.type = 'button';
      go.textContent = 'Go to';
      go.addEventListener('click', () => code.goTo(e.line, e.column));
      p.append(go);
      message.append(p);
    }
    for (const w of report.warnings) {
      if (!marks.has(w.line)) marks.set(w.line, 'warn');
      const p = document.createElement('p');
      p.className = 'note';
      p.textContent = `${place(w)} (note): ${w.message}`;
      message.append(p);
    }
    message.dataset.kind = report.error ? 'error' : report.warnings.length ? 'warn' : '';
    code.mark(marks);
    const count = (n, one, many) => `${n.toLocaleString('en')} ${n === 1 ? one : many}`;
    const parts = [];
    if (report.triangles) parts.push(count(report.triangles, 'triangle', 'triangles'));
    if (report.segments) parts.push(count(report.segments, 'segment', 'segments'));
    if (report.points) parts.push(count(report.points, 'point', 'points'));
    $('script-info').textContent = (report.error ? 'Stopped at an error' : `Ran in ${ms.toFixed(0)} ms`)
      + ` (${count(report.steps, 'step', 'steps')}${workerMs !== undefined ? `, ${workerMs.toFixed(0)} ms in the worker` : ''}): `
      + (report.complexes ? `${count(report.complexes, 'result', 'results')} drawn, ${parts.join(', ')}.` : 'nothing to draw.')
      + (report.left_out ? ` Left out of the view: ${report.left_out}.` : '');
    const ranScript = editor.value;
    $('script-values').replaceChildren(...report.values.map((v, index) => {
      const li = document.createElement('li');
      const line = document.createElement('span');
      line.className = 'line';
      line.textContent = `line ${v.line}`;
      li.append(line, v.text);
      // A surface opens as a patch, a solid as a volume, each as the control net of its map.
      for (const [volume, kind, title] of [
        [false, 'patch', 'Open this surface in the Bézier mode as a patch solid (x, y, ξ = z): its control net, found from the map'],
        [true, 'volume', 'Open this solid in the Bézier mode as a volume solid (x, y, z, ξ = 1/4 everywhere): its control net, found from the map'],
      ]) {
        if (!v[kind]) continue;
        const edit = document.createElement('button');
        edit.type = 'button';
        edit.className = `edit-${kind}`;
        edit.textContent = `Edit as a Bézier ${kind}`;
        edit.title = title;
        edit.addEventListener('click', () => editAsNet(ranScript, index, v.line, volume));
        li.append(edit);
      }
      return li;
    }));
    document.body.dataset.scriptState = report.error ? 'error' : 'done';
    document.body.dataset.scriptMs = ms.toFixed(1);
    document.body.dataset.scriptWorkerMs = workerMs === undefined ? '' : workerMs.toFixed(1);
    document.body.dataset.scriptCounts = `${report.triangles},${report.segments},${report.points}`;
  };

  let runSeq = 0;
  let drew = false; // whether the drawing shown is of a run that drew something
  let runTask = null; // the run under way in the work list
  const stop = () => {
    runSeq += 1;
    worker()?.cancelAll();
    runTask?.end();
    runTask = null;
    $('script-stop').disabled = true;
    document.body.dataset.scriptState = 'stopped';
    $('script-info').textContent = 'Stopped; the drawing is from the last run.';
  };
  const run = async ({ refit = false } = {}) => {
    const script = editor.value;
    const seq = ++runSeq;
    ran = true;
    $('script-stop').disabled = false;
    document.body.dataset.scriptState = 'running';
    runTask?.end();
    const task = app.work.start('script', 'Running the script', stop);
    runTask = task;
    const t0 = performance.now();
    let result;
    try {
      const w = worker();
      if (w) {
        w.cancelAll();
        result = await w.run({ kind: 'plasm', script }, { onStart: () => task.started() });
      } else {
        task.started();
        const r = (await tools()).headless_plasm(script);
        result = { report: r.report(), data: r.take_floats() };
        r.free();
      }
    } catch (err) {
      if (err.cancelled || seq !== runSeq) return; // a newer run or Stop took over
      result = null;
      say(`The script could not run: ${messageOf(err)}`, 'error');
      document.body.dataset.scriptState = 'error';
    }
    if (seq !== runSeq) return;
    $('script-stop').disabled = true;
    runTask?.end();
    runTask = null;
    if (!result) return;
    const report = JSON.parse(result.report);
    // A run that fails before drawing anything keeps the last drawing on screen, marked as the
    // last run's.
    const kept = !result.data.length && !!report.error;
    if (!kept) {
      sv.set_drawing(result.data, refit);
      drew = result.data.length > 0;
    }
    $('script-stale').hidden = !(kept && drew);
    showReport(report, performance.now() - t0, result.ms);
    app.redraw(VIEW3);
  };
  /** Puts `text` in the editor (kept in this browser), not run yet. */
  const load = (text) => {
    code.load(text);
    ran = false;
  };
  /** Opens `text` in the mode, says `note`, and runs it. */
  const open = (text, note) => {
    app.setWorkspace('script');
    load(text);
    app.resize();
    app.resize3();
    say(note);
    run({ refit: true });
  };

  for (const e of examples) {
    const item = document.createElement('li');
    item.setAttribute('role', 'menuitem');
    item.tabIndex = -1;
    item.dataset.value = e.id;
    item.textContent = `Script ${e.id}: ${e.title}`;
    $('script-example-menu').append(item);
  }
  setupMenu($('script-example'), (id) => {
    const example = examples.find((x) => x.id === id);
    if (example) open(example.source, `Opened the paper's Script ${example.id}.`);
  });
  $('script-run').addEventListener('click', () => run());
  $('script-stop').addEventListener('click', stop);
  return {
    /** The script in the editor. */
    text: () => editor.value,
    load,
    open,
    run,
    /** Runs the script once the mode shows, if it has not run since it was opened. */
    runIfNew: () => {
      if (!ran) run({ refit: true });
    },
    update: () => {
      $('model-name').textContent = 'PLaSM script';
      app.canvas3.setAttribute('aria-label', 'Drawing of the PLaSM script: the curves, surfaces and solids of its top-level expressions. Drag to orbit, right-drag or Shift-drag to pan, turn the wheel to zoom, F frames the drawing again');
      enableItems('#export-menu [data-volume], #export-menu [data-script]', true);
      enableItems('#export-menu [data-bezier]', false);
    },
    /** Draws the 3D view. */
    render3d: (viewer) => sv.render(viewer),
    follow: () => {},
    prune: () => {},
    timings: () => [],
  };
}
