//! Nets that fold over themselves, as a hostile user drags them: every command finishes within its
//! budget, whatever the net (contours of degree-16 patches with shuffled control points took minutes
//! or never ended; a shuffled degree-16 volume took 35 s to mesh at resolution 8), and no finite
//! input gives NaN. The limits are the budgets with room for a loaded machine; `cargo xtask bench`
//! has the figures.

#![allow(clippy::unwrap_used)] // a test: a failed unwrap is a failed test

mod common;

use std::fmt::Write as _;
use std::time::Duration;

use common::{Feed, Rng, bezsolid_bounded, out_path, scratch};

/// A model file of a patch (`degree` of 2) or volume (3) with `points` in the file's order.
fn model(degree: &[usize], points: &[Vec<f64>]) -> String {
    let kind = if degree.len() == 2 { "patch" } else { "volume" };
    let points: Vec<String> = points
        .iter()
        .map(|p| {
            let c: Vec<String> = p.iter().map(|v| format!("{v:?}")).collect();
            format!("[{}]", c.join(","))
        })
        .collect();
    format!(
        r#"{{"format":"bezsolid","version":1,"solid":{{"kind":"{kind}","degree":{degree:?},"points":[{}]}}}}"#,
        points.join(",")
    )
}

/// The `solid` of a model file made by [`model`]: a node to put in a tree.
fn solid(text: String) -> String {
    let (_, solid) = text.split_once(r#""solid":"#).unwrap();
    solid.strip_suffix('}').unwrap().to_string()
}

/// The regular grid over the unit box with the positions of its control points shuffled among
/// them and ξ random: a net that folds over itself everywhere.
fn shuffled(rng: &mut Rng, degree: &[usize]) -> String {
    shuffled_at(rng, degree, 0.0)
}

/// [`shuffled`] over the unit box moved by `x` along the first axis.
fn shuffled_at(rng: &mut Rng, degree: &[usize], x: f64) -> String {
    shuffled_by(rng, degree, &[x])
}

/// [`shuffled`] over the unit box moved by `offset` (its first coordinates).
fn shuffled_by(rng: &mut Rng, degree: &[usize], offset: &[f64]) -> String {
    let dims: Vec<usize> = degree.iter().map(|d| d + 1).collect();
    let count: usize = dims.iter().product();
    let mut spots: Vec<Vec<f64>> = (0..count)
        .map(|mut index| {
            let mut at = vec![0.0; dims.len()];
            for a in (0..dims.len()).rev() {
                at[a] = (index % dims[a]) as f64 / degree[a] as f64;
                index /= dims[a];
            }
            at
        })
        .collect();
    for k in (1..count).rev() {
        let j = (rng.unit() * (k + 1) as f64) as usize;
        spots.swap(k, j.min(k));
    }
    for s in &mut spots {
        for (c, o) in s.iter_mut().zip(offset) {
            *c += o;
        }
        s.push(rng.unit() * 2.0 - 1.0);
    }
    model(degree, &spots)
}

/// The regular unit grid of `degree` with random ξ.
fn regular(rng: &mut Rng, degree: &[usize]) -> Vec<Vec<f64>> {
    let dims: Vec<usize> = degree.iter().map(|d| d + 1).collect();
    let count: usize = dims.iter().product();
    (0..count)
        .map(|mut index| {
            let mut at = vec![0.0; dims.len()];
            for a in (0..dims.len()).rev() {
                at[a] = (index % dims[a]) as f64 / degree[a] as f64;
                index /= dims[a];
            }
            at.push(rng.unit() * 2.0 - 1.0);
            at
        })
        .collect()
}

/// Runs `bezsolid args` within `limit` and gives its stdout; it must succeed.
fn run_within(args: &[&str], limit: Duration) -> String {
    let out = bezsolid_bounded(args, Feed::Nothing, 2048, limit);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "bezsolid {args:?} failed: {err}");
    String::from_utf8(out.stdout).unwrap()
}

