//! `bezsolid plasm`: the paper's scripts run, their OBJ is read back and checked against the
//! formulas they stand for (written out here), and a script travels through a model file and a
//! link unchanged. Bad scripts fail with their line and column.

#![allow(clippy::unwrap_used)] // a test: a failed unwrap is a failed test

mod common;

use bezsolid_core::mesh::{Format, Mesh};
use common::{bezsolid, out_path, scratch};

/// The objects of an OBJ file: vertices and the cells of each `o` group (indices from 0 within
/// the group), with the cell tag (`f`, `l` or `p`).
struct Object {
    vertices: Vec<[f64; 3]>,
    cells: Vec<(String, Vec<usize>)>,
}

fn read_obj(text: &str) -> Vec<Object> {
    let mut objects: Vec<Object> = Vec::new();
    let mut base = 0;
    let mut total = 0;
    for line in text.lines() {
        let mut words = line.split_whitespace();
        match words.next() {
            Some("o") => {
                base = total;
                objects.push(Object {
                    vertices: Vec::new(),
                    cells: Vec::new(),
                });
            }
            Some("v") => {
                let v: Vec<f64> = words.map(|w| w.parse().unwrap()).collect();
                objects
                    .last_mut()
                    .unwrap()
                    .vertices
                    .push([v[0], v[1], v[2]]);
                total += 1;
            }
            Some(tag @ ("f" | "l" | "p")) => {
                let cell: Vec<usize> = words
                    .map(|w| w.parse::<usize>().unwrap() - 1 - base)
                    .collect();
                let o = objects.last_mut().unwrap();
                assert!(cell.iter().all(|&i| i < o.vertices.len()), "{line}");
                o.cells.push((tag.to_string(), cell));
            }
            _ => {}
        }
    }
    objects
}

fn run_ok(args: &[&str]) -> String {
    let out = bezsolid(args);
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).unwrap()
}

fn bernstein(n: usize, i: usize, t: f64) -> f64 {
    let c = (0..i).fold(1.0, |c, k| c * (n - k) as f64 / (k + 1) as f64);
    c * t.powi(i as i32) * (1.0 - t).powi((n - i) as i32)
}

fn curve(points: &[[f64; 3]], t: f64) -> [f64; 3] {
    let n = points.len() - 1;
    let mut out = [0.0; 3];
    for (i, p) in points.iter().enumerate() {
        for d in 0..3 {
            out[d] += p[d] * bernstein(n, i, t);
        }
    }
    out
}

#[test]
fn script_4_4_writes_the_blended_surface_and_its_curves() {
    let obj = out_path("s44.obj");
    run_ok(&["plasm", "example:4.4", "-o", obj.to_str().unwrap()]);
    let objects = read_obj(&std::fs::read_to_string(&obj).unwrap());
    // The surface, then the four curves the example adds.
    assert_eq!(objects.len(), 5);
    let surface = &objects[0];
    assert_eq!((surface.vertices.len(), surface.cells.len()), (441, 800));
    assert!(surface.cells.iter().all(|(t, c)| t == "f" && c.len() == 3));
    let curves: [&[[f64; 3]]; 4] = [
        &[[0., 0., 0.], [10., 0., 0.]],
        &[[0., 2., 0.], [8., 3., 0.], [9., 2., 0.]],
        &[[0., 4., 1.], [7., 5., -1.], [8., 5., 1.], [12., 4., 0.]],
        &[[0., 6., 0.], [9., 6., 3.], [10., 6., -1.]],
    ];
    for i in 0..=20 {
        for j in 0..=20 {
            let (u1, u2) = (i as f64 / 20.0, j as f64 / 20.0);
            let mut want = [0.0; 3];
            for (k, c) in curves.iter().enumerate() {
                let p = curve(c, u1);
                for d in 0..3 {
                    want[d] += p[d] * bernstein(3, k, u2);
                }
            }
            let got = surface.vertices[i * 21 + j];
            assert!(
                (0..3).all(|d| (got[d] - want[d]).abs() < 1e-9),
                "{got:?} ≠ {want:?} at ({u1}, {u2})"
            );
        }
    }
    for (o, c) in objects[1..].iter().zip(curves) {
        assert_eq!((o.vertices.len(), o.cells.len()), (33, 32));
        assert!(o.cells.iter().all(|(t, c)| t == "l" && c.len() == 2));
        assert!((0..3).all(|d| (o.vertices[32][d] - c[c.len() - 1][d]).abs() < 1e-12));
    }
}

#[test]
fn script_3_1_arcs_are_on_the_unit_circle() {
    let obj = out_path("s31.obj");
    run_ok(&["plasm", "example:3.1", "-o", obj.to_str().unwrap()]);
    let objects = read_obj(&std::fs::read_to_string(&obj).unwrap());
    assert_eq!(objects.len(), 3);
    for o in &objects {
        assert_eq!((o.vertices.len(), o.cells.len()), (11, 10));
        for v in &o.vertices {
            assert!(
                (v[0].hypot(v[1]) - 1.0).abs() < 1e-12 && v[2] == 0.0,
                "{v:?}"
            );
        }
    }
}

