//! `bezsolid mesh` and `bezsolid hf` end to end: the binary writes files, which are parsed back here
//! (with parsers written independently of the writers) and checked.

#![allow(clippy::unwrap_used)] // a test: a failed unwrap is a failed test
mod common;
use common::{bezsolid, out_path, scratch, succeed};

use bezsolid_core::mesh::Mesh;
use glam::DVec3;

fn read_obj(text: &str) -> Mesh {
    let mut mesh = Mesh::default();
    for line in text.lines() {
        let w: Vec<&str> = line.split_whitespace().collect();
        let vec3 = || DVec3::from_array(std::array::from_fn(|k| w[k + 1].parse().unwrap()));
        match w.first() {
            Some(&"v") => mesh.positions.push(vec3()),
            Some(&"vn") => mesh.normals.push(vec3()),
            Some(&"f") => mesh.triangles.push(std::array::from_fn(|k| {
                w[k + 1].split('/').next().unwrap().parse::<u32>().unwrap() - 1
            })),
            _ => {}
        }
    }
    mesh
}

#[test]
fn every_preset_meshes_to_a_closed_surface_of_its_genus() {
    for (preset, euler) in [("blob", 2), ("ring", 0), ("fish", 2)] {
        let path = out_path(&format!("{preset}.obj"));
        succeed(&[
            "mesh",
            &format!("preset:{preset}"),
            "--res",
            "40",
            "-o",
            path.to_str().unwrap(),
        ]);
        let mesh = read_obj(&std::fs::read_to_string(&path).unwrap());
        assert!(mesh.triangle_count() > 100);
        mesh.check_closed_manifold().unwrap();
        assert_eq!(mesh.euler_characteristic(), euler, "{preset}");
        assert!(mesh.volume() > 0.0);
        assert_eq!(mesh.normals.len(), mesh.positions.len());
    }
}

#[test]
fn threads_write_the_same_file_as_one_thread() {
    let tree = scratch(
        "threads-tree.bsolid.json",
        r#"{"format":"bezsolid","version":1,"solid":{"kind":"union","of":[
            {"kind":"sphere","center":[0,0,0],"radius":1},
            {"kind":"box","min":[0.5,0.5,0.5],"max":[1.5,1.5,1.5]}]}}"#,
    );
    for (name, model) in [("blob", "preset:blob"), ("tree", tree.to_str().unwrap())] {
        let mut files = Vec::new();
        for threads in ["1", "2", "3"] {
            let path = out_path(&format!("{name}-threads-{threads}.ply"));
            succeed(&[
                "mesh",
                model,
                "--res",
                "48",
                "--threads",
                threads,
                "-o",
                path.to_str().unwrap(),
            ]);
            files.push(std::fs::read(&path).unwrap());
        }
        assert!(files[0].len() > 1000, "{name}");
        assert!(
            files.iter().all(|f| *f == files[0]),
            "{name}: the files differ"
        );
    }
}

#[test]
fn stl_and_ply_hold_the_same_triangles_as_obj() {
    let obj = out_path("blob16.obj");
    let stl = out_path("blob16.stl");
    let ply = out_path("blob16.PLY");
    for p in [&obj, &stl, &ply] {
        succeed(&[
            "mesh",
            "preset:blob",
            "--res",
            "16",
            "-o",
            p.to_str().unwrap(),
        ]);
    }
    let mesh = read_obj(&std::fs::read_to_string(&obj).unwrap());
    let stl = std::fs::read(&stl).unwrap();
    let count = u32::from_le_bytes(stl[80..84].try_into().unwrap()) as usize;
    assert_eq!(count, mesh.triangle_count());
    assert_eq!(stl.len(), 84 + 50 * count);
    let f = |at: usize| f32::from_le_bytes(stl[at..at + 4].try_into().unwrap());
    for t in 0..count {
        for v in 0..3 {
            let p = mesh.positions[mesh.triangles[t][v] as usize].as_vec3();
            let at = 84 + 50 * t + 12 + 12 * v;
            assert_eq!([f(at), f(at + 4), f(at + 8)], p.to_array());
        }
    }
    let ply = std::fs::read(&ply).unwrap();
    let header_end = ply.windows(11).position(|w| w == b"end_header\n").unwrap() + 11;
    let header = std::str::from_utf8(&ply[..header_end]).unwrap();
    assert!(header.contains(&format!("element vertex {}", mesh.positions.len())));
    assert!(header.contains(&format!("element face {}", count)));
    assert_eq!(
        ply.len() - header_end,
        24 * mesh.positions.len() + 13 * count
    );
}

