//! `bezsolid esc classify` and `esc bool` against the shapes the built-in examples approximate,
//! written out here: the PN surface of the icosphere lies within 1e-3 of the unit sphere and that
//! of the torus near `(√(x² + y²) − 1)² + z² = 0.4²`, so points farther than a margin from those
//! are classified by the formulas. Bad meshes fail with their reason.

#![allow(clippy::unwrap_used)] // a test: a failed unwrap is a failed test

mod common;

use common::{bezsolid, out_path, scratch, succeed};

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

/// The cube `[lo, hi]³` as an OBJ file of 12 triangles, counter-clockwise from outside.
fn cube_obj(lo: f64, hi: f64) -> String {
    let mut obj = String::new();
    for v in 0..8 {
        let [x, y, z] = [v & 1, (v >> 1) & 1, (v >> 2) & 1].map(|b| if b == 1 { hi } else { lo });
        obj.push_str(&format!("v {x} {y} {z}\n"));
    }
    for [a, b, c, d] in [
        [1, 3, 4, 2],
        [5, 6, 8, 7],
        [1, 2, 6, 5],
        [3, 7, 8, 4],
        [1, 5, 7, 3],
        [2, 4, 8, 6],
    ] {
        obj.push_str(&format!("f {a} {b} {c}\nf {a} {c} {d}\n"));
    }
    obj
}

#[test]
fn complements_and_expressions_of_many_solids_agree_with_the_set_operations() {
    let pts = points();
    let file = scratch("expr.csv", &csv(&pts));
    let file = file.to_str().unwrap();
    // A complement, written either way round.
    for args in [
        ["complement", "example:icosphere"],
        ["example:icosphere", "complement"],
    ] {
        let got = run(&[&["esc", "bool"][..], &args, &["--points", file]].concat());
        assert_eq!(got.len(), pts.len());
        for (p, &g) in pts.iter().zip(&got) {
            if sphere(*p).abs() > 0.02 {
                assert_eq!(g == 1, sphere(*p) < 0.0, "complement at {p:?}");
            }
        }
    }
    // Three solids, one of them a free-form model file that places a ball of radius 0.5 at
    // (1, 0, 0) by scale and offset, and one a mesh file.
    let small = scratch(
        "small-ball.bsolid.json",
        r#"{ "format": "bezsolid", "version": 1,
             "solid": { "kind": "esc", "operands": [
               { "example": "icosphere", "scale": [0.5, 0.5, 0.5], "offset": [1, 0, 0] }] } }"#,
    );
    let ball = |p: [f64; 3]| sphere([2.0 * (p[0] - 1.0), 2.0 * p[1], 2.0 * p[2]]) / 2.0;
    let cube_file = scratch("corner.obj", &cube_obj(-1.4, -0.2));
    // The cube [−1.4, −0.2]³, its edges sharp (creases).
    let corner = |p: [f64; 3]| -> Option<bool> {
        let d = p.iter().map(|c| (c + 0.8).abs()).fold(0.0, f64::max);
        if d < 0.59 {
            Some(true)
        } else if d > 0.61 {
            Some(false)
        } else {
            None
        }
    };
    let a = "A=example:icosphere".to_string();
    let b = format!("Ball={}", small.to_str().unwrap());
    let c = format!("c_1={}", cube_file.to_str().unwrap());
    let got = run(&[
        "esc",
        "expr",
        "!(A | Ball) - c_1 | A & Ball",
        &a,
        &b,
        &c,
        "--points",
        file,
    ]);
    assert_eq!(got.len(), pts.len());
    let mut compared = 0;
    for (p, &g) in pts.iter().zip(&got) {
        let (s, t) = (sphere(*p), ball(*p));
        let Some(k) = corner(*p) else { continue };
        if s.abs() > 0.02 && t.abs() > 0.02 {
            let (s, t) = (s > 0.0, t > 0.0);
            assert_eq!(g == 1, !(s || t || k) || (s && t), "at {p:?}");
            compared += 1;
        }
    }
    assert!(compared > 200, "only {compared} points compared");
}

#[test]
fn crease_angles_keep_edges_sharp_or_round_them() {
    let cube = scratch("unit-cube.obj", &cube_obj(-1.0, 1.0));
    let cube = cube.to_str().unwrap();
    let file = scratch("crease.csv", "1.2,0,0\n0,0,1.05\n0.99,0.99,0.99\n0,0,0\n");
    let file = file.to_str().unwrap();
    assert_eq!(
        run(&["esc", "classify", cube, "--points", file]),
        [0, 0, 1, 1]
    );
    let round = ["esc", "classify", cube, "--crease", "180", "--points", file];
    assert_eq!(
        run(&round),
        [1, 1, 1, 1],
        "every edge rounded bulges the faces"
    );
    let a = format!("A={cube}");
    let expr = ["esc", "expr", "A", &a, "--crease", "180", "--points", file];
    assert_eq!(run(&expr), [1, 1, 1, 1]);
    let out = common::bezsolid(&["esc", "classify", cube, "--crease", "200", "--points", file]);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("from 0 to 180, not 200"));
}

