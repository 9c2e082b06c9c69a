//! The `tree` target: models of many solids with numbers at the edges of what a tree accepts.

use bezsolid_core::model::{CoordAxis, ModelFile, Rotation, SolidSpec};
use bezsolid_core::tree::{ModelTree, Tree, TreeMeshError};
use glam::DVec3;

use crate::input::Input;

/// The deepest tree decoded.
const DEPTH: usize = 4;

/// Decodes a 3D tree of spheres, boxes, tori, cylinders, half-spaces and regular piecewise
/// volumes under unions, intersections, differences, blends, morphs and transforms, with every
/// number from the edges of the accepted range (`1e-12` and `1e12` in magnitude, just past them,
/// 0, ordinary sizes, any double), then checks what every accepted tree promises:
///
/// - `f` and its gradient are finite at every finite point, to `±f64::MAX`;
/// - every point where `f > 0` lies within the tree's bounds;
/// - a bounded tree of finite bounds meshes, coarsely, to a closed manifold, or says it lost the
///   solid with an inside point where `f > 0`.
///
/// # Panics
///
/// On a bug: a broken promise above, or any panic in the building, evaluation or meshing.
pub fn tree(data: &[u8]) {
    let mut input = Input::new(data);
    let spec = node(&mut input, DEPTH);
    let Ok(ModelTree::Space(tree)) = ModelFile::from_spec(spec).to_tree() else {
        return;
    };
    let bounds = tree.bounds();
    for _ in 0..8 {
        let p = DVec3::from_array(core::array::from_fn(|_| far(&mut input)));
        check_point(&tree, p, bounds);
    }
    // Points in and about the bounds, where the solid is.
    if let Some((lo, hi)) = bounds.filter(|(lo, hi)| (0..3).all(|i| lo[i] <= hi[i])) {
        for _ in 0..24 {
            let p = DVec3::from_array(core::array::from_fn(|i| {
                let t = 1.2 * input.unit() - 0.1;
                lo[i] + t * (hi[i] - lo[i])
            }));
            if p.is_finite() {
                check_point(&tree, p, bounds);
            }
        }
        let finite = lo
            .iter()
            .chain(&hi)
            .all(|v| v.is_finite() && v.abs() < 1e12);
        if finite {
            match tree.polygonize(6, 1e-9, None) {
                Ok(mesh) => assert!(
                    mesh.check_closed_manifold().is_ok(),
                    "a tree's mesh is not closed"
                ),
                Err(TreeMeshError::Lost { at, f, .. }) => {
                    assert!(
                        f > 0.0 && tree.f(DVec3::from_array(at)) == f,
                        "lost at {at:?}"
                    );
                }
                Err(e) => panic!("a bounded tree does not mesh: {e}"),
            }
        }
    }
}

fn check_point(tree: &Tree<3>, p: DVec3, bounds: Option<([f64; 3], [f64; 3])>) {
    let f = tree.f(p);
    assert!(f.is_finite(), "f = {f} at {p}");
    let (_, g) = tree.f_with_gradient(p);
    assert!(g.is_finite(), "∇f = {g} at {p}");
    if let Some((lo, hi)) = bounds
        && f > 0.0
    {
        // To rounding at the bounds' own magnitude.
        let slack = |v: f64| 1e-9 * (1.0 + v.abs());
        assert!(
            (0..3).all(|i| lo[i] - slack(lo[i]) <= p[i] && p[i] <= hi[i] + slack(hi[i])),
            "f = {f} > 0 at {p}, outside the bounds {lo:?} .. {hi:?}"
        );
    }
}

/// A magnitude from the edges of the accepted range, an ordinary one, or any double.
fn magnitude(input: &mut Input<'_>) -> f64 {
    let m = match input.below(10) {
        0 => 1e-12,
        1 => 1e-12 * 0.99,
        2 => 1e12,
        3 => 1e12 * 1.01,
        4 => 1e-6,
        5 => 1e6,
        6 => 0.0,
        7 => return input.raw_f64(),
        _ => 1.0,
    };
    m * (0.25 + 3.0 * input.unit())
}

