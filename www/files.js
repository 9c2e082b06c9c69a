// Models in and out of the page: links (the address's fragment, the Share button), files (the
// picker, a drop) and exports (model files, meshes, contours, HyperFun, pictures). An export that
// takes time runs in the export worker, in the work list with a Cancel.
import { tools } from './modules.js';
import { $, say, messageOf, download, capture, setupMenu } from './ui.js';
import { runHere } from './hyperfun.js';

const MESH_FILE = /\.(obj|stl|ply)$/i;
const MESH_FORMATS = ['stl', 'obj', 'ply', '3mf', 'glb'];
const MESH_TYPES = { stl: 'model/stl', obj: 'model/obj', ply: 'application/octet-stream', '3mf': 'model/3mf', glb: 'model/gltf-binary' };

/** Sets up links, files and exports on `app` (see main.js); returns what the page asks of them. */
export function setupFiles(app) {
  const { modeler, ff, sv, hv } = app;
  const { is_free_form, script_link, script_model_json, script_of, hyperfun_of, hyperfun_link, hyperfun_carries_model } = app.glue;
  const freeform = () => app.workspace() === 'freeform';
  const scripting = () => app.workspace() === 'script';
  const hyperfun = () => app.workspace() === 'hyperfun';
  // A HyperFun model (a file or link of kind `hyperfun`): `{ program, box }`, or undefined.
  const hyperfunIn = (text) => {
    const json = hyperfun_of(text);
    return json === undefined ? undefined : JSON.parse(json);
  };

  // Opens a link in the address over the model (a script, a free-form scene or a Bézier model).
  // The fragment is removed once opened: the model lives on in the autosave, so a reload brings
  // back the edits rather than the link's original. Returns whether something was opened.
  const openFromAddress = () => {
    if (!location.hash || location.hash === '#') return false;
    const script = script_of(location.href);
    const program = script === undefined ? hyperfunIn(location.href) : undefined;
    const free = script === undefined && program === undefined && is_free_form(location.href);
    let opened = false;
    try {
      if (program !== undefined) {
        app.hyperfun.load(program.program, program.box);
        app.setWorkspace('hyperfun');
        say('Opened the HyperFun program from the link.');
        opened = true;
      } else if (script !== undefined) {
        app.script.load(script);
        app.setWorkspace('script');
        say('Opened the script from the link.');
        opened = true;
      } else {
        if (free) ff.open(location.href);
        else modeler.open_link(location.href);
        app.setWorkspace(free ? 'freeform' : 'bezier');
        say(`Opened the ${free ? 'free-form ' : ''}model from the link.`);
        opened = true;
      }
    } catch (err) {
      say(`This link could not be opened, so the current model was kept: ${messageOf(err)}`, 'error');
    }
    history.replaceState(null, '', location.pathname + location.search);
    return opened;
  };
  addEventListener('hashchange', () => {
    if (openFromAddress()) {
      app.changed();
      if (scripting()) app.script.runIfNew();
      if (hyperfun()) app.hyperfun.runIfNew();
    }
  });

  // Share: the link goes into the box (always) and the clipboard (where allowed).
  $('copy-link').addEventListener('click', async () => {
    let fragment;
    try {
      fragment = scripting() ? script_link(app.script.text())
        : hyperfun() ? hyperfun_link(app.hyperfun.text(), new Float64Array(app.hyperfun.box()))
          : freeform() ? ff.link() : modeler.link();
    } catch (err) {
      say(messageOf(err), 'error');
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

  // Files: open by the picker or a drop. A mesh goes to the Free-form mode (a drop with Shift
  // there makes it solid B).
  const openFile = async (file) => {
    if (!file) return;
    if (MESH_FILE.test(file.name)) {
      app.freeform.importMesh(0, file);
      return;
    }
    if (file.size > 16 * 1024 * 1024) {
      say(`${file.name} is too large for a model file (${file.size} bytes).`, 'error');
      return;
    }
    try {
      const text = await file.text();
      const script = /\.psm$/i.test(file.name) ? text : script_of(text);
      if (script !== undefined) {
        app.script.open(script, `Opened ${file.name}.`);
        return;
      }
      // A HyperFun model file, or a HyperFun program that is not one of bezsolid's exports (an
      // export opens as the model it carries, below).
      const program = hyperfunIn(text);
      if (program !== undefined) {
        app.hyperfun.open(program.program, program.box, `Opened ${file.name}.`);
        return;
      }
      if (/\.hf$/i.test(file.name) && !hyperfun_carries_model(text)) {
        app.hyperfun.open(text, undefined, `Opened ${file.name} in the HyperFun mode: it is drawn within the box (set it in the panel).`);
        return;
      }
      if (is_free_form(text)) {
        ff.open(text);
        app.setWorkspace('freeform');
        app.resize3();
        say(`Opened ${file.name}.`);
        app.changed();
        return;
      }
      modeler.load_model(text);
      app.setWorkspace('bezier');
      say(`Opened ${file.name}; Undo brings back the previous model.`);
      app.changed();
    } catch (err) {
      say(`${file.name} could not be opened, so the current model was kept: ${messageOf(err)}`, 'error');
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
    if (MESH_FILE.test(file.name)) app.freeform.importMesh(freeform() && e.shiftKey ? 1 : 0, file);
    else openFile(file);
  });

  // A file made in the export worker (in the work list while it runs, with a Cancel), or on the
  // page without one (`here`, which may have to fetch the tools' module first).
  const exportJob = async (name, type, label, message, here) => {
    const worker = app.runners.export;
    if (!worker) {
      try {
        download(name, new Blob([await here()], { type }));
      } catch (err) {
        say(`Export failed, nothing was changed: ${messageOf(err)}`, 'error');
      }
      return;
    }
    const running = worker.run(message, {
      onProgress: (done, total) => task.progress(done, total),
      onStart: () => task.started(),
    });
    const task = app.work.start('export', label, () => running.cancel());
    try {
      const { data, approximate } = await running;
      download(name, new Blob([data], { type }));
      if (approximate) {
        say(`Saved ${name}, approximate where the net folds over itself very many times: `
          + `${approximate} ${approximate === 1 ? 'evaluation' : 'evaluations'} ran out of their work budget.`, 'warn');
      }
    } catch (err) {
      if (err.cancelled) say(`${label} was cancelled; nothing was saved.`);
      else say(`Export failed, nothing was changed: ${messageOf(err)}`, 'error');
    } finally {
      task.end();
    }
  };
  const exportMesh = (name, kind, format, model, resolution, here) => exportJob(
    name, MESH_TYPES[format], `Exporting ${format.toUpperCase()}`, { kind, model, format, resolution }, here);

  // What each mode exports, by the value of the Export menu's options.
  const bezierExports = {
    model: () => download('bezsolid.bsolid.json', new Blob([modeler.model_json()], { type: 'application/json' })),
    // The exact contour: on a folded net, the inverse map at every sample (seconds).
    // Exports are written by the tools' module (in the export worker, or here without one): the
    // page's module has no writers, so that the first download is small.
    svg: () => {
      const model = modeler.patch_json();
      exportJob('bezsolid-contours.svg', 'image/svg+xml', 'Exporting SVG', { kind: 'svg', model }, async () => (await tools()).headless_svg(model));
    },
    hf: () => {
      const model = modeler.model_json();
      exportJob('bezsolid.hf', 'text/plain', 'Exporting HyperFun', { kind: 'hf', model }, async () => (await tools()).headless_hyperfun(model));
    },
    ...Object.fromEntries(MESH_FORMATS.map((format) => [format, () => {
      const model = modeler.model_json();
      const resolution = modeler.resolution();
      exportMesh(`bezsolid.${format}`, 'mesh', format, model, resolution, async () => (await tools()).headless_mesh(model, format, resolution));
    }])),
    // The canvas is read in the same task as the frame is drawn, before the browser clears it.
    png: () => {
      modeler.render();
      capture(app.canvas, 'bezsolid-view.png');
    },
  };
  const freeformExports = {
    model: () => download('bezsolid.bsolid.json', new Blob([ff.model_json()], { type: 'application/json' })),
    // The result's closed mesh at the chosen resolution.
    ...Object.fromEntries(MESH_FORMATS.map((format) => [format, () => {
      const model = ff.model_json();
      const resolution = ff.resolution();
      exportMesh(`bezsolid-result.${format}`, 'esc-mesh', format, model, resolution, async () => (await tools()).headless_esc_mesh(model, format, resolution));
    }])),
    png: () => {
      if (!app.viewer) return;
      ff.render(app.viewer);
      capture(app.canvas3, 'bezsolid-free-form.png');
    },
  };
  const scriptExports = {
    model: () => download('bezsolid-script.bsolid.json', new Blob([script_model_json(app.script.text())], { type: 'application/json' })),
    psm: () => download('bezsolid.psm', new Blob([app.script.text()], { type: 'text/plain' })),
    ...Object.fromEntries(MESH_FORMATS.map((format) => [format, () => {
      const script = app.script.text();
      exportMesh(`bezsolid-script.${format}`, 'plasm-mesh', format, script, 0, async () => (await tools()).headless_plasm_mesh(script, format));
    }])),
    png: () => {
      if (!app.viewer) return;
      sv.render(app.viewer);
      capture(app.canvas3, 'bezsolid-script.png');
    },
  };
  const hyperfunExports = {
    model: () => download('bezsolid-hyperfun.bsolid.json', new Blob([app.hyperfun.modelJson()], { type: 'application/json' })),
    hf: () => download('bezsolid.hf', new Blob([app.hyperfun.text()], { type: 'text/plain' })),
    ...Object.fromEntries(MESH_FORMATS.map((format) => [format, () => {
      const model = app.hyperfun.modelJson();
      const resolution = app.hyperfun.resolution();
      const job = { kind: 'hyperfun-mesh', model, format, resolution };
      exportMesh(`bezsolid-hyperfun.${format}`, 'hyperfun-mesh', format, model, resolution, async () => (await runHere(job)).data);
    }])),
    png: () => {
      if (!app.viewer) return;
      hv.render(app.viewer);
      capture(app.canvas3, 'bezsolid-hyperfun.png');
    },
  };
  // What the solid measures, on the mesh (or contour) the exports make: in the export worker, in
  // the work list with a Cancel, shown beside the button until the model changes (the modes'
  // updates clear it: `data-revision` is the model's revision it measured).
  const fixed = (v) => Number(v.toPrecision(6)).toString();
  const describeMeasure = (m) => (m.dimension === 3
    ? `Volume ${fixed(m.volume)}, surface area ${fixed(m.area)}, bounding box `
      + `${fixed(m.bbox[0])} to ${fixed(m.bbox[3])} × ${fixed(m.bbox[1])} to ${fixed(m.bbox[4])} × `
      + `${fixed(m.bbox[2])} to ${fixed(m.bbox[5])}: measured on the mesh at ${m.resolution} cells `
      + `along the longest side (${m.triangles} triangles), as the mesh exports make it.`
    : `Area ${fixed(m.area)}, perimeter ${fixed(m.perimeter)}: measured on the contour at `
      + `${m.resolution} cells per side, as the SVG export draws it`
      + (m.open ? `; ${m.open} open ${m.open === 1 ? 'piece ends' : 'pieces end'} on the drawn box and ${m.open === 1 ? 'is' : 'are'} left out.` : '.'));
  const measure = async () => {
    const free = freeform();
    const hf = hyperfun();
    let model;
    try {
      model = hf ? app.hyperfun.modelJson() : free ? ff.model_json() : modeler.model_json();
    } catch (err) {
      say(`Could not measure the solid: ${messageOf(err)}`, 'error');
      return;
    }
    const resolution = hf ? app.hyperfun.resolution() : free ? ff.resolution() : modeler.resolution();
    const revision = String(hf ? app.hyperfun.revision() : free ? ff.revision() : modeler.revision());
    const out = $(hf ? 'hf-measure-out' : free ? 'ff-measure-out' : 'measure-out');
    const kind = hf ? 'hyperfun-measure' : 'measure';
    out.dataset.kind = '';
    out.textContent = 'Measuring…';
    delete out.dataset.revision;
    const worker = app.runners.export;
    let text;
    let approximate = 0;
    try {
      if (worker) {
        const running = worker.run({ kind, model, resolution }, {
          onProgress: (done, total) => task.progress(done, total),
          onStart: () => task.started(),
        });
        const task = app.work.start('measure', 'Measuring', () => running.cancel());
        try {
          const done = await running;
          text = new TextDecoder().decode(done.data);
          approximate = done.approximate ?? 0;
        } finally {
          task.end();
        }
      } else {
        text = hf ? new TextDecoder().decode((await runHere({ kind, model, resolution })).data)
          : (await tools()).headless_measure(model, resolution);
      }
    } catch (err) {
      out.textContent = '';
      if (err.cancelled) say('Measuring was cancelled.');
      else say(`Could not measure the solid: ${messageOf(err)}`, 'error');
      return;
    }
    const m = JSON.parse(text);
    document.body.dataset.measure = text;
    out.textContent = describeMeasure(m) + (approximate
      ? ` Approximate where the net folds over itself very many times: ${approximate} ${approximate === 1 ? 'evaluation' : 'evaluations'} ran out of their work budget.`
      : '');
    out.dataset.kind = approximate ? 'warn' : '';
    out.dataset.revision = revision;
  };
  for (const button of document.querySelectorAll('button.measure')) {
    button.addEventListener('click', () => {
      if (!scripting()) measure();
    });
  }

  setupMenu($('export'), (kind) => {
    const exporters = scripting() ? scriptExports : hyperfun() ? hyperfunExports : freeform() ? freeformExports : bezierExports;
    if (!Object.hasOwn(exporters, kind)) return;
    try {
      exporters[kind]();
    } catch (err) {
      say(`Export failed, nothing was changed: ${messageOf(err)}`, 'error');
    }
  });

  return { openFromAddress };
}
