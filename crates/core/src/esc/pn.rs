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
//!
//! **Sharp edges.** One normal per vertex rounds every edge of the mesh, a cube's too. An edge
//! whose two triangles' normals differ by more than a *crease angle* ([`DEFAULT_CREASE_ANGLE`], or
//! the caller's, see [`PnSurface::with_crease_angle`]) is a crease, and the surface keeps it
//! ([`creases`]):
//!
//! - a crease's curve is its straight segment (inner points at a third and two thirds,
//!   [`straight_point`]), the same bits from both sides;
//! - the creases at a vertex split the triangles around it into *sectors* (triangles joined across
//!   edges that are not creases), and each corner takes its sector's normal, the angle-weighted
//!   mean of the sector's face normals; a vertex with one sector (no crease, or the end of one)
//!   keeps the mesh's vertex normal. At a cube's corner, where three creases meet, each sector is
//!   one face and its normal is the face's.
//!
//! An edge that is not a crease has its two triangles in one sector at each end, so both get the
//! same corner normals and the same curve: the surface stays closed. A mesh without creases (the
//! built-in examples at the default angle) gets the same patches, bit for bit, as from its vertex
//! normals.

use alloc::vec;
use alloc::vec::Vec;

use glam::DVec3;

use super::chain::EscError;
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

/// The inner control point of the straight edge from `a` to `b` next to `a`: `(2a + b)/3`, the
/// bits [`super::ray::Wall::new`] subtracts, so a crease's wall is exactly flat.
#[must_use]
pub fn straight_point(a: DVec3, b: DVec3) -> DVec3 {
    (a * 2.0 + b) / 3.0
}

/// The cubic PN patch of the triangle `p` with unit vertex normals `n`.
#[must_use]
pub fn pn_patch(p: [DVec3; 3], n: [DVec3; 3]) -> CubicNet {
    pn_patch_creased(p, n, [false; 3])
}

/// The cubic PN patch of the triangle `p` with unit corner normals `n`, whose edge `e` (from corner
/// `e` to corner `e + 1`) is straight where `sharp[e]` (a crease).
#[must_use]
pub fn pn_patch_creased(p: [DVec3; 3], n: [DVec3; 3], sharp: [bool; 3]) -> CubicNet {
    let inner = |e: usize| {
        let (i, j) = (e, (e + 1) % 3);
        if sharp[e] {
            [straight_point(p[i], p[j]), straight_point(p[j], p[i])]
        } else {
            [edge_point(p[i], n[i], p[j]), edge_point(p[j], n[j], p[i])]
        }
    };
    let [b210, b120] = inner(0);
    let [b021, b012] = inner(1);
    let [b102, b201] = inner(2);
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

/// The crease angle the solids use unless told otherwise, in degrees: an edge whose two triangles'
/// normals differ by more is kept sharp. More than twice the largest such angle of the built-in
/// examples (22.6° around the torus's tube; under 15° on the blob, under 10° on the icosphere), so
/// they have no creases, and well below a cube's 90°. Away from the angles of regular shapes: an
/// icosahedron (42°) and an octagonal prism's sides (45°) are rounded; an octahedron (71°), a
/// dodecahedron (63°) and the sides of a prism of up to seven sides (51.4°) keep their edges.
pub const DEFAULT_CREASE_ANGLE: f64 = 50.0;

/// Whether `degrees` is a crease angle: a finite number from 0 to 180 (180: no edge is a crease).
#[must_use]
pub fn valid_crease_angle(degrees: f64) -> bool {
    degrees.is_finite() && (0.0..=180.0).contains(&degrees)
}

/// The angle between two unit vectors, in degrees (accurate near 0 and 180, unlike `acos`); 0 when
/// either is zero.
#[must_use]
pub fn angle_degrees(a: DVec3, b: DVec3) -> f64 {
    libm::atan2(a.cross(b).length(), a.dot(b)).to_degrees()
}

/// The creases of a mesh at a crease angle, and the normals the patches take at their corners (see
/// the module documentation).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Creases {
    /// Per triangle, whether its edge `e` (from corner `e` to corner `e + 1`) is a crease.
    pub sharp: Vec<[bool; 3]>,
    /// Per triangle, the unit normal at each corner: the mesh's vertex normal where the vertex has
    /// one sector, the sector's normal where creases split the triangles around it.
    pub corner_normals: Vec<[DVec3; 3]>,
    /// The number of crease edges.
    pub edges: usize,
}

