//! Control nets from bytes, for the targets that evaluate, contour and mesh solids: a regular grid
//! over a box of some size, then edits that move, fold, collapse and line up its points, with ξ of
//! any sign and size; every coordinate within [`Solid2::MAX_COORDINATE`], so every net is valid.

use bezsolid_core::{Patch, Solid2, Solid3, Volume};
use glam::{DVec2, DVec3, DVec4};

use crate::input::Input;

const MAX: f64 = Solid2::MAX_COORDINATE;

/// The spatial part (`S` coordinates per point) and ξ of a net of degree `degree`.
struct Net<const S: usize> {
    degree: [usize; S],
    points: Vec<[f64; S]>,
    xi: Vec<f64>,
}

/// A degree in `1..=max`, mostly at most 6: 15 bytes in 16 give `1..=min(6, max)`, the rest up to
/// `max`.
fn degree(input: &mut Input<'_>, max: usize) -> usize {
    let b = usize::from(input.byte());
    if b < 240 {
        1 + b % max.min(6)
    } else {
        1 + b % max
    }
}

/// A size for a box side or a move: mostly about 1, sometimes tiny or huge.
fn scale(input: &mut Input<'_>) -> f64 {
    match input.below(16) {
        0 => 1e-9,
        1 => 1e-3,
        2 => 1e3,
        3 => 1e9,
        4 => MAX / 4.0,
        5 => f64::MIN_POSITIVE,
        _ => 1.0,
    }
}

/// A value clamped into the accepted range (NaN to 0).
fn clamp(v: f64) -> f64 {
    if v.is_nan() { 0.0 } else { v.clamp(-MAX, MAX) }
}

fn decode<const S: usize>(input: &mut Input<'_>, max_degree: usize) -> Net<S> {
    let degree: [usize; S] = core::array::from_fn(|_| degree(input, max_degree));
    let count: usize = degree.iter().map(|d| d + 1).product();
    let side = scale(input);
    let origin: [f64; S] = core::array::from_fn(|_| clamp(input.signed() * scale(input)));
    let mut points = Vec::with_capacity(count);
    for index in 0..count {
        // The last axis varies fastest, as in the model file.
        let mut rest = index;
        let mut p = [0.0; S];
        for c in (0..S).rev() {
            let i = rest % (degree[c] + 1);
            rest /= degree[c] + 1;
            p[c] = clamp(origin[c] + side * i as f64 / degree[c] as f64);
        }
        points.push(p);
    }
    let xi_scale = scale(input);
    let xi_mode = input.below(4);
    let mut xi: Vec<f64> = (0..count)
        .map(|_| match xi_mode {
            // All one value, with a sign.
            0 => xi_scale * if input.byte() < 128 { 1.0 } else { -1.0 },
            _ => clamp(input.signed() * xi_scale),
        })
        .collect();
    let edits = input.below(12);
    for _ in 0..edits {
        let i = input.index(count);
        let j = input.index(count);
        match input.below(9) {
            // Moved by up to a box side times a scale.
            0 => {
                let s = side * input.unit() * 2.0;
                for x in &mut points[i] {
                    *x = clamp(*x + input.signed() * s);
                }
            }
            // Onto another point.
            1 => points[i] = points[j],
            // Onto the line through two others.
            2 => {
                let k = input.index(count);
                let t = input.signed() * 2.0;
                let (a, b) = (points[j], points[k]);
                points[i] = core::array::from_fn(|c| clamp(a[c] + t * (b[c] - a[c])));
            }
            // Mirrored through another point: the net folds over.
            3 => {
                let (p, m) = (points[i], points[j]);
                points[i] = core::array::from_fn(|c| clamp(2.0 * m[c] - p[c]));
            }
            // One coordinate to the edge of the range.
            4 => {
                let c = input.below(S);
                points[i][c] = if input.byte() < 128 { MAX } else { -MAX };
            }
            // One coordinate to a tiny number (subnormal or smallest normal).
            5 => {
                let c = input.below(S);
                points[i][c] = if input.byte() < 128 {
                    f64::MIN_POSITIVE
                } else {
                    -4.9e-324
                };
            }
            // One coordinate (or ξ) to any number in range.
            6 => {
                let c = input.below(S + 1);
                let v = clamp(input.raw_f64());
                if c == S {
                    xi[i] = v;
                } else {
                    points[i][c] = v;
                }
            }
            // Every point onto one: the whole net collapses.
            7 => {
                let p = points[i];
                points.iter_mut().for_each(|q| *q = p);
            }
            // Two points swap places.
            _ => points.swap(i, j),
        }
    }
    Net { degree, points, xi }
}

