//! Curved PN triangles (Vlachos, Peters, Boyd, Mitchell 2001): one cubic triangular Bézier patch
//! per triangle of a mesh, from its three vertices and vertex normals alone, and the quadratic normal
//! field that shades it.
//!
//! For a triangle `P1, P2, P3` with unit normals `N1, N2, N3` and `wᵢⱼ = (Pⱼ − Pᵢ)·Nᵢ`:
//!
//! - corners `b300 = P1`, `b030 = P2`, `b003 = P3`;
//! - edge points `b210 = (2P1 + P2 − w12·N1)/3` and so on: each is the point a third along the
//!   edge, projected into the tangent plane of the nearer vertex;
//! - centre `b111 = E + (E − V)/2`, `E` the mean of the six edge points, `V` the mean of the corners.
//!
//! An edge's two inner points depend on that edge's ends only, so neighbouring patches share the
//! curved edge: the surface is closed (C⁰, C¹ at the corners). [`edge_point`] is the one place they
//! are computed, so both neighbours get the same bits.
//!
//! Normals: `n200 = N1`, `n020 = N2`, `n002 = N3`, and
//! `n110 = normalize(N1 + N2 − v12·(P2 − P1))`, `v12 = 2 (P2 − P1)·(N1 + N2) / |P2 − P1|²` (and the
//! same for the other edges): the average of the end normals reflected across the edge's
//! perpendicular plane, which keeps inflections.

use alloc::vec::Vec;

use glam::DVec3;

use crate::mesh::Mesh;
use crate::triangular::{TriangularPatch, net_index};

/// The control points of a cubic triangular patch, in the storage order of [`TriangularPatch`]
/// (`P_ijk` at `i·(9 − i)/2 + j`): `P_003, P_012, P_021, P_030, P_102, P_111, P_120, P_201, P_210,
/// P_300`.
pub type CubicNet = [DVec3; 10];

/// Storage index of `P_ijk` in a [`CubicNet`].
#[must_use]
pub const fn cubic_index(i: usize, j: usize) -> usize {
    net_index(3, i, j)
}

/// The inner control point of the curved edge from `a` (normal `na`) to `b` next to `a`:
/// `(2a + b − ((b − a)·na)·na)/3`.
#[must_use]
pub fn edge_point(a: DVec3, na: DVec3, b: DVec3) -> DVec3 {
    let w = (b - a).dot(na);
    (a * 2.0 + b - na * w) / 3.0
}

/// The cubic PN patch of the triangle `p` with unit vertex normals `n`.
#[must_use]
pub fn pn_patch(p: [DVec3; 3], n: [DVec3; 3]) -> CubicNet {
    let b210 = edge_point(p[0], n[0], p[1]);
    let b120 = edge_point(p[1], n[1], p[0]);
    let b021 = edge_point(p[1], n[1], p[2]);
    let b012 = edge_point(p[2], n[2], p[1]);
    let b102 = edge_point(p[2], n[2], p[0]);
    let b201 = edge_point(p[0], n[0], p[2]);
    let e = (b210 + b120 + b021 + b012 + b102 + b201) / 6.0;
    let v = (p[0] + p[1] + p[2]) / 3.0;
    let b111 = e + (e - v) / 2.0;
    let mut net = [DVec3::ZERO; 10];
    net[cubic_index(3, 0)] = p[0];
    net[cubic_index(0, 3)] = p[1];
    net[cubic_index(0, 0)] = p[2];
    net[cubic_index(2, 1)] = b210;
    net[cubic_index(1, 2)] = b120;
    net[cubic_index(0, 2)] = b021;
    net[cubic_index(0, 1)] = b012;
    net[cubic_index(1, 0)] = b102;
    net[cubic_index(2, 0)] = b201;
    net[cubic_index(1, 1)] = b111;
    net
}

/// The quadratic normal field of the PN triangle `p` with unit vertex normals `n`, in the storage
/// order of a degree-2 [`TriangularPatch`]: `n002, n011, n020, n101, n110, n200`. Evaluate and
/// normalise to shade.
#[must_use]
pub fn pn_normals(p: [DVec3; 3], n: [DVec3; 3]) -> [DVec3; 6] {
    let mid = |i: usize, j: usize| {
        let d = p[j] - p[i];
        let len2 = d.length_squared();
        let v = if len2 > 0.0 {
            2.0 * d.dot(n[i] + n[j]) / len2
        } else {
            0.0
        };
        (n[i] + n[j] - d * v).normalize_or_zero()
    };
    [n[2], mid(1, 2), n[1], mid(2, 0), mid(0, 1), n[0]]
}

