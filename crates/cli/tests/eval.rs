//! `bezsolid eval` end to end: model files and point lists written to disk, the binary run, its CSV
//! parsed back and compared with the paper's formulas written out independently here.

#![allow(clippy::unwrap_used)] // a test: a failed unwrap is a failed test
mod common;
use common::{Feed, bezsolid, bezsolid_bounded, out_path, scratch, succeed};
use std::process::Output;
use std::time::Duration;

fn binom(n: usize, k: usize) -> f64 {
    (0..k).fold(1.0, |c, i| c * (n - i) as f64 / (i + 1) as f64)
}

/// `B_i^n(t) = C(n,i) tⁱ(1−t)ⁿ⁻ⁱ`.
fn b(n: usize, i: usize, t: f64) -> f64 {
    binom(n, i) * t.powi(i as i32) * (1.0 - t).powi((n - i) as i32)
}

/// The R-function intersection as the paper writes it.
fn and(f1: f64, f2: f64) -> f64 {
    f1 + f2 - (f1 * f1 + f2 * f2).sqrt()
}

fn fb(t: f64) -> f64 {
    t * (1.0 - t)
}

fn rows(out: &Output) -> Vec<Vec<f64>> {
    assert!(
        out.status.success(),
        "stderr: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8(out.stdout.clone()).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap();
    assert!(header.starts_with("x,y"), "{header}");
    lines
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect()
}

#[test]
fn eval_patch_matches_the_paper() {
    // A degree (2, 3) patch over [1, 3] × [−1, 0.5] with uneven ξ.
    let (n, m) = (2usize, 3usize);
    let xi = |i: usize, j: usize| ((i * 7 + j * 3) % 5) as f64 * 0.5 - 1.0;
    let mut points = Vec::new();
    for i in 0..=n {
        for j in 0..=m {
            let x = 1.0 + 2.0 * i as f64 / n as f64;
            let y = -1.0 + 1.5 * j as f64 / m as f64;
            points.push(format!("[{x}, {y}, {}]", xi(i, j)));
        }
    }
    let model = format!(
        r#"{{"format": "bezsolid", "version": 1, "solid": {{"kind": "patch", "degree": [{n}, {m}], "points": [{}]}}}}"#,
        points.join(", ")
    );
    let model = scratch("patch.bsolid.json", &model);
    let queries = [
        (1.5, -0.5),
        (2.0, 0.0),
        (2.9, 0.4),
        (0.5, 0.0),
        (3.5, -2.0),
        (1.0, -1.0),
    ];
    let csv: String = queries.iter().map(|(x, y)| format!("{x},{y}\n")).collect();
    let pts = scratch("patch.csv", &format!("x,y\n{csv}"));
    let got = rows(&bezsolid(&[
        "eval",
        model.to_str().unwrap(),
        "--points",
        pts.to_str().unwrap(),
    ]));
    assert_eq!(got.len(), queries.len());
    for (row, &(x, y)) in got.iter().zip(&queries) {
        let (u, v) = ((x - 1.0) / 2.0, (y + 1.0) / 1.5);
        let mut s = 0.0;
        for i in 0..=n {
            for j in 0..=m {
                s += xi(i, j) * b(n, i, u) * b(m, j, v);
            }
        }
        let f = and(s, and(fb(u), fb(v)));
        assert_eq!((row[0], row[1]), (x, y));
        assert!(
            (row[2] - f).abs() <= 1e-12 * f.abs().max(1.0),
            "f({x}, {y}) = {} vs {f}",
            row[2]
        );
        let inside = (0.0..=1.0).contains(&u) && (0.0..=1.0).contains(&v);
        assert_eq!(row[3], if inside { 1.0 } else { 0.0 });
    }
}

#[test]
fn eval_volume_matches_the_paper() {
    let (n, m, l) = (1usize, 2usize, 2usize);
    let xi = |i: usize, j: usize, k: usize| {
        if (i, j, k) == (1, 1, 1) {
            2.0
        } else {
            ((i + 2 * j + k) % 3) as f64 - 1.2
        }
    };
    let mut points = Vec::new();
    for i in 0..=n {
        for j in 0..=m {
            for k in 0..=l {
                let (x, y, z) = (
                    i as f64 / n as f64,
                    j as f64 / m as f64,
                    2.0 * k as f64 / l as f64,
                );
                points.push(format!("[{x}, {y}, {z}, {}]", xi(i, j, k)));
            }
        }
    }
    let model = format!(
        r#"{{"format": "bezsolid", "version": 1, "solid": {{"kind": "volume", "degree": [{n}, {m}, {l}], "points": [{}]}}}}"#,
        points.join(", ")
    );
    let model = scratch("volume.bsolid.json", &model);
    let queries = [
        (0.5, 0.5, 1.0),
        (0.2, 0.7, 0.3),
        (0.9, 0.1, 1.9),
        (1.2, 0.5, 1.0),
    ];
    let csv: String = queries
        .iter()
        .map(|(x, y, z)| format!("{x},{y},{z}\n"))
        .collect();
    let pts = scratch("volume.csv", &csv);
    let got = rows(&bezsolid(&[
        "eval",
        model.to_str().unwrap(),
        "--points",
        pts.to_str().unwrap(),
    ]));
    assert_eq!(got.len(), queries.len());
    for (row, &(x, y, z)) in got.iter().zip(&queries) {
        let (u, v, w) = (x, y, z / 2.0);
        let mut s = 0.0;
        for i in 0..=n {
            for j in 0..=m {
                for k in 0..=l {
                    s += xi(i, j, k) * b(n, i, u) * b(m, j, v) * b(l, k, w);
                }
            }
        }
        let f = and(s, and(and(fb(u), fb(v)), fb(w)));
        assert!(
            (row[3] - f).abs() <= 1e-12 * f.abs().max(1.0),
            "f({x}, {y}, {z}) = {} vs {f}",
            row[3]
        );
        assert_eq!(row[4], if x <= 1.0 { 1.0 } else { 0.0 });
    }
}

/// A space mapping that folds: degree (2, 1), `x(u) = 3u − 2.5u²` rises to 0.9 at `u = 0.6` and falls
/// back to 0.5, `y = v`. A point with `0.5 < x < 0.9` has two preimages and `f` is the larger clipped
/// `S_ξ` (the extended space mapping), one with `x < 0.5` has one, and one with `x > 0.9` none.
#[test]
fn eval_space_mapping_counts_preimages_and_takes_the_max() {
    let xs = [0.0, 1.5, 0.5];
    let xis = [[1.0, 0.6], [1.0, -0.4], [-1.0, 0.8]];
    let mut points = Vec::new();
    for (x, row) in xs.iter().zip(&xis) {
        for (y, xi) in row.iter().enumerate() {
            points.push(format!("[{x}, {y}, {xi}]"));
        }
    }
    let model = format!(
        r#"{{"format": "bezsolid", "version": 1, "solid": {{"kind": "patch", "degree": [2, 1], "points": [{}]}}}}"#,
        points.join(", ")
    );
    let model = scratch("folded.bsolid.json", &model);
    let queries = [
        (0.7, 0.5),
        (0.55, 0.3),
        (0.3, 0.5),
        (0.85, 0.9),
        (1.0, 0.5),
        (0.7, 1.2),
    ];
    let csv: String = queries.iter().map(|(x, y)| format!("{x},{y}\n")).collect();
    let pts = scratch("folded.csv", &csv);
    let out = bezsolid(&[
        "eval",
        model.to_str().unwrap(),
        "--points",
        pts.to_str().unwrap(),
    ]);
    let rows = rows(&out);
    assert_eq!(rows.len(), queries.len());
    for (row, &(x, y)) in rows.iter().zip(&queries) {
        // The preimages u of x, from 2.5u² − 3u + x = 0, and v = y.
        let disc: f64 = 9.0 - 10.0 * x;
        let roots: Vec<f64> = if disc < 0.0 {
            Vec::new()
        } else {
            [(3.0 - disc.sqrt()) / 5.0, (3.0 + disc.sqrt()) / 5.0]
                .into_iter()
                .filter(|u| (0.0..=1.0).contains(u) && (0.0..=1.0).contains(&y))
                .collect()
        };
        assert_eq!(row[3], roots.len() as f64, "preimages of ({x}, {y})");
        let s_xi = |u: f64, v: f64| -> f64 {
            (0..=2)
                .map(|i| {
                    (0..=1)
                        .map(|j| xis[i][j] * b(2, i, u) * b(1, j, v))
                        .sum::<f64>()
                })
                .sum()
        };
        let values: Vec<f64> = roots
            .iter()
            .map(|&u| and(s_xi(u, y), and(fb(u), fb(y))))
            .collect();
        if values.len() == 2 {
            // The two preimages differ, so taking the max is not taking either one.
            assert!((values[0] - values[1]).abs() > 1e-3, "{values:?}");
        }
        let f = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        if roots.is_empty() {
            assert!(row[2] < 0.0, "outside the image f < 0 at ({x}, {y})");
        } else {
            assert!((row[2] - f).abs() < 1e-9, "f({x}, {y}) = {} vs {f}", row[2]);
        }
    }
}

#[test]
fn eval_refuses_bad_input_with_a_message() {
    let good = r#"{"format":"bezsolid","version":1,"solid":{"kind":"patch","degree":[1,1],"points":[[0,0,1],[0,1,1],[1,0,1],[1,1,1]]}}"#;
    let pts = scratch("ok.csv", "0.5,0.5\n");
    let cases = [
        (
            "v2.json",
            good.replace("\"version\":1", "\"version\":2"),
            "version 2",
        ),
        (
            "count.json",
            good.replace(",[1,1,1]", ""),
            "expected 4 control points",
        ),
        (
            "nan.json",
            good.replace("[1,1,1]", "[1,1,1e999]"),
            "valid model file",
        ),
        ("junk.json", "{\"format\": ".to_string(), "valid model file"),
        ("degree.json", good.replace("[1,1]", "[17,1]"), "degree 17"),
    ];
    for (name, text, message) in cases {
        let model = scratch(name, &text);
        let out = bezsolid(&[
            "eval",
            model.to_str().unwrap(),
            "--points",
            pts.to_str().unwrap(),
        ]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{name}: {err}");
        assert!(err.contains(message), "{name}: {err}");
        assert!(!err.contains("panicked"), "{name}: {err}");
    }
    let model = scratch("good.json", good);
    let bad_points = scratch("bad.csv", "0.5,0.5\n0.5\n");
    let out = bezsolid(&[
        "eval",
        model.to_str().unwrap(),
        "--points",
        bad_points.to_str().unwrap(),
    ]);
    assert!(String::from_utf8_lossy(&out.stderr).contains("line 2"));
    assert!(
        !bezsolid(&["eval", "/no/such/model.json", "--points", "x.csv"])
            .status
            .success()
    );
}

#[test]
fn contour_svg_lies_on_the_zero_set() {
    // The Fig. 9 patch, moved to the box [2, 4] × [0, 1].
    let xi = [[-1.0, 0.25, -1.0], [0.25, 1.0, 0.25], [-1.0, 0.25, -1.0]];
    let mut points = Vec::new();
    for (i, row) in xi.iter().enumerate() {
        for (j, v) in row.iter().enumerate() {
            points.push(format!("[{}, {}, {v}]", 2.0 + i as f64, j as f64 * 0.5));
        }
    }
    let model = format!(
        r#"{{"format": "bezsolid", "version": 1, "solid": {{"kind": "patch", "degree": [2, 2], "points": [{}]}}}}"#,
        points.join(",")
    );
    let model = scratch("fig9.bsolid.json", &model);
    let svg_path = out_path("fig9.svg");
    succeed(&[
        "contour",
        model.to_str().unwrap(),
        "--res",
        "64",
        "-o",
        svg_path.to_str().unwrap(),
    ]);
    let svg = std::fs::read_to_string(&svg_path).unwrap();
    // Parse the paths back: one closed loop, every vertex on f = 0.
    let paths: Vec<&str> = svg
        .split("d=\"")
        .skip(1)
        .map(|s| s.split('"').next().unwrap())
        .collect();
    assert_eq!(paths.len(), 1, "{svg}");
    assert!(paths[0].ends_with('Z'));
    let mut count = 0;
    for token in paths[0].trim_end_matches('Z').split_whitespace() {
        let (x, y) = token
            .trim_start_matches(['M', 'L'])
            .split_once(',')
            .unwrap();
        let (x, y): (f64, f64) = (x.parse().unwrap(), y.parse().unwrap());
        let (u, v) = ((x - 2.0) / 2.0, y);
        let mut s = 0.0;
        for (i, row) in xi.iter().enumerate() {
            for (j, value) in row.iter().enumerate() {
                s += value * b(2, i, u) * b(2, j, v);
            }
        }
        let f = and(s, and(fb(u), fb(v)));
        assert!(f.abs() <= 1e-9 + 1e-15, "f({x}, {y}) = {f}");
        count += 1;
    }
    assert!(count > 20, "a loop with many vertices ({count})");
    // A volume model is refused with a pointer to the right command.
    let vol = scratch(
        "cube.json",
        r#"{"format":"bezsolid","version":1,"solid":{"kind":"volume","degree":[1,1,1],"points":[[0,0,0,1],[0,0,1,1],[0,1,0,1],[0,1,1,1],[1,0,0,1],[1,0,1,1],[1,1,0,1],[1,1,1,1]]}}"#,
    );
    let out = bezsolid(&[
        "contour",
        vol.to_str().unwrap(),
        "-o",
        svg_path.to_str().unwrap(),
    ]);
    assert!(!out.status.success() && String::from_utf8_lossy(&out.stderr).contains("patch"));
}

/// The CSV that `eval` wrote when it held all points and all rows in memory: the same numbers,
/// formatted the same way, made here from the core.
fn csv_in_memory(preset: &str, points: &[[f64; 3]]) -> String {
    use bezsolid_core::inverse::Method;
    use bezsolid_core::model::ModelSolid;
    use bezsolid_core::presets::Preset;
    use std::fmt::Write as _;
    let mut csv = String::new();
    match Preset::from_name(preset).unwrap().solid() {
        ModelSolid::Patch(s) => {
            csv.push_str("x,y,f,preimages\n");
            for p in points {
                let v = s.evaluate(glam::DVec2::new(p[0], p[1]), Method::Fast);
                writeln!(csv, "{},{},{},{}", p[0], p[1], v.f, v.preimages).unwrap();
            }
        }
        ModelSolid::Volume(s) => {
            csv.push_str("x,y,z,f,preimages\n");
            for p in points {
                let v = s.evaluate(glam::DVec3::from_array(*p), Method::Fast);
                writeln!(csv, "{},{},{},{},{}", p[0], p[1], p[2], v.f, v.preimages).unwrap();
            }
        }
    }
    csv
}

#[test]
fn eval_streams_points_from_a_pipe_as_it_wrote_them_from_memory() {
    let mut state = 0x9e37_79b9_7f4a_7c15u64;
    let mut next = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 0.5
    };
    for (preset, dim, count) in [("fig9", 2, 100_000), ("ring", 3, 10_000)] {
        let points: Vec<[f64; 3]> = (0..count)
            .map(|_| [next(), next(), if dim == 3 { next() } else { 0.0 }])
            .collect();
        // A header, comments, blank lines and CRLF on the way, as a file may have them.
        let mut text = String::from(if dim == 2 { "x,y\n" } else { "x,y,z\r\n" });
        for (k, p) in points.iter().enumerate() {
            if k % 1000 == 0 {
                text.push_str("# a comment\n\n");
            }
            let line = if dim == 2 {
                format!("{},{}", p[0], p[1])
            } else {
                format!("{}, {} ,{}", p[0], p[1], p[2])
            };
            text.push_str(&line);
            text.push_str(if k % 2 == 0 { "\n" } else { "\r\n" });
        }
        let out = bezsolid_bounded(
            &[
                "eval",
                &format!("preset:{preset}"),
                "--points",
                "/dev/stdin",
            ],
            Feed::Once(text.into_bytes()),
            1024,
            Duration::from_secs(300),
        );
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        assert!(
            String::from_utf8(out.stdout).unwrap() == csv_in_memory(preset, &points),
            "{preset}: the rows differ"
        );
    }
}

#[test]
fn eval_of_a_million_points_fits_in_48_mib() {
    // Holding them took about 120 MB (points, text and rows); streaming takes about 15 MB of
    // address space.
    let out = bezsolid_bounded(
        &["eval", "preset:fig9", "--points", "/dev/stdin"],
        Feed::Once(b"0.25,0.75\n".repeat(1_000_000)),
        48,
        Duration::from_secs(300),
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let csv = String::from_utf8(out.stdout).unwrap();
    let mut lines = csv.lines();
    assert_eq!(lines.next(), Some("x,y,f,preimages"));
    let row = lines.next().unwrap();
    assert!(
        row.starts_with("0.25,0.75,") && row.ends_with(",1"),
        "{row}"
    );
    assert_eq!(lines.clone().count(), 999_999);
    assert!(lines.all(|l| l == row));
}

#[test]
fn eval_stops_at_a_bad_line_and_names_it() {
    let pts = scratch("bad-late.csv", "0.5,0.5\n0.25,0.25\n1\n0.75,0.75\n");
    let out_file = out_path("bad-late-out.csv");
    let out = bezsolid(&[
        "eval",
        "preset:fig9",
        "--points",
        pts.to_str().unwrap(),
        "-o",
        out_file.to_str().unwrap(),
    ]);
    let err = common::one_line_error(&out);
    assert!(
        err.ends_with("bad-late.csv: line 3: expected 2 coordinates, found 1"),
        "{err}"
    );
    // The rows before the bad line were written; none after it.
    let written = std::fs::read_to_string(out_file).unwrap();
    assert_eq!(written.lines().count(), 3, "{written}");
}

/// The R-function union as HyperFun writes it.
fn or(f1: f64, f2: f64) -> f64 {
    f1 + f2 + (f1 * f1 + f2 * f2).sqrt()
}

#[test]
fn eval_takes_trees_of_many_solids() {
    // (sphere ∪ box) moved by (1, 0, 0), blended with a torus: DESIGN §5's formulas, written out.
    let model = r#"{"format": "bezsolid", "version": 1, "solid": {"kind": "blend_union",
        "a0": 0.5, "a1": 1.0, "a2": 2.0, "of": [
        {"kind": "transform", "translate": [1, 0, 0], "solid": {"kind": "union", "of": [
            {"kind": "sphere", "center": [0, 0, 0], "radius": 1},
            {"kind": "box", "min": [-0.5, -0.5, -0.5], "max": [2, 0.5, 0.5]}]}},
        {"kind": "torus", "center": [0, 0, 1], "axis": "z", "major": 1.5, "minor": 0.25}]}}"#;
    let model = scratch("tree.bsolid.json", model);
    let pts: Vec<[f64; 3]> = (0..60)
        .map(|k| {
            let t = k as f64;
            [
                (t * 0.37).sin() * 2.5,
                (t * 0.91).cos() * 2.0,
                (t * 0.23).sin() * 1.5,
            ]
        })
        .collect();
    let csv: String = pts
        .iter()
        .map(|p| format!("{},{},{}\n", p[0], p[1], p[2]))
        .collect();
    let pts_path = scratch("tree.csv", &format!("x,y,z\n{csv}"));
    let got = rows(&bezsolid(&[
        "eval",
        model.to_str().unwrap(),
        "--points",
        pts_path.to_str().unwrap(),
    ]));
    assert_eq!(got.len(), pts.len());
    for (row, p) in got.iter().zip(&pts) {
        let [x, y, z] = *p;
        let q = [x - 1.0, y, z];
        let sphere = 1.0 - (q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
        let s = |v: f64, lo: f64, hi: f64| (v - lo) * (hi - v);
        let bx = and(
            and(s(q[0], -0.5, 2.0), s(q[1], -0.5, 0.5)),
            s(q[2], -0.5, 0.5),
        );
        let f1 = or(sphere, bx);
        let ring = (x * x + y * y).sqrt() - 1.5;
        let f2 = 0.0625 - ring * ring - (z - 1.0) * (z - 1.0);
        let want = or(f1, f2) + 0.5 / (1.0 + f1 * f1 + (f2 / 2.0) * (f2 / 2.0));
        assert!(
            (row[3] - want).abs() <= 1e-9 * want.abs().max(1.0),
            "{p:?}: {} vs {want}",
            row[3]
        );
        assert_eq!(row[4], 0.0, "no Bézier leaf, no preimages");
    }
    // A bad node is named by its path.
    let bad = scratch(
        "bad-tree.bsolid.json",
        r#"{"format": "bezsolid", "version": 1, "solid": {"kind": "union", "of": [
            {"kind": "sphere", "center": [0, 0, 0], "radius": 1},
            {"kind": "transform", "solid": {"kind": "sphere", "center": [0, 0, 0], "radius": 0}}]}}"#,
    );
    let out = bezsolid(&[
        "eval",
        bad.to_str().unwrap(),
        "--points",
        pts_path.to_str().unwrap(),
    ]);
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("solid.of[1].solid.radius"), "{err}");
}

