//! Rays against the pieces of a free-form cell: a cubic triangular patch (subdivision and Newton)
//! and the ruled wall between a straight mesh edge and its curved PN edge (a quadratic).
//!
//! Every crossing is reported with its sign, `+1` where the surface's normal points along the ray
//! (the ray leaves the side the normal points to) and `−1` against it, so that a sum over a closed
//! surface is a winding number. A crossing that cannot be told reliably (grazing, or within a hair of
//! a seam between pieces) makes the whole count [`Crossings::Unsure`]; the caller then casts again
//! in another direction.

use glam::{DVec2, DVec3};

use super::pn::{CubicNet, cubic_index, eval_cubic, tangents_cubic};

/// A ray `origin + λ·dir`, `0 < λ ≤ max`, with an orthonormal frame `(e1, e2, dir)`.
#[derive(Clone, Copy, Debug)]
pub struct Ray {
    /// The start, not itself on the ray.
    pub origin: DVec3,
    /// The unit direction.
    pub dir: DVec3,
    /// The largest `λ` counted: `f64::INFINITY` for a ray, the length for a segment.
    pub max: f64,
    e1: DVec3,
    e2: DVec3,
}

impl Ray {
    /// The ray from `origin` along `dir` (normalised here) up to distance `max`.
    #[must_use]
    pub fn new(origin: DVec3, dir: DVec3, max: f64) -> Self {
        let dir = dir.normalize();
        let e1 = dir.any_orthonormal_vector();
        let e2 = dir.cross(e1);
        Self {
            origin,
            dir,
            max,
            e1,
            e2,
        }
    }

    /// `p` in the ray's frame: `(p − origin)·e1`, `·e2`, `·dir`.
    #[must_use]
    pub fn local(&self, p: DVec3) -> DVec3 {
        let d = p - self.origin;
        DVec3::new(d.dot(self.e1), d.dot(self.e2), d.dot(self.dir))
    }
}

/// The signed number of crossings of a ray with a surface, or the report that one of them could
/// not be told apart from a seam or a tangency.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Crossings {
    /// The sum of the crossings' signs.
    Count(i32),
    /// A crossing sits on a seam or grazes: cast another ray.
    Unsure,
}

impl Crossings {
    /// The sum of two counts; unsure if either is.
    #[must_use]
    pub fn plus(self, other: Self) -> Self {
        match (self, other) {
            (Self::Count(a), Self::Count(b)) => Self::Count(a + b),
            _ => Self::Unsure,
        }
    }
}

/// How close (in barycentric coordinates) a crossing may come to the patch's edge before it counts
/// as on the seam with the next piece.
const SEAM: f64 = 1e-7;
/// Subdivision depth limit of [`patch_crossings`].
const MAX_DEPTH: u32 = 24;
/// Sub-patches at least this many levels deep, whose hull holds the ray, are handed to Newton.
const NEWTON_DEPTH: u32 = 4;

/// One crossing of a ray with a patch.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// The distance along the ray.
    pub lambda: f64,
    /// The barycentric coordinates on the patch.
    pub bary: DVec3,
    /// `+1` where the patch's normal points along the ray, `−1` against it.
    pub sign: i8,
}

/// A crossing sat on a seam or grazed, so the crossings of this ray cannot be trusted.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Unsure;

/// The signed crossings of `ray` with the cubic patch `net` (over `u, v, w ≥ 0`), whose normal is
/// `∂/∂s × ∂/∂t` (counter-clockwise corners `P300 → P030 → P003` seen from the side it points to).
#[must_use]
pub fn patch_crossings(net: &CubicNet, ray: &Ray) -> Crossings {
    let mut sum = 0;
    match patch_hits(net, ray, &mut |h| sum += i32::from(h.sign)) {
        Ok(()) => Crossings::Count(sum),
        Err(Unsure) => Crossings::Unsure,
    }
}

/// Every crossing of `ray` with the cubic patch `net`, by subdivision of the patch (newest vertex
/// bisection, pruned by the control net's box around the ray) and Newton in the small
/// sub-patches, each root counted once.
///
/// # Errors
///
/// [`Unsure`] where a crossing is within a hair of the patch's edge (the seam with the next piece)
/// or the ray grazes the patch.
pub fn patch_hits(net: &CubicNet, ray: &Ray, visit: &mut dyn FnMut(Hit)) -> Result<(), Unsure> {
    let mut local = [DVec3::ZERO; 10];
    for (l, p) in local.iter_mut().zip(net) {
        *l = ray.local(*p);
    }
    let (lo, hi) = bounds(&local);
    let scale = (hi - lo).max_element().max(1e-300);
    let mut search = Search {
        local,
        max: ray.max,
        scale,
        found: [DVec3::ZERO; 8],
        found_count: 0,
        visit,
    };
    search.sub_patch(&local, [DVec3::X, DVec3::Y, DVec3::Z], 0)
}

