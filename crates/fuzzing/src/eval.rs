//! The `eval` target: `f` of patch and volume solids on random control nets.

use bezsolid_core::inverse::Method;
use bezsolid_core::{Solid2, Solid3};
use glam::{DVec2, DVec3};

use crate::input::Input;
use crate::net;

/// The most query points of one input.
const MAX_QUERIES: usize = 4;

/// Decodes a patch solid (first byte even) or a volume solid (odd) of degree 1 to 16 per axis
/// (mostly at most 6) with moved, folded, collapsed and lined-up control points and coordinates
/// from tiny to [`Solid2::MAX_COORDINATE`], then evaluates it at a few points: inside its box, at
/// control points, outside its box and anywhere.
///
/// At every point `f` (by each [`Method`] on a net of at most 64 points, by [`Method::Fast`] on
/// larger ones, with its gradient, and on a small grid) is not NaN, nor
/// is the gradient. Strictly outside the box of the control points, which holds the image of the
/// map, `f ≤ 0` and no point has a preimage.
///
/// # Panics
///
/// On a bug: a broken promise above, a valid net refused, or any panic in the evaluation.
pub fn eval(data: &[u8]) {
    let mut input = Input::new(data);
    if input.byte().is_multiple_of(2) {
        patch(&mut input);
    } else {
        volume(&mut input);
    }
}

fn patch(input: &mut Input<'_>) {
    let solid = net::solid2(input, bezsolid_core::MAX_DEGREE);
    let (lo, hi) = solid.domain();
    let control: Vec<[f64; 2]> = solid
        .net()
        .points()
        .iter()
        .map(|p| p.truncate().to_array())
        .collect();
    for _ in 0..1 + input.below(MAX_QUERIES) {
        let (p, outside) = net::query(input, lo.to_array(), hi.to_array(), &control);
        let p = DVec2::from_array(p);
        check2(&solid, p, outside);
    }
}

/// The methods to check on a net of `points` control points: every one on a small net; on a large
/// one only [`Method::Fast`], the one the product uses: whole-domain clipping, the reference,
/// takes seconds there by design.
fn methods(points: usize) -> &'static [Method] {
    if points <= 64 {
        &Method::ALL
    } else {
        &[Method::Fast]
    }
}

fn check2(solid: &Solid2, p: DVec2, outside: bool) {
    for &method in methods(solid.net().points().len()) {
        let v = solid.evaluate(p, method);
        check_value(v.f, v.preimages, outside, method, p);
    }
    let f = solid.f(p);
    check_value(f, 0, outside, Method::Fast, p);
    let (f, g) = solid.f_with_gradient(p);
    assert!(!f.is_nan() && !g.is_nan(), "f {f}, ∇f {g} at {p}");
    for f in solid.f_grid([&[p.x, p.x], &[p.y]]) {
        check_value(f, 0, outside, Method::Fast, p);
    }
}

fn volume(input: &mut Input<'_>) {
    let solid = net::solid3(input, bezsolid_core::MAX_DEGREE);
    let (lo, hi) = solid.domain();
    let control: Vec<[f64; 3]> = solid
        .net()
        .points()
        .iter()
        .map(|p| p.truncate().to_array())
        .collect();
    for _ in 0..1 + input.below(MAX_QUERIES) {
        let (p, outside) = net::query(input, lo.to_array(), hi.to_array(), &control);
        let p = DVec3::from_array(p);
        check3(&solid, p, outside);
    }
}

fn check3(solid: &Solid3, p: DVec3, outside: bool) {
    for &method in methods(solid.net().points().len()) {
        let v = solid.evaluate(p, method);
        check_value(v.f, v.preimages, outside, method, p);
    }
    let f = solid.f(p);
    check_value(f, 0, outside, Method::Fast, p);
    let (f, g) = solid.f_with_gradient(p);
    assert!(!f.is_nan() && !g.is_nan(), "f {f}, ∇f {g} at {p}");
    for f in solid.f_grid([&[p.x, p.x], &[p.y], &[p.z]]) {
        check_value(f, 0, outside, Method::Fast, p);
    }
}

fn check_value(f: f64, preimages: usize, outside: bool, method: Method, p: impl core::fmt::Debug) {
    assert!(!f.is_nan(), "f is NaN at {p:?} ({method:?})");
    if outside {
        assert!(
            f <= 0.0 && preimages == 0,
            "f = {f} with {preimages} preimages at {p:?} ({method:?}), outside the control points' box"
        );
    }
}
