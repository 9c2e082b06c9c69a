//! The command line's help, version, completions and progress, and its refusals of bad arguments
//! in the words they had before the commands were parsed by clap.

#![allow(clippy::unwrap_used)] // a test: a failed unwrap is a failed test
mod common;
use std::process::Command;

use common::{bezsolid, out_path, scratch, succeed};

const ESC_USAGE: &str = "usage: bezsolid esc classify MESH --points FILE.csv [-o OUT] | \
     bezsolid esc bool A OP B --points FILE.csv [-o OUT] (OP: union, intersection, difference) | ";

/// Each bad command line with the exit code and the line (after `bezsolid: `) that the command
/// line said before it was parsed by clap, written down from that binary.
#[test]
fn argument_errors_keep_their_words() {
    let pts = scratch("words.csv", "0.5,0.5\n");
    let pts = pts.to_str().unwrap();
    let svg = out_path("words.svg");
    let svg = svg.to_str().unwrap();
    let hf = out_path("words.hf");
    let hf = hf.to_str().unwrap();
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (
            vec!["mesh", "preset:blob", "--frob", "3", "-o", "x.stl"],
            "mesh: unknown option --frob",
        ),
        (
            vec!["mesh", "preset:blob", "extra", "-o", "x.stl"],
            "mesh: unexpected argument extra",
        ),
        (
            vec!["mesh", "preset:blob", "A=b", "-o", "x.stl"],
            "mesh: unexpected argument A=b",
        ),
        (vec!["mesh", "preset:blob", "--res"], "--res needs a value"),
        (vec!["mesh", "preset:blob", "-o"], "-o needs a value"),
        (
            vec!["mesh", "preset:blob", "--res", "abc", "-o", "x.stl"],
            "--res abc is not a valid number here",
        ),
        (
            vec!["mesh", "preset:blob", "--res", "-4", "-o", "x.stl"],
            "--res -4 is not a valid number here",
        ),
        (
            vec!["mesh", "preset:blob", "--res", "0", "-o", "x.stl"],
            "--res 0 is outside 1..=512",
        ),
        (
            vec!["mesh", "preset:blob", "--threads", "0", "-o", "x.stl"],
            "--threads 0 is outside 1..=256",
        ),
        (
            vec!["mesh", "preset:blob", "--accuracy", "x", "-o", "x.stl"],
            "--accuracy x is not a valid number here",
        ),
        (
            vec!["mesh", "preset:blob"],
            "mesh: -o OUT.stl, OUT.obj or OUT.ply is required",
        ),
        (
            vec!["mesh", "-o", "x.stl"],
            "mesh: which model? usage: bezsolid mesh MODEL --res N -o OUT.stl",
        ),
        (
            vec!["mesh", "preset:blob", "-o", "x.txt"],
            "mesh: x.txt should end in .stl, .obj or .ply, or in .3mf or .glb",
        ),
        (
            vec!["contour", "preset:fig9", "--res", "1", "-o", svg],
            "--res 1 is outside 2..=4096",
        ),
        (
            vec!["contour", "preset:fig9"],
            "contour: -o OUT.svg is required",
        ),
        (
            vec!["contour", "preset:fig9", "--section", "w=1", "-o", svg],
            "--section w=1: a plane is x=C, y=C or z=C with C a finite number",
        ),
        (
            vec!["contour", "preset:fig9", "--accuracy", "-1", "-o", svg],
            "--accuracy must be a positive number",
        ),
        (
            vec!["eval", "preset:fig9"],
            "eval: --points FILE.csv is required",
        ),
        (
            vec!["eval", "--points", pts],
            "eval: which model? usage: bezsolid eval MODEL --points FILE.csv",
        ),
        (
            vec!["eval", "preset:fig9", "--points", pts, "--inverse", "magic"],
            "eval: --inverse magic: the inverse map is one of paper (the paper's spline guess and Bézier clipping), clip (Bézier clipping over the whole domain) or fast (the default)",
        ),
        (
            vec!["eval", "preset:fig9", "--points"],
            "--points needs a value",
        ),
        (vec!["hf", "preset:fig9"], "hf: -o OUT.hf is required"),
        (
            vec!["hf", "preset:fig9", "-o", hf, "--height", "-1"],
            "--height -1: the extrusion's height is a positive number",
        ),
        (
            vec!["hf", "preset:fig9", "-o", hf, "--height", "abc"],
            "--height abc is not a valid number here",
        ),
        (
            vec!["hf", "preset:fig9", "-o", hf, "--height", "-1.50"],
            "--height -1.50: the extrusion's height is a positive number",
        ),
        (
            vec!["link"],
            "link: which model? usage: bezsolid link MODEL [--base URL]",
        ),
        (
            vec!["link", "preset:fig9", "--base", "http://a/#b"],
            "link: --base http://a/#b already has a fragment ('#')",
        ),
        (
            vec!["plasm"],
            "plasm: which model? usage: bezsolid plasm SCRIPT [-o OUT.obj]",
        ),
        (
            vec!["plasm", "example:3.1", "-o", "x.txt"],
            "plasm: x.txt should end in .obj, .stl or .ply",
        ),
        (
            vec!["esc", "classify", "example:torus"],
            "esc classify: --points FILE.csv is required",
        ),
        (
            vec![
                "esc",
                "classify",
                "example:torus",
                "--points",
                pts,
                "--crease",
                "x",
            ],
            "--crease x is not a valid number here",
        ),
        (
            vec![
                "esc",
                "classify",
                "example:torus",
                "--points",
                pts,
                "--crease",
                "500",
            ],
            "the crease angle must be a number of degrees from 0 to 180, not 500",
        ),
        (
            vec![
                "esc",
                "bool",
                "example:torus",
                "xor",
                "example:torus",
                "--points",
                pts,
            ],
            "esc bool: unknown operation `xor`; use union, intersection or difference (or `complement A`)",
        ),
        (
            vec![
                "esc",
                "bool",
                "complement",
                "example:torus",
                "extra",
                "--points",
                pts,
            ],
            "esc bool: unexpected argument extra: a complement takes one solid",
        ),
        (
            vec![
                "esc",
                "bool",
                "example:torus",
                "union",
                "example:torus",
                "extra",
                "--points",
                pts,
            ],
            "esc bool: unexpected argument extra",
        ),
        (
            vec!["esc", "expr", "A|B", "--points", pts],
            "esc expr: no solids: give them as NAME=SOLID, e.g. A=a.obj B=example:torus",
        ),
        (
            vec!["esc", "expr", "A|B", "1=x", "--points", pts],
            "esc expr: `1=x` is not NAME=SOLID (a name is a letter or _, then letters, digits or _)",
        ),
        (
            vec![
                "esc",
                "expr",
                "A",
                "A=example:torus",
                "--points",
                pts,
                "--frob",
                "1",
            ],
            "esc expr: unknown option --frob",
        ),
        (
            vec!["bench"],
            "`bench` is not in this build; run `cargo xtask bench` in the repository",
        ),
    ];
    for (args, said) in cases {
        let out = bezsolid(&args);
        let err = String::from_utf8(out.stderr).unwrap();
        assert_eq!(out.status.code(), Some(1), "{args:?}: {err}");
        assert_eq!(err, format!("bezsolid: {said}\n"), "{args:?}");
    }
    // The esc commands' refusals end with the whole usage of esc.
    for (args, said) in [
        (vec!["esc"], "esc: which command? "),
        (
            vec!["esc", "frobnicate"],
            "esc: unknown command `frobnicate`; ",
        ),
        (vec!["esc", "-x"], "esc: unknown command `-x`; "),
        (
            vec!["esc", "classify", "--points", pts],
            "esc classify: which model? ",
        ),
        (
            vec!["esc", "bool", "example:torus"],
            "esc bool: expected A OP B or complement A; ",
        ),
        (vec!["esc", "expr"], "esc expr: which expression? "),
    ] {
        let out = bezsolid(&args);
        let err = String::from_utf8(out.stderr).unwrap();
        assert_eq!(out.status.code(), Some(1), "{args:?}: {err}");
        assert!(
            err.starts_with(&format!("bezsolid: {said}{ESC_USAGE}")),
            "{args:?}: {err}"
        );
        assert_eq!(err.lines().count(), 1, "{args:?}: {err}");
    }
    // An unknown command (or an option where the command goes), and no command: the usage, with
    // exit code 2.
    for word in ["frobnicate", "--frob"] {
        let out = bezsolid(&[word, "mesh"]);
        let err = String::from_utf8(out.stderr).unwrap();
        assert_eq!(out.status.code(), Some(2));
        assert!(
            err.starts_with(&format!("bezsolid: unknown command `{word}`\n\n")),
            "{err}"
        );
        assert!(err.contains("Usage: bezsolid <COMMAND>"), "{err}");
    }
    let out = bezsolid(&[]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        String::from_utf8(out.stderr)
            .unwrap()
            .contains("Usage: bezsolid <COMMAND>")
    );
}

