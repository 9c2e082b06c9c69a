//! A HyperFun program as a leaf of a tree: its value within its box, sound bounds and intervals
//! around it, a closed mesh, links and files, and the tree's HyperFun export read back.

use alloc::boxed::Box;
use alloc::format;
use alloc::string::String;
use alloc::vec;
use glam::DVec3;

use crate::hyperfun::read::Program;
use crate::model::{ModelFile, Rotation, SolidSpec as S};
use crate::rfunc::intersect;
use crate::testutil::{Rng, random_point as point, random_tree};
use crate::tree::{ModelTree, Tree};
#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

/// A wavy ball of radius about 0.9, larger than its box along x.
const WAVY: &str = "-- a wavy ball
my_model(x[3], a[1])
{
  r2 = x[1]*x[1] + x[2]*x[2] + x[3]*x[3];
  my_model = 0.8 - r2 + 0.1*sin(5*x[1]);
}";
const BOX: [[f64; 3]; 2] = [[-0.6, -1.0, -1.0], [0.6, 1.0, 1.0]];

fn leaf() -> S {
    S::Hyperfun {
        program: WAVY.into(),
        bounds: Some(BOX),
    }
}

fn space(spec: S) -> Tree<3> {
    match ModelFile::from_spec(spec).to_tree().unwrap() {
        ModelTree::Space(t) => t,
        ModelTree::Plane(_) => panic!("2D"),
    }
}

fn program_value(p: [f64; 3]) -> f64 {
    Program::parse(WAVY).unwrap().eval(p).unwrap()
}

fn box_value(p: [f64; 3]) -> f64 {
    let s = |i: usize| (p[i] - BOX[0][i]) * (BOX[1][i] - p[i]);
    intersect(intersect(s(0), s(1)), s(2))
}

#[test]
fn a_leaf_is_its_program_cut_by_its_box() {
    let far = S::Sphere {
        center: [5.0, 5.0, 5.0],
        radius: 0.5,
    };
    let tree = space(S::Union {
        of: vec![leaf(), far.clone()],
    });
    let sphere = space(far);
    let mut rng = Rng::new(3);
    for _ in 0..500 {
        let p = point(&mut rng, 1.2);
        let want = crate::rfunc::union(
            intersect(program_value(p), box_value(p)),
            sphere.f(DVec3::from_array(p)),
        );
        let got = tree.f(DVec3::from_array(p));
        assert!(
            (got - want).abs() <= 1e-12 * want.abs().max(1.0),
            "{p:?}: {got} vs {want}"
        );
    }
    // Inside the program, outside its box: outside.
    assert!(program_value([0.8, 0.0, 0.0]) > 0.0);
    assert!(tree.f(DVec3::new(0.8, 0.0, 0.0)) < 0.0);
    assert!(tree.f(DVec3::ZERO) > 0.0);
}

#[test]
fn bounds_and_intervals_hold_around_hyperfun_leaves() {
    let mut rng = Rng::new(21);
    for k in 0..24 {
        let other = random_tree(&mut rng, 2);
        let placed = S::Transform {
            solid: Box::new(leaf()),
            translate: Some(point(&mut rng, 0.5).to_vec()),
            rotate: Some(Rotation::Angles(point(&mut rng, 180.0))),
            scale: Some(vec![
                rng.range(0.6, 1.4),
                rng.range(0.6, 1.4),
                rng.range(0.6, 1.4),
            ]),
        };
        let spec = match k % 3 {
            0 => S::Union {
                of: vec![placed, other],
            },
            1 => S::Intersection {
                of: vec![other, placed],
            },
            _ => S::Difference {
                of: vec![placed, other],
            },
        };
        let tree = space(spec);
        let (lo, hi) = tree.bounds().expect("a bounded tree");
        for _ in 0..400 {
            let p = point(&mut rng, 3.0);
            if tree.f(DVec3::from_array(p)) > 0.0 {
                assert!(
                    (0..3).all(|i| lo[i] <= p[i] && p[i] <= hi[i]),
                    "{p:?} outside {lo:?}..{hi:?}"
                );
            }
        }
        for _ in 0..10 {
            let c = point(&mut rng, 1.5);
            let h: [f64; 3] = core::array::from_fn(|_| rng.range(0.01, 0.8));
            let lo: [f64; 3] = core::array::from_fn(|i| c[i] - h[i]);
            let hi: [f64; 3] = core::array::from_fn(|i| c[i] + h[i]);
            let range = tree.interval(lo, hi);
            for _ in 0..30 {
                let p: [f64; 3] = core::array::from_fn(|i| rng.range(lo[i], hi[i]));
                let f = tree.f(DVec3::from_array(p));
                let slack = 1e-9 * f.abs().max(1.0);
                assert!(
                    range.lo - slack <= f && f <= range.hi + slack,
                    "{p:?}: {f} outside {range:?}"
                );
            }
        }
    }
}

#[test]
fn a_tree_with_a_hyperfun_leaf_meshes_closed() {
    let tree = space(S::Difference {
        of: vec![
            leaf(),
            S::Sphere {
                center: [0.0, 0.0, 0.9],
                radius: 0.5,
            },
        ],
    });
    let mesh = tree.polygonize(24, 1e-9, None).unwrap();
    mesh.check_closed_manifold().unwrap();
    assert!(mesh.triangle_count() > 500);
    // Every vertex lies on the surface: the tree's value there is near zero.
    for p in &mesh.positions {
        assert!(tree.f(*p).abs() < 1e-3, "{p}: {}", tree.f(*p));
    }
}

