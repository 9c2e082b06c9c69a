// Long work off the page's thread, and what the page shows of it.
//
// A runner is one Web Worker (worker.js, the page's own module) that runs one job at a time, in the
// order asked; replies are matched to their jobs by id, and a job may report progress on the way.
// Cancelling a job that has not started drops it; cancelling the one under way terminates the
// worker (a wasm computation cannot be interrupted otherwise) and starts a fresh one for the rest.
//
// The work list shows every job the user waits for: what it is, how far it got (a fraction where
// the work comes in steps), how long it has run, and a Cancel button.
//
// A follower keeps one kind of result up to date with the model (a volume's fine surface, its
// contour stack, a free-form result's surface): it asks for what the model wants now, and drops
// what the model has moved past.

import { say } from './ui.js';

const cancelled = () => Object.assign(new Error('cancelled'), { cancelled: true });

// Jobs under way in all workers at once: one core is left to the page (its thread, and the
// browser's drawing, which is software on some machines), so the page keeps drawing however many
// jobs are asked for; the others wait their turn.
const cores = { free: Math.max(1, (navigator.hardwareConcurrency || 2) - 1), waiting: [] };
const acquire = () => new Promise((resolve) => {
  if (cores.free > 0) {
    cores.free -= 1;
    resolve();
  } else {
    cores.waiting.push(resolve);
  }
});
const release = () => {
  const next = cores.waiting.shift();
  if (next) next();
  else cores.free += 1;
};

/**
 * A worker and its queue; throws where the browser has no Web Workers. The worker (and the tools'
 * module it fetches) starts with the first job, or with `warm()`.
 */
export function runner() {
  if (typeof Worker !== 'function') throw new Error('this browser has no Web Workers');
  let worker = null;
  const queue = []; // { id, message, resolve, reject, onProgress, onStart }
  let current = null; // waiting for a core, or under way (`running`)
  let next = 0;
  const pump = async () => {
    if (current || !queue.length) return;
    const job = queue.shift();
    current = job;
    await acquire();
    if (current !== job) {
      release(); // cancelled while it waited
      return;
    }
    job.running = true;
    job.onStart?.();
    try {
      if (!worker) start();
    } catch (err) {
      finish(job);
      job.reject(err);
      pump();
      return;
    }
    worker.postMessage({ ...job.message, id: job.id });
  };
  const finish = (job) => {
    if (current === job) current = null;
    if (job.running) release();
    job.running = false;
  };
  const start = () => {
    worker = new Worker(new URL('./worker.js', import.meta.url), { type: 'module' });
    worker.onmessage = ({ data }) => {
      const job = current;
      if (!job?.running || data.id !== job.id) return;
      if (data.progress) {
        job.onProgress?.(...data.progress);
        return;
      }
      finish(job);
      if (data.fatal) restart(); // a trap may leave the module's state broken: a fresh one
      else pump();
      if (data.error) job.reject(new Error(data.error));
      else job.resolve(data);
    };
    worker.onerror = (e) => {
      e.preventDefault();
      const job = current?.running ? current : null;
      if (job) finish(job);
      restart();
      job?.reject(new Error(e.message || 'the worker failed'));
    };
  };
  // The next job starts a fresh worker (its module comes from the browser's cache).
  const restart = () => {
    worker?.terminate();
    worker = null;
    pump();
  };
  const cancel = (id) => {
    const k = queue.findIndex((j) => j.id === id);
    if (k >= 0) {
      queue.splice(k, 1)[0].reject(cancelled());
    } else if (current?.id === id) {
      const job = current;
      const wasRunning = job.running;
      finish(job);
      if (wasRunning) restart();
      else pump();
      job.reject(cancelled());
    }
  };
  return {
    /**
     * Runs `message` (`{ kind, ... }`, see worker.js); `onProgress(done, total)` on the way and
     * `onStart()` when it leaves the queue for a core. The promise has `cancel()`.
     */
    run(message, { onProgress, onStart } = {}) {
      next += 1;
      const id = next;
      const promise = new Promise((resolve, reject) => {
        queue.push({ id, message, resolve, reject, onProgress, onStart });
      });
      pump();
      promise.cancel = () => cancel(id);
      return promise;
    },
    /** Starts the worker now, so that its module is fetched and ready before the first job. */
    warm() {
      if (!worker) start();
    },
    /** Cancels every job, waiting or under way. */
    cancelAll() {
      for (const job of queue.splice(0)) job.reject(cancelled());
      if (current) cancel(current.id);
    },
  };
}