/// The numbers of the `points` attributes and `d` paths of an SVG, all finite.
fn svg_numbers(path: &std::path::Path) -> usize {
    let svg = std::fs::read_to_string(path).unwrap();
    let mut count = 0;
    for token in svg.split(|c: char| c == '"' || c == ' ' || c == ',' || c.is_ascii_alphabetic()) {
        if let Ok(v) = token.parse::<f64>() {
            assert!(v.is_finite(), "{token} in {}", path.display());
            count += 1;
        }
    }
    count
}

#[test]
fn contours_of_folded_patches_finish_within_their_budget() {
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    // A degree-14×2 corner net: the first corner pulled over the opposite one.
    let mut corner = regular(&mut rng, &[14, 2]);
    corner[0][0] = 1.5;
    corner[0][1] = 1.5;
    let cases = [
        ("shuffled 6×6", shuffled(&mut rng, &[6, 6])),
        ("corner 14×2", model(&[14, 2], &corner)),
        ("shuffled 16×16", shuffled(&mut rng, &[16, 16])),
    ];
    for (name, text) in cases {
        let file = scratch(&format!("{name}.bsolid.json"), &text);
        let svg = out_path(&format!("{name}.svg"));
        // The budget at the default resolution (256) is 2 s on one core.
        run_within(
            &[
                "contour",
                file.to_str().unwrap(),
                "-o",
                svg.to_str().unwrap(),
            ],
            Duration::from_secs(8),
        );
        assert!(svg_numbers(&svg) > 8, "{name}: no contour drawn");
    }
}

#[test]
fn folded_volumes_mesh_and_evaluate_within_their_budget() {
    let mut rng = Rng(0x2545_f491_4f6c_dd1d);
    let flat = scratch("shuffled-661.bsolid.json", &shuffled(&mut rng, &[6, 6, 1]));
    let big = scratch(
        "shuffled-16.bsolid.json",
        &shuffled(&mut rng, &[16, 16, 16]),
    );
    let stl = out_path("folded.stl");
    // Resolution 64: the budget is 30 s.
    run_within(
        &[
            "mesh",
            flat.to_str().unwrap(),
            "--res",
            "64",
            "-o",
            stl.to_str().unwrap(),
        ],
        Duration::from_secs(30),
    );
    assert!(std::fs::metadata(&stl).unwrap().len() > 84);
    // The degree-16 volume at resolution 8 took 35 s, and 7 points 5.4 s.
    run_within(
        &[
            "mesh",
            big.to_str().unwrap(),
            "--res",
            "8",
            "-o",
            stl.to_str().unwrap(),
        ],
        Duration::from_secs(10),
    );
    let mut points = String::new();
    for _ in 0..7 {
        let p: Vec<f64> = (0..3).map(|_| rng.unit() * 0.6 + 0.2).collect();
        writeln!(points, "{},{},{}", p[0], p[1], p[2]).unwrap();
    }
    let csv = scratch("seven.csv", &points);
    let out = run_within(
        &[
            "eval",
            big.to_str().unwrap(),
            "--points",
            csv.to_str().unwrap(),
        ],
        Duration::from_secs(5),
    );
    let rows: Vec<&str> = out.lines().skip(1).collect();
    assert_eq!(rows.len(), 7);
    for row in rows {
        let f: f64 = row.split(',').nth(3).unwrap().parse().unwrap();
        assert!(f.is_finite(), "{row}");
    }
}

#[test]
fn the_contour_stack_of_a_folded_volume_is_cheap() {
    // The 3D view's stack draws each control slice's contour at 48 cells; on a folded
    // degree-(6, 6, 1) volume it cost 38 s. Its two slices across w, as the patches they are.
    let mut rng = Rng(0x94d0_49bb_1331_11eb);
    let text = shuffled(&mut rng, &[6, 6, 1]);
    let json: Vec<Vec<f64>> = {
        let start = text.find("\"points\":").unwrap() + 9;
        let end = text.len() - 2;
        let inner = &text[start..end];
        inner
            .trim_matches(|c| c == '[' || c == ']')
            .split("],[")
            .map(|p| p.split(',').map(|v| v.parse().unwrap()).collect())
            .collect()
    };
    for k in 0..2 {
        // Point (i, j, k) is at (i·7 + j)·2 + k; the slice keeps x, y and ξ.
        let slice: Vec<Vec<f64>> = (0..49)
            .map(|ij| {
                let p = &json[ij * 2 + k];
                vec![p[0], p[1], p[3]]
            })
            .collect();
        let file = scratch(&format!("slice-{k}.bsolid.json"), &model(&[6, 6], &slice));
        let svg = out_path(&format!("slice-{k}.svg"));
        run_within(
            &[
                "contour",
                file.to_str().unwrap(),
                "--res",
                "48",
                "--accuracy",
                "1e-7",
                "-o",
                svg.to_str().unwrap(),
            ],
            Duration::from_secs(2),
        );
    }
}