#[test]
fn mesh_refuses_bad_input_with_a_message() {
    let out_obj = out_path("bad.obj");
    let o = out_obj.to_str().unwrap();
    for (args, needle) in [
        (
            vec!["mesh", "preset:blob", "-o", "x.xyz"],
            ".stl, .obj or .ply",
        ),
        (
            vec!["mesh", "preset:blob", "--res", "0", "-o", o],
            "--res 0",
        ),
        (
            vec!["mesh", "preset:blob", "--res", "99999", "-o", o],
            "--res 99999",
        ),
        (
            vec!["mesh", "preset:blob", "--accuracy", "nan", "-o", o],
            "accuracy",
        ),
        (vec!["mesh", "preset:fig9", "-o", o], "volume"),
        (vec!["mesh", "preset:whale", "-o", o], "no preset"),
        (vec!["mesh", "preset:blob"], "-o"),
        (
            vec!["mesh", "preset:blob", "--threads", "0", "-o", o],
            "--threads 0",
        ),
    ] {
        let out = bezsolid(&args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{args:?}");
        assert!(err.contains(needle), "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{err}");
    }
}

#[test]
fn hf_writes_a_hyperfun_model() {
    for preset in ["fig9", "fish"] {
        let path = out_path(&format!("{preset}.hf"));
        succeed(&[
            "hf",
            &format!("preset:{preset}"),
            "-o",
            path.to_str().unwrap(),
        ]);
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(text.contains("my_model(x[3], a[1])"));
        assert!(text.trim_end().ends_with('}'));
        assert_eq!(text.contains("hfBezierVolume"), preset == "fish");
    }
}

/// A space mapping: the degree-2 ball with its top slice lifted and one corner pulled. `mesh` writes a
/// closed surface whose vertices are on `f = 0` as the inverse map (Bézier clipping) sees it, and
/// `contour` draws a moved patch.
#[test]
fn mapped_models_mesh_and_contour() {
    let c = [0.25, -0.25, 0.25];
    let mut points = Vec::new();
    for i in 0..3 {
        for j in 0..3 {
            for k in 0..3 {
                let (x, y) = (i as f64 / 2.0, j as f64 / 2.0);
                let mut z = k as f64 / 2.0;
                if k == 2 {
                    z += 0.3;
                }
                let x = if (i, j, k) == (0, 0, 0) { -0.2 } else { x };
                let xi = 0.16 - c[i] - c[j] - c[k];
                points.push(format!("[{x}, {y}, {z}, {xi}]"));
            }
        }
    }
    let model = format!(
        r#"{{"format": "bezsolid", "version": 1, "solid": {{"kind": "volume", "degree": [2, 2, 2], "points": [{}]}}}}"#,
        points.join(", ")
    );
    let model_path = out_path("mapped.bsolid.json");
    std::fs::write(&model_path, &model).unwrap();
    let obj = out_path("mapped.obj");
    succeed(&[
        "mesh",
        model_path.to_str().unwrap(),
        "--res",
        "24",
        "-o",
        obj.to_str().unwrap(),
    ]);
    let mesh = read_obj(&std::fs::read_to_string(&obj).unwrap());
    mesh.check_closed_manifold().unwrap();
    assert_eq!(mesh.euler_characteristic(), 2);
    let file: bezsolid_core::model::ModelFile = serde_json::from_str(&model).unwrap();
    let bezsolid_core::model::ModelSolid::Volume(solid) = file.to_solid().unwrap() else {
        panic!("a volume");
    };
    assert!(solid.inverse().is_some());
    let (_, hi) = solid.domain();
    assert!((hi.z - 1.3).abs() < 1e-12);
    let mut top = f64::NEG_INFINITY;
    for p in &mesh.positions {
        let v = solid.evaluate(*p, bezsolid_core::inverse::Method::Clipping);
        // OBJ keeps 17 significant digits; the vertex was on f = 0 to 1e-9 before it was written.
        assert!(v.f.abs() < 1e-8, "f = {} at {p}", v.f);
        top = top.max(p.z);
    }
    // The ball was stretched upwards with the lifted slice.
    assert!(top > 0.95, "{top}");

    let patch = r#"{"format":"bezsolid","version":1,"solid":{"kind":"patch","degree":[2,2],"points":[[0,0,-1],[0,0.5,0.25],[0,1,-1],[0.5,0,0.25],[0.8,0.6,1],[0.5,1,0.25],[1,0,-1],[1,0.5,0.25],[1.2,1.1,-1]]}}"#;
    let patch_path = out_path("mapped-patch.bsolid.json");
    std::fs::write(&patch_path, patch).unwrap();
    let svg = out_path("mapped.svg");
    succeed(&[
        "contour",
        patch_path.to_str().unwrap(),
        "--res",
        "64",
        "-o",
        svg.to_str().unwrap(),
    ]);
    let text = std::fs::read_to_string(&svg).unwrap();
    assert_eq!(text.matches("<path").count(), 1, "one loop: {text}");
}

/// Trees of many solids: a 3D tree meshes closed within its own bounds, a half-space needs `--box`
/// and is cut by it, a 2D tree draws its contour.
#[test]
fn trees_mesh_and_contour() {
    let tree = scratch(
        "tree3.bsolid.json",
        r#"{"format": "bezsolid", "version": 1, "solid": {"kind": "blend_union", "a0": 0.3,
            "a1": 1, "a2": 1, "of": [
            {"kind": "sphere", "center": [0, 0, 0], "radius": 1},
            {"kind": "transform", "rotate": [0, 0, 30], "translate": [1, 0, 0],
             "solid": {"kind": "box", "min": [-0.3, -1, -0.3], "max": [0.3, 1, 0.3]}}]}}"#,
    );
    let obj = out_path("tree3.obj");
    let run = |args: &[&str]| {
        let out = bezsolid(args);
        assert!(
            out.status.success(),
            "{args:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
    };
    run(&[
        "mesh",
        tree.to_str().unwrap(),
        "--res",
        "48",
        "-o",
        obj.to_str().unwrap(),
    ]);
    let mesh = read_obj(&std::fs::read_to_string(&obj).unwrap());
    mesh.check_closed_manifold().unwrap();
    assert_eq!(mesh.euler_characteristic(), 2, "one blob, no hole");
    // The volume, against a Monte Carlo estimate from `eval` in the cube [-2.5, 2.5]³.
    let v = mesh.volume();
    let mut state = 0x9E37_79B9_7F4A_7C15u64;
    let mut next = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64 * 5.0 - 2.5
    };
    let n = 100_000;
    let csv: String = (0..n)
        .map(|_| format!("{},{},{}\n", next(), next(), next()))
        .collect();
    let pts = out_path("tree3-points.csv");
    std::fs::write(&pts, csv).unwrap();
    let out = bezsolid(&[
        "eval",
        tree.to_str().unwrap(),
        "--points",
        pts.to_str().unwrap(),
    ]);
    assert!(out.status.success());
    let inside = String::from_utf8(out.stdout)
        .unwrap()
        .lines()
        .skip(1)
        .filter(|l| l.split(',').nth(3).unwrap().parse::<f64>().unwrap() > 0.0)
        .count();
    let mc = 125.0 * inside as f64 / f64::from(n);
    assert!((v - mc).abs() < 0.05 * mc, "mesh {v}, Monte Carlo {mc}");

    let half = scratch(
        "half.bsolid.json",
        r#"{"format": "bezsolid", "version": 1, "solid": {"kind": "halfspace", "normal": [0, 0, 1], "offset": 0.5}}"#,
    );
    let out = bezsolid(&["mesh", half.to_str().unwrap(), "-o", obj.to_str().unwrap()]);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("--box"));
    run(&[
        "mesh",
        half.to_str().unwrap(),
        "--res",
        "16",
        "--box",
        "-1,-1,-1,1,1,1",
        "-o",
        obj.to_str().unwrap(),
    ]);
    let mesh = read_obj(&std::fs::read_to_string(&obj).unwrap());
    mesh.check_closed_manifold().unwrap();
    assert!(
        (mesh.volume() - 6.0).abs() < 0.05,
        "z below 0.5 in the box: {}",
        mesh.volume()
    );

    // HyperFun: the tree with HyperFun's own blend (its numbers are checked against eval by the
    // core's test interpreter).
    let hf = out_path("tree3.hf");
    run(&["hf", tree.to_str().unwrap(), "-o", hf.to_str().unwrap()]);
    let text = std::fs::read_to_string(&hf).unwrap();
    assert!(
        text.contains("my_model(x[3], a[1])") && text.contains("hfBlendUni("),
        "{text}"
    );

    let plane = scratch(
        "tree2.bsolid.json",
        r#"{"format": "bezsolid", "version": 1, "solid": {"kind": "difference", "of": [
            {"kind": "circle", "center": [0, 0], "radius": 1},
            {"kind": "circle", "center": [0, 0], "radius": 0.5}]}}"#,
    );
    let svg = out_path("tree2.svg");
    run(&[
        "contour",
        plane.to_str().unwrap(),
        "--res",
        "64",
        "-o",
        svg.to_str().unwrap(),
    ]);
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(text.contains("<svg"), "{text}");
    let loops = text.matches("<path").count()
        + text.matches("<polygon").count()
        + text.matches("<polyline").count();
    assert!(loops >= 2, "two loops: {text}");
}