/// Options keep what the hand-written parser took: the last of a repeated option wins, and a
/// value may begin with `-`.
#[test]
fn repeated_options_and_values_with_a_dash_parse_as_before() {
    let svg = out_path("twice.svg");
    succeed(&[
        "contour",
        "preset:fig9",
        "--res",
        "9999",
        "--res",
        "16",
        "-o",
        svg.to_str().unwrap(),
    ]);
    // A tree cut by a box whose corner is negative.
    let tree = scratch(
        "sphere.bsolid.json",
        r#"{"format": "bezsolid", "version": 1, "solid": {"kind": "sphere", "center": [0, 0, 0], "radius": 1}}"#,
    );
    let out = succeed(&[
        "mesh",
        tree.to_str().unwrap(),
        "--box",
        "-2,-2,-2,0,2,2",
        "--res",
        "16",
        "--stats",
    ]);
    let stdout = String::from_utf8(out.stdout).unwrap();
    let bbox = stdout
        .lines()
        .find_map(|l| l.strip_prefix("bbox: "))
        .unwrap();
    let bbox: Vec<f64> = bbox.split(' ').map(|v| v.parse().unwrap()).collect();
    // The half of the sphere with x <= 0.
    assert!(
        bbox[3].abs() < 1e-9 && (bbox[0] + 1.0).abs() < 0.05,
        "{bbox:?}"
    );
}

