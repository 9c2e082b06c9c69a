//! The injectivity certificate: `det J` one-signed on the parameter box (its Bernstein
//! coefficients, refined by subdivision) and the image of the box's boundary simple (see the
//! [module documentation](super)).

use alloc::vec::Vec;

use super::clip::Bernstein;
use crate::bernstein::binomial;
use crate::tensor::multi_index;

/// Scalar tensor-product Bernstein polynomial.
struct Poly<const D: usize> {
    dims: [usize; D],
    c: Vec<f64>,
}

/// The most multiply-adds spent on the Bernstein form of `det J`.
const MAX_WORK: usize = 40_000_000;

fn derivative<const D: usize>(t: &Bernstein<D, D>, axis: usize, comp: usize) -> Poly<D> {
    let mut dims = t.dims;
    dims[axis] -= 1;
    let n = (t.dims[axis] - 1) as f64;
    let stride: usize = t.dims[axis + 1..].iter().product();
    let total: usize = dims.iter().product();
    let c = (0..total)
        .map(|index| {
            let idx = multi_index(dims, index);
            let flat = idx.iter().zip(t.dims).fold(0, |acc, (&i, d)| acc * d + i);
            n * (t.coefs[flat + stride][comp] - t.coefs[flat][comp])
        })
        .collect();
    Poly { dims, c }
}

fn mul<const D: usize>(a: &Poly<D>, b: &Poly<D>) -> Poly<D> {
    let dims: [usize; D] = core::array::from_fn(|x| a.dims[x] + b.dims[x] - 1);
    let total: usize = dims.iter().product();
    let mut c = alloc::vec![0.0; total];
    let scaled = |p: &Poly<D>| -> Vec<(f64, [usize; D])> {
        p.c.iter()
            .enumerate()
            .map(|(index, v)| {
                let idx = multi_index(p.dims, index);
                let w = (0..D).fold(1.0, |w, x| w * binomial(p.dims[x] - 1, idx[x]));
                (v * w, idx)
            })
            .collect()
    };
    let (sa, sb) = (scaled(a), scaled(b));
    for (va, ia) in &sa {
        for (vb, ib) in &sb {
            let flat = (0..D).fold(0, |acc, x| acc * dims[x] + ia[x] + ib[x]);
            c[flat] += va * vb;
        }
    }
    for (index, v) in c.iter_mut().enumerate() {
        let idx = multi_index(dims, index);
        *v /= (0..D).fold(1.0, |w, x| w * binomial(dims[x] - 1, idx[x]));
    }
    Poly { dims, c }
}

/// `det J` in Bernstein form, `None` when that costs more than [`MAX_WORK`].
fn det_j<const D: usize>(t: &Bernstein<D, D>) -> Option<Poly<D>> {
    let d = |axis: usize, comp: usize| derivative(t, axis, comp);
    let size = |p: &Poly<D>| p.c.len();
    let first = size(&d(0, 0));
    // Two products of two factors in 2D; six of three in 3D, the second factor 8 times larger.
    let work = first * first * if D == 2 { 2 } else { 54 };
    if work > MAX_WORK {
        return None;
    }
    let terms: &[([usize; 3], f64)] = if D == 2 {
        &[([0, 1, 0], 1.0), ([1, 0, 0], -1.0)]
    } else {
        &[
            ([0, 1, 2], 1.0),
            ([1, 2, 0], 1.0),
            ([2, 0, 1], 1.0),
            ([0, 2, 1], -1.0),
            ([2, 1, 0], -1.0),
            ([1, 0, 2], -1.0),
        ]
    };
    let mut sum: Option<Poly<D>> = None;
    for (perm, sign) in terms {
        // Component r differentiated along axis perm[r].
        let mut prod = d(perm[0], 0);
        for (r, &axis) in perm.iter().enumerate().take(D).skip(1) {
            prod = mul(&prod, &d(axis, r));
        }
        match &mut sum {
            None => {
                prod.c.iter_mut().for_each(|v| *v *= sign);
                sum = Some(prod);
            }
            Some(s) => {
                s.c.iter_mut()
                    .zip(&prod.c)
                    .for_each(|(a, b)| *a += sign * b);
            }
        }
    }
    sum
}

/// Whether `det J` keeps one strict sign on the box, by its Bernstein coefficients refined by
/// subdivision (at most 256 boxes).
fn one_signed<const D: usize>(det: Poly<D>) -> bool {
    let corner = det.c[0];
    if corner == 0.0 {
        return false;
    }
    let sign = corner.signum();
    let mut line = Vec::new();
    let mut stack = alloc::vec![Bernstein::<D, 1> {
        dims: det.dims,
        coefs: det.c.iter().map(|&v| [v * sign]).collect(),
    }];
    let mut boxes = 0;
    while let Some(t) = stack.pop() {
        boxes += 1;
        if boxes > 256 {
            return false;
        }
        let min = t.coefs.iter().fold(f64::INFINITY, |m, c| m.min(c[0]));
        if min > 0.0 {
            continue;
        }
        // A vertex coefficient is a value of det J: a sign change is certain.
        let max_index = t.coefs.len() - 1;
        if t.coefs[0][0] <= 0.0 || t.coefs[max_index][0] <= 0.0 {
            return false;
        }
        let axis = (0..D).max_by_key(|&a| t.dims[a]).unwrap_or(0);
        let (mut l, mut r) = (t.clone(), t);
        l.restrict(axis, 0.0, 0.5, &mut line);
        r.restrict(axis, 0.5, 1.0, &mut line);
        stack.push(l);
        stack.push(r);
    }
    true
}

