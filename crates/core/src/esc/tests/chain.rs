//! Point-in-solid: the flat chain against the flat mesh's winding number, the full chain against
//! the fine PN surface and ray parity, and the work a query does.

use alloc::vec::Vec;

use glam::DVec3;

use super::{agrees_with_fine_surface, imported_cube, queries, random_star, random_torus, winding};
use crate::esc::chain::{EscSolid, Stats};
use crate::esc::examples::{Example, icosphere};
use crate::testutil::Rng;
#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

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
            let q = crate::esc::pn::eval_cubic(&pn.patches[t], b);
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
