//! The shells of a closed mesh (its connected pieces) and their orientation from nesting.
//!
//! A closed mesh may bound a solid with several pieces, or with cavities: each piece of its surface
//! is a *shell*. A shell inside an even number of others (0: an outer boundary) must face outward,
//! with positive signed volume; one inside an odd number bounds a cavity and faces inward, negative.
//! [`orient_shells`] refuses shells whose flat triangles meet, tells nesting by ray parity against
//! the flat triangles, with exact orientation predicates, and turns over every shell that faces the
//! wrong way.

use alloc::vec;
use alloc::vec::Vec;
use core::fmt;

use glam::{DVec2, DVec3};

use super::Mesh;
use crate::esc::predicates::{orient_sign, orient2_sign};

/// The most work [`orient_shells`] does to tell the shells' nesting, in pairs of boxes compared
/// and triangles tested: about a second. A hostile mesh of thousands of shells whose boxes all
/// overlap would otherwise take hours.
pub const MAX_SHELL_WORK: usize = 50_000_000;

/// Why [`orient_shells`] cannot orient a mesh's shells. Shells are numbered from 0 in the order of
/// their first triangle.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ShellError {
    /// Two shells cross (or touch) each other: a triangle of one meets a triangle of the other, side
    /// by side or one inside the other (a cavity that reaches through its outer shell).
    Intersect {
        /// The lower shell number.
        first: usize,
        /// The higher shell number.
        second: usize,
    },
    /// So many shells overlap that telling their nesting would take more than
    /// [`MAX_SHELL_WORK`].
    TooManyOverlaps {
        /// The number of shells.
        shells: usize,
    },
}

impl fmt::Display for ShellError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Intersect { first, second } => write!(
                f,
                "the mesh does not bound a solid: its pieces {} and {} (numbered from 1 in the \
                 order of their triangles) cross each other",
                first + 1,
                second + 1
            ),
            Self::TooManyOverlaps { shells } => write!(
                f,
                "the mesh has {shells} pieces whose bounding boxes overlap too much to tell which \
                 lie inside which"
            ),
        }
    }
}

impl core::error::Error for ShellError {}

/// What [`orient_shells`] found and did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct ShellOrientation {
    /// The number of shells (connected pieces of the surface).
    pub shells: usize,
    /// The number of shells that faced the wrong way and were turned over.
    pub turned_over: usize,
}

/// The shell of each triangle, numbered from 0 in the order of their first triangle, and the number
/// of shells: triangles sharing a vertex are in one shell (in a closed 2-manifold that is the same
/// as sharing an edge). Triangles with an index past `vertices` are put in shell 0.
#[must_use]
pub fn shells(vertices: usize, triangles: &[[u32; 3]]) -> (Vec<u32>, usize) {
    let mut parent: Vec<usize> = (0..vertices).collect();
    for tri in triangles {
        if tri.iter().any(|&i| i as usize >= vertices) {
            continue;
        }
        let r0 = find(&mut parent, tri[0] as usize);
        for &i in &tri[1..] {
            let r = find(&mut parent, i as usize);
            if r != r0 {
                parent[r] = r0;
            }
        }
    }
    let mut number = vec![u32::MAX; vertices];
    let mut count = 0usize;
    let labels = triangles
        .iter()
        .map(|tri| {
            if tri.iter().any(|&i| i as usize >= vertices) {
                return 0;
            }
            let root = find(&mut parent, tri[0] as usize);
            if number[root] == u32::MAX {
                number[root] = count as u32;
                count += 1;
            }
            number[root]
        })
        .collect();
    (labels, count)
}