#[test]
fn eval_on_a_folded_patch_takes_20k_points_a_second() {
    let mut rng = Rng(0xd1b5_4a32_d192_ed03);
    // A net folded everywhere, and a regular degree-16 net with one control point swapped with
    // its diagonal neighbour (a fold in one corner of an otherwise regular map: 10⁶ points took
    // 119 s).
    let mut swapped = regular(&mut rng, &[16, 16]);
    let (a, b) = (3 * 17 + 4, 4 * 17 + 5);
    let (pa, pb) = (swapped[a][..2].to_vec(), swapped[b][..2].to_vec());
    swapped[a][..2].copy_from_slice(&pb);
    swapped[b][..2].copy_from_slice(&pa);
    let cases = [
        ("shuffled", shuffled(&mut rng, &[6, 6])),
        ("one-swap", model(&[16, 16], &swapped)),
    ];
    let mut points = String::new();
    for _ in 0..100_000 {
        let (x, y) = (rng.unit() * 1.2 - 0.1, rng.unit() * 1.2 - 0.1);
        writeln!(points, "{x},{y}").unwrap();
    }
    let csv = scratch("eval-folded.csv", &points);
    for (name, text) in cases {
        let file = scratch(&format!("eval-{name}.bsolid.json"), &text);
        // 100 000 points in 5 s is 20 000 a second; the limit has room for a loaded machine.
        let out = run_within(
            &[
                "eval",
                file.to_str().unwrap(),
                "--points",
                csv.to_str().unwrap(),
            ],
            Duration::from_secs(15),
        );
        let mut preimages = 0;
        for row in out.lines().skip(1) {
            let mut fields = row.split(',').skip(2);
            let f: f64 = fields.next().unwrap().parse().unwrap();
            assert!(f.is_finite(), "{name}: {row}");
            preimages += fields.next().unwrap().parse::<usize>().unwrap();
        }
        assert!(
            preimages > 1000,
            "{name}: the net should cover part of the box"
        );
    }
}

#[test]
fn no_finite_point_gives_nan() {
    let mut rng = Rng(0xbf58_476d_1ce4_e5b9);
    // A regular degree-16 patch far away (its Bernstein terms overflow), and a 2×2 net in a box
    // 2e-300 wide.
    let big = scratch(
        "regular-16.bsolid.json",
        &model(&[16, 16], &regular(&mut rng, &[16, 16])),
    );
    let tiny: Vec<Vec<f64>> = regular(&mut rng, &[1, 1])
        .into_iter()
        .map(|p| vec![p[0] * 2e-300, p[1] * 2e-300, p[2]])
        .collect();
    let tiny = scratch("tiny.bsolid.json", &model(&[1, 1], &tiny));
    let csv = scratch(
        "far.csv",
        "1e-300,1e-300\n1e20,0\n-1e300,1e300\n1.7976931348623157e308,-1.7976931348623157e308\n0.5,0.5\n",
    );
    for file in [big, tiny] {
        let out = run_within(
            &[
                "eval",
                file.to_str().unwrap(),
                "--points",
                csv.to_str().unwrap(),
            ],
            Duration::from_secs(10),
        );
        for row in out.lines().skip(1) {
            let fields: Vec<&str> = row.split(',').collect();
            let (x, y, f): (f64, f64, f64) = (
                fields[0].parse().unwrap(),
                fields[1].parse().unwrap(),
                fields[2].parse().unwrap(),
            );
            assert!(f.is_finite(), "{} gives {row}", file.display());
            if x.abs() > 2.0 || y.abs() > 2.0 {
                assert!(f < 0.0, "outside, {row}");
            }
        }
    }
}