/// The state of one [`patch_hits`]: the patch in the ray's frame, and the crossings found so far.
struct Search<'a> {
    local: [DVec3; 10],
    max: f64,
    scale: f64,
    /// Crossings found so far, by their barycentric coordinates, to drop repeats found by two
    /// neighbouring sub-patches.
    found: [DVec3; 8],
    found_count: usize,
    visit: &'a mut dyn FnMut(Hit),
}

impl Search<'_> {
    /// The crossings in the sub-patch `sub` (in the ray's frame) over the barycentric `corners` of
    /// the whole patch, `depth` splits down; the edge split next is always the one from corner 0 to
    /// corner 1 (newest vertex bisection). Depth first, each call's frame holding one pending
    /// sibling, so that nothing is set up beyond the levels a query visits.
    fn sub_patch(
        &mut self,
        sub: &[DVec3; 10],
        corners: [DVec3; 3],
        depth: u32,
    ) -> Result<(), Unsure> {
        let (lo, hi) = bounds(sub);
        let slack = 1e-12 * self.scale;
        if lo.x > slack || hi.x < -slack || lo.y > slack || hi.y < -slack {
            return Ok(());
        }
        if hi.z <= 0.0 || lo.z > self.max {
            return Ok(());
        }
        if depth >= NEWTON_DEPTH && regular(sub) {
            match newton(&self.local, &corners, self.max, self.scale) {
                Leaf::Crossing(b, sign, lambda) => {
                    if self.found[..self.found_count]
                        .iter()
                        .any(|f| (*f - b).abs().max_element() < 1e-9)
                    {
                        return Ok(());
                    }
                    if b.min_element() < SEAM || self.found_count == self.found.len() {
                        return Err(Unsure);
                    }
                    self.found[self.found_count] = b;
                    self.found_count += 1;
                    (self.visit)(Hit {
                        lambda,
                        bary: b,
                        sign,
                    });
                    return Ok(());
                }
                Leaf::Elsewhere => return Ok(()),
                Leaf::Seam => return Err(Unsure),
                Leaf::Failed => {}
            }
        }
        if depth >= MAX_DEPTH {
            // A hull that still holds the ray at this size, with no regular root: a tangency, a
            // fold along the ray, or a crossing on the seam.
            return Err(Unsure);
        }
        let (first, second) = bisect(sub);
        let mid = (corners[0] + corners[1]) * 0.5;
        // Children (mid, B, C) and (A, mid, C), each rotated so that its newest vertex `mid` is
        // corner 2: (B, C, mid) and (C, A, mid); the second first.
        self.sub_patch(&second, [corners[2], corners[0], mid], depth + 1)?;
        self.sub_patch(&first, [corners[1], corners[2], mid], depth + 1)
    }
}

enum Leaf {
    /// A regular crossing at these barycentric coordinates of the whole patch, with its sign and
    /// distance.
    Crossing(DVec3, i8, f64),
    /// Newton converged to a root outside this sub-patch (another one owns it) or behind the ray.
    Elsewhere,
    /// No convergence: subdivide further.
    Failed,
    /// A root on the patch's edge.
    Seam,
}

