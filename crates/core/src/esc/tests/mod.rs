//! The chain against independent oracles: the flat chain against the winding number of the flat
//! mesh by solid angles, the full chain against the winding number of the PN surface tessellated
//! finely, and the Boolean identities.
//!
//! The oracles and meshes shared by the tests are here; the tests, one file per concept:
//! `chain.rs` (point-in-solid against winding numbers and ray parity), `boolean.rs` (Boolean
//! identities and complements), `pn.rs` (PN surfaces, creases and imported meshes), `shells.rs`
//! (the orientation and nesting of shells).

use alloc::vec::Vec;

use glam::DVec3;

use crate::esc::chain::{EscSolid, Stats};
use crate::esc::examples::{icosphere, torus};
use crate::esc::pn::{PnSurface, eval_cubic};
use crate::mesh::Mesh;
use crate::mesh::angle_weighted_normals;
use crate::testutil::Rng;

mod boolean;
mod chain;
mod pn;
mod shells;

/// The generalised winding number of a closed triangle mesh at `q`: the sum of the triangles'
/// signed solid angles (Van Oosterom and Strackee) over 4π.
fn winding(positions: &[DVec3], triangles: &[[u32; 3]], q: DVec3) -> f64 {
    let mut sum = 0.0;
    for t in triangles {
        let [a, b, c] = t.map(|i| positions[i as usize] - q);
        let (la, lb, lc) = (a.length(), b.length(), c.length());
        let num = a.dot(b.cross(c));
        let den = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
        sum += 2.0 * num.atan2(den);
    }
    sum / (4.0 * core::f64::consts::PI)
}

/// A star-shaped random closed mesh: an icosphere with each vertex at a random radius, moved and
/// turned away from the origin.
fn random_star(seed: u64) -> Mesh {
    let mut rng = Rng::new(seed);
    let mut mesh = icosphere(2);
    let shift = DVec3::new(
        rng.range(-5.0, 5.0),
        rng.range(-5.0, 5.0),
        rng.range(-5.0, 5.0),
    );
    let scale = DVec3::new(
        rng.range(0.5, 2.0),
        rng.range(0.5, 2.0),
        rng.range(0.5, 2.0),
    );
    for p in &mut mesh.positions {
        *p = *p * rng.range(0.75, 1.25) * scale + shift;
    }
    mesh.normals = angle_weighted_normals(&mesh.positions, &mesh.triangles);
    mesh
}

/// A closed mesh that is not star-shaped from any point: a bent torus.
fn random_torus(seed: u64) -> Mesh {
    let mut rng = Rng::new(seed);
    let mut mesh = torus(1.0, rng.range(0.25, 0.45), 20, 10);
    let bend = rng.range(0.2, 0.6);
    for p in &mut mesh.positions {
        p.z += bend * p.x * p.x + rng.range(-0.02, 0.02);
    }
    mesh.normals = angle_weighted_normals(&mesh.positions, &mesh.triangles);
    mesh
}

/// Query points for `mesh`: uniform in its enlarged box, and points in the shell between the flat
/// triangles and their patches (where the free-form cells matter).
fn queries(solid: &EscSolid, rng: &mut Rng, count: usize) -> Vec<DVec3> {
    let (lo, hi) = solid.bounds();
    let pad = (hi - lo) * 0.1;
    let mut out = Vec::with_capacity(count);
    let pn = solid.surface();
    for k in 0..count {
        if k % 2 == 0 {
            out.push(DVec3::new(
                rng.range(lo.x - pad.x, hi.x + pad.x),
                rng.range(lo.y - pad.y, hi.y + pad.y),
                rng.range(lo.z - pad.z, hi.z + pad.z),
            ));
        } else {
            let t = rng.int(0, solid.triangles().len() - 1);
            let (s, r) = (rng.range(0.0, 1.0), rng.range(0.0, 1.0));
            let (s, r) = if s + r > 1.0 {
                (1.0 - s, 1.0 - r)
            } else {
                (s, r)
            };
            let b = DVec3::new(1.0 - s - r, s, r);
            let [p0, p1, p2] = solid.triangles()[t].map(|i| solid.positions()[i as usize]);
            let flat = p0 * b.x + p1 * b.y + p2 * b.z;
            let curved = super::pn::eval_cubic(&pn.patches[t], b);
            out.push(flat.lerp(curved, rng.range(-0.5, 1.5)));
        }
    }
    out
}