// The jobs a team makes in shares (`share: [k, n]`: blocks of a surface, slices of a stack), whose
// results, one after another, are the whole result (jobs.rs).
const SHARED = new Set(['surface', 'stack']);

/**
 * Up to `size` runners that make one result together, so that long work uses every core the page
 * may: a job that comes in shares goes to each runner with its share, and their results (typed
 * arrays) are joined in order; other jobs go to the first runner. The same face as a runner.
 */
export function team(size) {
  const runners = [runner()];
  const member = (k) => (runners[k] ??= runner());
  return {
    size,
    run(message, { onProgress, onStart } = {}) {
      if (size === 1 || !SHARED.has(message.kind)) return runners[0].run(message, { onProgress, onStart });
      let started = false;
      // Progress is the shares' together: their steps done of their steps in all.
      const steps = Array.from({ length: size }, () => [0, 0]);
      const parts = Array.from({ length: size }, (_, k) => member(k).run({ ...message, share: [k, size] }, {
        onStart: () => {
          if (!started) onStart?.();
          started = true;
        },
        onProgress: (done, total) => {
          steps[k] = [done, total];
          onProgress?.(steps.reduce((n, s) => n + s[0], 0), steps.reduce((n, s) => n + s[1], 0));
        },
      }));
      const cancel = () => {
        for (const p of parts) p.cancel();
      };
      const promise = Promise.all(parts).then((replies) => {
        const data = new replies[0].data.constructor(replies.reduce((n, r) => n + r.data.length, 0));
        let at = 0;
        for (const r of replies) {
          data.set(r.data, at);
          at += r.data.length;
        }
        const approximate = replies.reduce((n, r) => n + (r.approximate ?? 0), 0);
        // A surface of many solids: the blocks the workers kept from their last meshes, of all.
        const kept = replies.every((r) => r.kept)
          ? replies.reduce(([k, n], r) => [k + r.kept[0], n + r.kept[1]], [0, 0]) : undefined;
        return { ...replies[0], data, approximate, kept, ms: Math.max(...replies.map((r) => r.ms)), shares: size };
      }, (err) => {
        cancel();
        throw err;
      });
      promise.cancel = cancel;
      return promise;
    },
    warm() {
      runners[0].warm();
    },
    cancelAll() {
      for (const r of runners) r?.cancelAll();
    },
  };
}

const seconds = (ms) => `${(ms / 1000).toFixed(1)} s`;

/**
 * The list of work under way in `container`: `start(kind, label, cancel)` adds a line with a Cancel
 * button that calls `cancel` (none without it: work on the page's thread cannot be stopped), and
 * returns `{ started(), progress(done, total, unit), end() }`. A line says "waiting" until
 * `started()` (a job waits for a free core), then how long it has run and how far it got. The
 * body's `data-working` names the kinds under way or waiting (empty when idle), for tests and styles.
 */
