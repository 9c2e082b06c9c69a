//! `bezsolid mesh` and `bezsolid hf` end to end: the binary writes files, which are parsed back here
//! (with parsers written independently of the writers) and checked.

#![allow(clippy::unwrap_used)] // a test: a failed unwrap is a failed test
use std::path::PathBuf;
use std::process::{Command, Output};

use bezsolid_core::mesh::Mesh;
use glam::DVec3;

fn out_path(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("bezsolid-mesh-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

fn bezsolid(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_bezsolid"))
        .args(args)
        .output()
        .unwrap()
}

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
        let out = bezsolid(&[
            "mesh",
            &format!("preset:{preset}"),
            "--res",
            "40",
            "-o",
            path.to_str().unwrap(),
        ]);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let mesh = read_obj(&std::fs::read_to_string(&path).unwrap());
        assert!(mesh.triangle_count() > 100);
        mesh.check_closed_manifold().unwrap();
        assert_eq!(mesh.euler_characteristic(), euler, "{preset}");
        assert!(mesh.volume() > 0.0);
        assert_eq!(mesh.normals.len(), mesh.positions.len());
    }
}

#[test]
fn stl_and_ply_hold_the_same_triangles_as_obj() {
    let obj = out_path("blob16.obj");
    let stl = out_path("blob16.stl");
    let ply = out_path("blob16.PLY");
    for p in [&obj, &stl, &ply] {
        let out = bezsolid(&[
            "mesh",
            "preset:blob",
            "--res",
            "16",
            "-o",
            p.to_str().unwrap(),
        ]);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
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
        let out = bezsolid(&[
            "hf",
            &format!("preset:{preset}"),
            "-o",
            path.to_str().unwrap(),
        ]);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(text.contains("my_model(x[3], a[1])"));
        assert!(text.trim_end().ends_with('}'));
        assert_eq!(text.contains("hfBezierVolume"), preset == "fish");
    }
}