#[test]
fn a_hyperfun_leaf_travels_in_files_and_links() {
    let file = ModelFile::from_spec(S::Union {
        of: vec![
            leaf(),
            S::Hyperfun {
                program: WAVY.into(),
                bounds: None,
            },
        ],
    });
    let link = crate::link::encode(&file).unwrap();
    assert_eq!(crate::link::decode_file(&link).unwrap(), file);
    #[cfg(feature = "serde")]
    {
        let json = serde_json::to_string(&file).unwrap();
        let back: ModelFile = serde_json::from_str(&json).unwrap();
        assert_eq!(back, file);
    }
    // A program HyperFun refuses is refused at its node, with HyperFun's message.
    let bad = ModelFile::from_spec(S::Union {
        of: vec![
            S::Sphere {
                center: [0.0; 3],
                radius: 1.0,
            },
            S::Hyperfun {
                program: "my_model(x[3], a[1]) { s = 1; my_model = s; }".into(),
                bounds: None,
            },
        ],
    });
    let err = format!("{}", bad.to_tree().unwrap_err());
    assert!(
        err.contains("solid.of[1].program") && err.contains("Left bracket expected"),
        "{err}"
    );
    let bad_box = ModelFile::from_spec(S::Union {
        of: vec![
            leaf(),
            S::Hyperfun {
                program: WAVY.into(),
                bounds: Some([[0.0; 3], [0.0, 1.0, 1.0]]),
            },
        ],
    });
    let err = format!("{}", bad_box.to_tree().unwrap_err());
    assert!(err.contains("solid.of[1].box"), "{err}");
}

#[test]
fn the_trees_hyperfun_export_calls_the_leaf_and_agrees() {
    // Two leaves (their bodies both named my_model, renamed apart), one moved.
    let spec = S::BlendUnion {
        of: vec![
            leaf(),
            S::Transform {
                solid: Box::new(leaf()),
                translate: Some(vec![1.0, 0.2, 0.0]),
                rotate: None,
                scale: None,
            },
        ],
        a0: 0.1,
        a1: 1.0,
        a2: 1.0,
    };
    let file = ModelFile::from_spec(spec.clone());
    let text = crate::hyperfun::tree_hf(&file).unwrap();
    let program = Program::parse(&text).unwrap();
    assert_eq!(program.body(), "my_model");
    let names: vec::Vec<String> = program.body_names().map(String::from).collect();
    assert_eq!(names.len(), 3, "{names:?}");
    let tree = space(spec);
    let mut rng = Rng::new(8);
    for _ in 0..300 {
        let p = point(&mut rng, 2.0);
        let want = tree.f(DVec3::from_array(p));
        let got = program.eval(p).unwrap();
        assert!(
            (got - want).abs() <= 1e-9 * want.abs().max(1.0),
            "{p:?}: {got} vs {want}"
        );
    }
    // The export opens back as the model it came from.
    assert_eq!(crate::hyperfun::model_of(&text).unwrap().unwrap(), file);
}

#[test]
fn a_leafs_work_is_capped_and_shared_by_a_plan() {
    // 40,000 loops a point: within a point's own cap, past a plan's share of a million points.
    let slow = "my_model(x[3], a[1])\n{\n  i = 0;\n  while i < 10000 loop i = i + 1; endloop;\n  \
                my_model = 1 - x[1]*x[1] - x[2]*x[2] - x[3]*x[3];\n}";
    let tree = space(S::Union {
        of: vec![
            S::Hyperfun {
                program: slow.into(),
                bounds: Some([[-2.0; 3], [2.0; 3]]),
            },
            S::Sphere {
                center: [9.0; 3],
                radius: 0.5,
            },
        ],
    });
    let v = tree.evaluate(DVec3::ZERO);
    assert!(v.f > 0.0 && !v.exhausted, "{v:?}");
    tree.plan(1_000_000);
    let v = tree.evaluate(DVec3::ZERO);
    assert!(
        v.exhausted && v.f < 0.0,
        "past its share: outside, and said: {v:?}"
    );
    tree.plan(100);
    assert!(!tree.evaluate(DVec3::ZERO).exhausted);
    // An endless loop stops at the point's cap.
    let endless = "my_model(x[3], a[1]) { i = 0; while 1 loop i = i + 1; endloop; my_model = i; }";
    let tree = space(S::Union {
        of: vec![
            S::Hyperfun {
                program: endless.into(),
                bounds: None,
            },
            leaf(),
        ],
    });
    assert!(tree.evaluate(DVec3::ZERO).exhausted);
}

#[test]
fn a_part_is_a_model_of_a_point_and_one_parameter_within_a_memory_cap() {
    let refused = |program: &str| {
        let file = ModelFile::from_spec(S::Union {
            of: vec![
                leaf(),
                S::Hyperfun {
                    program: program.into(),
                    bounds: None,
                },
            ],
        });
        format!("{}", file.to_tree().unwrap_err())
    };
    let err = refused("m(x[2], a[1]) { m = 1 - x[1]*x[1]; }");
    assert!(
        err.contains("solid.of[1].program") && err.contains("x[2]"),
        "{err}"
    );
    let err = refused("m(x[3], a[2]) { m = 1; }");
    assert!(err.contains("a[2]"), "{err}");
    let err = refused("m(x[3], a[1]) { array big[100000]; big[1] = 1; m = big[1]; }");
    assert!(err.contains("at most 65536"), "{err}");
}
