//! HyperFun files on the command line: an export opens back as the model it carries (eval, mesh),
//! and a program written for HyperFun is evaluated as HyperFun reads it, its refusals HyperFun's
//! messages at their places.

#![allow(clippy::unwrap_used)] // a test: a failed unwrap is a failed test
mod common;
use common::{bezsolid, one_line_error, out_path, scratch, succeed};

fn stdout(out: &std::process::Output) -> String {
    String::from_utf8(out.stdout.clone()).unwrap()
}

#[test]
fn an_export_opens_back_as_the_model_it_came_from() {
    let hf = out_path("chair.hf");
    succeed(&["hf", "preset:chair", "-o", hf.to_str().unwrap()]);
    let points = scratch(
        "chair-points.csv",
        "0,0,1\n0.3,-0.2,0.5\n5,5,5\n-0.9,0.8,1.9\n",
    );
    let points = points.to_str().unwrap();
    let from_file = succeed(&["eval", hf.to_str().unwrap(), "--points", points]);
    let from_preset = succeed(&["eval", "preset:chair", "--points", points]);
    // The same model: the same rows, preimages included.
    assert_eq!(stdout(&from_file), stdout(&from_preset));
    let stl = out_path("chair.stl");
    succeed(&[
        "mesh",
        hf.to_str().unwrap(),
        "--res",
        "8",
        "-o",
        stl.to_str().unwrap(),
    ]);
    assert!(std::fs::metadata(&stl).unwrap().len() > 84);
}

#[test]
fn a_hyperfun_program_evaluates_as_hyperfun_reads_it() {
    let program = scratch(
        "ball.hf",
        "-- written for HyperFun\nmy_model(x[3], a[1])\n{\n  array centre[3];\n  centre = [1, 0, 0];\n  \
         my_model = hfSphere(x, centre, 2) | hfBlock(x, centre, 1, 1, 1);\n}\n",
    );
    let points = scratch("ball-points.csv", "x,y,z\n1,0,0\n4,0,0\n1,1.5,0\n");
    let out = succeed(&[
        "eval",
        program.to_str().unwrap(),
        "--points",
        points.to_str().unwrap(),
    ]);
    let rows: Vec<Vec<f64>> = stdout(&out)
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    // hfSphere is r² − |x − c|², hfBlock the box [c, c + 1]³ by R-functions, | the R-union.
    let union = |f1: f64, f2: f64| f1 + f2 + (f1 * f1 + f2 * f2).sqrt();
    let block = |p: [f64; 3]| {
        let and = |f1: f64, f2: f64| f1 + f2 - (f1 * f1 + f2 * f2).sqrt();
        let slab = |t: f64| t * (1.0 - t);
        and(and(slab(p[0] - 1.0), slab(p[1])), slab(p[2]))
    };
    for row in &rows {
        let p = [row[0], row[1], row[2]];
        let sphere = 4.0 - ((p[0] - 1.0).powi(2) + p[1] * p[1] + p[2] * p[2]);
        let want = union(sphere, block(p));
        assert!(
            (row[3] - want).abs() <= 1e-12 * want.abs().max(1.0),
            "{row:?}: {want}"
        );
    }
    assert_eq!(rows.len(), 3);
}

#[test]
fn hyperfun_refusals_are_its_messages_at_their_places() {
    let points = scratch("one-point.csv", "0,0,0\n")
        .to_str()
        .unwrap()
        .to_owned();
    // `s` is HyperFun's attribute array, never a variable.
    let local_s = scratch(
        "local-s.hf",
        "my_model(x[3], a[1])\n{\n  s = x[1]*x[1] + x[2]*x[2];\n  my_model = 1 - s;\n}\n",
    );
    let err = one_line_error(&bezsolid(&[
        "eval",
        local_s.to_str().unwrap(),
        "--points",
        &points,
    ]));
    assert!(
        err.ends_with("local-s.hf: line 3, position 7: Left bracket expected"),
        "{err}"
    );
    // A condition's operand that opens with a bracket is a nested condition to HyperFun.
    let bracket = scratch(
        "bracket.hf",
        "my_model(x[3], a[1])\n{\n  a1 = x[1]; b1 = x[2]; c1 = 1;\n  r = -1;\n  \
         if ((a1 - b1) * (a1 - b1) <= c1) then\n    r = 1;\n  endif;\n  my_model = r;\n}\n",
    );
    let err = one_line_error(&bezsolid(&[
        "eval",
        bracket.to_str().unwrap(),
        "--points",
        &points,
    ]));
    assert!(
        err.ends_with("line 5, position 17: Right parenthes expected"),
        "{err}"
    );
    // HyperFun divides by nothing under 1e-6.
    let tiny = scratch(
        "tiny.hf",
        "my_model(x[3], a[1])\n{\n  d = 0.0000001;\n  my_model = 1 / d;\n}\n",
    );
    let err = one_line_error(&bezsolid(&[
        "eval",
        tiny.to_str().unwrap(),
        "--points",
        &points,
    ]));
    assert!(
        err.contains("at point 1 (0, 0, 0)") && err.ends_with("Division by zero"),
        "{err}"
    );
    // Meshing stops at the first point it fails at, with its message.
    let err = one_line_error(&bezsolid(&[
        "mesh",
        tiny.to_str().unwrap(),
        "--box",
        "-1,-1,-1,1,1,1",
        "--stats",
    ]));
    assert!(
        err.contains("at (-1, -1, -1)") && err.ends_with("Division by zero"),
        "{err}"
    );
    // A program carries no model for the commands that need one.
    let err = one_line_error(&bezsolid(&["link", tiny.to_str().unwrap()]));
    assert!(err.contains("carries no bezsolid model"), "{err}");
}