/// The three inverse maps of `eval --inverse` find the same preimages: on a net with one point
/// moved (injective) and on one moved so far that it folds, f and the preimages agree point by
/// point; an unknown name is refused with the names it takes.
#[test]
fn the_three_inverse_maps_agree_on_moved_and_folded_nets() {
    let mut rng = Rng(0x5851_f42d_4c95_7f2d);
    let mut points = regular(&mut rng, &[2, 2]);
    // The middle point pulled a little (injective), then the middle column past the last (a
    // fold: x ∈ (1, 1.16) has two preimages).
    for name in ["moved", "folded"] {
        if name == "moved" {
            points[4][0] = 0.65;
        } else {
            for p in &mut points[3..6] {
                p[0] = 1.6;
            }
        }
        let model = scratch(
            &format!("inverse-{name}.bsolid.json"),
            &model(&[2, 2], &points),
        );
        let mut csv = String::new();
        for _ in 0..40 {
            let _ = writeln!(csv, "{},{}", rng.unit() * 1.4 - 0.2, rng.unit() * 1.4 - 0.2);
        }
        let csv = scratch(&format!("inverse-{name}.csv"), &csv);
        let rows: Vec<Vec<Vec<f64>>> = ["paper", "clip", "fast"]
            .iter()
            .map(|method| {
                let out = bezsolid_bounded(
                    &[
                        "eval",
                        model.to_str().unwrap(),
                        "--points",
                        csv.to_str().unwrap(),
                        "--inverse",
                        method,
                    ],
                    Feed::Nothing,
                    1024,
                    Duration::from_secs(60),
                );
                assert!(
                    out.status.success(),
                    "{method}: {}",
                    String::from_utf8_lossy(&out.stderr)
                );
                String::from_utf8(out.stdout)
                    .unwrap()
                    .lines()
                    .skip(1)
                    .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
                    .collect()
            })
            .collect();
        if name == "folded" {
            assert!(
                rows[0].iter().any(|r| r[3] >= 2.0),
                "no point has two preimages"
            );
        }
        for ((paper, clip), fast) in rows[0].iter().zip(&rows[1]).zip(&rows[2]) {
            for other in [clip, fast] {
                assert!(
                    (paper[2] - other[2]).abs() <= 1e-9 * paper[2].abs().max(1.0),
                    "{name} at {:?}: f {} against {}",
                    &paper[..2],
                    paper[2],
                    other[2]
                );
                assert_eq!(paper[3], other[3], "{name} at {:?}: preimages", &paper[..2]);
            }
        }
    }
    let out = bezsolid_bounded(
        &[
            "eval",
            "x.bsolid.json",
            "--points",
            "p.csv",
            "--inverse",
            "newton",
        ],
        Feed::Nothing,
        1024,
        Duration::from_secs(10),
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && err.contains("paper") && err.contains("clip"),
        "{err}"
    );
}

/// A tree of two shuffled degree-16 volumes, meshed where their queries run out of their work
/// budget: closed, and the same on one thread and two (its blocks sample a shared face each, and
/// a query's work depended on the work spent before it: 45 open edges at resolution 16).
#[test]
fn a_tree_of_folded_volumes_meshes_closed_whatever_the_order() {
    let mut rng = Rng(0x94d0_49bb_1331_11eb);
    let (a, b) = (
        solid(shuffled(&mut rng, &[16, 16, 16])),
        solid(shuffled_at(&mut rng, &[16, 16, 16], 0.5)),
    );
    let tree = scratch(
        "two-folded.bsolid.json",
        &format!(
            r#"{{"format":"bezsolid","version":1,"solid":{{"kind":"union","of":[{a},{b}]}}}}"#
        ),
    );
    let mut files = Vec::new();
    for threads in ["1", "2"] {
        let obj = out_path(&format!("two-folded-{threads}.obj"));
        run_within(
            &[
                "mesh",
                tree.to_str().unwrap(),
                "--res",
                "16",
                "--threads",
                threads,
                "-o",
                obj.to_str().unwrap(),
            ],
            Duration::from_secs(60),
        );
        files.push(std::fs::read_to_string(&obj).unwrap());
    }
    assert_eq!(files[0], files[1], "two threads made another mesh");
    let mut mesh = bezsolid_core::mesh::Mesh::default();
    for line in files[0].lines() {
        let w: Vec<&str> = line.split_whitespace().collect();
        match w.first() {
            Some(&"v") => mesh
                .positions
                .push(glam::DVec3::from_array(std::array::from_fn(|k| {
                    w[k + 1].parse().unwrap()
                }))),
            Some(&"f") => mesh.triangles.push(std::array::from_fn(|k| {
                w[k + 1].split('/').next().unwrap().parse::<u32>().unwrap() - 1
            })),
            _ => {}
        }
    }
    assert!(mesh.triangle_count() > 50);
    mesh.check_closed_manifold().unwrap();
}