/// The signed area the closed `loops` enclose (the shoelace sum over each).
fn enclosed_area(loops: &[Vec<[f64; 2]>]) -> f64 {
    loops
        .iter()
        .map(|l| {
            (0..l.len())
                .map(|k| {
                    let (a, b) = (l[k], l[(k + 1) % l.len()]);
                    a[0] * b[1] - a[1] * b[0]
                })
                .sum::<f64>()
                / 2.0
        })
        .sum()
}

/// The closed loops of a contours SVG, parsed back: `<path d="Mx,y Lx,y …Z">`.
fn svg_loops(text: &str) -> Vec<Vec<[f64; 2]>> {
    text.split("d=\"")
        .skip(1)
        .filter_map(|rest| {
            let d = &rest[..rest.find('"')?];
            let closed = d.ends_with('Z');
            let points: Vec<[f64; 2]> = d
                .trim_end_matches('Z')
                .split_whitespace()
                .map(|p| {
                    let (x, y) = p[1..].split_once(',').unwrap();
                    [x.parse().unwrap(), y.parse().unwrap()]
                })
                .collect();
            closed.then_some(points)
        })
        .collect()
}

/// `contour --section`: the true section of the blob preset by z = 0.2, written as SVG and read
/// back, has the area of the cut that the paper's formula, written out here, gives on the plane;
/// a plane past the model and a bad plane are refused with what is wrong.
#[test]
fn sections_of_volumes_have_the_area_of_the_cut() {
    let svg = out_path("blob-section.svg");
    succeed(&[
        "contour",
        "preset:blob",
        "--section",
        "z=0.2",
        "--res",
        "128",
        "-o",
        svg.to_str().unwrap(),
    ]);
    let loops = svg_loops(&std::fs::read_to_string(&svg).unwrap());
    assert_eq!(loops.len(), 1);
    let area = enclosed_area(&loops);
    // The blob: degree (2, 2, 2) over [−1, 1]³, ξ = 1 at the centre, −1 at the corners, 0.25
    // elsewhere; f = S_ξ & F_b(t_u) & F_b(t_v) & F_b(t_w).
    let b = |i: usize, t: f64| [(1.0 - t) * (1.0 - t), 2.0 * t * (1.0 - t), t * t][i];
    let and = |a: f64, b: f64| a + b - (a * a + b * b).sqrt();
    let f = |p: [f64; 3]| {
        let t = p.map(|x| (x + 1.0) / 2.0);
        let mut s = 0.0;
        for i in 0..3 {
            for j in 0..3 {
                for k in 0..3 {
                    let xi = match (i, j, k) {
                        (1, 1, 1) => 1.0,
                        (0 | 2, 0 | 2, 0 | 2) => -1.0,
                        _ => 0.25,
                    };
                    s += b(i, t[0]) * b(j, t[1]) * b(k, t[2]) * xi;
                }
            }
        }
        let strip = |t: f64| t * (1.0 - t);
        and(s, and(and(strip(t[0]), strip(t[1])), strip(t[2])))
    };
    let n = 400;
    let inside = (0..n * n)
        .filter(|k| {
            let (x, y) = ((k % n) as f64 + 0.5, (k / n) as f64 + 0.5);
            f([x / n as f64 * 2.0 - 1.0, y / n as f64 * 2.0 - 1.0, 0.2]) > 0.0
        })
        .count();
    let want = 4.0 * inside as f64 / (n * n) as f64;
    assert!(
        (area - want).abs() < 0.01 * want,
        "section area {area}, on the plane {want}"
    );
    for (plane, says) in [
        (
            "z=3",
            "the plane z = 3 misses the model: it fills z from -1 to 1",
        ),
        ("w=0", "a plane is x=C, y=C or z=C"),
        ("z=inf", "a plane is x=C, y=C or z=C"),
    ] {
        let out = bezsolid(&[
            "contour",
            "preset:blob",
            "--section",
            plane,
            "-o",
            "/dev/null",
        ]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            !out.status.success() && err.contains(says),
            "{plane}: {err}"
        );
    }
    let out = bezsolid(&[
        "contour",
        "preset:fig9",
        "--section",
        "x=0.5",
        "-o",
        "/dev/null",
    ]);
    assert!(String::from_utf8_lossy(&out.stderr).contains("cuts 3D models"));
}