/// `Σ P_ijk · 3!/(i! j! k!) uⁱ vʲ wᵏ` for a [`CubicNet`] at `(u, v, w)`.
#[must_use]
pub fn eval_cubic(net: &CubicNet, b: DVec3) -> DVec3 {
    let (u, v, w) = (b.x, b.y, b.z);
    let (u2, v2, w2) = (u * u, v * v, w * w);
    net[9] * (u2 * u)
        + net[3] * (v2 * v)
        + net[0] * (w2 * w)
        + (net[8] * (u2 * v)
            + net[7] * (u2 * w)
            + net[6] * (u * v2)
            + net[4] * (u * w2)
            + net[2] * (v2 * w)
            + net[1] * (v * w2))
            * 3.0
        + net[5] * (6.0 * u * v * w)
}

/// The partial derivatives `(∂/∂v − ∂/∂u, ∂/∂w − ∂/∂u)` of the patch at `(u, v, w)`: the tangents
/// along `s` and `t` for `(u, v, w) = (1 − s − t, s, t)`.
#[must_use]
pub fn tangents_cubic(net: &CubicNet, b: DVec3) -> (DVec3, DVec3) {
    // Two de Casteljau levels leave the quadratic... one level short: do two levels to the linear
    // net (three points Q_100, Q_010, Q_001), whose differences times 3 are the derivatives.
    let (u, v, w) = (b.x, b.y, b.z);
    let p = |i: usize, j: usize| net[cubic_index(i, j)];
    // Level 1: degree-2 net, index by (i, j) with i + j ≤ 2.
    let l1 = |i: usize, j: usize| p(i + 1, j) * u + p(i, j + 1) * v + p(i, j) * w;
    let q200 = l1(2, 0);
    let q110 = l1(1, 1);
    let q101 = l1(1, 0);
    let q020 = l1(0, 2);
    let q011 = l1(0, 1);
    let q002 = l1(0, 0);
    // Level 2: linear net.
    let r100 = q200 * u + q110 * v + q101 * w;
    let r010 = q110 * u + q020 * v + q011 * w;
    let r001 = q101 * u + q011 * v + q002 * w;
    ((r010 - r100) * 3.0, (r001 - r100) * 3.0)
}

/// The PN surface of a closed mesh: one cubic patch and one quadratic normal field per triangle,
/// in the mesh's triangle order, corner `i` of patch `t` at vertex `mesh.triangles[t][i]`.
#[derive(Clone, Debug, Default)]
pub struct PnSurface {
    /// One cubic net per triangle.
    pub patches: Vec<CubicNet>,
    /// One quadratic normal net per triangle (see [`pn_normals`]).
    pub normals: Vec<[DVec3; 6]>,
}

impl PnSurface {
    /// The PN patches of every triangle of `mesh`, whose `normals` are its unit vertex normals.
    ///
    /// # Panics
    ///
    /// If a triangle indexes past `mesh.positions` or `mesh.normals`.
    #[must_use]
    pub fn new(mesh: &Mesh) -> Self {
        let mut patches = Vec::with_capacity(mesh.triangles.len());
        let mut normals = Vec::with_capacity(mesh.triangles.len());
        for tri in &mesh.triangles {
            let p = tri.map(|i| mesh.positions[i as usize]);
            let n = tri.map(|i| mesh.normals[i as usize]);
            patches.push(pn_patch(p, n));
            normals.push(pn_normals(p, n));
        }
        Self { patches, normals }
    }

    /// Patch `t` as a general [`TriangularPatch`].
    ///
    /// # Panics
    ///
    /// If `t` is out of range.
    #[must_use]
    pub fn patch(&self, t: usize) -> TriangularPatch<DVec3> {
        TriangularPatch::from_fn(3, |i, j, _| self.patches[t][cubic_index(i, j)])
            .unwrap_or_else(|_| unreachable!("degree 3 is valid"))
    }

    /// The unit normal of patch `t` at `(u, v, w)` from the quadratic field.
    ///
    /// # Panics
    ///
    /// If `t` is out of range.
    #[must_use]
    pub fn normal(&self, t: usize, b: DVec3) -> DVec3 {
        let n = &self.normals[t];
        let (u, v, w) = (b.x, b.y, b.z);
        (n[5] * (u * u)
            + n[2] * (v * v)
            + n[0] * (w * w)
            + (n[4] * (u * v) + n[3] * (u * w) + n[1] * (v * w)) * 2.0)
            .normalize_or_zero()
    }
}