/// A union of 200 folded (6, 6, 1) volumes side by side, 20 by 10: its leaves share one net's
/// budget of work and atlases (each leaf cut its own atlas and spent its own second of work: 680
/// MB and 5 s before the first point, 14 s of processor time to mesh at resolution 16).
#[test]
fn a_tree_of_many_folded_volumes_shares_one_budget() {
    let mut rng = Rng(0x6a09_e667_f3bc_c909);
    let leaves: Vec<String> = (0..200)
        .map(|k| {
            let at = [0.5 * (k % 20) as f64, 0.5 * (k / 20) as f64];
            solid(shuffled_by(&mut rng, &[6, 6, 1], &at))
        })
        .collect();
    let tree = scratch(
        "two-hundred-folded.bsolid.json",
        &format!(
            r#"{{"format":"bezsolid","version":1,"solid":{{"kind":"union","of":[{}]}}}}"#,
            leaves.join(",")
        ),
    );
    let mut points = String::new();
    for _ in 0..300 {
        let p = [rng.unit() * 10.0, rng.unit() * 5.0, rng.unit()];
        writeln!(points, "{},{},{}", p[0], p[1], p[2]).unwrap();
    }
    let csv = scratch("two-hundred-points.csv", &points);
    let out = bezsolid_bounded(
        &[
            "eval",
            tree.to_str().unwrap(),
            "--points",
            csv.to_str().unwrap(),
        ],
        Feed::Nothing,
        256,
        Duration::from_secs(15),
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    let csv = String::from_utf8(out.stdout).unwrap();
    let mut inside = 0;
    for row in csv.lines().skip(1) {
        let f: f64 = row.split(',').nth(3).unwrap().parse().unwrap();
        assert!(f.is_finite(), "{row}");
        inside += usize::from(f > 0.0);
    }
    assert!(inside > 15, "{inside} of 300 points inside");
    let stl = out_path("two-hundred-folded.stl");
    let out = bezsolid_bounded(
        &[
            "mesh",
            tree.to_str().unwrap(),
            "--res",
            "16",
            "-o",
            stl.to_str().unwrap(),
        ],
        Feed::Nothing,
        256,
        Duration::from_secs(30),
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(std::fs::metadata(&stl).unwrap().len() > 84 + 50 * 50);
}

/// The contour of 60 folded (6, 6) patches side by side, 10 by 6: each tile of the grid samples
/// the few patches near it, not all 60 at every sample (26 s of processor time, now under 3 s).
#[test]
fn the_contour_of_many_folded_patches_samples_the_near_ones() {
    let mut rng = Rng(0x3c6e_f372_fe94_f82b);
    let leaves: Vec<String> = (0..60)
        .map(|k| {
            let at = [(k % 10) as f64, (k / 10) as f64];
            solid(shuffled_by(&mut rng, &[6, 6], &at))
        })
        .collect();
    let tree = scratch(
        "sixty-folded.bsolid.json",
        &format!(
            r#"{{"format":"bezsolid","version":1,"solid":{{"kind":"union","of":[{}]}}}}"#,
            leaves.join(",")
        ),
    );
    let svg = out_path("sixty-folded.svg");
    run_within(
        &[
            "contour",
            tree.to_str().unwrap(),
            "-o",
            svg.to_str().unwrap(),
        ],
        Duration::from_secs(15),
    );
    assert!(svg_numbers(&svg) > 1000, "too few contour vertices");
}
