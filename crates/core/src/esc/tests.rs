//! The chain against independent oracles: the flat chain against the winding number of the flat
//! mesh by solid angles, the full chain against the winding number of the PN surface tessellated
//! finely, and the Boolean identities.

use alloc::vec::Vec;

use glam::DVec3;

use super::bool::{Expr, Op};
use super::chain::{EscSolid, Stats};
use super::examples::{Example, icosphere, torus};
use crate::mesh::Mesh;
use crate::mesh::angle_weighted_normals;
use crate::testutil::Rng;
#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

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

#[test]
fn the_flat_chain_is_the_flat_mesh_winding_number() {
    for seed in 0..4 {
        let mesh = random_star(seed);
        for apex in [None, Some(DVec3::ZERO), Some(DVec3::new(30.0, -7.0, 2.0))] {
            let solid = match apex {
                None => EscSolid::new(&mesh),
                Some(a) => EscSolid::with_apex(&mesh, a),
            }
            .expect("valid mesh");
            let mut rng = Rng::new(seed + 100);
            let mut stats = Stats::default();
            for q in queries(&solid, &mut rng, 300) {
                let w = winding(&mesh.positions, &mesh.triangles, q);
                if (w - w.round()).abs() > 1e-6 {
                    continue; // on the mesh within rounding: the solid angles cannot tell
                }
                assert_eq!(
                    solid.flat_value(q, &mut stats),
                    w.round() as i32,
                    "{q} apex {apex:?}"
                );
            }
        }
    }
}

#[test]
fn the_flat_chain_is_exact_on_faces_edges_and_vertices() {
    // Points exactly on the mesh, on shared faces of the tetrahedra (the apex's planes), and the
    // apex itself: the perturbation puts each in exactly one place, so f is 0 or 1.
    let mesh = icosphere(1);
    let solid = EscSolid::with_apex(&mesh, DVec3::ZERO).expect("valid");
    let mut stats = Stats::default();
    // On the mesh (vertices, edge midpoints): either side, but one.
    let mut on_mesh: Vec<DVec3> = mesh.positions.clone();
    // Strictly inside, on faces shared by tetrahedra: exactly 1.
    let mut inside = Vec::new();
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
        on_mesh.push((a + b) * 0.5);
        inside.push(a * 0.5); // on the face through the apex and the edge a–b
        inside.push((a + b + c) * 0.25);
    }
    for q in on_mesh {
        let f = solid.flat_value(q, &mut stats);
        assert!(f == 0 || f == 1, "f = {f} at {q}");
    }
    for q in inside {
        assert_eq!(solid.flat_value(q, &mut stats), 1, "at {q}");
    }
    assert_eq!(solid.flat_value(DVec3::ZERO, &mut stats), 1);
    assert_eq!(solid.flat_value(DVec3::new(0.5, 0.0, 0.0), &mut stats), 1);
}

#[test]
fn the_chain_agrees_with_the_fine_pn_surface_on_the_examples() {
    for example in Example::ALL {
        let solid = EscSolid::new(&example.mesh()).expect("valid");
        let n = agrees_with_fine_surface(&solid, 7, 150);
        assert!(n > 60, "{example:?}: only {n} points compared");
    }
}

#[test]
fn the_chain_agrees_with_the_fine_pn_surface_on_random_meshes() {
    for seed in 0..3 {
        for mesh in [random_star(seed), random_torus(seed)] {
            let solid = EscSolid::new(&mesh).expect("valid");
            let n = agrees_with_fine_surface(&solid, seed, 150);
            assert!(n > 60, "only {n} points compared");
            // The paper's apex at the origin gives the same solid.
            let origin = EscSolid::with_apex(&mesh, DVec3::ZERO).expect("valid");
            let n = agrees_with_fine_surface(&origin, seed + 9, 40);
            assert!(n > 15, "only {n} points compared");
        }
    }
}

#[test]
fn ray_parity_agrees_with_the_chain() {
    let mesh = random_torus(4);
    let solid = EscSolid::new(&mesh).expect("valid");
    let mut rng = Rng::new(5);
    let mut stats = Stats::default();
    let mut seen = Vec::new();
    let fine = solid.surface().tessellate(12);
    let mut compared = 0;
    for q in queries(&solid, &mut rng, 200) {
        let w = winding(&fine.positions, &fine.triangles, q);
        if (w - w.round()).abs() > 1e-3 {
            continue;
        }
        let near = fine.positions.iter().any(|p| (*p - q).length() < 0.02);
        if near {
            continue;
        }
        assert_eq!(
            solid.parity_value(q, &mut stats, &mut seen),
            solid.value(q, &mut stats),
            "{q}"
        );
        compared += 1;
    }
    assert!(compared > 100, "only {compared} points compared");
}