export function workList(container) {
  const tasks = new Set();
  let timer = 0;
  const tick = () => {
    const now = performance.now();
    for (const t of tasks) {
      // Steps with a unit are counted ("3 of 9 slices"); plain steps are a share ("40%").
      const fraction = !t.total ? '' : t.unit ? `${t.done} of ${t.total} ${t.unit}, ` : `${Math.floor((100 * t.done) / t.total)}%, `;
      t.how.textContent = t.t0 === null ? 'waiting' : `${fraction}${seconds(now - t.t0)}`;
    }
  };
  const update = () => {
    container.hidden = tasks.size === 0;
    document.body.dataset.working = [...tasks].map((t) => t.kind).join(' ');
    if (tasks.size && !timer) timer = setInterval(tick, 200);
    if (!tasks.size && timer) {
      clearInterval(timer);
      timer = 0;
    }
    tick();
  };
  update();
  return {
    start(kind, label, cancel) {
      const line = document.createElement('div');
      line.className = 'task';
      line.dataset.kind = kind;
      const what = document.createElement('span');
      what.textContent = `${label}…`;
      const how = document.createElement('span');
      how.className = 'how';
      how.setAttribute('aria-hidden', 'true'); // the time ticks: not read out five times a second
      line.append(what, how);
      if (cancel) {
        const button = document.createElement('button');
        button.type = 'button';
        button.textContent = 'Cancel';
        button.title = `Cancel ${label[0].toLowerCase()}${label.slice(1)}`;
        button.addEventListener('click', () => cancel());
        line.append(button);
      }
      const task = { kind, how, t0: null, done: 0, total: 0, unit: '' };
      container.append(line);
      tasks.add(task);
      update();
      return {
        started() {
          task.t0 = performance.now();
          line.dataset.state = 'running';
          tick();
        },
        progress(done, total, unit = '') {
          Object.assign(task, { done, total, unit });
          line.dataset.progress = String(total ? done / total : 0);
          tick();
        },
        end() {
          if (!tasks.delete(task)) return;
          line.remove();
          update();
        },
      };
    },
  };
}

/**
 * A runner (a team of `size` for more than one) made on first use (most visits never open a volume
 * or a script); null when `enabled` is false or the browser refuses.
 */
export function lazyRunner(enabled, size = 1) {
  let made;
  return () => {
    if (made === undefined) {
      try {
        made = enabled ? (size > 1 ? team(size) : runner()) : null;
      } catch {
        made = null;
      }
    }
    return made;
  };
}

/**
 * Work that follows the model. `request()` says what is wanted now (an array whose first entry is
 * the model's revision, or undefined), `job(request)` the worker's message for it, and
 * `accept(request, reply)` hands the result in (false when the model moved on); `onAccepted()`
 * runs after a result was taken. A newer request cancels the job under way, and so does any change
 * of the model (`revision()`: its result would be dropped); one the user cancelled is not asked
 * again until the model changes. `label(request)` names the job in `list`, `unit` its steps, and
 * `failed` starts the message of an error.
 */
export function follower({ list, worker, request, revision, job, accept, onAccepted, label, unit, failed }) {
  let busy = ''; // the request in flight, as a key
  let busyRevision = null;
  let declined = '';
  let lastMs = 0;
  let inFlight = null;
  const send = async (wanted) => {
    const key = wanted.join(',');
    busy = key;
    busyRevision = wanted[0];
    inFlight?.cancel();
    const message = job(wanted);
    const task = list.start(message.kind, label(wanted), () => {
      declined = key;
      inFlight?.cancel();
    });
    const running = worker().run(message, {
      onProgress: (done, total) => task.progress(done, total, unit),
      onStart: () => task.started(),
    });
    inFlight = running;
    try {
      const reply = await running;
      if (accept(wanted, reply)) {
        lastMs = reply.ms;
        onAccepted();
      }
    } catch (err) {
      if (!err.cancelled) say(`${failed}: ${err.message}`, 'error');
    } finally {
      task.end();
      if (busy === key) busy = '';
      if (inFlight === running) {
        inFlight = null;
        busyRevision = null;
      }
    }
  };
  return {
    /** Asks for what the model wants, unless it is in flight or was cancelled. */
    check() {
      const wanted = request();
      if (!wanted) return;
      const key = wanted.join(',');
      if (key === busy || key === declined) return;
      send(wanted);
    },
    /** Cancels the job under way if the model has changed since it was asked for. */
    prune() {
      if (inFlight && busyRevision !== revision()) inFlight.cancel();
    },
    /** How long the last result took in the worker, in ms. */
    lastMs: () => lastMs,
  };
}