/// Newton on the whole patch for `x = y = 0` (the ray in local coordinates), from the centre of
/// the sub-triangle `corners`; the root counts for this sub-patch only if it lies in it.
fn newton(local: &[DVec3; 10], corners: &[DVec3; 3], max: f64, scale: f64) -> Leaf {
    let mut b = (corners[0] + corners[1] + corners[2]) / 3.0;
    for _ in 0..12 {
        let p = eval_cubic(local, b);
        let (ds, dt) = tangents_cubic(local, b);
        let det = ds.x * dt.y - ds.y * dt.x;
        let (fx, fy) = (p.x, p.y);
        let jscale = ds.truncate().length() * dt.truncate().length();
        if det.abs() <= 1e-12 * jscale || jscale == 0.0 {
            return Leaf::Failed;
        }
        // Solve [ds dt]·(δs, δt) = −(fx, fy).
        let s = -(fx * dt.y - fy * dt.x) / det;
        let t = -(ds.x * fy - ds.y * fx) / det;
        b += DVec3::new(-s - t, s, t);
        if (s.abs() + t.abs()) < 1e-14 && fx.abs().max(fy.abs()) < 1e-10 * scale {
            let p = eval_cubic(local, b);
            if p.x.abs().max(p.y.abs()).is_nan() || p.x.abs().max(p.y.abs()) >= 1e-9 * scale {
                return Leaf::Failed;
            }
            // A root on the ray within a hair of the patch's edge, inside or just outside: the
            // seam with the next piece, where either patch may claim or drop it.
            if b.min_element().abs() < SEAM && p.z > 0.0 && p.z <= max {
                return Leaf::Seam;
            }
            // Inside the sub-triangle? Solve for b in the corners' barycentric frame.
            if !inside(corners, b, 1e-9) || p.z > max {
                return Leaf::Elsewhere;
            }
            if p.z <= 0.0 {
                return Leaf::Elsewhere;
            }
            if det.abs() <= 1e-7 * jscale || p.z <= 1e-12 * scale {
                return Leaf::Failed;
            }
            return Leaf::Crossing(b, if det > 0.0 { 1 } else { -1 }, p.z);
        }
        if b.min_element() < -0.5 || b.max_element() > 1.5 {
            return Leaf::Failed;
        }
    }
    Leaf::Failed
}

/// Whether the sub-patch's projection along the ray is regular: `det ∂(x, y)/∂(s, t)` has one
/// strict sign over the whole sub-triangle, so it crosses the ray at most once (a fold, where a
/// ray crosses twice, makes the sign change). Sufficient test: `det J = Σ Bₐ·B_b·(Dsₐ × Dt_b)`
/// with non-negative weights over the derivative nets `Ds`, `Dt`, so one sign of every product
/// suffices.
fn regular(net: &[DVec3; 10]) -> bool {
    let mut ds = [DVec2::ZERO; 6];
    let mut dt = [DVec2::ZERO; 6];
    let mut n = 0;
    for i in 0..=2usize {
        for j in 0..=2 - i {
            let base = net[cubic_index(i + 1, j)].truncate();
            ds[n] = net[cubic_index(i, j + 1)].truncate() - base;
            dt[n] = net[cubic_index(i, j)].truncate() - base;
            n += 1;
        }
    }
    let (mut pos, mut neg) = (false, false);
    for a in &ds {
        for b in &dt {
            let c = a.perp_dot(*b);
            pos |= c > 0.0;
            neg |= c <= 0.0;
            if pos && neg {
                return false;
            }
        }
    }
    true
}

/// Whether the barycentric point `b` (of the whole patch) lies in the sub-triangle `corners`, up to
/// `tol`.
fn inside(corners: &[DVec3; 3], b: DVec3, tol: f64) -> bool {
    // Use (v, w) as 2D coordinates of the domain.
    let p = |c: DVec3| DVec2::new(c.y, c.z);
    let (a, bb, c, q) = (p(corners[0]), p(corners[1]), p(corners[2]), p(b));
    let area = (bb - a).perp_dot(c - a);
    if area == 0.0 {
        return false;
    }
    let l0 = (bb - q).perp_dot(c - q) / area;
    let l1 = (c - q).perp_dot(a - q) / area;
    let l2 = 1.0 - l0 - l1;
    l0 >= -tol && l1 >= -tol && l2 >= -tol
}

fn bounds(net: &[DVec3; 10]) -> (DVec3, DVec3) {
    net.iter()
        .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), &p| {
            (lo.min(p), hi.max(p))
        })
}