/// `hf --height H`: a 2D model as the extrusion 0 ≤ z ≤ H (its last line intersects the slab's
/// strip); a 3D model and a bad height are refused.
#[test]
fn hf_extrudes_2d_models_to_a_slab() {
    let out_file = out_path("fig9-slab.hf");
    succeed(&[
        "hf",
        "preset:fig9",
        "--height",
        "0.25",
        "-o",
        out_file.to_str().unwrap(),
    ]);
    let text = std::fs::read_to_string(&out_file).unwrap();
    assert!(text.contains("& (x[3] * (0.25 - x[3]));"), "{text}");
    assert!(text.contains("from z = 0 to z = 0.25"), "{text}");
    for (args, says) in [
        (
            &["hf", "preset:fish", "--height", "1", "-o", "/dev/null"][..],
            "extrudes 2D models",
        ),
        (
            &["hf", "preset:fig9", "--height", "0", "-o", "/dev/null"][..],
            "positive number",
        ),
    ] {
        let out = bezsolid(args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            !out.status.success() && err.contains(says),
            "{args:?}: {err}"
        );
    }
}

/// The `name: numbers` lines of a `--stats` output, by name.
fn stats_lines(stdout: &[u8]) -> std::collections::HashMap<String, Vec<f64>> {
    String::from_utf8_lossy(stdout)
        .lines()
        .filter_map(|line| {
            let (name, values) = line.split_once(':')?;
            let values = values.split_whitespace().map(|v| v.parse().unwrap());
            Some((name.to_string(), values.collect()))
        })
        .collect()
}

