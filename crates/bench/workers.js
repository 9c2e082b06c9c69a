// The drawn surface made in shares by worker threads, as the page's Web Workers make it: each
// worker loads the benchmark module (wasm) and makes its share of the benchmark solid's surface;
// a round is timed from the request to the last share's answer. Run by `cargo xtask bench`:
//   node crates/bench/workers.js <bezsolid_bench.js built for node> [quick]
// Prints rows (JSON) as the suite's: one worker making the whole, then two making a share each.
'use strict';
const { Worker, isMainThread, parentPort, workerData } = require('node:worker_threads');

if (!isMainThread) {
  const bench = require(workerData.module);
  parentPort.on('message', ({ n, index, count }) => parentPort.postMessage(bench.surface_share(n, index, count)));
} else {
  const [module, quick] = [process.argv[2], process.argv[3] === 'true'];
  const round = (workers, n) => new Promise((resolve) => {
    const t0 = performance.now();
    let left = workers.length;
    let triangles = 0;
    for (const [index, w] of workers.entries()) {
      w.once('message', (t) => {
        triangles += t;
        left -= 1;
        if (!left) resolve([performance.now() - t0, triangles]);
      });
      w.postMessage({ n, index, count: workers.length });
    }
  });
  // The teams' rounds alternate, so that a machine that slows down or speeds up meanwhile
  // weighs on both alike.
  (async () => {
    const sizes = [1, 2];
    const teams = sizes.map((count) => Array.from({ length: count }, () => new Worker(__filename, { workerData: { module } })));
    const rows = [];
    for (const n of quick ? [64] : [128, 256]) {
      // Each worker compiles the module and warms up (its code tiers up to the optimising
      // compiler in the background over the first runs).
      for (const t0 = performance.now(); performance.now() - t0 < (quick ? 100 : 1000);) {
        for (const team of teams) await round(team, n);
      }
      const times = teams.map(() => []);
      const triangles = teams.map(() => 0);
      const budget = quick ? 300 : 4000;
      const start = performance.now();
      while (times[0].length < 3 || (performance.now() - start < budget && times[0].length < 50)) {
        for (const [k, team] of teams.entries()) {
          const [ms, t] = await round(team, n);
          times[k].push(ms);
          triangles[k] = t;
        }
      }
      for (const [k, count] of sizes.entries()) {
        const sorted = [...times[k]].sort((a, b) => a - b);
        rows.push({
          case: 'drawn surface in shares (page workers)',
          who: `bezsolid (wasm, ${count} worker${count > 1 ? 's' : ''})`,
          n,
          ms: sorted[Math.floor(sorted.length / 2)],
          runs: sorted.length,
          extra: triangles[k],
          note: '',
        });
      }
    }
    await Promise.all(teams.flat().map((w) => w.terminate()));
    process.stdout.write(JSON.stringify(rows));
  })();
}