#[test]
fn bad_expressions_say_what_and_where() {
    let file = scratch("bad-expr.csv", "0,0,0\n");
    let file = file.to_str().unwrap();
    for (args, says) in [
        (vec!["A | B", "A=example:blob"], "no solid is named \"B\""),
        (
            vec!["A | (B", "A=example:blob", "B=example:torus"],
            "character 7",
        ),
        (vec!["A", "1A=example:blob"], "not NAME=SOLID"),
        (
            vec!["A", "A=example:blob", "A=example:torus"],
            "given twice",
        ),
        (vec!["A"], "no solids"),
        (vec!["A", "A=example:cube"], "no example `cube`"),
    ] {
        let out = common::bezsolid(&[&["esc", "expr"][..], &args, &["--points", file]].concat());
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            !out.status.success() && err.contains(says),
            "{args:?}: {err}"
        );
    }
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
    let out = succeed(&["link", model]);
    let link = String::from_utf8(out.stdout).unwrap();
    assert_eq!(
        run(&["esc", "classify", link.trim(), "--points", file]),
        got
    );
    // The result's surface as STL: parsed back, closed, with every vertex outside the torus
    // and inside the sphere (to the grid's and the PN surface's tolerance).
    let stl = out_path("diff.stl");
    succeed(&["mesh", model, "--res", "32", "-o", stl.to_str().unwrap()]);
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
    // A complement holds everything outside its solid: no mesh (it printed volume −3.97).
    let complement = scratch(
        "complement.bsolid.json",
        r#"{ "format": "bezsolid", "version": 1,
             "solid": { "kind": "esc", "operation": "complement",
                        "operands": [ { "example": "icosphere" } ] } }"#,
    );
    let out = bezsolid(&["mesh", complement.to_str().unwrap(), "--stats"]);
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("unbounded") && err.lines().count() == 1,
        "{err}"
    );
    assert!(out.stdout.is_empty());
}

/// The cube `[-1, 1]³` and, inside it, an octahedron of half-diagonal `reach` (its corners poke
/// through the cube's faces when `reach > 1`): vertices and 0-based triangles.
#[allow(clippy::type_complexity)]
fn cube_and_octahedron(reach: f64) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    let mut positions: Vec<[f64; 3]> = (0..8)
        .map(|v: u32| [0, 1, 2].map(|k| if v >> k & 1 == 1 { 1.0 } else { -1.0 }))
        .collect();
    let mut triangles = Vec::new();
    for [a, b, c, d] in [
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ] {
        triangles.extend([[a, b, c], [a, c, d]]);
    }
    for k in 0..3 {
        let mut p = [0.0; 3];
        p[k] = reach;
        positions.push(p);
        p[k] = -reach;
        positions.push(p);
    }
    for octant in 0..8u32 {
        let [x, y, z] = [0, 1, 2].map(|k| 8 + 2 * k + (octant >> k & 1));
        triangles.push(if octant.count_ones() % 2 == 0 {
            [x, y, z]
        } else {
            [x, z, y]
        });
    }
    (positions, triangles)
}

#[test]
fn an_inner_shell_crossing_its_outer_shell_is_refused() {
    let file = scratch("cross.csv", "0,0,0\n0.9,0.9,0.9\n");
    let file = file.to_str().unwrap();
    for (reach, crosses) in [(1.3, true), (0.9, false)] {
        let (positions, triangles) = cube_and_octahedron(reach);
        let mut obj = String::new();
        for [x, y, z] in &positions {
            obj.push_str(&format!("v {x} {y} {z}\n"));
        }
        for [a, b, c] in &triangles {
            obj.push_str(&format!("f {} {} {}\n", a + 1, b + 1, c + 1));
        }
        let obj = scratch(&format!("cube-octahedron-{reach}.obj"), &obj);
        let model = scratch(
            &format!("cube-octahedron-{reach}.bsolid.json"),
            &format!(
                r#"{{ "format": "bezsolid", "version": 1,
                     "solid": {{ "kind": "esc",
                                "operands": [ {{ "mesh": {{ "positions": {positions:?},
                                                           "triangles": {triangles:?} }} }} ] }} }}"#
            ),
        );
        for input in [obj.to_str().unwrap(), model.to_str().unwrap()] {
            let args = ["esc", "classify", input, "--points", file];
            if crosses {
                let out = bezsolid(&args);
                assert_eq!(out.status.code(), Some(1), "{input}");
                let err = String::from_utf8_lossy(&out.stderr);
                assert!(
                    err.contains("pieces 1 and 2") && err.contains("cross each other"),
                    "{input}: {err}"
                );
                assert_eq!(err.trim_end().lines().count(), 1, "{err}");
            } else {
                // The octahedron is a cavity: its centre is outside, the cube's corner region inside.
                assert_eq!(run(&args), vec![0, 1], "{input}");
            }
        }
    }
}