/// A piece of the parameter box's boundary: its parameter box (one coordinate fixed) and the
/// spatial bounds of its image.
struct Piece<const D: usize> {
    lo: [f64; D],
    hi: [f64; D],
    xlo: [f64; D],
    xhi: [f64; D],
    /// The hodograph vectors of a curve piece (2D only), for the monotonicity test.
    tangents: Vec<[f64; D]>,
}

/// The boundary of the box cut into `2^level` pieces per free axis of each face.
fn pieces<const D: usize>(t: &Bernstein<D, D>, level: u32) -> Vec<Piece<D>> {
    let mut out = Vec::new();
    let cuts = 1usize << level;
    for axis in 0..D {
        for side in [0usize, 1] {
            // The face u_axis = side as a net over the other D − 1 axes, cut into pieces.
            let free: Vec<usize> = (0..D).filter(|&a| a != axis).collect();
            let face_index = |idx: &[usize]| {
                let mut full = [0usize; D];
                for (k, &a) in free.iter().enumerate() {
                    full[a] = idx[k];
                }
                full[axis] = side * (t.dims[axis] - 1);
                (0..D).fold(0, |acc, x| acc * t.dims[x] + full[x])
            };
            for piece in 0..cuts.pow((D - 1) as u32) {
                let mut pidx = [0usize; 2];
                let mut rest = piece;
                for k in (0..D - 1).rev() {
                    pidx[k] = rest % cuts;
                    rest /= cuts;
                }
                let mut lo = [0.0; D];
                let mut hi = [1.0; D];
                lo[axis] = side as f64;
                hi[axis] = side as f64;
                for (k, &a) in free.iter().enumerate() {
                    lo[a] = pidx[k] as f64 / cuts as f64;
                    hi[a] = (pidx[k] + 1) as f64 / cuts as f64;
                }
                let (xlo, xhi, tangents) = if D == 2 {
                    let n = t.dims[free[0]];
                    let mut c = Bernstein::<1, D> {
                        dims: [n],
                        coefs: (0..n).map(|i| t.coefs[face_index(&[i])]).collect(),
                    };
                    let mut line = Vec::new();
                    c.restrict(0, lo[free[0]], hi[free[0]], &mut line);
                    let tangents = c
                        .coefs
                        .windows(2)
                        .map(|w| core::array::from_fn(|e| w[1][e] - w[0][e]))
                        .collect();
                    let (a, b) = super::bounds(&c.coefs);
                    (a, b, tangents)
                } else {
                    let (n0, n1) = (t.dims[free[0]], t.dims[free[1]]);
                    let mut c = Bernstein::<2, D> {
                        dims: [n0, n1],
                        coefs: (0..n0 * n1)
                            .map(|f| t.coefs[face_index(&[f / n1, f % n1])])
                            .collect(),
                    };
                    let mut line = Vec::new();
                    c.restrict(0, lo[free[0]], hi[free[0]], &mut line);
                    c.restrict(1, lo[free[1]], hi[free[1]], &mut line);
                    let (a, b) = super::bounds(&c.coefs);
                    (a, b, Vec::new())
                };
                out.push(Piece {
                    lo,
                    hi,
                    xlo,
                    xhi,
                    tangents,
                });
            }
        }
    }
    out
}

/// Whether the tangents of two curve pieces all lie in one open half-plane (the pieces form
/// one curve monotone in that direction).
fn jointly_monotone<const D: usize>(a: &Piece<D>, b: &Piece<D>) -> bool {
    let vs: Vec<[f64; D]> = a.tangents.iter().chain(&b.tangents).copied().collect();
    let norm = |v: &[f64; D]| crate::math::sqrt(v.iter().map(|x| x * x).sum());
    let mut d = [0.0; D];
    for v in &vs {
        let l = norm(v);
        if l == 0.0 {
            return false;
        }
        for c in 0..D {
            d[c] += v[c] / l;
        }
    }
    vs.iter()
        .all(|v| (0..D).map(|c| v[c] * d[c]).sum::<f64>() > 1e-9 * norm(v))
}

fn boundary_simple<const D: usize>(t: &Bernstein<D, D>) -> bool {
    let levels = if D == 2 { 1..=6 } else { 1..=3 };
    'level: for level in levels {
        let ps = pieces(t, level);
        for (i, a) in ps.iter().enumerate() {
            for b in &ps[i + 1..] {
                let adjacent = (0..D).all(|c| a.lo[c] <= b.hi[c] && b.lo[c] <= a.hi[c]);
                if adjacent {
                    if D == 2 && !jointly_monotone(a, b) {
                        continue 'level;
                    }
                } else if (0..D).all(|c| a.xlo[c] <= b.xhi[c] && b.xlo[c] <= a.xhi[c]) {
                    continue 'level;
                }
            }
        }
        return true;
    }
    false
}

pub(super) fn injective<const D: usize>(t: &Bernstein<D, D>) -> bool {
    det_j(t).is_some_and(one_signed) && boundary_simple(t)
}