/// The root of `i` in a union–find forest, halving paths on the way.
fn find(parent: &mut [usize], mut i: usize) -> usize {
    while parent[i] != i {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    i
}

/// Turns over the shells of a closed mesh that face the wrong way for their nesting: outward
/// (positive signed volume) inside an even number of other shells, inward (a cavity) inside an odd
/// number. A turned-over shell has its triangles' corners reversed and, where `mesh.normals` has
/// one normal per vertex, its vertices' normals negated (they are taken to follow the triangles).
///
/// Nesting is told by one vertex of each shell, by ray parity against the other shell's flat
/// triangles with exact orientation predicates (a ray through an edge or a vertex is cast again in
/// another direction; a vertex that lies on the other shell gives way to the next one, up to 16).
/// Only pairs whose bounding boxes overlap are tested, so the work is about the number of such
/// pairs times the triangles of a shell; a mesh of one shell only has its volume summed.
///
/// The mesh should be a closed, consistently oriented 2-manifold ([`super::validate`]); shells that
/// cross or touch each other do not bound a solid, and are refused ([`ShellError::Intersect`]): the
/// triangles of two shells whose boxes overlap are compared exactly where their own boxes reach
/// into both shells' boxes, swept along x. Shells whose surfaces do not meet are nested or apart
/// as one vertex says, so nesting is then exact.
///
/// # Errors
///
/// [`ShellError`], the mesh unchanged: shells that cross, or more work than [`MAX_SHELL_WORK`].
///
/// # Panics
///
/// If a triangle indexes past `mesh.positions`.
pub fn orient_shells(mesh: &mut Mesh) -> Result<ShellOrientation, ShellError> {
    orient_shells_within(mesh, MAX_SHELL_WORK)
}

/// [`orient_shells`] with at most `budget` work.
fn orient_shells_within(mesh: &mut Mesh, budget: usize) -> Result<ShellOrientation, ShellError> {
    let (labels, count) = shells(mesh.positions.len(), &mesh.triangles);
    // Per shell: its triangles, bounding box, one list of vertices to test.
    let mut members: Vec<Vec<u32>> = vec![Vec::new(); count];
    let mut boxes = vec![(DVec3::INFINITY, DVec3::NEG_INFINITY); count];
    for (t, tri) in mesh.triangles.iter().enumerate() {
        let s = labels[t] as usize;
        members[s].push(t as u32);
        for &i in tri {
            let p = mesh.positions[i as usize];
            boxes[s] = (boxes[s].0.min(p), boxes[s].1.max(p));
        }
    }
    let volume = |s: usize| {
        let o = (boxes[s].0 + boxes[s].1) * 0.5;
        members[s]
            .iter()
            .map(|&t| {
                let [a, b, c] = mesh.triangles[t as usize].map(|i| mesh.positions[i as usize] - o);
                a.dot(b.cross(c))
            })
            .sum::<f64>()
    };
    let mut depth = vec![0usize; count];
    // Pairs of shells whose boxes overlap, by sweeping along x: the shells in order of their boxes'
    // low x, each against those before it whose boxes reach it.
    let mut order: Vec<usize> = (0..count).collect();
    order.sort_unstable_by(|&a, &b| boxes[a].0.x.total_cmp(&boxes[b].0.x));
    let mut active: Vec<usize> = Vec::new();
    let mut budget = budget;
    let too_much = ShellError::TooManyOverlaps { shells: count };
    for &b in &order {
        let (blo, bhi) = boxes[b];
        active.retain(|&a| boxes[a].1.x >= blo.x);
        budget = budget.checked_sub(active.len()).ok_or(too_much)?;
        for &a in &active {
            let (alo, ahi) = boxes[a];
            if !(alo.cmple(bhi).all() && blo.cmple(ahi).all()) {
                continue;
            }
            let crossing = Err(ShellError::Intersect {
                first: a.min(b),
                second: a.max(b),
            });
            let b_in_a = shell_holds(mesh, &members[a], boxes[a], &members[b], &mut budget)
                .ok_or(too_much)?
                == Some(true);
            let a_in_b = shell_holds(mesh, &members[b], boxes[b], &members[a], &mut budget)
                .ok_or(too_much)?
                == Some(true);
            // A point of one inside the other and one outside the other's box, or each inside the
            // other: their surfaces cross.
            if (b_in_a && !(alo.cmple(blo).all() && bhi.cmple(ahi).all()))
                || (a_in_b && !(blo.cmple(alo).all() && ahi.cmple(bhi).all()))
                || (a_in_b && b_in_a)
            {
                return crossing;
            }
            // Neither vertex test shows it (an inner shell poking through its outer one, or pieces
            // side by side whose tested vertices are outside each other): the surfaces.
            let overlap = (alo.max(blo), ahi.min(bhi));
            if surfaces_meet(mesh, [&members[a], &members[b]], overlap, &mut budget)
                .ok_or(too_much)?
            {
                return crossing;
            }
            if b_in_a {
                depth[b] += 1;
            }
            if a_in_b {
                depth[a] += 1;
            }
        }
        active.push(b);
    }
    let mut turned_over = 0;
    let mut flip = vec![false; count];
    for s in 0..count {
        let v = volume(s);
        let outward = depth[s].is_multiple_of(2);
        if v != 0.0 && (v > 0.0) != outward {
            flip[s] = true;
            turned_over += 1;
        }
    }
    if turned_over > 0 {
        let normals = mesh.normals.len() == mesh.positions.len();
        let mut negated = vec![false; mesh.positions.len()];
        for (t, tri) in mesh.triangles.iter_mut().enumerate() {
            if !flip[labels[t] as usize] {
                continue;
            }
            tri.swap(1, 2);
            for &i in tri.iter() {
                if normals && !negated[i as usize] {
                    negated[i as usize] = true;
                    mesh.normals[i as usize] = -mesh.normals[i as usize];
                }
            }
        }
    }
    Ok(ShellOrientation {
        shells: count,
        turned_over,
    })
}

/// Whether a triangle of the shell `shells[0]` meets one of `shells[1]` (their triangles), exactly.
/// Only triangles whose boxes reach into `overlap` (the box both shells' boxes hold) are compared,
/// swept along x, each against those of the other shell whose boxes overlap its own. `None` when
/// that would take more than `budget`, which is spent by the triangles listed and the pairs
/// compared.
fn surfaces_meet(
    mesh: &Mesh,
    shells: [&[u32]; 2],
    overlap: (DVec3, DVec3),
    budget: &mut usize,
) -> Option<bool> {
    // Per triangle near the overlap: its box, its shell (0 or 1) and its corners.
    let mut near: Vec<(DVec3, DVec3, usize, [DVec3; 3])> = Vec::new();
    for (side, shell) in shells.iter().enumerate() {
        *budget = budget.checked_sub(shell.len())?;
        for &t in *shell {
            let p = mesh.triangles[t as usize].map(|i| mesh.positions[i as usize]);
            let (lo, hi) = (p[0].min(p[1]).min(p[2]), p[0].max(p[1]).max(p[2]));
            if lo.cmple(overlap.1).all() && overlap.0.cmple(hi).all() {
                near.push((lo, hi, side, p));
            }
        }
    }
    near.sort_unstable_by(|x, y| x.0.x.total_cmp(&y.0.x));
    // The triangles of each shell whose boxes reach the sweep's x.
    let mut active: [Vec<usize>; 2] = [Vec::new(), Vec::new()];
    for (k, &(lo, hi, side, p)) in near.iter().enumerate() {
        for list in &mut active {
            list.retain(|&j| near[j].1.x >= lo.x);
        }
        let other = &active[1 - side];
        *budget = budget.checked_sub(other.len())?;
        for &j in other {
            let (jlo, jhi, _, q) = near[j];
            if jlo.cmple(hi).all() && lo.cmple(jhi).all() && triangles_meet(p, q) {
                return Some(true);
            }
        }
        active[side].push(k);
    }
    Some(false)
}

/// Whether the closed triangles `s` and `t` share a point, exactly. Their intersection is convex,
/// and its extreme points lie on edges of one or the other, so they meet where an edge of one meets
/// the other.
fn triangles_meet(s: [DVec3; 3], t: [DVec3; 3]) -> bool {
    // All of one strictly on one side of the other's plane: apart.
    let t_side = t.map(|p| orient_sign(s[0], s[1], s[2], p));
    let s_side = s.map(|p| orient_sign(t[0], t[1], t[2], p));
    if [t_side, s_side]
        .iter()
        .any(|sides| *sides == [1; 3] || *sides == [-1; 3])
    {
        return false;
    }
    (0..3).any(|i| {
        segment_meets_triangle(s[i], s[(i + 1) % 3], t)
            || segment_meets_triangle(t[i], t[(i + 1) % 3], s)
    })
}

/// Whether the segment `p–q` meets the closed triangle `a, b, c`, exactly. A triangle whose corners
/// are collinear meets nothing here (its edges are tested as segments of the other triangle).
fn segment_meets_triangle(p: DVec3, q: DVec3, [a, b, c]: [DVec3; 3]) -> bool {
    let (sp, sq) = (orient_sign(a, b, c, p), orient_sign(a, b, c, q));
    if sp == sq && sp != 0 {
        return false;
    }
    if sp == 0 && sq == 0 {
        // In the triangle's plane: in the coordinate plane where the triangle's shadow is largest.
        let Some(flat) = projection(a, b, c) else {
            return false;
        };
        return segment_meets_triangle_2d(flat(p), flat(q), [flat(a), flat(b), flat(c)]);
    }
    // The segment meets the plane at one point: within the triangle when the line through the
    // segment passes no edge on the wrong side.
    let e = [
        orient_sign(p, q, a, b),
        orient_sign(p, q, b, c),
        orient_sign(p, q, c, a),
    ];
    !(e.contains(&1) && e.contains(&-1))
}

/// The projection that drops the axis along which the triangle `a, b, c` is seen largest (exact, as
/// dropping a coordinate is), or `None` for a triangle whose corners are collinear.
fn projection(a: DVec3, b: DVec3, c: DVec3) -> Option<fn(DVec3) -> DVec2> {
    let drops: [fn(DVec3) -> DVec2; 3] = [
        |p| DVec2::new(p.y, p.z),
        |p| DVec2::new(p.z, p.x),
        |p| DVec2::new(p.x, p.y),
    ];
    let normal = (b - a).cross(c - a).abs();
    let mut order = [0, 1, 2];
    order.sort_unstable_by(|&i, &j| normal[j].total_cmp(&normal[i]));
    // The largest rounded component first; any projection with a non-zero exact area will do.
    order
        .into_iter()
        .map(|k| drops[k])
        .find(|f| orient2_sign(f(a), f(b), f(c)) != 0)
}

/// Whether the segment `p–q` meets the closed triangle `a, b, c` (not collinear), in the plane.
fn segment_meets_triangle_2d(p: DVec2, q: DVec2, [a, b, c]: [DVec2; 3]) -> bool {
    let turn = orient2_sign(a, b, c);
    let inside = |x: DVec2| {
        [(a, b), (b, c), (c, a)]
            .iter()
            .all(|&(u, v)| orient2_sign(u, v, x) * turn >= 0)
    };
    inside(p)
        || inside(q)
        || [(a, b), (b, c), (c, a)]
            .iter()
            .any(|&(u, v)| segments_meet(p, q, u, v))
}

/// Whether the closed segments `p–q` and `u–v` share a point, in the plane, exactly.
fn segments_meet(p: DVec2, q: DVec2, u: DVec2, v: DVec2) -> bool {
    let (d1, d2) = (orient2_sign(u, v, p), orient2_sign(u, v, q));
    let (d3, d4) = (orient2_sign(p, q, u), orient2_sign(p, q, v));
    // On the segment's line and within its box: on the segment.
    let on = |s: DVec2, e: DVec2, x: DVec2, d: i8| {
        d == 0 && x.cmpge(s.min(e)).all() && x.cmple(s.max(e)).all()
    };
    (d1 * d2 < 0 && d3 * d4 < 0)
        || on(u, v, p, d1)
        || on(u, v, q, d2)
        || on(p, q, u, d3)
        || on(p, q, v, d4)
}

/// The most vertices of a shell tried when the first ones lie on the other shell.
const MAX_TRIES: usize = 16;

/// Directions tried in turn for a ray (none along an axis or a diagonal).
const DIRECTIONS: [[f64; 3]; 4] = [
    [0.539_3, 0.807_1, 0.241_2],
    [-0.613_7, 0.283_1, 0.737_3],
    [0.171_9, -0.521_3, 0.835_9],
    [-0.334_1, -0.774_5, -0.537_2],
];

/// Whether the shell `inner` (its triangles) has a vertex inside the shell `outer` (bounding box
/// `outer_box`): `Some(None)` when every vertex tried lies on `outer` or no ray told; `None` when
/// the triangles to test would take more than `budget`, which is spent by those tested.
#[allow(clippy::option_option)]
fn shell_holds(
    mesh: &Mesh,
    outer: &[u32],
    outer_box: (DVec3, DVec3),
    inner: &[u32],
    budget: &mut usize,
) -> Option<Option<bool>> {
    let mut tried = 0;
    for &t in inner {
        for &v in &mesh.triangles[t as usize] {
            if tried == MAX_TRIES {
                return Some(None);
            }
            tried += 1;
            let q = mesh.positions[v as usize];
            match point_in_shell(mesh, outer, outer_box, q, budget)? {
                Parity::Inside => return Some(Some(true)),
                Parity::Outside => return Some(Some(false)),
                Parity::OnSurface | Parity::Unsure => {}
            }
        }
    }
    Some(None)
}

/// Where a point is against a closed shell.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Parity {
    Inside,
    Outside,
    /// On one of the shell's triangles.
    OnSurface,
    /// Every ray passed through an edge or a vertex.
    Unsure,
}