#[test]
fn eval_piecewise_volume_matches_design_cells_clipped_on_the_outer_box_only() {
    // 2 × 1 × 3 cells of degree (1, 2, 1) over [−1, 1] × [0, 2] × [0, 3].
    let (cells, degree) = ([2usize, 1, 3], [1usize, 2, 1]);
    let dims: Vec<usize> = (0..3).map(|a| cells[a] * degree[a] + 1).collect();
    let (lo, hi) = ([-1.0, 0.0, 0.0], [1.0, 2.0, 3.0]);
    let xi = |i: usize, j: usize, k: usize| ((i * 5 + j * 3 + k * 7) % 6) as f64 * 0.4 - 0.9;
    let mut points = Vec::new();
    for i in 0..dims[0] {
        for j in 0..dims[1] {
            for k in 0..dims[2] {
                let at = [i, j, k];
                let x: Vec<f64> = (0..3)
                    .map(|a| lo[a] + (hi[a] - lo[a]) * at[a] as f64 / (dims[a] - 1) as f64)
                    .collect();
                points.push(format!("[{}, {}, {}, {}]", x[0], x[1], x[2], xi(i, j, k)));
            }
        }
    }
    let model = format!(
        r#"{{"format": "bezsolid", "version": 1, "solid": {{"kind": "piecewise", "cells": [2, 1, 3], "degree": [1, 2, 1], "points": [{}]}}}}"#,
        points.join(", ")
    );
    let model = scratch("piecewise.bsolid.json", &model);
    let queries = [
        [0.0, 1.0, 1.5],
        [-0.5, 0.3, 0.2],
        [0.7, 1.9, 2.5],
        [0.0, 1.0, 1.0],
        [1.5, 1.0, 1.0],
        [-0.2, -0.5, 3.2],
    ];
    let csv: String = queries
        .iter()
        .map(|p| format!("{},{},{}\n", p[0], p[1], p[2]))
        .collect();
    let pts = scratch("piecewise.csv", &csv);
    let got = rows(&bezsolid(&[
        "eval",
        model.to_str().unwrap(),
        "--points",
        pts.to_str().unwrap(),
    ]));
    assert_eq!(got.len(), queries.len());
    for (row, p) in got.iter().zip(&queries) {
        let t: Vec<f64> = (0..3).map(|a| (p[a] - lo[a]) / (hi[a] - lo[a])).collect();
        // The cell t falls in (the nearest outside), and the local parameter in it.
        let cell: Vec<usize> = (0..3)
            .map(|a| ((t[a] * cells[a] as f64).floor().max(0.0) as usize).min(cells[a] - 1))
            .collect();
        let u: Vec<f64> = (0..3)
            .map(|a| t[a] * cells[a] as f64 - cell[a] as f64)
            .collect();
        let mut s = 0.0;
        for i in 0..=degree[0] {
            for j in 0..=degree[1] {
                for k in 0..=degree[2] {
                    let g = [
                        cell[0] * degree[0] + i,
                        cell[1] * degree[1] + j,
                        cell[2] * degree[2] + k,
                    ];
                    s += b(degree[0], i, u[0])
                        * b(degree[1], j, u[1])
                        * b(degree[2], k, u[2])
                        * xi(g[0], g[1], g[2]);
                }
            }
        }
        // f = S_ξ & F_s, F_s = F_b(t_u) & F_b(t_v) & F_b(t_w) left to right.
        let want = and(s, and(and(fb(t[0]), fb(t[1])), fb(t[2])));
        assert!(
            (row[3] - want).abs() <= 1e-12 * want.abs().max(1.0),
            "{p:?}: {} against {want}",
            row[3]
        );
        let inside = t.iter().all(|x| (0.0..=1.0).contains(x));
        assert_eq!(row[4], f64::from(u8::from(inside)), "{p:?}: preimages");
    }
}
