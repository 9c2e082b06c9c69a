// The Script mode: a PLaSM script in an editor with line numbers and marks where the last run had
// errors or warnings; Ctrl+Enter runs it in a worker of its own (a newer run or Stop cancels the one
// under way) and the 3D view draws its results. A surface of two parameters opens in the Bézier
// mode as a patch, a solid of three parameters as a volume.
import { tools } from './modules.js';
import { $, say, messageOf, setupMenu, enableItems } from './ui.js';
import { KEYS, storage } from './storage.js';
import { lazyRunner } from './work.js';

/** Sets up the mode on `app` (see main.js); returns what the page asks of it. */
export function setupScript(app) {
  const { sv, VIEW3 } = app;
  const { plasm_examples, plasm_prelude } = app.glue;
  const editor = $('script');
  const examples = JSON.parse(plasm_examples());
  const prelude = JSON.parse(plasm_prelude());
  $('prelude-names').replaceChildren(...prelude.names.flatMap((name, k) => {
    const code = document.createElement('code');
    code.textContent = name;
    return k ? [', ', code] : [code];
  }));
  $('prelude-text').textContent = prelude.text;
  editor.value = storage.get(KEYS.script) ?? examples.find((e) => e.id === '4.4').source;
  let ran = false; // whether the editor's script was run since it was opened

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
  let saveTimer = 0;
  editor.addEventListener('input', () => {
    renderGutter();
    clearTimeout(saveTimer);
    saveTimer = setTimeout(() => {
      if (!storage.set(KEYS.script, editor.value)) say('The script could not be saved in this browser; use Export → Script.', 'warn');
    }, 300);
  });
  addEventListener('pagehide', () => storage.set(KEYS.script, editor.value));

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
    marks = new Map();
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
      go.addEventListener('click', () => goTo(e.line, e.column));
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
    // In the mode, through the editor's own editing, so that its undo (Ctrl+Z) brings back the
    // text replaced; otherwise (a link opened at start-up, the editor hidden) set plainly.
    if (editor.value !== text) {
      let typed = false;
      if (app.workspace() === 'script') {
        editor.focus();
        if (document.activeElement === editor) {
          editor.select();
          typed = document.execCommand('insertText', false, text) && editor.value === text;
        }
      }
      if (!typed) editor.value = text;
      editor.setSelectionRange(0, 0);
      editor.scrollTop = 0;
    }
    storage.set(KEYS.script, text);
    ran = false;
    renderGutter(true);
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
  // Tab indents; after Esc it leaves the editor (the usual way out of a code editor's Tab).
  let tabEscapes = false;
  editor.addEventListener('keydown', (e) => {
    if ((e.ctrlKey || e.metaKey) && e.key === 'Enter') {
      e.preventDefault();
      run();
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