/// The commands the help lists.
const COMMANDS: [&str; 8] = [
    "eval",
    "contour",
    "mesh",
    "hf",
    "link",
    "esc",
    "plasm",
    "completions",
];

/// Every command's `--help` (and `-h`, and `help COMMAND`) says how it is used, with an example,
/// on stdout.
#[test]
fn every_command_has_help_with_an_example() {
    let esc = ["esc classify", "esc bool", "esc expr"];
    for cmd in COMMANDS.into_iter().chain(esc) {
        let words: Vec<&str> = cmd.split(' ').collect();
        let mut runs = vec![
            [words.as_slice(), &["--help"]].concat(),
            [words.as_slice(), &["-h"]].concat(),
        ];
        runs.push([&["help"], words.as_slice()].concat());
        for args in runs {
            let out = bezsolid(&args);
            let help = String::from_utf8(out.stdout).unwrap();
            assert!(out.status.success(), "{args:?}");
            assert!(
                help.contains(&format!("Usage: bezsolid {cmd}")),
                "{args:?}: {help}"
            );
            assert!(help.contains("Example"), "{args:?}: {help}");
            assert!(
                help.contains(&format!("bezsolid {cmd} ")),
                "{args:?}: no example run"
            );
        }
    }
    let out = bezsolid(&["--help"]);
    let help = String::from_utf8(out.stdout).unwrap();
    assert!(out.status.success());
    for cmd in COMMANDS {
        assert!(
            help.contains(&format!("\n  {cmd} ")),
            "{cmd} missing from {help}"
        );
    }
    assert!(
        help.contains("preset:blob") && help.contains("a model file 16 MiB"),
        "{help}"
    );
    // A command's options are described, each with its value's name.
    let out = bezsolid(&["mesh", "--help"]);
    let help = String::from_utf8(out.stdout).unwrap();
    for option in [
        "-o, --output <OUT>",
        "--res <N>",
        "--box <X0,Y0,Z0,X1,Y1,Z1>",
        "--stats",
        ".3mf",
    ] {
        assert!(help.contains(option), "{option}: {help}");
    }
    // The limit the help states is the one the command keeps.
    let most = format!("at most {}", bezsolid_core::mesh::MAX_RESOLUTION);
    assert!(help.contains(&most), "{most}: {help}");
}

#[test]
fn the_version_is_the_crates() {
    for flag in ["--version", "-V"] {
        let out = bezsolid(&[flag]);
        assert!(out.status.success());
        assert_eq!(
            String::from_utf8(out.stdout).unwrap(),
            format!("bezsolid {}\n", env!("CARGO_PKG_VERSION"))
        );
    }
}

