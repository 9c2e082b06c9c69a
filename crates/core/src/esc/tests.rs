//! The chain against independent oracles: the flat chain against the winding number of the flat
//! mesh by solid angles, the full chain against the winding number of the PN surface tessellated
//! finely, and the Boolean identities.

use alloc::string::ToString;
use alloc::vec;
use alloc::vec::Vec;

use glam::DVec3;

use super::bool::{Expr, Op};
use super::chain::{EscError, EscSolid, Stats};
use super::examples::{Example, icosphere, torus};
use super::pn::{DEFAULT_CREASE_ANGLE, PnSurface, angle_degrees, eval_cubic, pn_normals, pn_patch};
use crate::mesh::Mesh;
use crate::mesh::ShellError;
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
    // At the default crease angle some of this torus's edges are sharp, and fewer of the points
    // lie clear of its surface than with all of them round: more points are drawn.
    for q in queries(&solid, &mut rng, 250) {
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
/// far from its faces' normals, so that with its edges rounded (crease angle 180) its PN patches
/// bulge far from their triangles and the free-form cells are thick (the shell between the cube and
/// its PN surface is most of the box).
fn imported_cube() -> Mesh {
    let obj = "v -1 -1 -1\nv 1 -1 -1\nv -1 1 -1\nv 1 1 -1\nv -1 -1 1\nv 1 -1 1\nv -1 1 1\nv 1 1 1\n\
               f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
    crate::mesh::read(obj.as_bytes()).expect("a closed mesh")
}

#[test]
fn queries_in_the_thick_cells_of_a_coarse_mesh_are_bounded_and_told_by_the_first_ray() {
    // Every edge rounded (crease angle 180): the cube of one normal per vertex.
    let solid = EscSolid::with_crease_angle(&imported_cube(), 180.0).expect("valid");
    assert_eq!(solid.crease_edges(), 0);
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

/// A wedge read from OBJ text: the right triangle `(0, 0), (2, 0), (0, 1)` in the xz plane swept
/// along y from 0 to 1; nine edges, all sharp (90°, 117° and 153° between face normals).
fn imported_wedge() -> Mesh {
    let obj = "v 0 0 0\nv 2 0 0\nv 0 0 1\nv 0 1 0\nv 2 1 0\nv 0 1 1\n\
               f 1 3 2\nf 4 5 6\nf 1 2 5 4\nf 1 4 6 3\nf 2 3 6 5\n";
    crate::mesh::read(obj.as_bytes()).expect("a closed mesh")
}

/// A regular tetrahedron-like corner: `(0,0,0), (1,0,0), (0,1,0), (0,0,1)`, six sharp edges.
fn imported_tetrahedron() -> Mesh {
    let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
    crate::mesh::read(obj.as_bytes()).expect("a closed mesh")
}

/// A closed cylinder of radius 1 from z = 0 to 1 with `sides` sides and fan caps: smooth along its
/// side where the sides meet at less than the crease angle, sharp at its rims.
fn cylinder(sides: u32) -> Mesh {
    let mut positions = Vec::new();
    for z in [0.0, 1.0] {
        for i in 0..sides {
            let a = core::f64::consts::TAU * f64::from(i) / f64::from(sides);
            positions.push(DVec3::new(libm::cos(a), libm::sin(a), z));
        }
    }
    positions.push(DVec3::new(0.0, 0.0, 0.0));
    positions.push(DVec3::new(0.0, 0.0, 1.0));
    let (bottom, top) = (2 * sides, 2 * sides + 1);
    let mut triangles = Vec::new();
    for i in 0..sides {
        let j = (i + 1) % sides;
        triangles.push([i, j, sides + j]);
        triangles.push([i, sides + j, sides + i]);
        triangles.push([bottom, j, i]);
        triangles.push([top, sides + i, sides + j]);
    }
    let normals = angle_weighted_normals(&positions, &triangles);
    Mesh {
        positions,
        normals,
        triangles,
    }
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

#[test]
fn a_cube_keeps_its_edges_sharp() {
    let cube = imported_cube();
    let solid = EscSolid::new(&cube).expect("valid");
    assert_eq!(solid.crease_edges(), 12);
    assert_eq!(solid.crease_angle(), DEFAULT_CREASE_ANGLE);
    let mut stats = Stats::default();
    for q in [
        DVec3::new(1.2, 0.0, 0.0),
        DVec3::new(0.0, 0.0, 1.05),
        DVec3::new(1.01, 1.01, 0.0),
    ] {
        assert_eq!(solid.value(q, &mut stats), 0, "{q} is outside");
    }
    for q in [DVec3::splat(0.99), DVec3::ZERO] {
        assert_eq!(solid.value(q, &mut stats), 1, "{q} is inside");
    }
    // The PN surface is the cube: its box too.
    let (lo, hi) = solid.bounds();
    assert!((lo + DVec3::ONE).abs().max_element() < 1e-8, "{lo}");
    assert!((hi - DVec3::ONE).abs().max_element() < 1e-8, "{hi}");
    let oracle = |q: DVec3| in_box(q, -DVec3::ONE, DVec3::ONE).map(i32::from);
    let n = agrees_with_oracle_and_parity(&solid, &oracle, 21, 400);
    assert!(n > 350, "only {n} points compared");
    // With every edge rounded, the PN surface bulges past the faces.
    let round = EscSolid::with_crease_angle(&cube, 180.0).expect("valid");
    assert!(round.contains(DVec3::new(1.2, 0.0, 0.0)));
    assert!(round.contains(DVec3::new(0.0, 0.0, 1.05)));
}

#[test]
fn a_wedge_and_a_tetrahedron_keep_their_edges_sharp() {
    let wedge = EscSolid::new(&imported_wedge()).expect("valid");
    assert_eq!(wedge.crease_edges(), 9);
    // Inside: 0 < y < 1, x > 0, z > 0, x/2 + z < 1.
    let oracle = |q: DVec3| {
        let d = [q.y, 1.0 - q.y, q.x, q.z, 1.0 - q.x / 2.0 - q.z];
        if d.iter().any(|v| v.abs() < 1e-9) {
            return None;
        }
        Some(i32::from(d.iter().all(|&v| v > 0.0)))
    };
    let mut stats = Stats::default();
    for (q, v) in [
        (DVec3::new(0.5, 0.5, 0.3), 1),
        (DVec3::new(1.9, 0.5, 0.02), 1),
        (DVec3::new(1.0, 0.5, 0.55), 0),
        (DVec3::new(2.05, 0.5, 0.0), 0),
        (DVec3::new(0.5, 1.02, 0.3), 0),
    ] {
        assert_eq!(wedge.value(q, &mut stats), v, "{q}");
    }
    let n = agrees_with_oracle_and_parity(&wedge, &oracle, 22, 400);
    assert!(n > 350, "only {n} points compared");

    let tetra = EscSolid::new(&imported_tetrahedron()).expect("valid");
    assert_eq!(tetra.crease_edges(), 6);
    let oracle = |q: DVec3| {
        let d = [q.x, q.y, q.z, 1.0 - q.x - q.y - q.z];
        if d.iter().any(|v| v.abs() < 1e-9) {
            return None;
        }
        Some(i32::from(d.iter().all(|&v| v > 0.0)))
    };
    let n = agrees_with_oracle_and_parity(&tetra, &oracle, 23, 400);
    assert!(n > 350, "only {n} points compared");
}

#[test]
fn the_examples_have_no_creases_and_are_unchanged() {
    for example in Example::ALL {
        let mesh = example.mesh();
        // The largest angle between neighbouring triangles' normals stays well below the default.
        let face = |t: &[u32; 3]| {
            let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
            (b - a).cross(c - a).normalize()
        };
        let mut edges: Vec<(u32, u32, usize)> = Vec::new();
        for (t, tri) in mesh.triangles.iter().enumerate() {
            for e in 0..3 {
                let (a, b) = (tri[e], tri[(e + 1) % 3]);
                edges.push((a.min(b), a.max(b), t));
            }
        }
        edges.sort_unstable();
        let largest = edges
            .chunks(2)
            .map(|p| angle_degrees(face(&mesh.triangles[p[0].2]), face(&mesh.triangles[p[1].2])))
            .fold(0.0, f64::max);
        assert!(largest < 23.0, "{example:?}: {largest}°");
        assert!(largest * 2.0 <= DEFAULT_CREASE_ANGLE);
        // The same patches and normal fields as from the vertex normals alone, bit for bit.
        let pn = PnSurface::new(&mesh);
        for (t, tri) in mesh.triangles.iter().enumerate() {
            let p = tri.map(|i| mesh.positions[i as usize]);
            let n = tri.map(|i| mesh.normals[i as usize]);
            assert_eq!(pn.patches[t], pn_patch(p, n));
            assert_eq!(pn.normals[t], pn_normals(p, n));
        }
        let solid = EscSolid::new(&mesh).expect("valid");
        assert_eq!(solid.crease_edges(), 0);
        assert_eq!(solid.shells(), 1);
        assert_eq!(solid.shells_turned_over(), 0);
        let round = EscSolid::with_crease_angle(&mesh, 180.0).expect("valid");
        assert_eq!(solid.surface().patches, round.surface().patches);
        let mut rng = Rng::new(31);
        let (mut a, mut b) = (Stats::default(), Stats::default());
        for q in queries(&solid, &mut rng, 200) {
            assert_eq!(solid.value(q, &mut a), round.value(q, &mut b), "{q}");
        }
        assert_eq!(a, b);
    }
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

#[test]
fn creased_surfaces_are_closed() {
    let cube = imported_cube();
    let cyl = cylinder(12);
    for (mesh, degrees, creases) in [
        (&cube, DEFAULT_CREASE_ANGLE, 12),
        (&imported_wedge(), DEFAULT_CREASE_ANGLE, 9),
        (&imported_tetrahedron(), DEFAULT_CREASE_ANGLE, 6),
        // Twelve sides meet at 30°: smooth, the rims sharp.
        (&cyl, DEFAULT_CREASE_ANGLE, 24),
        (&cyl, 20.0, 36),
        (&random_star(5), 12.0, 0),
        (&random_torus(6), 25.0, 0),
    ] {
        let solid = EscSolid::with_crease_angle(mesh, degrees).expect("valid");
        if creases > 0 {
            assert_eq!(solid.crease_edges(), creases);
        }
        assert_watertight(solid.surface(), mesh);
    }
}

#[test]
fn irregular_creases_keep_the_chain_right() {
    // A random star and a bent torus with a low crease angle: creases that end inside the mesh,
    // vertices with one, two or many sectors.
    for (mesh, degrees) in [(random_star(7), 10.0), (random_torus(8), 25.0)] {
        let solid = EscSolid::with_crease_angle(&mesh, degrees).expect("valid");
        assert!(solid.crease_edges() > 20, "{}", solid.crease_edges());
        assert_watertight(solid.surface(), &mesh);
        let n = agrees_with_fine_surface(&solid, 3, 200);
        assert!(n > 80, "only {n} points compared");
    }
    // The cylinder: smooth sides, flat caps.
    let solid = EscSolid::new(&cylinder(12)).expect("valid");
    let n = agrees_with_fine_surface(&solid, 4, 300);
    assert!(n > 60, "only {n} points compared");
    let mut stats = Stats::default();
    for z in [0.02, 0.5, 0.98] {
        assert_eq!(solid.value(DVec3::new(0.0, 0.0, z), &mut stats), 1);
        assert_eq!(
            solid.value(DVec3::new(0.3, 0.2, -z * 0.01 - 1e-3), &mut stats),
            0
        );
        assert_eq!(
            solid.value(DVec3::new(0.3, 0.2, 1.0 + z * 0.01 + 1e-3), &mut stats),
            0
        );
    }
}

#[test]
fn the_tessellated_cube_is_closed_and_on_its_faces() {
    let solid = EscSolid::new(&imported_cube()).expect("valid");
    let mut mesh = solid.surface().tessellate(5);
    for (p, n) in mesh.positions.iter().zip(&mesh.normals) {
        // On a face: one coordinate ±1, the others within.
        let m = p.abs().max_element();
        assert!((m - 1.0).abs() < 1e-13, "{p}");
        // The normal is the face's.
        let axis = p.abs().cmpeq(DVec3::splat(m));
        let face = DVec3::select(axis, p.signum(), DVec3::ZERO);
        if face.abs().element_sum() == 1.0 {
            assert!((*n - face).length() < 1e-12, "{p} {n}");
        }
    }
    // Welded where the patches meet, it is a closed 2-manifold.
    let mut index = vec![0u32; mesh.positions.len()];
    let mut welded: Vec<DVec3> = Vec::new();
    for (i, p) in mesh.positions.iter().enumerate() {
        index[i] = match welded.iter().position(|w| (*w - *p).length() < 1e-12) {
            Some(k) => k as u32,
            None => {
                welded.push(*p);
                (welded.len() - 1) as u32
            }
        };
    }
    for t in &mut mesh.triangles {
        *t = t.map(|i| index[i as usize]);
    }
    mesh.normals = vec![DVec3::ZERO; welded.len()];
    mesh.positions = welded;
    mesh.check_closed_manifold().expect("closed");
    assert_eq!(mesh.euler_characteristic(), 2);
    assert!((mesh.volume() - 8.0).abs() < 1e-12);
}

#[test]
fn crease_angles_are_checked() {
    let cube = imported_cube();
    for bad in [f64::NAN, f64::INFINITY, -1.0, 180.5] {
        assert!(matches!(
            EscSolid::with_crease_angle(&cube, bad),
            Err(EscError::CreaseAngle { .. })
        ));
        assert!(PnSurface::with_crease_angle(&cube, bad).is_err());
    }
    let err = EscSolid::with_crease_angle(&cube, -1.0).expect_err("refused");
    assert_eq!(err, EscError::CreaseAngle { degrees: -1.0 });
    assert!(err.to_string().contains("from 0 to 180"), "{err}");
    // 0 makes every bent edge a crease (the cube's face diagonals are flat, not bent), more than
    // 90 none of the cube's.
    for (degrees, creases) in [(0.0, 12), (89.0, 12), (91.0, 0), (180.0, 0)] {
        let solid = EscSolid::with_crease_angle(&cube, degrees).expect("valid");
        assert_eq!(solid.crease_edges(), creases, "{degrees}");
    }
}

/// The boxes `[lo, hi]`, each as 12 triangles, outward unless `inward`, normals computed from the
/// triangles as given (an import's would be).
fn boxes(parts: &[(DVec3, DVec3, bool)]) -> Mesh {
    let mut mesh = Mesh::default();
    for &(lo, hi, inward) in parts {
        let base = mesh.positions.len() as u32;
        let (positions, triangles) = crate::testutil::box_mesh(lo, hi, base);
        mesh.positions.extend(positions);
        mesh.triangles.extend(
            triangles
                .into_iter()
                .map(|t| if inward { [t[0], t[2], t[1]] } else { t }),
        );
    }
    mesh.normals = angle_weighted_normals(&mesh.positions, &mesh.triangles);
    mesh
}

#[test]
fn shells_facing_the_wrong_way_are_turned_over() {
    let (a, b) = (DVec3::splat(-1.0), DVec3::splat(1.0));
    let (c, d) = (DVec3::new(3.0, -1.0, -1.0), DVec3::new(5.0, 1.0, 1.0));
    // Two cubes apart, either or both inside out: both are solid.
    let oracle = |q: DVec3| Some(i32::from(in_box(q, a, b)? || in_box(q, c, d)?));
    let right = EscSolid::new(&boxes(&[(a, b, false), (c, d, false)])).expect("valid");
    assert_eq!((right.shells(), right.shells_turned_over()), (2, 0));
    for (flips, turned) in [([false, true], 1), ([true, false], 1), ([true, true], 2)] {
        let mesh = boxes(&[(a, b, flips[0]), (c, d, flips[1])]);
        let solid = EscSolid::new(&mesh).expect("valid");
        assert_eq!(solid.shells(), 2);
        assert_eq!(solid.shells_turned_over(), turned);
        let mut stats = Stats::default();
        assert_eq!(solid.value(DVec3::ZERO, &mut stats), 1);
        assert_eq!(solid.value(DVec3::new(4.0, 0.0, 0.0), &mut stats), 1);
        assert_eq!(solid.value(DVec3::new(2.0, 0.0, 0.0), &mut stats), 0);
        let n = agrees_with_oracle_and_parity(&solid, &oracle, 41, 300);
        assert!(n > 250, "only {n} points compared");
        assert_eq!(solid.triangles(), right.triangles());
    }
}

#[test]
fn cavities_face_inward_whichever_way_they_come() {
    let (a, b) = (DVec3::splat(-2.0), DVec3::splat(2.0));
    let (c, d) = (DVec3::splat(-1.0), DVec3::splat(1.0));
    // Solid between the two cubes, empty inside the small one.
    let oracle = |q: DVec3| Some(i32::from(in_box(q, a, b)? && !in_box(q, c, d)?));
    let right = EscSolid::new(&boxes(&[(a, b, false), (c, d, true)])).expect("valid");
    assert_eq!((right.shells(), right.shells_turned_over()), (2, 0));
    // (outer inward?, cavity inward?) → shells turned over.
    for (flips, turned) in [
        ([false, true], 0),
        ([false, false], 1),
        ([true, true], 1),
        ([true, false], 2),
    ] {
        let solid = EscSolid::new(&boxes(&[(a, b, flips[0]), (c, d, flips[1])])).expect("valid");
        assert_eq!(solid.shells_turned_over(), turned, "{flips:?}");
        let mut stats = Stats::default();
        assert_eq!(
            solid.value(DVec3::ZERO, &mut stats),
            0,
            "the cavity is empty"
        );
        assert_eq!(solid.value(DVec3::new(1.5, 0.2, 0.1), &mut stats), 1);
        assert_eq!(solid.value(DVec3::new(-1.5, -1.7, 1.9), &mut stats), 1);
        assert_eq!(solid.value(DVec3::new(2.5, 0.0, 0.0), &mut stats), 0);
        let n = agrees_with_oracle_and_parity(&solid, &oracle, 42, 300);
        assert!(n > 250, "only {n} points compared");
        // The same answers as the well-oriented input.
        let mut rng = Rng::new(43);
        for q in queries(&right, &mut rng, 200) {
            assert_eq!(
                solid.value(q, &mut stats),
                right.value(q, &mut stats),
                "{q}"
            );
        }
    }
    // Crossing shells are refused.
    let crossing = boxes(&[(a, b, false), (DVec3::splat(1.0), DVec3::splat(3.0), false)]);
    assert!(matches!(
        EscSolid::new(&crossing),
        Err(EscError::Shells(ShellError::Intersect { .. }))
    ));
}

/// The cube `[-1, 1]³` with an octahedron of half-diagonal `reach` inside it, as one mesh: its
/// corners poke through the cube's faces when `reach > 1`.
fn cube_with_octahedron(reach: f64) -> Mesh {
    let mut mesh = boxes(&[(DVec3::splat(-1.0), DVec3::splat(1.0), false)]);
    let base = mesh.positions.len() as u32;
    for axis in [DVec3::X, DVec3::Y, DVec3::Z] {
        mesh.positions.extend([axis * reach, -axis * reach]);
    }
    for octant in 0..8u32 {
        let [x, y, z] = [0, 1, 2].map(|k| base + 2 * k + (octant >> k & 1));
        // Counter-clockwise from outside in the octants with an even number of negative axes.
        let tri = if octant.count_ones() % 2 == 0 {
            [x, y, z]
        } else {
            [x, z, y]
        };
        mesh.triangles.push(tri);
    }
    mesh.normals = angle_weighted_normals(&mesh.positions, &mesh.triangles);
    mesh
}

#[test]
fn an_inner_shell_that_crosses_its_outer_shell_is_refused_like_pieces_side_by_side() {
    // Neither shell's tested vertex is inside the other: only the surfaces show the crossing.
    let e = EscSolid::new(&cube_with_octahedron(1.3)).unwrap_err();
    assert_eq!(
        e,
        EscError::Shells(ShellError::Intersect {
            first: 0,
            second: 1
        })
    );
    let message = e.to_string();
    assert!(
        message.contains("pieces 1 and 2") && message.contains("cross each other"),
        "{message}"
    );
    assert!(!message.contains('\n'));
    // Within the cube, the octahedron is a cavity.
    let solid = EscSolid::new(&cube_with_octahedron(0.9)).expect("a cavity");
    assert_eq!((solid.shells(), solid.shells_turned_over()), (2, 1));
    let mut stats = Stats::default();
    assert_eq!(solid.value(DVec3::ZERO, &mut stats), 0);
    assert_eq!(solid.value(DVec3::splat(0.8), &mut stats), 1);
}

#[test]
fn complements_and_unions_with_them_are_unbounded() {
    let sphere = EscSolid::new(&Example::Icosphere.mesh()).expect("valid");
    let torus = EscSolid::new(&Example::Torus.mesh()).expect("valid");
    let s = |i| Expr::Solid(i);
    let not = Expr::complement;
    let op = Expr::binary;
    let far = [
        DVec3::new(100.0, 0.0, 0.0),
        DVec3::new(-3.0, 40.0, 7.0),
        DVec3::splat(-1e6),
    ];
    let mut stats = Stats::default();
    for (expr, bounded) in [
        (s(0), true),
        (not(s(0)), false),
        (not(not(s(0))), true),
        (op(Op::Union, s(0), not(s(1))), false),
        (op(Op::Intersection, s(0), not(s(1))), true),
        (op(Op::Difference, s(0), s(1)), true),
        (op(Op::Difference, not(s(0)), s(1)), false),
        (not(op(Op::Intersection, s(0), s(1))), false),
        (not(op(Op::Union, not(s(0)), s(1))), true),
    ] {
        let boolean = super::Boolean {
            solids: vec![sphere.clone(), torus.clone()],
            expr: expr.clone(),
        };
        assert_eq!(boolean.is_bounded(), bounded, "{expr:?}");
        // Far from both solids, the result holds every point or none.
        for q in far {
            assert_eq!(
                boolean.value(q, &mut stats),
                i32::from(!bounded),
                "{expr:?} {q}"
            );
        }
    }
}
