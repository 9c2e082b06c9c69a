//! Error messages: every refusal is one line on stderr that says each cause once (an error prints
//! its cause or gives it as its source, never both).

#![allow(clippy::unwrap_used)] // a test: a failed unwrap is a failed test
mod common;
use bezsolid_core::link;
use bezsolid_core::model::{ModelFile, SolidSpec};
use common::{bezsolid, one_line_error, repeated_phrase, scratch};

/// A patch of degree 17 along u: one past the cap.
fn degree_17() -> ModelFile {
    ModelFile {
        format: "bezsolid".into(),
        version: 1,
        solid: SolidSpec::Patch {
            degree: [17, 1],
            points: vec![[0.0; 3]; 36],
        },
    }
}

/// An open mesh: one triangle.
const OPEN_OBJ: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";

#[test]
fn the_phrase_check_finds_repeats() {
    let said = "invalid control net: degree 17 is outside 1..=16: degree 17 is outside 1..=16";
    assert_eq!(repeated_phrase(said, 12), Some(": degree 17 "));
    assert_eq!(repeated_phrase("cannot read x.csv: no such file", 12), None);
    // Characters, not bytes; a phrase and its repeat do not overlap.
    let twelve = "é".repeat(12);
    assert_eq!(
        repeated_phrase(&twelve.repeat(2), 12),
        Some(twelve.as_str())
    );
    assert_eq!(repeated_phrase(&format!("{twelve}é"), 12), None);
}

#[test]
fn errors_say_their_cause_once_on_one_line() {
    let deg17 = scratch(
        "deg17.bsolid.json",
        &serde_json::to_string(&degree_17()).unwrap(),
    );
    let deg17 = deg17.to_str().unwrap();
    let deg17_link = link::encode(&degree_17()).unwrap();
    let open = scratch("open.obj", OPEN_OBJ);
    let open = open.to_str().unwrap();
    let open_model = scratch(
        "open.bsolid.json",
        r#"{"format": "bezsolid", "version": 1, "solid": {"kind": "esc", "operands": [{"mesh":
           {"positions": [[0, 0, 0], [1, 0, 0], [0, 1, 0]], "triangles": [[0, 1, 2]]}}]}}"#,
    );
    let open_model = open_model.to_str().unwrap();
    let nan = scratch("nan.csv", "0.5,0.5\n1,NaN\n");
    let nan = nan.to_str().unwrap();
    let nan3 = scratch("nan3.csv", "0,0,0\n1,inf,0\n");
    let nan3 = nan3.to_str().unwrap();
    let pts = scratch("pts.csv", "0.5,0.5\n");
    let pts = pts.to_str().unwrap();
    let pts3 = scratch("pts3.csv", "0,0,0\n");
    let pts3 = pts3.to_str().unwrap();
    // A link with three zero bytes after its deflate stream: "AAAA" appends them to base64 whose
    // length is a multiple of 4.
    let stray = ["fig9", "blob", "ring", "fish"]
        .iter()
        .map(|p| {
            let out = bezsolid(&["link", &format!("preset:{p}")]);
            String::from_utf8(out.stdout).unwrap().trim().to_string()
        })
        .find(|link| link.split_once("#v1.").unwrap().1.len() % 4 == 0)
        .unwrap()
        + "AAAA";
    let svg = common::out_path("x.svg");
    let svg = svg.to_str().unwrap();
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (
            vec!["eval", deg17, "--points", pts],
            "degree 17 is outside 1..=16",
        ),
        (vec!["link", deg17], "degree 17 is outside 1..=16"),
        (vec!["contour", deg17, "-o", svg], "degree 17 is outside"),
        (
            vec!["eval", &deg17_link, "--points", pts],
            "the share link's model: invalid solid: invalid control net: degree 17",
        ),
        (vec!["link", "#v1.AAAA"], "cut off"),
        (
            vec!["eval", &stray, "--points", pts],
            "the link is damaged: 3 stray bytes follow the end of its packed data",
        ),
        (vec!["link", "#v9.AAAA"], "version \"v9\""),
        (
            vec!["esc", "classify", open, "--points", pts3],
            "3 open edges",
        ),
        (
            vec!["esc", "classify", open_model, "--points", pts3],
            "operand 1: the mesh is not a closed solid: 3 open edges",
        ),
        (vec!["link", open_model], "3 open edges"),
        (
            vec!["eval", "preset:fig9", "--points", nan],
            "line 2: coordinates must be finite numbers",
        ),
        (
            vec!["esc", "classify", "example:torus", "--points", nan3],
            "line 2: coordinates must be finite numbers",
        ),
    ];
    for (args, says) in cases {
        let line = one_line_error(&bezsolid(&args));
        assert!(line.contains(says), "{args:?}: {line}");
    }
}