/// The creases of `mesh` at `degrees` (an edge is a crease where its two triangles' normals differ
/// by more) and the corner normals they give. Only an edge with exactly two triangles can be a
/// crease; a crease angle of 180 or more, or NaN, makes none.
///
/// # Panics
///
/// If a triangle indexes past `mesh.positions` or `mesh.normals`.
#[must_use]
pub fn creases(mesh: &Mesh, degrees: f64) -> Creases {
    let tris = &mesh.triangles;
    let face: Vec<DVec3> = tris
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
            (b - a).cross(c - a).normalize_or_zero()
        })
        .collect();
    let mut sharp = vec![[false; 3]; tris.len()];
    // Corners 3t + k, joined across edges that are not creases: the sectors.
    let mut parent: Vec<usize> = (0..tris.len() * 3).collect();
    let mut edges: Vec<(u32, u32, u32, u8)> = Vec::with_capacity(tris.len() * 3);
    for (t, tri) in tris.iter().enumerate() {
        for e in 0..3 {
            let (a, b) = (tri[e], tri[(e + 1) % 3]);
            edges.push((a.min(b), a.max(b), t as u32, e as u8));
        }
    }
    edges.sort_unstable();
    let mut count = 0;
    for group in edges.chunk_by(|x, y| x.0 == y.0 && x.1 == y.1) {
        let &[(_, _, t1, e1), (_, _, t2, e2)] = group else {
            continue;
        };
        let (t1, t2) = (t1 as usize, t2 as usize);
        if angle_degrees(face[t1], face[t2]) > degrees {
            sharp[t1][e1 as usize] = true;
            sharp[t2][e2 as usize] = true;
            count += 1;
            continue;
        }
        // The corners of the two triangles at each end of the edge are in one sector.
        for v in [group[0].0, group[0].1] {
            let k1 = tris[t1].iter().position(|&i| i == v).unwrap_or(0);
            let k2 = tris[t2].iter().position(|&i| i == v).unwrap_or(0);
            let (r1, r2) = (
                find(&mut parent, 3 * t1 + k1),
                find(&mut parent, 3 * t2 + k2),
            );
            parent[r1] = r2;
        }
    }
    // Per vertex: its first sector, and whether it has another.
    let n = mesh.positions.len();
    let mut first = vec![usize::MAX; n];
    let mut split = vec![false; n];
    let mut sums = vec![DVec3::ZERO; tris.len() * 3];
    for (t, tri) in tris.iter().enumerate() {
        let p = tri.map(|i| mesh.positions[i as usize]);
        for k in 0..3 {
            let v = tri[k] as usize;
            let root = find(&mut parent, 3 * t + k);
            if first[v] == usize::MAX {
                first[v] = root;
            } else if first[v] != root {
                split[v] = true;
            }
            let u = p[(k + 1) % 3] - p[k];
            let w = p[(k + 2) % 3] - p[k];
            sums[root] += face[t] * libm::atan2(u.cross(w).length(), u.dot(w));
        }
    }
    let corner_normals = tris
        .iter()
        .enumerate()
        .map(|(t, tri)| {
            core::array::from_fn(|k| {
                let v = tri[k] as usize;
                if split[v] {
                    let root = find(&mut parent, 3 * t + k);
                    let n = sums[root].normalize_or_zero();
                    if n == DVec3::ZERO { face[t] } else { n }
                } else {
                    mesh.normals[v]
                }
            })
        })
        .collect();
    Creases {
        sharp,
        corner_normals,
        edges: count,
    }
}

/// The root of `i` in a union–find forest, halving paths on the way.
fn find(parent: &mut [usize], mut i: usize) -> usize {
    while parent[i] != i {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    i
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
    /// The PN patches of every triangle of `mesh`, whose `normals` are its unit vertex normals, with
    /// the edges sharper than [`DEFAULT_CREASE_ANGLE`] kept sharp (see the module documentation).
    ///
    /// # Panics
    ///
    /// If a triangle indexes past `mesh.positions` or `mesh.normals`.
    #[must_use]
    pub fn new(mesh: &Mesh) -> Self {
        Self::creased(mesh, &creases(mesh, DEFAULT_CREASE_ANGLE))
    }

    /// As [`PnSurface::new`] with the crease angle `degrees`: an edge whose triangles' normals differ
    /// by more is kept sharp; 180 rounds every edge (one normal per vertex everywhere).
    ///
    /// # Errors
    ///
    /// [`EscError::CreaseAngle`] unless `degrees` is finite and from 0 to 180.
    ///
    /// # Panics
    ///
    /// If a triangle indexes past `mesh.positions` or `mesh.normals`.
    pub fn with_crease_angle(mesh: &Mesh, degrees: f64) -> Result<Self, EscError> {
        if !valid_crease_angle(degrees) {
            return Err(EscError::CreaseAngle { degrees });
        }
        Ok(Self::creased(mesh, &creases(mesh, degrees)))
    }

    /// The PN patches of every triangle of `mesh` with the corner normals and crease edges of
    /// `creases` (from [`creases`] of the same mesh).
    ///
    /// # Panics
    ///
    /// If `creases` does not have one entry per triangle, or a triangle indexes past
    /// `mesh.positions`.
    #[must_use]
    pub fn creased(mesh: &Mesh, creases: &Creases) -> Self {
        let mut patches = Vec::with_capacity(mesh.triangles.len());
        let mut normals = Vec::with_capacity(mesh.triangles.len());
        for (t, tri) in mesh.triangles.iter().enumerate() {
            let p = tri.map(|i| mesh.positions[i as usize]);
            let n = creases.corner_normals[t];
            patches.push(pn_patch_creased(p, n, creases.sharp[t]));
            normals.push(pn_normals(p, n));
        }
        Self { patches, normals }
    }

    /// The unit normals of patch `t` at its corners `P300`, `P030`, `P003` (the corner normals its
    /// net was made from).
    ///
    /// # Panics
    ///
    /// If `t` is out of range.
    #[must_use]
    pub fn corner_normals(&self, t: usize) -> [DVec3; 3] {
        let n = &self.normals[t];
        [n[5], n[2], n[0]]
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
        // Every edge's curve is the same from both sides.
        crate::esc::tests::assert_watertight(&pn, &mesh);
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