/// Runs `bezsolid` with `args`, which must succeed, and gives its `--stats` lines.
fn stats_of(args: &[&str]) -> std::collections::HashMap<String, Vec<f64>> {
    let out = bezsolid(args);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    stats_lines(&out.stdout)
}

/// `mesh --stats` and `contour --stats` print what the mesh and the contour measure, on stdout,
/// with or without a file written: a ball of radius 1 minus a box has the ball's volume less the
/// box's part, a ring of radii 1 and 0.5 its area and both circles' length, each near the
/// formula at a fine resolution and exact for the mesh written beside it.
#[test]
fn meshes_and_contours_are_measured_on_stdout() {
    let tree = scratch(
        "stats-tree.bsolid.json",
        r#"{"format":"bezsolid","version":1,"solid":{"kind":"difference","of":[
            {"kind":"sphere","center":[0,0,0],"radius":1},
            {"kind":"box","min":[0,0,0],"max":[2,2,2]}]}}"#,
    );
    let path = out_path("stats-tree.obj");
    let stats = stats_of(&[
        "mesh",
        tree.to_str().unwrap(),
        "--res",
        "64",
        "--stats",
        "-o",
        path.to_str().unwrap(),
    ]);
    let mesh = read_obj(&std::fs::read_to_string(&path).unwrap());
    let (volume, area) = (stats["volume"][0], stats["area"][0]);
    // The OBJ's coordinates are rounded: the file's mesh agrees to its digits.
    assert!((volume - mesh.volume()).abs() < 1e-6 * volume, "{volume}");
    assert!((area - mesh.area()).abs() < 1e-6 * area, "{area}");
    let ball = 4.0 / 3.0 * std::f64::consts::PI;
    assert!((volume - ball * 7.0 / 8.0).abs() < 0.01 * ball, "{volume}");
    let sphere = 4.0 * std::f64::consts::PI;
    let expected_area = sphere * 7.0 / 8.0 + 3.0 * std::f64::consts::PI / 4.0;
    assert!(
        (area - expected_area).abs() < 0.02 * expected_area,
        "{area}"
    );
    let bbox = &stats["bbox"];
    assert_eq!(bbox.len(), 6);
    for (k, want) in [-1.0, -1.0, -1.0, 1.0, 1.0, 1.0].into_iter().enumerate() {
        assert!((bbox[k] - want).abs() < 0.02, "{bbox:?}");
    }
    // Without -o: only the measurements.
    let stats = stats_of(&["mesh", "preset:blob", "--res", "24", "--stats"]);
    assert!(stats["volume"][0] > 0.0 && stats["area"][0] > 0.0);
    // And without either, the error it always gave.
    let out = bezsolid(&["mesh", "preset:blob"]);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("-o OUT.stl"));

    let plane = scratch(
        "stats-ring.bsolid.json",
        r#"{"format": "bezsolid", "version": 1, "solid": {"kind": "difference", "of": [
            {"kind": "circle", "center": [0, 0], "radius": 1},
            {"kind": "circle", "center": [0, 0], "radius": 0.5}]}}"#,
    );
    let stats = stats_of(&[
        "contour",
        plane.to_str().unwrap(),
        "--res",
        "256",
        "--stats",
    ]);
    let pi = std::f64::consts::PI;
    let (area, perimeter) = (stats["area"][0], stats["perimeter"][0]);
    assert!((area - pi * 0.75).abs() < 1e-3 * pi, "{area}");
    assert!((perimeter - 3.0 * pi).abs() < 1e-3 * pi, "{perimeter}");
    // A patch solid: its area is the one its SVG's loops enclose.
    let svg = out_path("stats-fig9.svg");
    let stats = stats_of(&[
        "contour",
        "preset:fig9",
        "--res",
        "128",
        "--stats",
        "-o",
        svg.to_str().unwrap(),
    ]);
    let loops = svg_loops(&std::fs::read_to_string(&svg).unwrap());
    assert!(!loops.is_empty());
    let shoelace = enclosed_area(&loops);
    assert!(
        (stats["area"][0] - shoelace.abs()).abs() < 1e-3 * shoelace.abs(),
        "{} {shoelace}",
        stats["area"][0]
    );
}

