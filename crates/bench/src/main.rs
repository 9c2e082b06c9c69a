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
    let quick = std::env::args().any(|a| a == "--quick");
    let mut clock = Wall(Instant::now());
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

#[cfg(feature = "peers")]
mod peers;