#[test]
fn a_script_file_its_model_file_and_its_link_draw_the_same() {
    let script = "% a parabola %\nDEF SQR = ID * ID;\nMAP:(CONS:< S1, SQR ~ S1 >):(Domain:16);\n\
                  Chooze:<5,2>;\nDEF Pred = C:-:1;\nPred:3;\n";
    let path = scratch("parabola.psm", script);
    let link = run_ok(&["link", path.to_str().unwrap()]);
    let link = link.trim();
    assert!(link.contains("#v1."), "{link}");
    let from_file = out_path("file.obj");
    let from_link = out_path("link.obj");
    // Chooze is defined nowhere: the values before it print, then the error.
    let out = bezsolid(&["plasm", link, "-o", from_link.to_str().unwrap()]);
    assert!(!out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("line 4, column 1: unknown name `Chooze`"),
        "{stderr}"
    );
    assert!(!from_link.exists());
    // Without Chooze, the link and the file give the same OBJ.
    let fixed = script.replace("Chooze:<5,2>;\n", "");
    let path = scratch("parabola2.psm", &fixed);
    run_ok(&[
        "plasm",
        path.to_str().unwrap(),
        "-o",
        from_file.to_str().unwrap(),
    ]);
    let link = run_ok(&["link", path.to_str().unwrap()]);
    let printed = run_ok(&["plasm", link.trim(), "-o", from_link.to_str().unwrap()]);
    assert_eq!(printed, "line 5: 2\n");
    let (a, b) = (
        std::fs::read_to_string(&from_file).unwrap(),
        std::fs::read_to_string(&from_link).unwrap(),
    );
    assert_eq!(a, b);
    let objects = read_obj(&a);
    assert_eq!(objects[0].vertices[8], [0.5, 0.25, 0.0]);
    // The model file holding the script too.
    let model = scratch(
        "parabola.bsolid.json",
        &format!(
            "{{\"format\":\"bezsolid\",\"version\":1,\"solid\":{{\"kind\":\"plasm\",\"script\":{:?}}}}}",
            fixed
        ),
    );
    let from_model = out_path("model.obj");
    run_ok(&[
        "plasm",
        model.to_str().unwrap(),
        "-o",
        from_model.to_str().unwrap(),
    ]);
    assert_eq!(std::fs::read_to_string(&from_model).unwrap(), a);
    // Without -o, every value is printed.
    let printed = run_ok(&["plasm", path.to_str().unwrap()]);
    assert!(
        printed.starts_with("line 3: a complex of 16 segments on 17 points in 2D\n"),
        "{printed}"
    );
}

#[test]
fn bad_scripts_fail_with_their_place() {
    for (script, words) in [
        ("DEF a = <1, 2;\n", "line 1, column 14"),
        ("DEF f (n::IsReal) = f:(n + 1);\nf:0;\n", "nested more than"),
        (
            "MAP:(CONS:<S1, S2>):(Domain:10000 * Domain:10000);",
            "past the limit",
        ),
        (
            "1 + <1, 2>;",
            "line 1, column 3: `+` takes numbers or functions",
        ),
    ] {
        let path = scratch("bad.psm", script);
        let out = bezsolid(&[
            "plasm",
            path.to_str().unwrap(),
            "-o",
            out_path("bad.obj").to_str().unwrap(),
        ]);
        assert!(!out.status.success());
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(stderr.contains(words), "{script}: {stderr}");
    }
    // Geometry that has no triangles cannot be an STL.
    let out = bezsolid(&[
        "plasm",
        "example:3.3",
        "-o",
        out_path("arc.stl").to_str().unwrap(),
    ]);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("no triangles"));
    let out = bezsolid(&["plasm", "example:9.9"]);
    assert!(String::from_utf8_lossy(&out.stderr).contains("the examples are 3.1, 3.3"));
}

#[test]
fn solids_are_written_facing_outward() {
    // The unit cube, mirrored in z by its map: the domain's cells turn inside out, the files' faces
    // still point out (volume +1).
    let path = scratch(
        "mirrored.psm",
        "MAP:<S1, S2, K:0 - S3>:(interval:<0,1>:2 * interval:<0,1>:2 * interval:<0,1>:2);\n",
    );
    for name in ["cube.stl", "cube.ply", "cube.obj"] {
        let out = out_path(name);
        run_ok(&["plasm", path.to_str().unwrap(), "-o", out.to_str().unwrap()]);
        let bytes = std::fs::read(&out).unwrap();
        let raw = Format::detect(&bytes).parse(&bytes).unwrap();
        let mesh = Mesh {
            positions: raw.positions,
            normals: Vec::new(),
            triangles: raw.triangles,
        };
        assert!(
            (mesh.volume() - 1.0).abs() < 1e-6,
            "{name}: {}",
            mesh.volume()
        );
    }
}