/// `mesh -o OUT.3mf` and `-o OUT.glb`: the containers hold the mesh the OBJ holds (its triangle
/// and vertex counts), the 3MF in millimetres with the preset's name, the GLB in metres with +Y
/// up (its bounds the OBJ's, turned).
#[test]
fn meshes_are_written_as_3mf_and_glb() {
    let obj = out_path("exchange.obj");
    let write = |path: &std::path::Path| {
        succeed(&[
            "mesh",
            "preset:blob",
            "--res",
            "20",
            "-o",
            path.to_str().unwrap(),
        ]);
        std::fs::read(path).unwrap()
    };
    let mesh = read_obj(&String::from_utf8(write(&obj)).unwrap());
    let (lo, hi) = mesh.bounds().unwrap();

    let glb = write(&out_path("exchange.glb"));
    assert_eq!(&glb[..4], b"glTF");
    let word = |at: usize| u32::from_le_bytes(glb[at..at + 4].try_into().unwrap()) as usize;
    assert_eq!(word(8), glb.len());
    let json: serde_json::Value = serde_json::from_slice(&glb[20..20 + word(12)]).unwrap();
    let primitive = &json["meshes"][0]["primitives"][0];
    let accessor =
        |name: &str| &json["accessors"][primitive["attributes"][name].as_u64().unwrap() as usize];
    let indices = &json["accessors"][primitive["indices"].as_u64().unwrap() as usize];
    assert_eq!(indices["count"], 3 * mesh.triangle_count());
    assert_eq!(accessor("POSITION")["count"], mesh.positions.len());
    let (min, max) = (&accessor("POSITION")["min"], &accessor("POSITION")["max"]);
    let near = |v: &serde_json::Value, want: f64| (v.as_f64().unwrap() - want).abs() < 1e-6;
    assert!(
        near(&min[0], lo.x / 1e3) && near(&max[0], hi.x / 1e3),
        "{min} {max}"
    );
    assert!(
        near(&min[1], lo.z / 1e3) && near(&max[1], hi.z / 1e3),
        "{min} {max}"
    );
    assert!(
        near(&min[2], -hi.y / 1e3) && near(&max[2], -lo.y / 1e3),
        "{min} {max}"
    );

    let three = write(&out_path("exchange.3mf"));
    assert_eq!(&three[..4], b"PK\x03\x04");
    let names = ["[Content_Types].xml", "_rels/.rels", "3D/3dmodel.model"];
    for name in names {
        assert!(
            three.windows(name.len()).any(|w| w == name.as_bytes()),
            "{name}"
        );
    }
    let bad = bezsolid(&[
        "mesh",
        "preset:blob",
        "-o",
        out_path("x.step").to_str().unwrap(),
    ]);
    assert!(
        String::from_utf8_lossy(&bad.stderr).contains(".stl, .obj or .ply, or in .3mf or .glb")
    );
}

