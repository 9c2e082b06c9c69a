//! `bezsolid link` and share links wherever a MODEL goes: the link printed for a model file opens
//! as the same model in every command, and damaged links fail with a message.

#![allow(clippy::unwrap_used)] // a test: a failed unwrap is a failed test
mod common;
use common::{bezsolid, out_path, scratch};
use std::process::Output;

fn stdout(out: &Output) -> String {
    assert!(
        out.status.success(),
        "stderr: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout.clone()).unwrap()
}

/// A degree (2, 1) patch with a moved control point and numbers that are not short decimals.
const MODEL: &str = r#"{"format": "bezsolid", "version": 1, "solid": {"kind": "patch", "degree": [2, 1],
  "points": [[0.0, 0.0, -0.3333333333333333], [0.0, 1.0, 0.7071067811865476],
             [0.5123456789, 0.0, 1.0], [0.5, 1.0, 0.25],
             [1.0, 0.0, -1e-300], [1.0, 1.0, 0.1]]}}"#;

#[test]
fn a_printed_link_opens_as_the_same_model_everywhere() {
    let model = scratch("moved.bsolid.json", MODEL);
    let model = model.to_str().unwrap();
    let link = stdout(&bezsolid(&["link", model]));
    let link = link.trim();
    assert!(link.starts_with("http://127.0.0.1:8080/#v1."), "{link}");
    assert_eq!(link.lines().count(), 1);
    let fragment = &link[link.find('#').unwrap()..];
    // Linking the link gives the same link: the model went through exactly.
    assert_eq!(stdout(&bezsolid(&["link", link])).trim(), link);
    assert_eq!(
        stdout(&bezsolid(&[
            "link",
            &fragment[1..],
            "--base",
            "https://example.invalid/m"
        ]))
        .trim(),
        format!("https://example.invalid/m{fragment}")
    );
    // eval from the file, the URL, the fragment with and without '#': identical output.
    let pts = scratch("pts.csv", "0.1,0.2\n0.5,0.5\n0.9,0.7\n1.4,0.5\n");
    let pts = pts.to_str().unwrap();
    let from_file = stdout(&bezsolid(&["eval", model, "--points", pts]));
    assert_eq!(from_file.lines().count(), 5);
    for m in [link, fragment, &fragment[1..]] {
        assert_eq!(
            stdout(&bezsolid(&["eval", m, "--points", pts])),
            from_file,
            "{m}"
        );
    }
    // And the contour export.
    let (a, b) = (out_path("a.svg"), out_path("b.svg"));
    stdout(&bezsolid(&[
        "contour",
        model,
        "--res",
        "64",
        "-o",
        a.to_str().unwrap(),
    ]));
    stdout(&bezsolid(&[
        "contour",
        link,
        "--res",
        "64",
        "-o",
        b.to_str().unwrap(),
    ]));
    let svg = std::fs::read(a).unwrap();
    assert!(String::from_utf8_lossy(&svg).contains("<path"));
    assert_eq!(svg, std::fs::read(b).unwrap());
    // HyperFun of a space mapping carries its inverse map (seeds, Newton's loop), the same from
    // the link as from the file.
    let (a, b) = (out_path("moved-file.hf"), out_path("moved-link.hf"));
    for (m, out) in [(model, &a), (link, &b)] {
        let run = bezsolid(&["hf", m, "-o", out.to_str().unwrap()]);
        assert!(
            run.status.success(),
            "{}",
            String::from_utf8_lossy(&run.stderr)
        );
    }
    let text = std::fs::read_to_string(&a).unwrap();
    assert!(
        text.contains("space-mapped") && text.contains("while (") && text.contains("endloop;"),
        "{text}"
    );
    assert_eq!(text, std::fs::read_to_string(&b).unwrap());
}

#[test]
fn presets_have_links_that_open() {
    for preset in ["fig9", "blob", "ring", "fish"] {
        let link = stdout(&bezsolid(&["link", &format!("preset:{preset}")]));
        assert!(link.trim().len() < 2000, "{preset}: {}", link.len());
        let again = stdout(&bezsolid(&["link", link.trim()]));
        assert_eq!(again, link, "{preset}");
    }
}

#[test]
fn damaged_links_fail_with_a_message() {
    let link = stdout(&bezsolid(&["link", "preset:fish"]));
    let link = link.trim();
    let cut = &link[..link.len() - 40];
    let cases: [(&str, &str); 6] = [
        (cut, "cut off"),
        ("http://127.0.0.1:8080/#v1.$$$", "characters"),
        ("#v7.AAAA", "version \"v7\""),
        ("#hello", "not a bezsolid link"),
        ("https://example.invalid/", "no model"),
        ("#v1.AAAA", "damaged"),
    ];
    for (arg, message) in cases {
        for cmd in [vec!["link", arg], vec!["hf", arg, "-o", "never.hf"]] {
            let out = bezsolid(&cmd);
            assert!(!out.status.success(), "{cmd:?} succeeded");
            let err = String::from_utf8_lossy(&out.stderr);
            assert!(err.contains(message), "{cmd:?}: {err}");
            assert!(!err.contains("panicked"), "{err}");
            assert!(out.stdout.is_empty());
        }
    }
    assert!(!std::path::Path::new("never.hf").exists());
}
