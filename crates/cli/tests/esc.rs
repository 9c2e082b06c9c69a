//! `bezsolid esc classify` and `esc bool` against the shapes the built-in examples approximate,
//! written out here: the PN surface of the icosphere lies within 1e-3 of the unit sphere and that
//! of the torus near `(√(x² + y²) − 1)² + z² = 0.4²`, so points farther than a margin from those
//! are classified by the formulas. Bad meshes fail with their reason.

#![allow(clippy::unwrap_used)] // a test: a failed unwrap is a failed test

mod common;

use common::{bezsolid, out_path, scratch};

/// A deterministic spread of points in `[-1.6, 1.6]³`.
fn points() -> Vec<[f64; 3]> {
    let mut state = 0x2545_F491_4F6C_DD1Du64;
    let mut unit = move || {
        state ^= state >> 12;
        state ^= state << 25;
        state ^= state >> 27;
        (state.wrapping_mul(0x9E37_79B9_7F4A_7C15) >> 11) as f64 / (1u64 << 53) as f64
    };
    (0..400)
        .map(|_| [0, 1, 2].map(|_| -1.6 + 3.2 * unit()))
        .collect()
}

fn csv(points: &[[f64; 3]]) -> String {
    let mut s = String::from("x,y,z\n");
    for p in points {
        s.push_str(&format!("{},{},{}\n", p[0], p[1], p[2]));
    }
    s
}

/// Signed distance-like values: positive inside.
fn sphere(p: [f64; 3]) -> f64 {
    1.0 - (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt()
}

fn torus(p: [f64; 3]) -> f64 {
    let r = (p[0] * p[0] + p[1] * p[1]).sqrt() - 1.0;
    0.4 - (r * r + p[2] * p[2]).sqrt()
}

fn run(args: &[&str]) -> Vec<u8> {
    let out = bezsolid(args);
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout)
        .unwrap()
        .lines()
        .map(|l| match l {
            "0" => 0,
            "1" => 1,
            other => panic!("not 0 or 1: {other:?}"),
        })
        .collect()
}

#[test]
fn classify_agrees_with_the_sphere_and_the_torus() {
    let pts = points();
    let file = scratch("points.csv", &csv(&pts));
    let file = file.to_str().unwrap();
    for (example, shape) in [
        ("example:icosphere", sphere as fn([f64; 3]) -> f64),
        ("example:torus", torus),
    ] {
        let got = run(&["esc", "classify", example, "--points", file]);
        assert_eq!(got.len(), pts.len());
        let mut compared = 0;
        for (p, &g) in pts.iter().zip(&got) {
            let d = shape(*p);
            if d.abs() > 0.02 {
                assert_eq!(g == 1, d > 0.0, "{example} at {p:?}");
                compared += 1;
            }
        }
        assert!(compared > 350);
    }
}