/// Compares the chain with the fine PN surface's winding number at points at least `tol` (times
/// the box size) from it; returns how many points were compared.
fn agrees_with_fine_surface(solid: &EscSolid, seed: u64, count: usize) -> usize {
    // About 100 k fine triangles at most.
    let level = ((100_000 / solid.triangles().len()) as f64)
        .sqrt()
        .clamp(3.0, 12.0) as usize;
    let fine = solid.surface().tessellate(level);
    let (lo, hi) = solid.bounds();
    let size = (hi - lo).max_element();
    // Distance to the surface ≥ distance to the nearest fine vertex − the fine edge length.
    let edge = fine
        .triangles
        .iter()
        .map(|t| (fine.positions[t[0] as usize] - fine.positions[t[1] as usize]).length())
        .fold(0.0, f64::max);
    let tol = 2e-3 * size + edge;
    let mut rng = Rng::new(seed);
    let mut stats = Stats::default();
    let mut compared = 0;
    for q in queries(solid, &mut rng, count) {
        let near = fine
            .positions
            .iter()
            .map(|p| (*p - q).length_squared())
            .fold(f64::INFINITY, f64::min)
            .sqrt();
        if near < tol {
            continue;
        }
        let expect = winding(&fine.positions, &fine.triangles, q).round() as i32;
        let got = solid.value(q, &mut stats);
        assert_eq!(got, expect, "at {q}: chain {got}, fine surface {expect}");
        compared += 1;
    }
    assert_eq!(stats.unsure, 0);
    compared
}

/// A cube read from OBJ text, as an import is: twelve large triangles, with normals at its corners
/// far from its faces' normals, so that with its edges rounded (crease angle 180) its PN patches
/// bulge far from their triangles and the free-form cells are thick (the shell between the cube and
/// its PN surface is most of the box).
fn imported_cube() -> Mesh {
    let obj = "v -1 -1 -1\nv 1 -1 -1\nv -1 1 -1\nv 1 1 -1\nv -1 -1 1\nv 1 -1 1\nv -1 1 1\nv 1 1 1\n\
               f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
    crate::mesh::read(obj.as_bytes()).expect("a closed mesh")
}

/// Checks the chain against an exact membership `oracle` (`None` within a hair of the surface) and
/// against ray parity on the PN surface, at `count` random points of the solid's box enlarged;
/// returns how many were compared.
fn agrees_with_oracle_and_parity(
    solid: &EscSolid,
    oracle: &dyn Fn(DVec3) -> Option<i32>,
    seed: u64,
    count: usize,
) -> usize {
    let (lo, hi) = solid.bounds();
    let pad = (hi - lo) * 0.2;
    let mut rng = Rng::new(seed);
    let mut stats = Stats::default();
    let mut seen = Vec::new();
    let mut compared = 0;
    for _ in 0..count {
        let q = DVec3::new(
            rng.range(lo.x - pad.x, hi.x + pad.x),
            rng.range(lo.y - pad.y, hi.y + pad.y),
            rng.range(lo.z - pad.z, hi.z + pad.z),
        );
        let Some(expect) = oracle(q) else {
            continue;
        };
        assert_eq!(solid.value(q, &mut stats), expect, "chain at {q}");
        assert_eq!(
            solid.parity_value(q, &mut stats, &mut seen),
            expect,
            "parity at {q}"
        );
        compared += 1;
    }
    assert_eq!(stats.unsure, 0, "{stats:?}");
    compared
}

/// Membership of the box `[lo, hi]`, `None` within `1e-9` of its faces.
fn in_box(q: DVec3, lo: DVec3, hi: DVec3) -> Option<bool> {
    let d = (q - lo).min(hi - q).min_element();
    (d.abs() > 1e-9).then_some(d > 0.0)
}

/// Every edge's curve is the same from both of its patches: the control points bit for bit, and
/// points along it evaluated on each patch agree to rounding.
pub(crate) fn assert_watertight(pn: &PnSurface, mesh: &Mesh) {
    for (t, tri) in mesh.triangles.iter().enumerate() {
        for e in 0..3 {
            let (a, b) = (tri[e], tri[(e + 1) % 3]);
            let (u, f) = mesh
                .triangles
                .iter()
                .enumerate()
                .find_map(|(u, o)| {
                    (0..3)
                        .find(|&f| o[f] == b && o[(f + 1) % 3] == a)
                        .map(|f| (u, f))
                })
                .expect("closed mesh");
            let mine = pn.patch(t).edge(e).expect("edge").points().to_vec();
            let mut theirs = pn.patch(u).edge(f).expect("edge").points().to_vec();
            theirs.reverse();
            assert_eq!(mine, theirs, "edge {a}–{b}");
            // Corner k at barycentric unit vector k; the edge from corner e to e + 1.
            let unit = |k: usize| DVec3::from_array(core::array::from_fn(|i| f64::from(i == k)));
            for s in [0.1, 0.25, 0.5, 0.8] {
                let p = eval_cubic(&pn.patches[t], unit(e) * (1.0 - s) + unit((e + 1) % 3) * s);
                let q = eval_cubic(&pn.patches[u], unit((f + 1) % 3) * (1.0 - s) + unit(f) * s);
                assert!((p - q).length() < 1e-13, "edge {a}–{b} at {s}: {p} {q}");
            }
        }
    }
}