#[test]
fn a_hyperfun_program_meshes_within_its_box() {
    let ball = scratch(
        "unit-ball.hf",
        "my_model(x[3], a[1]) {\n  array c[3];\n  c = [0.5, 0, 0];\n  my_model = hfSphere(x, c, 1);\n}\n",
    );
    let ball = ball.to_str().unwrap();
    let stats = |args: &[&str]| -> Vec<(String, Vec<f64>)> {
        let out = succeed(args);
        stdout(&out)
            .lines()
            .map(|l| {
                let (name, rest) = l.split_once(':').unwrap();
                let v = rest
                    .split_whitespace()
                    .map(|v| v.parse().unwrap())
                    .collect();
                (name.to_string(), v)
            })
            .collect()
    };
    // The whole ball: its volume 4π/3 to marching cubes' accuracy (the inscribed polyhedron of
    // 1/16 cells, within 1.5 %), its box [-0.5, 1.5] × [-1, 1]².
    let whole = stats(&[
        "mesh",
        ball,
        "--box",
        "-2,-2,-2,2,2,2",
        "--res",
        "32",
        "--stats",
    ]);
    let volume = whole[0].1[0];
    assert!(
        (volume - 4.0 * std::f64::consts::PI / 3.0).abs() < 0.065,
        "{whole:?}"
    );
    let bbox = &whole[2].1;
    // Its extreme points are samples where the program is exactly zero: their vertices keep a
    // thousandth of a cell (1/8 here) off them, so that no triangle is flat.
    for (got, want) in bbox.iter().zip([-0.5, -1.0, -1.0, 1.5, 1.0, 1.0]) {
        assert!((got - want).abs() < 2e-3 * 0.125, "{bbox:?}");
    }
    // Cut by a box through its centre: the half ball, closed by the cut.
    let half = stats(&[
        "mesh",
        ball,
        "--box",
        "0.5,-2,-2,2,2,2",
        "--res",
        "32",
        "--stats",
    ]);
    let volume = half[0].1[0];
    assert!(
        (volume - 2.0 * std::f64::consts::PI / 3.0).abs() < 0.06,
        "{half:?}"
    );
    // Without a box it says what it needs; outside the solid, that it is empty there.
    let err = one_line_error(&bezsolid(&["mesh", ball, "--stats"]));
    assert!(err.contains("--box X0,Y0,Z0,X1,Y1,Z1"), "{err}");
    let err = one_line_error(&bezsolid(&[
        "mesh",
        ball,
        "--box",
        "5,5,5,6,6,6",
        "--stats",
    ]));
    assert!(
        err.contains("no point of the grid in the box is inside"),
        "{err}"
    );
}

#[test]
fn a_hyperfun_program_is_cut_by_a_plane() {
    let ball = scratch(
        "section-ball.hf",
        "my_model(x[3], a[1]) {\n  array c[3];\n  c = [0.5, 0, 0];\n  my_model = hfSphere(x, c, 1);\n}\n",
    );
    let ball = ball.to_str().unwrap();
    // Through the centre, the unit disc; 0.6 above it, the disc of radius 0.8.
    for (plane, r) in [("z=0", 1.0f64), ("y=0.6", 0.8)] {
        let out = succeed(&[
            "contour",
            ball,
            "--section",
            plane,
            "--box",
            "-2,-2,-2,2,2,2",
            "--stats",
        ]);
        let area: f64 = stdout(&out)
            .lines()
            .find_map(|l| l.strip_prefix("area: "))
            .unwrap()
            .parse()
            .unwrap();
        let want = std::f64::consts::PI * r * r;
        assert!(
            (area - want).abs() < 1e-3 * want,
            "{plane}: {area} against {want}"
        );
    }
    let err = one_line_error(&bezsolid(&["contour", ball, "--stats"]));
    assert!(err.contains("--section x=C, y=C or z=C"), "{err}");
    let err = one_line_error(&bezsolid(&["contour", ball, "--section", "z=0", "--stats"]));
    assert!(err.contains("--box X0,Y0,Z0,X1,Y1,Z1"), "{err}");
}