#[test]
fn booleans_agree_with_the_set_operations() {
    let pts = points();
    let file = scratch("bool.csv", &csv(&pts));
    let file = file.to_str().unwrap();
    for (op, f) in [
        ("union", (|a, b| a || b) as fn(bool, bool) -> bool),
        ("intersection", |a, b| a && b),
        ("difference", |a, b| a && !b),
    ] {
        let got = run(&[
            "esc",
            "bool",
            "example:icosphere",
            op,
            "example:torus",
            "--points",
            file,
        ]);
        assert_eq!(got.len(), pts.len());
        let mut compared = 0;
        for (p, &g) in pts.iter().zip(&got) {
            let (a, b) = (sphere(*p), torus(*p));
            if a.abs() > 0.02 && b.abs() > 0.02 {
                assert_eq!(g == 1, f(a > 0.0, b > 0.0), "{op} at {p:?}");
                compared += 1;
            }
        }
        assert!(compared > 300, "{op}: only {compared} points compared");
    }
    // -o writes the same lines to a file.
    let out = out_path("bool-out.txt");
    let status = bezsolid(&[
        "esc",
        "bool",
        "example:icosphere",
        "union",
        "example:torus",
        "--points",
        file,
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(status.status.success());
    assert_eq!(
        std::fs::read_to_string(out).unwrap().lines().count(),
        pts.len()
    );
}

#[test]
fn mesh_files_are_read_and_bad_ones_refused() {
    let fixtures = concat!(env!("CARGO_MANIFEST_DIR"), "/../core/tests/fixtures/mesh/");
    let file = scratch("two.csv", "0.5,0.5,0.5\n5,5,5\n");
    let file = file.to_str().unwrap();
    // The cube fixtures span [0, 1]³: the centre is inside, a far point outside.
    for cube in ["cube.obj", "cube.ply"] {
        let got = run(&[
            "esc",
            "classify",
            &format!("{fixtures}{cube}"),
            "--points",
            file,
        ]);
        assert_eq!(got, vec![1, 0], "{cube}");
    }
    for (name, says) in [
        ("open.obj", "open edge"),
        ("nonmanifold.obj", "shared by more than two triangles"),
        ("flipped.obj", "inconsistent"),
        ("degenerate.obj", "degenerate"),
        ("truncated.stl", "truncated"),
        (
            "truncated_ascii.stl",
            "line 18: the file ends in the middle of a facet",
        ),
        ("garbage.bin", "truncated or damaged"),
        ("bad_index.obj", "index"),
        ("nan.obj", "finite"),
        ("no-such-file.obj", "cannot read"),
    ] {
        let out = bezsolid(&[
            "esc",
            "classify",
            &format!("{fixtures}{name}"),
            "--points",
            file,
        ]);
        assert_eq!(out.status.code(), Some(1), "{name}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains(says), "{name}: {err}");
        assert!(!err.contains("panicked"), "{name}: {err}");
    }
    for (args, says) in [
        (
            vec![
                "esc",
                "bool",
                "example:icosphere",
                "xor",
                "example:torus",
                "--points",
                file,
            ],
            "unknown operation",
        ),
        (
            vec!["esc", "classify", "example:cube", "--points", file],
            "no example",
        ),
        (vec!["esc", "frobnicate"], "unknown command"),
        (vec!["esc", "classify", "example:torus"], "--points"),
    ] {
        let out = bezsolid(&args);
        assert_eq!(out.status.code(), Some(1), "{args:?}");
        assert!(
            String::from_utf8_lossy(&out.stderr).contains(says),
            "{args:?}"
        );
    }
}

#[test]
fn free_form_model_files_and_links_classify_and_mesh() {
    let model = scratch(
        "diff.bsolid.json",
        r#"{ "format": "bezsolid", "version": 1,
             "solid": { "kind": "esc", "operation": "difference",
                        "operands": [ { "example": "icosphere" },
                                      { "example": "torus", "offset": [0.0, 0.0, 0.5] } ] } }"#,
    );
    let model = model.to_str().unwrap();
    let pts = points();
    let file = scratch("model-points.csv", &csv(&pts));
    let file = file.to_str().unwrap();
    let got = run(&["esc", "classify", model, "--points", file]);
    assert_eq!(got.len(), pts.len());
    let shifted = |p: [f64; 3]| torus([p[0], p[1], p[2] - 0.5]);
    let mut compared = 0;
    for (p, &g) in pts.iter().zip(&got) {
        let (a, b) = (sphere(*p), shifted(*p));
        if a.abs() > 0.02 && b.abs() > 0.02 {
            assert_eq!(g == 1, a > 0.0 && b <= 0.0, "at {p:?}");
            compared += 1;
        }
    }
    assert!(compared > 300, "only {compared} points compared");
    // Its share link gives the same answers.
    let out = bezsolid(&["link", model]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let link = String::from_utf8(out.stdout).unwrap();
    assert_eq!(
        run(&["esc", "classify", link.trim(), "--points", file]),
        got
    );
    // The result's surface as STL: parsed back, closed, with every vertex outside the torus
    // and inside the sphere (to the grid's and the PN surface's tolerance).
    let stl = out_path("diff.stl");
    let out = bezsolid(&["mesh", model, "--res", "32", "-o", stl.to_str().unwrap()]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let bytes = std::fs::read(&stl).unwrap();
    let count = u32::from_le_bytes(bytes[80..84].try_into().unwrap()) as usize;
    assert_eq!(bytes.len(), 84 + 50 * count);
    // The core's reader welds the corners and refuses anything but a closed 2-manifold.
    let mesh = bezsolid_core::mesh::read(&bytes).expect("a closed mesh");
    assert_eq!(mesh.triangles.len(), count);
    assert!(count > 500);
    for p in &mesh.positions {
        let p = p.to_array();
        assert!(sphere(p) > -0.01 && shifted(p) < 0.01, "{p:?}");
    }
    // A Bézier command refuses it with the reason.
    let out = bezsolid(&["eval", model, "--points", file]);
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("free-form"));
}
