//! The native benchmark runner: our suite, then the peers on the same data (with `--features peers`),
//! as JSON rows on stdout. `cargo xtask bench` runs it and writes BENCHMARKS.md.

use std::time::Instant;

use bezsolid_bench::{Clock, Row, suite};

struct Wall(Instant);

impl Clock for Wall {
    fn now_ms(&mut self) -> f64 {
        self.0.elapsed().as_secs_f64() * 1000.0
    }
}

fn main() {
    // Every row is one thread's unless it says otherwise: a pool of one is installed around them.
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap_or_else(|e| {
            eprintln!("bezsolid-bench: no thread pool: {e}");
            std::process::exit(1)
        });
    one.install(one_thread);
}

fn one_thread() {
    let quick = std::env::args().any(|a| a == "--quick");
    let mut clock = Wall(Instant::now());
    // `--mesh`: only grid evaluation and the polygonizer's cases (for working on them).
    if std::env::args().any(|a| a == "--mesh") {
        #[cfg_attr(not(feature = "peers"), allow(unused_mut))]
        let mut rows = bezsolid_bench::eval_suite(&mut clock, quick);
        rows.extend(bezsolid_bench::mesh_suite(&mut clock, quick));
        rows.extend(threaded(quick));
        #[cfg(feature = "peers")]
        rows.extend(peers::polygonize_peer(&mut clock, quick));
        println!("{}", serde_json::to_string(&rows).unwrap_or_default());
        return;
    }
    // `--hyperfun`: only the HyperFun exports' evaluation.
    if std::env::args().any(|a| a == "--hyperfun") {
        let rows = bezsolid_bench::hyperfun::suite(&mut clock, quick);
        println!("{}", serde_json::to_string(&rows).unwrap_or_default());
        return;
    }
    // `--esc`: only the point-in-solid cases (for working on them).
    if std::env::args().any(|a| a == "--esc") {
        let rows = bezsolid_bench::esc::suite(&mut clock, quick);
        println!("{}", serde_json::to_string(&rows).unwrap_or_default());
        return;
    }
    // `--tree`: only the model of many solids.
    if std::env::args().any(|a| a == "--tree") {
        #[cfg_attr(not(feature = "peers"), allow(unused_mut))]
        let mut rows = bezsolid_bench::tree::suite(&mut clock, quick);
        #[cfg(feature = "peers")]
        rows.extend(peers::tree_peer(&mut clock, quick));
        println!("{}", serde_json::to_string(&rows).unwrap_or_default());
        return;
    }
    // `--inverse`: only the space-mapping cases, folded nets included.
    if std::env::args().any(|a| a == "--inverse") {
        let rows = bezsolid_bench::inverse::suite(&mut clock, quick);
        println!("{}", serde_json::to_string(&rows).unwrap_or_default());
        return;
    }
    #[cfg_attr(not(feature = "peers"), allow(unused_mut))]
    let mut rows: Vec<Row> = suite(&mut clock, quick);
    rows.extend(threaded(quick));
    #[cfg(feature = "peers")]
    rows.extend(peers::run(&mut clock, quick));
    match serde_json::to_string(&rows) {
        Ok(json) => println!("{json}"),
        Err(e) => {
            eprintln!("bezsolid-bench: {e}");
            std::process::exit(1);
        }
    }
}

/// `mesh` timed inside `pool` on its own clock: the median, the runs, the triangles.
fn on_pool(
    pool: &rayon::ThreadPool,
    budget: f64,
    mesh: impl Fn() -> bezsolid_core::mesh::Mesh + Send,
) -> (f64, usize, usize) {
    pool.install(|| {
        let mut clock = Wall(Instant::now());
        let (ms, runs, mesh) = bezsolid_bench::time(&mut clock, budget, mesh);
        (ms, runs, mesh.triangle_count())
    })
}

/// The adaptive mesher and the tree's on every core of the machine (a pool of that many threads), each time taken
/// on its own clock inside the pool.
fn threaded(quick: bool) -> Vec<Row> {
    let budget = if quick { 50.0 } else { 1000.0 };
    let solid = bezsolid_bench::bench_solid();
    let threads = std::thread::available_parallelism().map_or(1, std::num::NonZero::get);
    let Ok(pool) = rayon::ThreadPoolBuilder::new().num_threads(threads).build() else {
        return Vec::new();
    };
    let sizes: &[usize] = if quick { &[128] } else { &[128, 256, 512] };
    let mut rows = Vec::new();
    for &n in sizes {
        let (ms, runs, triangles) = on_pool(&pool, budget, || {
            solid
                .polygonize(n, 1e-9)
                .unwrap_or_else(|_| unreachable!("valid arguments"))
        });
        rows.push(Row {
            case: "polygonize".into(),
            who: format!("bezsolid (adaptive, {threads} threads)"),
            n,
            ms,
            runs,
            extra: triangles as f64,
            note: String::new(),
        });
    }
    let tree = bezsolid_bench::tree::tree();
    for &n in if quick { &[128][..] } else { &[128, 256][..] } {
        let (ms, runs, triangles) = on_pool(&pool, budget, || {
            tree.polygonize(n, 1e-9, None)
                .unwrap_or_else(|_| unreachable!("a bounded tree"))
        });
        rows.push(Row {
            case: "tree of 20 solids: polygonize".into(),
            who: format!("bezsolid ({threads} threads)"),
            n,
            ms,
            runs,
            extra: triangles as f64,
            note: String::new(),
        });
    }
    rows
}

#[cfg(feature = "peers")]
mod peers;