#[test]
fn a_hyperfun_model_file_is_its_program_within_its_box() {
    let program = "my_model(x[3], a[1]) {\n  array c[3];\n  c = [0.5, 0, 0];\n  my_model = hfSphere(x, c, 1);\n}\n";
    let json = |bounds: &str| {
        let program = program.replace('\n', "\\n");
        format!(
            r#"{{"format": "bezsolid", "version": 1,
                "solid": {{"kind": "hyperfun", "program": "{program}"{bounds}}}}}"#
        )
    };
    let boxed = scratch(
        "ball-boxed.bsolid.json",
        &json(r#", "box": [[-2, -2, 0], [2, 2, 2]]"#),
    );
    let boxed = boxed.to_str().unwrap();
    // No box in the file: HyperFun's default box, [-10, 10]³.
    let plain = scratch("ball-plain.bsolid.json", &json(""));
    let plain = plain.to_str().unwrap();
    let volume = |args: &[&str]| -> f64 {
        let out = succeed(args);
        stdout(&out)
            .lines()
            .find_map(|l| l.strip_prefix("volume: "))
            .unwrap()
            .parse()
            .unwrap()
    };
    let third = std::f64::consts::PI / 3.0;
    // The file's box cuts the ball in half; --box overrides it.
    let half = volume(&["mesh", boxed, "--res", "32", "--stats"]);
    assert!((half - 2.0 * third).abs() < 0.06, "{half}");
    let whole = volume(&[
        "mesh",
        boxed,
        "--res",
        "32",
        "--box",
        "-2,-2,-2,2,2,2",
        "--stats",
    ]);
    assert!((whole - 4.0 * third).abs() < 0.065, "{whole}");
    let coarse = volume(&["mesh", plain, "--res", "64", "--stats"]);
    assert!((coarse - 4.0 * third).abs() < 0.5, "{coarse}");
    // Its section within the file's box; eval as the program.
    let out = succeed(&["contour", boxed, "--section", "z=0.6", "--stats"]);
    let area: f64 = stdout(&out)
        .lines()
        .find_map(|l| l.strip_prefix("area: "))
        .unwrap()
        .parse()
        .unwrap();
    let disc = std::f64::consts::PI * 0.64;
    assert!((area - disc).abs() < 1e-3 * disc, "{area}");
    let points = scratch("ball-file-points.csv", "0.5,0,0\n3,0,0\n");
    let out = succeed(&["eval", boxed, "--points", points.to_str().unwrap()]);
    assert_eq!(stdout(&out), "x,y,z,f\n0.5,0,0,1\n3,0,0,-5.25\n");
    // Its share link carries the program and the box.
    let out = succeed(&["link", boxed]);
    let link = stdout(&out).trim().to_string();
    let from_link = volume(&["mesh", &link, "--res", "32", "--stats"]);
    assert_eq!(from_link, half);
    // What is not a Bézier solid is said so; a bad box or program is refused.
    let err = one_line_error(&bezsolid(&["hf", boxed, "-o", "unused.hf"]));
    assert!(err.contains("this is a HyperFun program"), "{err}");
    let flat = scratch(
        "ball-flat.bsolid.json",
        &json(r#", "box": [[0, 0, 0], [1, 1, 0]]"#),
    );
    let flat = flat.to_str().unwrap();
    for args in [&["mesh", flat, "--stats"][..], &["link", flat]] {
        let err = one_line_error(&bezsolid(args));
        assert!(
            err.contains("box [[0.0, 0.0, 0.0], [1.0, 1.0, 0.0]] is refused"),
            "{err}"
        );
    }
    let broken = scratch(
        "broken.bsolid.json",
        r#"{"format": "bezsolid", "version": 1, "solid": {"kind": "hyperfun", "program": "m(x[3], a[1]) { m = ; }"}}"#,
    );
    let err = one_line_error(&bezsolid(&["mesh", broken.to_str().unwrap(), "--stats"]));
    assert!(err.contains("broken.bsolid.json: line 1"), "{err}");
}