/// The cubic net split at the midpoint of the edge from corner 0 (`P300`) to corner 1 (`P030`):
/// the halves over `(mid, B, C)` and `(A, mid, C)`, rotated to `(B, C, mid)` and `(C, A, mid)`.
///
/// Along each row of constant `k` the points `P_(i, j, k)`, `i + j = 3 − k`, form a curve of degree
/// `m = 3 − k` in the `(A, B)` direction, and the split at 1/2 is a de Casteljau split of each
/// row: from the row `r[i] = P_(i, m − i, k)` (from `B` at `i = 0` to `A`) the levels
/// `t[l][i] = (t[l − 1][i] + t[l − 1][i + 1])/2`. The half near `B` has the points `t[a][0]` with
/// exponents `(a, m − a, k)` of `(mid, B, C)`, stored rotated at `(m − a, k)` of `(B, C, mid)`;
/// the half near `A` has `t[m − a][a]` with exponents `(a, m − a, k)` of `(A, mid, C)`, stored
/// at `(k, a)` of `(C, A, mid)`. Written out row by row: this runs in every step of a ray's
/// subdivision.
pub(super) fn bisect(net: &[DVec3; 10]) -> ([DVec3; 10], [DVec3; 10]) {
    let half = |a: DVec3, b: DVec3| (a + b) * 0.5;
    let mut first = [DVec3::ZERO; 10];
    let mut second = [DVec3::ZERO; 10];
    // k = 0, m = 3: r = P030, P120, P210, P300.
    let r = [
        net[cubic_index(0, 3)],
        net[cubic_index(1, 2)],
        net[cubic_index(2, 1)],
        net[cubic_index(3, 0)],
    ];
    let t1 = [half(r[0], r[1]), half(r[1], r[2]), half(r[2], r[3])];
    let t2 = [half(t1[0], t1[1]), half(t1[1], t1[2])];
    let t3 = half(t2[0], t2[1]);
    first[cubic_index(3, 0)] = r[0];
    first[cubic_index(2, 0)] = t1[0];
    first[cubic_index(1, 0)] = t2[0];
    first[cubic_index(0, 0)] = t3;
    second[cubic_index(0, 0)] = t3;
    second[cubic_index(0, 1)] = t2[1];
    second[cubic_index(0, 2)] = t1[2];
    second[cubic_index(0, 3)] = r[3];
    // k = 1, m = 2: r = P021, P111, P201.
    let r = [
        net[cubic_index(0, 2)],
        net[cubic_index(1, 1)],
        net[cubic_index(2, 0)],
    ];
    let t1 = [half(r[0], r[1]), half(r[1], r[2])];
    let t2 = half(t1[0], t1[1]);
    first[cubic_index(2, 1)] = r[0];
    first[cubic_index(1, 1)] = t1[0];
    first[cubic_index(0, 1)] = t2;
    second[cubic_index(1, 0)] = t2;
    second[cubic_index(1, 1)] = t1[1];
    second[cubic_index(1, 2)] = r[2];
    // k = 2, m = 1: r = P012, P102.
    let r = [net[cubic_index(0, 1)], net[cubic_index(1, 0)]];
    let t1 = half(r[0], r[1]);
    first[cubic_index(1, 2)] = r[0];
    first[cubic_index(0, 2)] = t1;
    second[cubic_index(2, 0)] = t1;
    second[cubic_index(2, 1)] = r[1];
    // k = 3, m = 0: P003.
    first[cubic_index(0, 3)] = net[cubic_index(0, 0)];
    second[cubic_index(3, 0)] = net[cubic_index(0, 0)];
    (first, second)
}

/// The ruled wall between a straight mesh edge `a → b` and its curved PN edge: `W(t, s) = L(t) +
/// s·D(t)`, `L(t) = (1 − t)a + t·b`, `D(t) = 3t(1 − t)²·d1 + 3t²(1 − t)·d2` the curve minus the
/// line (`d1`, `d2` the inner control points less the line's). Its normal is `∂W/∂t × ∂W/∂s`.
#[derive(Clone, Copy, Debug)]
pub struct Wall {
    /// The edge's start.
    pub a: DVec3,
    /// The edge's end.
    pub b: DVec3,
    /// Inner control point next to `a`, less `(2a + b)/3`.
    pub d1: DVec3,
    /// Inner control point next to `b`, less `(a + 2b)/3`.
    pub d2: DVec3,
}

impl Wall {
    /// The wall of the edge `a → b` whose curved edge has the inner control points `c1` (next to
    /// `a`) and `c2`.
    #[must_use]
    pub fn new(a: DVec3, b: DVec3, c1: DVec3, c2: DVec3) -> Self {
        Self {
            a,
            b,
            d1: c1 - (a * 2.0 + b) / 3.0,
            d2: c2 - (a + b * 2.0) / 3.0,
        }
    }

    /// Whether the curved edge is the straight one (the wall has no area).
    #[must_use]
    pub fn is_flat(&self) -> bool {
        let len = (self.b - self.a).length();
        self.d1.length().max(self.d2.length()) <= 1e-14 * len
    }