/// Ray parity of `q` against the flat triangles `shell`, whose box is `bounds`: segments from `q` to
/// points beyond the box, each crossing decided by exact orientation signs. `None` when a ray's
/// triangles would take more than `budget`, which is spent by each ray cast.
fn point_in_shell(
    mesh: &Mesh,
    shell: &[u32],
    bounds: (DVec3, DVec3),
    q: DVec3,
    budget: &mut usize,
) -> Option<Parity> {
    let (lo, hi) = bounds;
    if !(q.cmpge(lo).all() && q.cmple(hi).all()) {
        return Some(Parity::Outside);
    }
    let reach = 2.0 * (hi - lo).length() + 1.0;
    'directions: for d in DIRECTIONS {
        *budget = budget.checked_sub(shell.len())?;
        let r = q + DVec3::from_array(d) * reach;
        if !r.is_finite() {
            return Some(Parity::Unsure);
        }
        let mut odd = false;
        for &t in shell {
            let [a, b, c] = mesh.triangles[t as usize].map(|i| mesh.positions[i as usize]);
            match crossing(q, r, a, b, c) {
                Crossing::No => {}
                Crossing::Yes => odd = !odd,
                Crossing::OnSurface => return Some(Parity::OnSurface),
                Crossing::Degenerate => continue 'directions,
            }
        }
        return Some(if odd { Parity::Inside } else { Parity::Outside });
    }
    Some(Parity::Unsure)
}