/// A model file of the 3D tree `solid` (JSON).
fn tree_file(name: &str, solid: &str) -> String {
    let path = scratch(
        name,
        &format!(r#"{{"format":"bezsolid","version":1,"solid":{solid}}}"#),
    );
    path.to_str().unwrap().to_string()
}

/// Models a hostile user gives that lost their solid: far from the origin (a unit sphere at 1e8
/// meshed to 0 triangles, a unit box at 1e9 too), parts far apart (a sphere and a torus 1000
/// apart: 0 triangles), a strong blend (a0 = 1e4 stopped at x = 4.26 with volume 277; 1e5 had no
/// triangles), sizes past what f64 evaluates (radius 1e200 gave NaN): each meshes whole or is
/// refused by name.
#[test]
fn far_strong_and_huge_models_mesh_whole_or_are_refused() {
    let ball = 4.0 / 3.0 * std::f64::consts::PI;
    let sphere = |c: f64| format!(r#"{{"kind":"sphere","center":[{c},0,0],"radius":1}}"#);
    let home = stats_of(&["mesh", &tree_file("home.json", &sphere(0.0)), "--stats"]);
    let far = stats_of(&["mesh", &tree_file("far.json", &sphere(1e8)), "--stats"]);
    let (v, w) = (far["volume"][0], home["volume"][0]);
    assert!(
        (v - w).abs() < 1e-6 * w && (w - ball).abs() < 0.01 * ball,
        "at 1e8: {v}"
    );
    assert!((far["bbox"][0] - 1e8 + 1.0).abs() < 1e-3);
    let boxed = r#"{"kind":"box","min":[1e9,0,0],"max":[1000000001,1,1]}"#;
    let v = stats_of(&["mesh", &tree_file("far-box.json", boxed), "--stats"])["volume"][0];
    assert!((v - 1.0).abs() < 1e-3, "a unit box at 1e9: {v}");
    let apart = format!(
        r#"{{"kind":"union","of":[{},{{"kind":"torus","center":[1000,0,0],"axis":"z","major":2,"minor":0.5}}]}}"#,
        sphere(0.0)
    );
    let v = stats_of(&["mesh", &tree_file("apart.json", &apart), "--stats"])["volume"][0];
    let torus = 2.0 * std::f64::consts::PI.powi(2) * 2.0 * 0.25;
    assert!(
        (v - ball - torus).abs() < 0.02 * (ball + torus),
        "1000 apart: {v}"
    );
    // The blends' volumes by Monte Carlo: about 404 and 1240.
    for (a0, want, reach) in [(1e4, 404.0, 4.5), (1e5, 1240.0, 6.5)] {
        let blend = format!(
            r#"{{"kind":"blend_union","a0":{a0},"a1":1,"a2":1,"of":[{},{}]}}"#,
            sphere(-1.0),
            sphere(1.0)
        );
        let stats = stats_of(&["mesh", &tree_file("blend.json", &blend), "--stats"]);
        let v = stats["volume"][0];
        assert!((v - want).abs() < 0.04 * want, "a0 = {a0}: {v}");
        assert!(stats["bbox"][3] > reach, "a0 = {a0}: {:?}", stats["bbox"]);
    }
    let huge = r#"{"kind":"intersection","of":[{"kind":"sphere","center":[0,0,0],"radius":1e200},{"kind":"sphere","center":[0,0,0],"radius":1}]}"#;
    let out = bezsolid(&["mesh", &tree_file("huge.json", huge), "--stats"]);
    let err = common::one_line_error(&out);
    assert!(
        err.contains("solid.of[0].radius: 1e200 is too large"),
        "{err}"
    );
    // A solid finer than the grid is an error, never an empty success.
    let thin = r#"{"kind":"box","min":[0,0,0],"max":[1,1,1e-9]}"#;
    let out = bezsolid(&["mesh", &tree_file("thin.json", thin), "--stats"]);
    let err = common::one_line_error(&out);
    assert!(err.contains("came out empty"), "{err}");
}
