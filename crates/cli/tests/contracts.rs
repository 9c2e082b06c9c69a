//! The contracts kept: model files and share links written by an earlier build (every preset, a
//! space-mapped patch, a patch that folds over itself, volumes, a free-form model with an imported
//! mesh, each of the paper's scripts), stored in `tests/contracts/` with what the command line
//! gave for them then: `eval` rows on a fixed grid of points, the statistics of contours and
//! meshes, free-form point classification, and each script's printed values and drawing. Every
//! one must open and give the same numbers, forever: a file or link once written never breaks.
//!
//! The fixtures were written once by `cargo test -p bezsolid --test contracts -- --ignored`
//! (which overwrites them: run it only to add a case, never to make a changed number pass).
//! Numbers are compared to a relative 1e-9 (a rewrite may round differently in the last bits);
//! counts and every other word exactly.

#![allow(clippy::unwrap_used)] // a test: a failed unwrap is a failed test

mod common;

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use bezsolid_core::esc::Example;
use bezsolid_core::esc::Op;
use bezsolid_core::model::{EscOperand, MeshSpec, ModelFile, ModelSolid};
use bezsolid_core::presets::Preset;
use bezsolid_core::{Solid2, Solid3};
use common::{Rng, bezsolid, out_path};

/// The fixtures' folder.
fn dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/contracts")
}

/// The models of the corpus, by name, as the earlier build wrote them.
fn models() -> Vec<(String, ModelFile)> {
    let mut out = Vec::new();
    for p in Preset::ALL {
        let file = match p.solid() {
            ModelSolid::Patch(s) => ModelFile::from_solid2(&s),
            ModelSolid::Volume(v) => ModelFile::from_solid3(&v),
        };
        out.push((format!("preset-{}", p.name()), file));
    }
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    // Fig. 9's patch with its inner points moved: a space mapping.
    let ModelSolid::Patch(fig9) = Preset::Fig9.solid() else {
        unreachable!()
    };
    let mut moved = fig9.clone();
    moved
        .set_point([1, 1], glam::DVec2::new(0.62, 0.41))
        .unwrap();
    moved
        .set_point([1, 2], glam::DVec2::new(0.55, 1.1))
        .unwrap();
    out.push(("space-mapped-patch".into(), ModelFile::from_solid2(&moved)));
    // A degree-(5, 5) patch whose control points are the regular grid's, shuffled: it folds over
    // itself everywhere.
    let mut spots: Vec<(f64, f64)> = (0..36)
        .map(|k| (f64::from(k / 6) / 5.0, f64::from(k % 6) / 5.0))
        .collect();
    for k in (1..spots.len()).rev() {
        let j = ((rng.unit() * (k + 1) as f64) as usize).min(k);
        spots.swap(k, j);
    }
    let mut folded =
        Solid2::regular([5, 5], glam::DVec2::ZERO, glam::DVec2::ONE, |[_, _]| 0.0).unwrap();
    for i in 0..6 {
        for j in 0..6 {
            let (x, y) = spots[i * 6 + j];
            folded.set_point([i, j], glam::DVec2::new(x, y)).unwrap();
            folded.set_xi([i, j], rng.unit() * 2.0 - 1.0).unwrap();
        }
    }
    out.push(("folded-patch".into(), ModelFile::from_solid2(&folded)));
    // A degree-(3, 3, 3) ball with its control points jittered: a space-mapped volume.
    let mut ball = Solid3::regular(
        [3, 3, 3],
        glam::DVec3::ZERO,
        glam::DVec3::ONE,
        |[i, j, k]| {
            let c = glam::DVec3::new(i as f64, j as f64, k as f64) / 3.0 - 0.5;
            0.8 - 2.0 * c.length_squared()
        },
    )
    .unwrap();
    for i in 0..4 {
        for j in 0..4 {
            for k in 0..4 {
                let p = glam::DVec3::new(i as f64, j as f64, k as f64) / 3.0;
                let jitter = glam::DVec3::new(rng.unit(), rng.unit(), rng.unit()) - 0.5;
                ball.set_point([i, j, k], p + 0.08 * jitter).unwrap();
            }
        }
    }
    out.push(("space-mapped-volume".into(), ModelFile::from_solid3(&ball)));
    // The blob minus an imported mesh (an octahedron), moved.
    let octahedron = MeshSpec {
        positions: vec![
            [0.8, 0.0, 0.0],
            [-0.8, 0.0, 0.0],
            [0.0, 0.8, 0.0],
            [0.0, -0.8, 0.0],
            [0.0, 0.0, 0.8],
            [0.0, 0.0, -0.8],
        ],
        triangles: vec![
            [0, 2, 4],
            [2, 1, 4],
            [1, 3, 4],
            [3, 0, 4],
            [2, 0, 5],
            [1, 2, 5],
            [3, 1, 5],
            [0, 3, 5],
        ],
    };
    out.push((
        "free-form-with-mesh".into(),
        ModelFile::from_esc(
            Some(Op::Difference),
            vec![
                EscOperand::example(Example::Blob, [0.0; 3]),
                EscOperand {
                    example: None,
                    mesh: Some(octahedron),
                    offset: [0.6, 0.1, 0.0],
                    ..EscOperand::default()
                },
            ],
        ),
    ));
    for s in bezsolid_plasm::scripts::EXAMPLES {
        out.push((
            format!("script-{}", s.id),
            ModelFile::from_plasm(&s.source()),
        ));
    }
    out
}