/// How the segment `q → r` meets a triangle.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Crossing {
    No,
    /// Through the triangle's inside.
    Yes,
    /// `q` is on the triangle.
    OnSurface,
    /// Through an edge or a vertex, or `r` on the triangle's plane: no answer.
    Degenerate,
}

/// The segment `q → r` against the triangle `a, b, c`, exactly.
fn crossing(q: DVec3, r: DVec3, a: DVec3, b: DVec3, c: DVec3) -> Crossing {
    let sr = orient_sign(a, b, c, r);
    if sr == 0 {
        return Crossing::Degenerate;
    }
    let sq = orient_sign(a, b, c, q);
    if sq == sr {
        return Crossing::No;
    }
    // The line q–r against the triangle's edges: all one sign, through the inside.
    let e = [
        orient_sign(q, r, a, b),
        orient_sign(q, r, b, c),
        orient_sign(q, r, c, a),
    ];
    let mixed = e.contains(&1) && e.contains(&-1);
    if mixed {
        return Crossing::No;
    }
    if sq == 0 {
        // q on the plane, and the line meets the plane at q: on the triangle or its border.
        return Crossing::OnSurface;
    }
    if e.contains(&0) {
        Crossing::Degenerate
    } else {
        Crossing::Yes
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::validate;
    use alloc::string::ToString;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    /// The box `[lo, hi]` as 12 outward triangles, its vertices numbered from `base`.
    fn cube(lo: DVec3, hi: DVec3, base: u32) -> (Vec<DVec3>, Vec<[u32; 3]>) {
        crate::testutil::box_mesh(lo, hi, base)
    }

    fn mesh_of(parts: &[(DVec3, DVec3, bool)]) -> Mesh {
        let mut mesh = Mesh::default();
        for &(lo, hi, inward) in parts {
            let (p, mut t) = cube(lo, hi, mesh.positions.len() as u32);
            if inward {
                for tri in &mut t {
                    tri.swap(1, 2);
                }
            }
            mesh.normals
                .extend(p.iter().map(|q| (*q - (lo + hi) * 0.5).normalize()));
            mesh.positions.extend(p);
            mesh.triangles.extend(t);
        }
        mesh
    }

    fn shell_volumes(mesh: &Mesh) -> Vec<f64> {
        let (labels, count) = shells(mesh.positions.len(), &mesh.triangles);
        let mut v = vec![0.0; count];
        for (t, tri) in mesh.triangles.iter().enumerate() {
            let [a, b, c] = tri.map(|i| mesh.positions[i as usize]);
            v[labels[t] as usize] += a.dot(b.cross(c)) / 6.0;
        }
        v
    }

    #[test]
    fn shells_are_numbered_in_triangle_order() {
        let mesh = mesh_of(&[
            (DVec3::splat(-1.0), DVec3::splat(1.0), false),
            (DVec3::splat(3.0), DVec3::splat(4.0), false),
        ]);
        let (labels, count) = shells(mesh.positions.len(), &mesh.triangles);
        assert_eq!(count, 2);
        assert!(labels[..12].iter().all(|&l| l == 0));
        assert!(labels[12..].iter().all(|&l| l == 1));
    }

    #[test]
    fn shells_face_the_way_their_nesting_says() {
        let outer = (DVec3::splat(-2.0), DVec3::splat(2.0));
        let cavity = (DVec3::splat(-1.0), DVec3::splat(1.0));
        let island = (DVec3::splat(-0.5), DVec3::splat(0.5));
        let apart = (DVec3::splat(5.0), DVec3::splat(6.0));
        // (outer inward?, cavity inward?, island inward?, apart inward?) → shells turned over.
        for flips in 0..16u32 {
            let f = |k: u32| flips & (1 << k) != 0;
            let mut mesh = mesh_of(&[
                (outer.0, outer.1, f(0)),
                (cavity.0, cavity.1, f(1)),
                (island.0, island.1, f(2)),
                (apart.0, apart.1, f(3)),
            ]);
            validate(&mesh.positions, &mesh.triangles).expect("closed");
            let before = mesh.clone();
            let done = orient_shells(&mut mesh).expect("nested, not crossing");
            // Right: outer and apart outward, cavity inward, island (in the cavity) outward.
            let wrong = u32::from(f(0)) + u32::from(!f(1)) + u32::from(f(2)) + u32::from(f(3));
            assert_eq!(done.shells, 4);
            assert_eq!(done.turned_over, wrong as usize, "flips {flips:04b}");
            let v = shell_volumes(&mesh);
            assert!(
                v[0] > 0.0 && v[1] < 0.0 && v[2] > 0.0 && v[3] > 0.0,
                "{v:?}"
            );
            // Normals follow their triangles.
            for (i, (n, m)) in mesh.normals.iter().zip(&before.normals).enumerate() {
                let s = i / 8;
                let turned = [f(0), !f(1), f(2), f(3)][s];
                assert_eq!(*n, if turned { -*m } else { *m });
            }
            // Again: nothing to do.
            let again = orient_shells(&mut mesh).expect("fine");
            assert_eq!(again.turned_over, 0);
        }
    }

    #[test]
    fn many_shells_apart_are_each_turned_outward() {
        let mut parts = Vec::new();
        for i in 0..1000 {
            let lo = DVec3::new(
                f64::from(i % 10),
                f64::from(i / 10 % 10),
                f64::from(i / 100),
            ) * 2.0;
            parts.push((lo, lo + DVec3::ONE, i % 3 == 0));
        }
        let mut mesh = mesh_of(&parts);
        let done = orient_shells(&mut mesh).expect("apart");
        assert_eq!(done.shells, 1000);
        assert_eq!(done.turned_over, 334);
        assert!(shell_volumes(&mesh).iter().all(|&v| v > 0.0));
    }

    #[test]
    fn too_many_overlapping_shells_are_refused() {
        // Twenty nested cubes: 190 pairs, each testing a vertex against 12 triangles or more.
        let parts: Vec<_> = (1..=20)
            .map(|i| {
                (
                    DVec3::splat(-f64::from(i)),
                    DVec3::splat(f64::from(i)),
                    false,
                )
            })
            .collect();
        let mut mesh = mesh_of(&parts);
        let before = mesh.clone();
        assert_eq!(
            orient_shells_within(&mut mesh, 1000),
            Err(ShellError::TooManyOverlaps { shells: 20 })
        );
        assert_eq!(mesh, before);
        // Within the budget: every other one is a cavity.
        let done = orient_shells(&mut mesh).expect("nested");
        assert_eq!(done.turned_over, 10);
        let v = shell_volumes(&mesh);
        for (k, v) in v.iter().enumerate() {
            // Shell k is the cube of half-side k + 1, inside 19 − k others.
            assert_eq!(*v > 0.0, (19 - k) % 2 == 0, "{k}");
        }
    }

    #[test]
    fn crossing_shells_are_refused_where_it_shows() {
        // The second cube's corner is inside the first, and it reaches outside its box.
        let mut mesh = mesh_of(&[
            (DVec3::splat(-1.0), DVec3::splat(1.0), false),
            (DVec3::splat(0.5), DVec3::splat(2.0), false),
        ]);
        let before = mesh.clone();
        assert_eq!(
            orient_shells(&mut mesh),
            Err(ShellError::Intersect {
                first: 0,
                second: 1
            })
        );
        assert_eq!(mesh, before);
        // The same, numbered the other way round, and a cube whose corner pokes into a bigger one.
        for parts in [
            [
                (DVec3::splat(0.5), DVec3::splat(2.0), false),
                (DVec3::splat(-1.0), DVec3::splat(1.0), true),
            ],
            [
                (DVec3::splat(-1.0), DVec3::splat(1.0), false),
                (DVec3::splat(-2.0), DVec3::splat(0.5), false),
            ],
        ] {
            let mut mesh = mesh_of(&parts);
            assert_eq!(
                orient_shells(&mut mesh),
                Err(ShellError::Intersect {
                    first: 0,
                    second: 1
                })
            );
        }
        assert!(
            ShellError::Intersect {
                first: 0,
                second: 1
            }
            .to_string()
            .contains("pieces 1 and 2")
        );
    }

    #[test]
    fn crossing_shells_are_refused_where_no_vertex_shows_it() {
        // A cube inside the unit sphere whose corners poke through it: the cube's box is within the
        // sphere's, its tested corner is outside the sphere and the sphere's vertex outside the cube.
        let sphere = crate::esc::examples::icosphere(2);
        let with = |lo: DVec3, hi: DVec3| {
            let mut mesh = sphere.clone();
            let (p, t) = cube(lo, hi, mesh.positions.len() as u32);
            mesh.normals.extend(p.iter().map(|q| -q.normalize()));
            mesh.positions.extend(p);
            mesh.triangles.extend(t);
            mesh
        };
        let mut mesh = with(DVec3::splat(-0.7), DVec3::splat(0.7));
        let before = mesh.clone();
        let e = orient_shells(&mut mesh).unwrap_err();
        assert_eq!(
            e,
            ShellError::Intersect {
                first: 0,
                second: 1
            }
        );
        assert_eq!(mesh, before);
        assert!(e.to_string().contains("pieces 1 and 2"), "{e}");
        // A cube well inside is a cavity (turned inward); a cavity touching its outer cube is refused.
        let mut inside = with(DVec3::splat(-0.5), DVec3::splat(0.5));
        let done = orient_shells(&mut inside).expect("a cavity");
        assert_eq!((done.shells, done.turned_over), (2, 1));
        let mut touching = mesh_of(&[
            (DVec3::splat(-1.0), DVec3::splat(1.0), false),
            (DVec3::new(-1.0, -0.5, -0.5), DVec3::splat(0.5), true),
        ]);
        assert!(matches!(
            orient_shells(&mut touching),
            Err(ShellError::Intersect { .. })
        ));
        // Two bars crossing like a plus sign: neither's first corner is inside the other.
        let mut plus = mesh_of(&[
            (
                DVec3::new(-3.0, -1.0, -1.0),
                DVec3::new(3.0, 1.0, 1.0),
                false,
            ),
            (
                DVec3::new(-1.0, -3.0, -0.5),
                DVec3::new(1.0, 3.0, 0.5),
                false,
            ),
        ]);
        assert_eq!(
            orient_shells(&mut plus),
            Err(ShellError::Intersect {
                first: 0,
                second: 1
            })
        );
    }

    #[test]
    fn triangles_meet_exactly_through_faces_edges_and_corners() {
        let t = [DVec3::ZERO, DVec3::X, DVec3::Y];
        let moved = |d: DVec3, s: [DVec3; 3]| s.map(|p| p + d);
        // Through the inside, edge to edge, corner to face, coplanar overlapping, coplanar apart,
        // parallel planes, and a slanted one that misses.
        let upright = [
            DVec3::new(0.2, 0.2, -1.0),
            DVec3::new(0.2, 0.2, 1.0),
            DVec3::new(0.3, 0.1, 0.0),
        ];
        assert!(triangles_meet(t, upright));
        assert!(triangles_meet(t, moved(DVec3::new(0.3, 0.0, 0.0), upright)));
        let corner_on_face = [
            DVec3::new(0.25, 0.25, 0.0),
            DVec3::new(0.25, 0.25, 1.0),
            DVec3::new(0.5, 0.0, 1.0),
        ];
        assert!(triangles_meet(t, corner_on_face));
        assert!(triangles_meet(t, moved(DVec3::new(0.5, 0.5, 0.0), t)));
        assert!(triangles_meet(t, moved(DVec3::new(1.0, 0.0, 0.0), t)));
        assert!(!triangles_meet(t, moved(DVec3::new(1.0, 0.5, 0.0), t)));
        assert!(!triangles_meet(t, moved(DVec3::new(0.0, 0.0, 1e-300), t)));
        assert!(!triangles_meet(
            t,
            moved(DVec3::new(0.5, 0.5, 0.0), upright)
        ));
        // A small triangle inside a large coplanar one.
        let small = [
            DVec3::new(0.1, 0.1, 0.0),
            DVec3::new(0.2, 0.1, 0.0),
            DVec3::new(0.1, 0.2, 0.0),
        ];
        assert!(triangles_meet(t, small) && triangles_meet(small, t));
    }

    #[test]
    fn points_on_a_shell_and_rays_through_its_edges_are_told() {
        let mesh = mesh_of(&[(DVec3::splat(-1.0), DVec3::splat(1.0), false)]);
        let all: Vec<u32> = (0..12).collect();
        let bounds = (DVec3::splat(-1.0), DVec3::splat(1.0));
        let mut budget = usize::MAX;
        let mut at =
            |q: DVec3| point_in_shell(&mesh, &all, bounds, q, &mut budget).expect("budget");
        assert_eq!(at(DVec3::ZERO), Parity::Inside);
        assert_eq!(at(DVec3::new(1.0, 0.2, 0.3)), Parity::OnSurface);
        assert_eq!(at(DVec3::new(1.0, 1.0, 1.0)), Parity::OnSurface);
        // On a face's diagonal, inside the face.
        assert_eq!(at(DVec3::new(0.5, 0.5, 1.0)), Parity::OnSurface);
        assert_eq!(at(DVec3::new(0.999, 0.0, 0.0)), Parity::Inside);
        assert_eq!(at(DVec3::new(1.5, 0.0, 0.0)), Parity::Outside);
    }
}