/// A patch solid from the bytes, degrees in `1..=max_degree`.
pub(crate) fn solid2(input: &mut Input<'_>, max_degree: usize) -> Solid2 {
    let net = decode::<2>(input, max_degree);
    let points = net
        .points
        .iter()
        .zip(&net.xi)
        .map(|(p, &xi)| DVec2::from_array(*p).extend(xi))
        .collect();
    let patch = Patch::try_new([net.degree[0], net.degree[1]], points)
        .unwrap_or_else(|e| panic!("the decoder made an invalid net: {e}"));
    Solid2::try_from_net(patch)
        .unwrap_or_else(|e| panic!("a net of finite values in range is refused: {e}"))
}

/// A volume solid from the bytes, degrees in `1..=max_degree`.
pub(crate) fn solid3(input: &mut Input<'_>, max_degree: usize) -> Solid3 {
    let net = decode::<3>(input, max_degree);
    let points = net
        .points
        .iter()
        .zip(&net.xi)
        .map(|(p, &xi)| DVec3::from_array(*p).extend(xi))
        .collect::<Vec<DVec4>>();
    let volume = Volume::try_new([net.degree[0], net.degree[1], net.degree[2]], points)
        .unwrap_or_else(|e| panic!("the decoder made an invalid net: {e}"));
    Solid3::try_from_net(volume)
        .unwrap_or_else(|e| panic!("a net of finite values in range is refused: {e}"))
}

/// A query point for a solid whose domain is `[lo, hi]`: inside the box, at a control point,
/// outside the box, or anywhere in range. The second value says whether it is strictly outside
/// the box (by a margin), where `f ≤ 0` and no point has a preimage.
pub(crate) fn query<const S: usize>(
    input: &mut Input<'_>,
    lo: [f64; S],
    hi: [f64; S],
    control: &[[f64; S]],
) -> ([f64; S], bool) {
    let p: [f64; S] = match input.below(8) {
        0 => control[input.index(control.len())],
        1 => core::array::from_fn(|_| clamp(input.raw_f64())),
        2 | 3 => {
            // Past one side of the box on one axis by at least a tenth of the box.
            let axis = input.below(S);
            let mut p: [f64; S] = core::array::from_fn(|c| lo[c] + (hi[c] - lo[c]) * input.unit());
            let size = (hi[axis] - lo[axis]).max(hi[axis].abs().max(lo[axis].abs()) * 1e-6);
            let past = size * (0.1 + input.unit());
            p[axis] = if input.byte() < 128 {
                lo[axis] - past
            } else {
                hi[axis] + past
            };
            p.map(clamp)
        }
        _ => core::array::from_fn(|c| lo[c] + (hi[c] - lo[c]) * input.unit()),
    };
    let outside = (0..S).any(|c| {
        // Relative to the box, and absolute below the normal numbers: the solvers' tolerances
        // have a floor there (a box of subnormal size is a point).
        let margin = (hi[c] - lo[c]) * 1e-6 + hi[c].abs().max(lo[c].abs()) * 1e-9 + 1e-300;
        p[c] < lo[c] - margin || p[c] > hi[c] + margin
    });
    (p, outside)
}