/// `completions SHELL` writes a script the shell reads; bash's is checked by bash itself.
#[test]
fn shell_completions_name_every_command_and_option() {
    for shell in ["bash", "zsh", "fish", "elvish", "powershell"] {
        let out = bezsolid(&["completions", shell]);
        assert!(out.status.success(), "{shell}");
        let script = String::from_utf8(out.stdout).unwrap();
        for word in ["contour", "mesh", "classify", "stats", "section", "inverse"] {
            assert!(script.contains(word), "{shell}: no {word}");
        }
    }
    let out = bezsolid(&["completions", "bash"]);
    let path = out_path("bezsolid.bash");
    std::fs::write(&path, &out.stdout).unwrap();
    // Sourced, it registers the completion function for `bezsolid`.
    let check = Command::new("bash")
        .arg("-c")
        .arg(format!("source {} && complete -p bezsolid", path.display()))
        .output()
        .unwrap();
    let said = String::from_utf8_lossy(&check.stdout);
    assert!(
        check.status.success(),
        "{}",
        String::from_utf8_lossy(&check.stderr)
    );
    assert!(
        said.contains("_bezsolid") && said.contains("bezsolid"),
        "{said}"
    );
    // Refused by clap itself: one sentence, after the command's name.
    let out = bezsolid(&["completions"]);
    assert_eq!(out.status.code(), Some(1));
    assert_eq!(
        String::from_utf8(out.stderr).unwrap(),
        "bezsolid: completions: the following required arguments were not provided: <SHELL>\n"
    );
    let out = bezsolid(&["completions", "tcsh"]);
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(
        err.starts_with("bezsolid: ") && err.contains("bash"),
        "{err}"
    );
}

/// A moved piecewise volume, whose points each need the inverse map: seconds of work.
fn slow_model() -> String {
    let seed = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../fuzz/seeds/model/piecewise-volume-moved.bsolid.json"
    );
    std::fs::read_to_string(seed).unwrap()
}

/// Long work draws a progress bar on a terminal (run here in a pseudo-terminal by `script`), and
/// none when stderr is a pipe: what is printed there is the same as before.
#[test]
fn long_work_shows_progress_on_a_terminal_only() {
    let model = scratch("slow.bsolid.json", &slow_model());
    let model = model.to_str().unwrap();
    // Points in the model's box.
    let mut state = 0x2545_F491_4F6C_DD1Du64;
    let mut next = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let csv: String = (0..60_000)
        .map(|_| format!("{},{},{}\n", 2.0 * next(), next(), next()))
        .collect();
    let pts = scratch("slow.csv", &csv);
    let pts = pts.to_str().unwrap();
    let values = out_path("slow-values.csv");
    let values = values.to_str().unwrap();
    let stl = out_path("slow.stl");
    let stl = stl.to_str().unwrap();
    let bin = env!("CARGO_BIN_EXE_bezsolid");
    for (args, bar) in [
        (
            vec!["eval", model, "--points", pts, "-o", values],
            "evaluating [",
        ),
        (vec!["mesh", model, "--res", "128", "-o", stl], "meshing ["),
    ] {
        // Piped: stderr holds what the command says, and no bar.
        let out = bezsolid(&args);
        let err = String::from_utf8(out.stderr).unwrap();
        assert!(out.status.success(), "{args:?}: {err}");
        assert!(
            !err.contains(bar) && !err.contains('\r') && !err.contains('\x1b'),
            "{err:?}"
        );
        // On a terminal: the bar, then the same lines.
        let line = std::iter::once(bin)
            .chain(args.iter().copied())
            .map(|a| format!("'{a}'"))
            .collect::<Vec<_>>()
            .join(" ");
        let tty = Command::new("script")
            .args(["-qec", &line, "/dev/null"])
            .output()
            .expect("`script` (util-linux) runs a command in a pseudo-terminal");
        let seen = String::from_utf8_lossy(&tty.stdout);
        assert!(tty.status.success(), "{args:?}: {seen}");
        assert!(seen.contains(bar), "{args:?}: no progress bar in {seen:?}");
        // The bar is cleared: what is left after the last clearing is the command's own output.
        let last = seen.rsplit("\x1b[2K").next().unwrap();
        assert_eq!(last.replace("\r\n", "\n"), err, "{args:?}");
    }
}