fn signed(input: &mut Input<'_>) -> f64 {
    let m = magnitude(input);
    if input.byte() & 1 == 0 { m } else { -m }
}

/// A point's coordinate: any of [`signed`], or far past every solid, to `±f64::MAX`.
fn far(input: &mut Input<'_>) -> f64 {
    let m = match input.below(6) {
        0 => f64::MAX,
        1 => 1e300,
        2 => 2e154,
        3 => 1e100,
        _ => return signed(input),
    };
    if input.byte() & 1 == 0 { m } else { -m }
}

fn point(input: &mut Input<'_>) -> [f64; 3] {
    core::array::from_fn(|_| signed(input))
}

fn axis(input: &mut Input<'_>) -> CoordAxis {
    [CoordAxis::X, CoordAxis::Y, CoordAxis::Z][input.below(3)]
}

fn node(input: &mut Input<'_>, depth: usize) -> SolidSpec {
    let choice = input.below(if depth == 0 { 6 } else { 13 });
    let two = |input: &mut Input<'_>| vec![node(input, depth - 1), node(input, depth - 1)];
    match choice {
        0 => SolidSpec::Sphere {
            center: point(input),
            radius: magnitude(input),
        },
        1 => {
            let (c, h) = (point(input), point(input));
            SolidSpec::Box {
                min: core::array::from_fn(|i| c[i] - h[i].abs()),
                max: core::array::from_fn(|i| c[i] + h[i].abs()),
            }
        }
        2 => SolidSpec::Torus {
            center: point(input),
            axis: axis(input),
            major: magnitude(input),
            minor: magnitude(input),
        },
        3 => SolidSpec::Cylinder {
            center: point(input),
            axis: axis(input),
            radius: magnitude(input),
        },
        4 => SolidSpec::Halfspace {
            normal: point(input),
            offset: signed(input),
        },
        5 => piecewise(input),
        6 => SolidSpec::Union { of: two(input) },
        7 => SolidSpec::Intersection { of: two(input) },
        8 => SolidSpec::Difference { of: two(input) },
        9 | 10 => {
            let of = two(input);
            let (a0, a1, a2) = (signed(input), signed(input), signed(input));
            if choice == 9 {
                SolidSpec::BlendUnion { of, a0, a1, a2 }
            } else {
                SolidSpec::BlendIntersection { of, a0, a1, a2 }
            }
        }
        11 => SolidSpec::Morph {
            of: two(input),
            t: signed(input),
        },
        _ => SolidSpec::Transform {
            solid: Box::new(node(input, depth - 1)),
            translate: Some(point(input).to_vec()),
            rotate: Some(Rotation::Angles(core::array::from_fn(|_| {
                360.0 * input.signed()
            }))),
            scale: Some(point(input).to_vec()),
        },
    }
}

/// A regular piecewise volume of 1 to 2 cells per axis, degree 1, over a box of extreme
/// corners, with extreme ξ.
fn piecewise(input: &mut Input<'_>) -> SolidSpec {
    let cells: Vec<usize> = (0..3).map(|_| 1 + input.below(2)).collect();
    let (lo, size) = (point(input), point(input));
    let count: usize = cells.iter().map(|c| c + 1).product();
    let points = (0..count)
        .map(|k| {
            let at = [
                k / ((cells[1] + 1) * (cells[2] + 1)),
                k / (cells[2] + 1) % (cells[1] + 1),
                k % (cells[2] + 1),
            ];
            let mut p: Vec<f64> = (0..3)
                .map(|i| lo[i] + size[i].abs() * at[i] as f64 / cells[i] as f64)
                .collect();
            p.push(signed(input));
            p
        })
        .collect();
    SolidSpec::Piecewise {
        cells,
        degree: vec![1; 3],
        points,
    }
}