impl PnSurface {
    /// The surface as triangles: each patch's domain split into `level²` triangles
    /// (`1 ≤ level ≤ 64`), vertices on the patch, normals from the quadratic field. Patches are
    /// not welded to each other (the shared edges are evaluated from each side).
    #[must_use]
    pub fn tessellate(&self, level: usize) -> Mesh {
        let l = level.clamp(1, 64);
        let per = (l + 1) * (l + 2) / 2;
        let mut mesh = Mesh {
            positions: Vec::with_capacity(per * self.patches.len()),
            normals: Vec::with_capacity(per * self.patches.len()),
            triangles: Vec::with_capacity(l * l * self.patches.len()),
        };
        for t in 0..self.patches.len() {
            let base = mesh.positions.len() as u32;
            // Row r (v = r/l) holds l − r + 1 points, w = c/l.
            for r in 0..=l {
                for c in 0..=l - r {
                    let (v, w) = (r as f64 / l as f64, c as f64 / l as f64);
                    let b = DVec3::new((1.0 - v - w).max(0.0), v, w);
                    mesh.positions.push(eval_cubic(&self.patches[t], b));
                    mesh.normals.push(self.normal(t, b));
                }
            }
            // Row r of the grid is row r of a degree-l net.
            let index = |r: usize, c: usize| base + net_index(l, r, c) as u32;
            for r in 0..l {
                for c in 0..l - r {
                    // (u, v, w) corners: moving along v then w keeps the patch's orientation
                    // (A → B → C is u → v → w).
                    mesh.triangles
                        .push([index(r, c), index(r + 1, c), index(r, c + 1)]);
                    if c + 1 < l - r {
                        mesh.triangles.push([
                            index(r + 1, c),
                            index(r + 1, c + 1),
                            index(r, c + 1),
                        ]);
                    }
                }
            }
        }
        mesh
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::esc::examples::icosphere;
    use crate::testutil::Rng;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    fn bary(rng: &mut Rng) -> DVec3 {
        let (s, t) = (rng.range(0.0, 1.0), rng.range(0.0, 1.0));
        let (s, t) = if s + t > 1.0 {
            (1.0 - s, 1.0 - t)
        } else {
            (s, t)
        };
        DVec3::new(1.0 - s - t, s, t)
    }

    #[test]
    fn the_cubic_evaluators_agree_with_the_general_patch() {
        let mesh = icosphere(1);
        let pn = PnSurface::new(&mesh);
        let mut rng = Rng::new(3);
        for t in 0..pn.patches.len() {
            let patch = pn.patch(t);
            let b = bary(&mut rng);
            assert!((eval_cubic(&pn.patches[t], b) - patch.eval(b)).length() < 1e-14);
            let (ds, dt) = tangents_cubic(&pn.patches[t], b);
            let (s, tt) = (b.y, b.z);
            assert!((ds - patch.ds(s, tt)).length() < 1e-13);
            assert!((dt - patch.dt(s, tt)).length() < 1e-13);
        }
    }

    #[test]
    fn corners_and_normals_interpolate_and_edges_are_shared() {
        let mesh = icosphere(1);
        let pn = PnSurface::new(&mesh);
        // Corners interpolate the vertices and the vertex normals.
        for (t, tri) in mesh.triangles.iter().enumerate() {
            for (c, bc) in [DVec3::X, DVec3::Y, DVec3::Z].into_iter().enumerate() {
                let v = tri[c] as usize;
                assert_eq!(eval_cubic(&pn.patches[t], bc), mesh.positions[v]);
                assert!((pn.normal(t, bc) - mesh.normals[v]).length() < 1e-15);
            }
        }
        // Every edge's curve is the same from both sides, bit for bit in its control points.
        for (t, tri) in mesh.triangles.iter().enumerate() {
            let patch = pn.patch(t);
            for e in 0..3 {
                let (a, b) = (tri[e], tri[(e + 1) % 3]);
                let (u, other) = mesh
                    .triangles
                    .iter()
                    .enumerate()
                    .find_map(|(u, o)| {
                        (0..3)
                            .find(|&f| o[f] == b && o[(f + 1) % 3] == a)
                            .map(|f| (u, f))
                    })
                    .expect("closed mesh");
                let mine = patch.edge(e).expect("edge").points().to_vec();
                let mut theirs = pn.patch(u).edge(other).expect("edge").points().to_vec();
                theirs.reverse();
                assert_eq!(mine, theirs);
            }
        }
    }

    #[test]
    fn a_sphere_is_approximated_closely() {
        // PN triangles of a sphere with exact normals stay within a few percent of its radius.
        let mesh = icosphere(2);
        let pn = PnSurface::new(&mesh);
        let mut rng = Rng::new(9);
        let mut flat = 0.0_f64;
        let mut curved = 0.0_f64;
        for t in 0..pn.patches.len() {
            let b = bary(&mut rng);
            curved = curved.max((eval_cubic(&pn.patches[t], b).length() - 1.0).abs());
            let [p, q, r] = mesh.corners(t);
            flat = flat.max(((p * b.x + q * b.y + r * b.z).length() - 1.0).abs());
        }
        assert!(curved < flat / 4.0, "curved {curved} flat {flat}");
    }
}