/// What the command line gives for `model` (a file or link), in the fixtures' text form.
fn outputs(name: &str, model: &str) -> String {
    let text = std::fs::read_to_string(if model.starts_with('#') || model.starts_with("http") {
        dir().join(format!("models/{name}.bsolid.json"))
    } else {
        PathBuf::from(model)
    })
    .unwrap();
    let kind: serde_json::Value = serde_json::from_str(&text).unwrap();
    let kind = kind["solid"]["kind"].as_str().unwrap().to_owned();
    let mut out = String::new();
    let run = |args: &[&str]| {
        let o = bezsolid(args);
        assert!(
            o.status.success(),
            "bezsolid {args:?}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        String::from_utf8(o.stdout).unwrap()
    };
    let points2 = dir().join("points2.csv");
    let points3 = dir().join("points3.csv");
    match kind.as_str() {
        "patch" => {
            writeln!(out, "# eval").unwrap();
            out += &run(&["eval", model, "--points", points2.to_str().unwrap()]);
            let svg = out_path(&format!("{name}.svg"));
            run(&["contour", model, "--res", "48", "-o", svg.to_str().unwrap()]);
            writeln!(out, "# contour --res 48").unwrap();
            out += &svg_stats(&std::fs::read_to_string(svg).unwrap());
        }
        "volume" => {
            writeln!(out, "# eval").unwrap();
            out += &run(&["eval", model, "--points", points3.to_str().unwrap()]);
            let obj = out_path(&format!("{name}.obj"));
            run(&["mesh", model, "--res", "16", "-o", obj.to_str().unwrap()]);
            writeln!(out, "# mesh --res 16").unwrap();
            out += &obj_stats(&std::fs::read_to_string(obj).unwrap());
        }
        "esc" => {
            writeln!(out, "# esc classify").unwrap();
            out += &run(&[
                "esc",
                "classify",
                model,
                "--points",
                points3.to_str().unwrap(),
            ]);
        }
        "plasm" => {
            writeln!(out, "# plasm").unwrap();
            out += &run(&["plasm", model]);
            let obj = out_path(&format!("{name}.obj"));
            run(&["plasm", model, "-o", obj.to_str().unwrap()]);
            writeln!(out, "# plasm -o obj").unwrap();
            out += &obj_stats(&std::fs::read_to_string(obj).unwrap());
        }
        other => panic!("no outputs for {other}"),
    }
    out
}

/// The counts of an OBJ's vertices, faces, lines and points, its bounds and (for closed
/// triangles) its enclosed volume.
fn obj_stats(obj: &str) -> String {
    let mut v: Vec<[f64; 3]> = Vec::new();
    let (mut faces, mut lines, mut points) = (Vec::new(), 0, 0);
    for line in obj.lines() {
        let mut w = line.split_whitespace();
        match w.next() {
            Some("v") => {
                let c: Vec<f64> = w.take(3).map(|t| t.parse().unwrap()).collect();
                v.push([c[0], c[1], c[2]]);
            }
            Some("f") => faces.push(
                w.map(|t| t.split('/').next().unwrap().parse::<usize>().unwrap() - 1)
                    .collect::<Vec<_>>(),
            ),
            Some("l") => lines += 1,
            Some("p") => points += 1,
            _ => {}
        }
    }
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in &v {
        for a in 0..3 {
            lo[a] = lo[a].min(p[a]);
            hi[a] = hi[a].max(p[a]);
        }
    }
    let mut volume = 0.0;
    for f in faces.iter().filter(|f| f.len() == 3) {
        let [a, b, c] = [v[f[0]], v[f[1]], v[f[2]]];
        volume += (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
            + a[2] * (b[0] * c[1] - b[1] * c[0]))
            / 6.0;
    }
    format!(
        "vertices {} faces {} lines {lines} points {points}\nbounds {lo:?} {hi:?}\nvolume {volume:e}\n",
        v.len(),
        faces.len()
    )
}

/// The counts of an SVG's paths and vertices and the bounds of its vertices.
fn svg_stats(svg: &str) -> String {
    let mut paths = 0;
    let mut xs = Vec::new();
    for piece in svg.split(" d=\"").skip(1) {
        paths += 1;
        let d = piece.split('"').next().unwrap();
        for t in d.split(|c: char| c.is_ascii_alphabetic() || c == ' ' || c == ',') {
            if let Ok(x) = t.parse::<f64>() {
                xs.push(x);
            }
        }
    }
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in xs.chunks(2).filter(|p| p.len() == 2) {
        for a in 0..2 {
            lo[a] = lo[a].min(p[a]);
            hi[a] = hi[a].max(p[a]);
        }
    }
    format!(
        "paths {paths} vertices {}\nbounds {lo:?} {hi:?}\n",
        xs.len() / 2
    )
}

/// Whether `got` says what `want` says: the same words, numbers within a relative 1e-9.
fn same(want: &str, got: &str) -> Result<(), String> {
    let split = |s: &str| -> Vec<String> {
        s.split(|c: char| c.is_whitespace() || c == ',' || c == '[' || c == ']')
            .filter(|t| !t.is_empty())
            .map(str::to_owned)
            .collect()
    };
    let (w, g) = (split(want), split(got));
    if w.len() != g.len() {
        return Err(format!("{} words against {}", g.len(), w.len()));
    }
    for (k, (a, b)) in w.iter().zip(&g).enumerate() {
        let close = match (a.parse::<f64>(), b.parse::<f64>()) {
            (Ok(x), Ok(y)) => x == y || (x - y).abs() <= 1e-9 * x.abs().max(y.abs()).max(1e-300),
            _ => a == b,
        };
        if !close {
            return Err(format!("word {k}: {b} where it was {a}"));
        }
    }
    Ok(())
}

#[test]
fn files_and_links_written_before_open_and_give_the_same_numbers() {
    let models = dir().join("models");
    let mut names: Vec<String> = std::fs::read_dir(&models)
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .filter_map(|n| n.strip_suffix(".bsolid.json").map(str::to_owned))
        .collect();
    names.sort();
    assert!(names.len() >= 15, "the corpus: {names:?}");
    let mut failures = Vec::new();
    for name in &names {
        let want = std::fs::read_to_string(dir().join(format!("expected/{name}.txt"))).unwrap();
        let file = models.join(format!("{name}.bsolid.json"));
        let link = std::fs::read_to_string(dir().join(format!("links/{name}.link"))).unwrap();
        for (how, model) in [
            ("file", file.to_str().unwrap().to_owned()),
            ("link", link.trim().to_owned()),
        ] {
            if let Err(e) = same(&want, &outputs(name, &model)) {
                failures.push(format!("{name} ({how}): {e}"));
            }
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

/// Writes the corpus with this build: only to add a case (see the module's docs).
#[test]
#[ignore = "writes the fixtures; run by hand to add a case"]
fn write_the_corpus() {
    let root = dir();
    for sub in ["models", "links", "expected"] {
        std::fs::create_dir_all(root.join(sub)).unwrap();
    }
    let mut points2 = String::new();
    for i in 0..=10 {
        for j in 0..=10 {
            writeln!(
                points2,
                "{},{}",
                f64::from(i) * 0.12 - 0.1,
                f64::from(j) * 0.12 - 0.1
            )
            .unwrap();
        }
    }
    std::fs::write(root.join("points2.csv"), points2).unwrap();
    // Across the presets' boxes ([-1, 1]³, the fish's [0, 3] × [-0.8, 0.8] × [-0.5, 0.5]) and the
    // unit cube.
    let mut points3 = String::new();
    for i in 0..=8 {
        for j in 0..=6 {
            for k in 0..=6 {
                let x = f64::from(i) * 0.525 - 1.1;
                let (y, z) = (f64::from(j) / 3.0 - 1.05, f64::from(k) / 3.0 - 0.95);
                writeln!(points3, "{x},{y},{z}").unwrap();
            }
        }
    }
    std::fs::write(root.join("points3.csv"), points3).unwrap();
    for (name, model) in models() {
        let file = root.join(format!("models/{name}.bsolid.json"));
        std::fs::write(&file, serde_json::to_string(&model).unwrap()).unwrap();
        let link = bezsolid(&["link", file.to_str().unwrap()]);
        assert!(link.status.success(), "{name}");
        std::fs::write(root.join(format!("links/{name}.link")), &link.stdout).unwrap();
        let text = outputs(&name, file.to_str().unwrap());
        std::fs::write(root.join(format!("expected/{name}.txt")), text).unwrap();
    }
}