#[test]
fn boolean_identities_hold_at_sample_points() {
    let a = EscSolid::new(&Example::Icosphere.mesh()).expect("valid");
    let mut moved = Example::Torus.mesh();
    for p in &mut moved.positions {
        *p += DVec3::new(0.6, 0.1, 0.05);
    }
    let b = EscSolid::new(&moved).expect("valid");
    let solids = [a, b];
    let mut stats = Stats::default();
    let mut rng = Rng::new(1);
    let s = |i| Expr::Solid(i);
    let not = Expr::complement;
    let op = Expr::binary;
    use Op::{Difference as Minus, Intersection as And, Union as Or};
    for _ in 0..300 {
        let q = DVec3::new(
            rng.range(-1.6, 2.0),
            rng.range(-1.6, 1.6),
            rng.range(-1.2, 1.2),
        );
        let values = [
            solids[0].value(q, &mut stats),
            solids[1].value(q, &mut stats),
        ];
        let mut f = |i: usize| values[i];
        let v = |e: &Expr, f: &mut dyn FnMut(usize) -> i32| e.value(&mut |i| f(i));
        assert_eq!(v(&op(Or, s(0), s(0)), &mut f), values[0], "A ∪ A = A");
        assert_eq!(v(&op(And, s(0), s(0)), &mut f), values[0], "A ∩ A = A");
        assert_eq!(v(&op(And, s(0), not(s(0))), &mut f), 0, "A ∩ Aᶜ = ∅");
        assert_eq!(
            v(&op(Or, s(0), not(s(0))), &mut f),
            1,
            "A ∪ Aᶜ = everything"
        );
        assert_eq!(
            v(&not(op(Or, s(0), s(1))), &mut f),
            v(&op(And, not(s(0)), not(s(1))), &mut f),
            "De Morgan"
        );
        assert_eq!(
            v(&not(op(And, s(0), s(1))), &mut f),
            v(&op(Or, not(s(0)), not(s(1))), &mut f),
            "De Morgan"
        );
        assert_eq!(
            v(&op(Minus, s(0), s(1)), &mut f),
            v(&op(And, s(0), not(s(1))), &mut f),
            "A − B = A ∩ Bᶜ"
        );
        for e in [
            op(Or, s(0), s(1)),
            op(And, s(0), s(1)),
            op(Minus, s(0), s(1)),
        ] {
            let r = v(&e, &mut f);
            assert!(r == 0 || r == 1, "normal chains stay normal");
        }
    }
}

#[test]
fn most_queries_compute_no_patch_intersection() {
    // The paper's Fig. 20 claim, as counts: ESC intersects a patch only for points in a cell's box;
    // ray parity for every patch a ray passes near.
    let solid = EscSolid::new(&Example::Icosphere.mesh()).expect("valid");
    let (lo, hi) = solid.bounds();
    let mut rng = Rng::new(3);
    let (mut esc, mut parity) = (Stats::default(), Stats::default());
    let mut seen = Vec::new();
    for _ in 0..500 {
        let q = DVec3::new(
            rng.range(lo.x, hi.x),
            rng.range(lo.y, hi.y),
            rng.range(lo.z, hi.z),
        );
        let a = solid.value(q, &mut esc);
        let b = solid.parity_value(q, &mut parity, &mut seen);
        assert_eq!(a, b, "{q}");
    }
    assert!(
        esc.patch_intersections * 10 < parity.patch_intersections,
        "{esc:?} {parity:?}"
    );
}

/// A cube read from OBJ text, as an import is: twelve large triangles, with normals at its corners
/// far from its faces' normals, so that its PN patches bulge far from their triangles and the
/// free-form cells are thick (the shell between the cube and its PN surface is most of the box).
fn imported_cube() -> Mesh {
    let obj = "v -1 -1 -1\nv 1 -1 -1\nv -1 1 -1\nv 1 1 -1\nv -1 -1 1\nv 1 -1 1\nv -1 1 1\nv 1 1 1\n\
               f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
    crate::mesh::read(obj.as_bytes()).expect("a closed mesh")
}

#[test]
fn queries_in_the_thick_cells_of_a_coarse_mesh_are_bounded_and_told_by_the_first_ray() {
    let solid = EscSolid::new(&imported_cube()).expect("valid");
    let n = agrees_with_fine_surface(&solid, 11, 600);
    assert!(n > 150, "only {n} points compared");
    // A grid of points over the box, off the cube's planes of symmetry. With a cell's box for its
    // bound, 0.97 ray–patch intersections a query, and rays along the faces' normals unsure at
    // every face diagonal's wall cast again, half as many more.
    let (lo, hi) = solid.bounds();
    let k = 24;
    let step = (hi - lo) / k as f64;
    let mut stats = Stats::default();
    for i in 0..k {
        for j in 0..k {
            for l in 0..k {
                let q = lo + step * DVec3::new(i as f64 + 0.37, j as f64 + 0.41, l as f64 + 0.43);
                let _ = solid.value(q, &mut stats);
            }
        }
    }
    assert_eq!(stats.retries, 0, "{stats:?}");
    assert_eq!(stats.unsure, 0, "{stats:?}");
    assert!(
        stats.patch_intersections * 10 < stats.queries * 7,
        "{stats:?}: more than 0.7 ray–patch intersections a query"
    );
}

#[test]
fn points_on_the_walls_between_cells_are_counted_once() {
    // On the icosphere the wall between two cells lies in the plane through the shared edge and
    // the centre (the normals are radial), so points just below a patch edge, moved towards the
    // centre, lie exactly on a wall: one of the two cells must claim each, not both or neither.
    let solid = EscSolid::new(&Example::Icosphere.mesh()).expect("valid");
    let pn = solid.surface();
    let mut stats = Stats::default();
    let mut checked = 0;
    for t in (0..pn.patches.len()).step_by(7) {
        for b in [
            DVec3::new(0.25, 0.75, 0.0),
            DVec3::new(0.5, 0.0, 0.5),
            DVec3::new(0.0, 0.6, 0.4),
        ] {
            let q = super::pn::eval_cubic(&pn.patches[t], b);
            let n = q.normalize();
            for h in [1e-5, 3e-4, 6e-4, 1e-3] {
                assert_eq!(solid.value(q - n * h, &mut stats), 1, "below {q} by {h}");
                assert_eq!(solid.value(q + n * h, &mut stats), 0, "above {q} by {h}");
                checked += 1;
            }
        }
    }
    assert!(checked > 100);
    assert_eq!(stats.unsure, 0);
}