    /// The point `W(t, s)`.
    #[must_use]
    pub fn point(&self, t: f64, s: f64) -> DVec3 {
        let l = self.a.lerp(self.b, t);
        let d = self.d1 * (3.0 * t * (1.0 - t) * (1.0 - t)) + self.d2 * (3.0 * t * t * (1.0 - t));
        l + d * s
    }

    /// The signed crossings of `ray` with the wall (`0 < t < 1`, `0 ≤ s ≤ 1`).
    #[must_use]
    pub fn crossings(&self, ray: &Ray) -> Crossings {
        if self.is_flat() {
            return Crossings::Count(0);
        }
        let la = ray.local(self.a);
        let lb = ray.local(self.b);
        let d1 = DVec3::new(
            self.d1.dot(ray.e1),
            self.d1.dot(ray.e2),
            self.d1.dot(ray.dir),
        );
        let d2 = DVec3::new(
            self.d2.dot(ray.e1),
            self.d2.dot(ray.e2),
            self.d2.dot(ray.dir),
        );
        // l(t) + s·δ(t) = 0 in (x, y) with δ(t) = 3t(1 − t)·((1 − t)d1 + t·d2): the cross product
        // l × δ vanishes, and for 0 < t < 1 that is the quadratic q(t) = l(t) × ((1 − t)d1 + t d2),
        // Bernstein coefficients c0, c1, c2.
        let cross = |p: DVec3, q: DVec3| p.x * q.y - p.y * q.x;
        let c0 = cross(la, d1);
        let c1 = 0.5 * (cross(la, d2) + cross(lb, d1));
        let c2 = cross(lb, d2);
        let size = (lb - la).length() * d1.length().max(d2.length()) + la.length() * d1.length();
        let (qa, qb, qc) = (c0 - 2.0 * c1 + c2, 2.0 * (c1 - c0), c0);
        let tiny = 1e-13 * size.max(1e-300);
        if qa.abs() <= tiny && qb.abs() <= tiny && qc.abs() <= tiny {
            // The ray lies in the wall's plane (the wall is planar here): no crossing can be told.
            return Crossings::Unsure;
        }
        let mut roots = [f64::NAN; 2];
        if qa.abs() <= tiny {
            if qb.abs() > tiny {
                roots[0] = -qc / qb;
            }
        } else {
            let disc = qb * qb - 4.0 * qa * qc;
            if disc < 0.0 {
                if disc > -1e-10 * qb * qb {
                    // A double root within rounding: the ray grazes the wall.
                    let t = -qb / (2.0 * qa);
                    if t > 0.0 && t < 1.0 && self.grazes(ray, t) {
                        return Crossings::Unsure;
                    }
                }
                return Crossings::Count(0);
            }
            let sq = crate::math::sqrt(disc);
            // The stable pair of roots.
            let q = -0.5 * (qb + qb.signum() * sq);
            roots[0] = q / qa;
            roots[1] = if q != 0.0 { qc / q } else { -qb / (2.0 * qa) };
            if sq <= 1e-7 * qb.abs().max(qa.abs()) {
                let t = 0.5 * (roots[0] + roots[1]);
                if t > 0.0 && t < 1.0 && self.grazes(ray, t) {
                    return Crossings::Unsure;
                }
            }
        }
        let mut sum = 0;
        for t in roots {
            if !(t > -SEAM && t < 1.0 + SEAM) {
                continue;
            }
            if !(SEAM..=1.0 - SEAM).contains(&t) {
                // At the ends the wall pinches to a vertex of the mesh.
                if self.near(ray, t.clamp(0.0, 1.0)) {
                    return Crossings::Unsure;
                }
                continue;
            }
            let l = la.lerp(lb, t);
            let g = 3.0 * t * (1.0 - t);
            let delta = (d1 * (1.0 - t) + d2 * t) * g;
            let dd = delta.truncate().length_squared();
            if dd == 0.0 {
                // The ruling at t runs along the ray, so q(t) vanishes wherever the ray is: a
                // crossing only if the ray lies in that ruling. Every ray along a cube's face
                // normal meets this at the wall of the face's diagonal, whose curved edge leaves
                // it along the normal at its middle.
                if l.truncate().length() <= 1e-9 * (self.b - self.a).length() {
                    return Crossings::Unsure;
                }
                continue;
            }
            let s = -l.truncate().dot(delta.truncate()) / dd;
            if !(-SEAM..=1.0 + SEAM).contains(&s) {
                continue;
            }
            let z = l.z + s * delta.z;
            if z.abs() <= 1e-12 * (self.b - self.a).length() {
                // The ray starts on the wall: no direction tells which side it is on.
                return Crossings::Unsure;
            }
            if z <= 0.0 || z > ray.max {
                continue;
            }
            if !(SEAM..=1.0 - SEAM).contains(&s) {
                return Crossings::Unsure;
            }
            // ∂W/∂t = (lb − la) + s·δ'(t); the sign of (∂W/∂t × δ)·dir.
            let dprime =
                d1 * (3.0 * (1.0 - t) * (1.0 - 3.0 * t)) + d2 * (3.0 * t * (2.0 - 3.0 * t));
            let wt = (lb - la) + dprime * s;
            let n = wt.x * delta.y - wt.y * delta.x;
            if n.abs() <= 1e-9 * wt.truncate().length() * delta.truncate().length() {
                return Crossings::Unsure;
            }
            sum += if n > 0.0 { 1 } else { -1 };
        }
        Crossings::Count(sum)
    }

    /// Whether the ray passes within rounding of the wall near parameter `t`.
    fn grazes(&self, ray: &Ray, t: f64) -> bool {
        let top = ray.local(self.point(t, 1.0));
        let bottom = ray.local(self.point(t, 0.0));
        // The segment from bottom to top in (x, y) passes near the origin, ahead on the ray.
        let d = (top - bottom).truncate();
        let len2 = d.length_squared();
        let s = if len2 > 0.0 {
            (-bottom.truncate().dot(d) / len2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let p = bottom.lerp(top, s);
        p.z > 0.0 && p.truncate().length() <= 1e-7 * (self.b - self.a).length()
    }

    /// Whether the ray passes within a hair of the wall's point at `t` (an end: a mesh vertex).
    fn near(&self, ray: &Ray, t: f64) -> bool {
        let p = ray.local(self.point(t, 0.0));
        p.z > 0.0 && p.truncate().length() <= 1e-6 * (self.b - self.a).length()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::esc::pn::{edge_point, pn_patch};
    use crate::testutil::Rng;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    fn curved() -> CubicNet {
        let p = [
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 0.1),
            DVec3::new(0.2, 1.0, -0.1),
        ];
        let n = [
            DVec3::new(-0.3, -0.2, 1.0).normalize(),
            DVec3::new(0.4, 0.1, 1.0).normalize(),
            DVec3::new(0.0, 0.5, 1.0).normalize(),
        ];
        pn_patch(p, n)
    }

    /// [`bisect`] as first written, row by row in loops: the written-out one must give its bits.
    fn bisect_by_rows(net: &[DVec3; 10]) -> ([DVec3; 10], [DVec3; 10]) {
        // Along each row of constant k the points P_(i, j, k), i + j = 3 − k, form a curve of degree
        // 3 − k in the (A, B) direction; the split at 1/2 is a de Casteljau split of each row.
        let mut left = [DVec3::ZERO; 10]; // over (mid, B, C): exponents (i', j', k) of (mid, B, C)
        let mut right = [DVec3::ZERO; 10]; // over (A, mid, C)
        for k in 0..=3usize {
            let m = 3 - k;
            // Row points ordered by i from 0 (at B) to m (at A): P_(i, m − i, k).
            let mut row = [DVec3::ZERO; 4];
            for (i, r) in row.iter_mut().enumerate().take(m + 1) {
                *r = net[cubic_index(i, m - i)];
            }
            // De Casteljau at 1/2 from B (i = 0) to A (i = m): the triangle of levels.
            let mut tri = [[DVec3::ZERO; 4]; 4];
            tri[0][..=m].copy_from_slice(&row[..=m]);
            for l in 1..=m {
                for i in 0..=m - l {
                    tri[l][i] = (tri[l - 1][i] + tri[l - 1][i + 1]) * 0.5;
                }
            }
            // Half near B (mid, B, C): exponent of mid is i', of B is j' = m − i'. Its points are
            // tri[i'][0] (l = i' levels from the B end).
            // Half near A (A, mid, C): exponent of A is i'', of mid j'' = m − i''; its points are
            // tri[j''][i''] (levels from the A end).
            for ip in 0..=m {
                let jp = m - ip;
                left[cubic_index(ip, jp)] = tri[ip][0];
                right[cubic_index(ip, jp)] = tri[jp][ip];
            }
        }
        // Rotate (mid, B, C) → (B, C, mid): new (i', j', k') = exponents of (B, C, mid), so the old
        // (i, j, k) of (mid, B, C) is (k', i', j').
        let rotate_left = |old: &[DVec3; 10]| {
            let mut out = [DVec3::ZERO; 10];
            for i in 0..=3usize {
                for j in 0..=3 - i {
                    let k = 3 - i - j;
                    out[cubic_index(i, j)] = old[cubic_index(k, i)];
                }
            }
            out
        };
        // Rotate (A, mid, C) → (C, A, mid): new exponents (i', j', k') of (C, A, mid), old (i, j, k)
        // of (A, mid, C) is (j', k', i').
        let rotate_right = |old: &[DVec3; 10]| {
            let mut out = [DVec3::ZERO; 10];
            for i in 0..=3usize {
                for j in 0..=3 - i {
                    let k = 3 - i - j;
                    out[cubic_index(i, j)] = old[cubic_index(j, k)];
                }
            }
            out
        };
        (rotate_left(&left), rotate_right(&right))
    }

    #[test]
    fn bisection_gives_the_bits_of_the_split_by_rows() {
        let mut rng = Rng::new(17);
        for _ in 0..100 {
            let net: CubicNet = core::array::from_fn(|_| {
                DVec3::new(
                    rng.range(-3.0, 3.0),
                    rng.range(-3.0, 3.0),
                    rng.range(-3.0, 3.0),
                )
            });
            assert_eq!(bisect(&net), bisect_by_rows(&net));
        }
    }

    #[test]
    fn bisection_reproduces_the_patch() {
        let net = curved();
        let (left, right) = bisect(&net);
        let mut rng = Rng::new(5);
        let (a, b, c) = (DVec3::X, DVec3::Y, DVec3::Z);
        let mid = (a + b) * 0.5;
        for _ in 0..50 {
            let (s, t) = (rng.range(0.0, 1.0), rng.range(0.0, 1.0));
            let (s, t) = if s + t > 1.0 {
                (1.0 - s, 1.0 - t)
            } else {
                (s, t)
            };
            let l = DVec3::new(1.0 - s - t, s, t);
            // left is over (B, C, mid), right over (C, A, mid).
            let pl = b * l.x + c * l.y + mid * l.z;
            let pr = c * l.x + a * l.y + mid * l.z;
            assert!((eval_cubic(&left, l) - eval_cubic(&net, pl)).length() < 1e-14);
            assert!((eval_cubic(&right, l) - eval_cubic(&net, pr)).length() < 1e-14);
        }
    }

    #[test]
    fn rays_through_a_patch_cross_it_once_with_the_normal_sign() {
        let net = curved();
        let mut rng = Rng::new(11);
        let mut hits = 0;
        for _ in 0..300 {
            let (s, t) = (rng.range(0.0, 1.0), rng.range(0.0, 1.0));
            let (s, t) = if s + t > 1.0 {
                (1.0 - s, 1.0 - t)
            } else {
                (s, t)
            };
            let b = DVec3::new(1.0 - s - t, s, t);
            let p = eval_cubic(&net, b);
            let dir = DVec3::new(rng.range(-0.3, 0.3), rng.range(-0.3, 0.3), 1.0);
            let below = Ray::new(p - dir * 2.0, dir, f64::INFINITY);
            let above = Ray::new(p + dir * 2.0, dir, f64::INFINITY);
            match patch_crossings(&net, &below) {
                Crossings::Count(c) => {
                    assert_eq!(c, 1, "{b}");
                    hits += 1;
                }
                Crossings::Unsure => assert!(b.min_element() < 1e-3, "{b}"),
            }
            assert_eq!(patch_crossings(&net, &above), Crossings::Count(0));
            // Against the ray, the sign flips.
            let back = Ray::new(p + dir * 2.0, -dir, f64::INFINITY);
            if let Crossings::Count(c) = patch_crossings(&net, &back) {
                assert_eq!(c, -1);
            }
            // A segment that stops short misses.
            let short = Ray::new(p - dir * 2.0, dir, 0.5 * (dir * 2.0).length());
            assert_eq!(patch_crossings(&net, &short), Crossings::Count(0));
        }
        assert!(hits > 250);
    }

    #[test]
    fn a_ray_can_cross_a_folded_patch_twice() {
        // A patch that bends back over itself along x: a ray along x at height 0.2 (where
        // 4·v·w = 0.2 twice on u = 0.3) crosses it twice with opposite signs.
        let mut net = [DVec3::ZERO; 10];
        for i in 0..=3usize {
            for j in 0..=3 - i {
                let k = 3 - i - j;
                let (u, v, w) = (i as f64 / 3.0, j as f64 / 3.0, k as f64 / 3.0);
                // x = v − w and y = u by linear precision; z = 4·v·w (the Bernstein coefficients
                // of v·w in degree 3 are j·k/6).
                let z = 4.0 * (j * k) as f64 / 6.0;
                net[cubic_index(i, j)] = DVec3::new(v - w, u, z);
            }
        }
        let ray = Ray::new(DVec3::new(-2.0, 0.3, 0.2), DVec3::X, f64::INFINITY);
        let mut sum = 0;
        let mut count = 0;
        // Count separately by cutting the ray at x = 0.
        for (o, m) in [
            (DVec3::new(-2.0, 0.3, 0.2), 2.0),
            (DVec3::new(0.0, 0.3, 0.2), 2.0),
        ] {
            if let Crossings::Count(c) = patch_crossings(&net, &Ray::new(o, DVec3::X, m)) {
                sum += c;
                count += c.abs();
            }
        }
        assert_eq!(count, 2);
        assert_eq!(sum, 0);
        assert_eq!(patch_crossings(&net, &ray), Crossings::Count(0));
    }

    #[test]
    fn rays_along_a_cube_face_normal_miss_its_diagonal_wall() {
        // The diagonal of a cube's face, with the cube's corner normals at its ends: the curved
        // edge bulges along the face's normal at its middle, and the wall lies in the plane
        // x = y. A ray along the face's normal off that plane never meets it.
        let (a, b) = (DVec3::new(-1.0, -1.0, 1.0), DVec3::new(1.0, 1.0, 1.0));
        let (na, nb) = (a.normalize(), b.normalize());
        let wall = Wall::new(a, b, edge_point(a, na, b), edge_point(b, nb, a));
        let mut rng = Rng::new(8);
        for _ in 0..200 {
            let q = DVec3::new(
                rng.range(-1.2, 1.2),
                rng.range(-1.2, 1.2),
                rng.range(0.9, 1.5),
            );
            if (q.x - q.y).abs() < 1e-6 {
                continue;
            }
            for dir in [DVec3::Z, -DVec3::Z] {
                let ray = Ray::new(q, dir, f64::INFINITY);
                assert_eq!(wall.crossings(&ray), Crossings::Count(0), "{q} {dir}");
            }
        }
    }

    #[test]
    fn walls_are_crossed_where_they_are() {
        let net = curved();
        let (a, b) = (net[cubic_index(3, 0)], net[cubic_index(0, 3)]);
        let wall = Wall::new(a, b, net[cubic_index(2, 1)], net[cubic_index(1, 2)]);
        let mut rng = Rng::new(2);
        for _ in 0..200 {
            let (t, s) = (rng.range(0.05, 0.95), rng.range(0.05, 0.95));
            let p = wall.point(t, s);
            let dir = DVec3::new(
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
            );
            // A short segment through W(t, s) crosses the wall there and nowhere else.
            let dir = dir.normalize();
            let ray = Ray::new(p - dir * 1e-3, dir, 2e-3);
            let c = wall.crossings(&ray);
            // The normal ∂t × ∂s, by finite differences.
            let h = 1e-6;
            let wt = (wall.point(t + h, s) - wall.point(t - h, s)) / (2.0 * h);
            let ws = (wall.point(t, s + h) - wall.point(t, s - h)) / (2.0 * h);
            let cos = wt.cross(ws).normalize().dot(dir);
            if cos.abs() < 1e-3 {
                continue; // grazing: either answer is allowed
            }
            let sign = if cos > 0.0 { 1 } else { -1 };
            assert_eq!(c, Crossings::Count(sign), "t {t} s {s}");
            // The segment after the point misses it.
            let after = Ray::new(p + dir * 1e-3, dir, 1e-3);
            assert_eq!(wall.crossings(&after), Crossings::Count(0));
        }
    }
}
