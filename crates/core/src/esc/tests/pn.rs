//! PN surfaces of imported meshes: sharp edges kept by the crease angle, closed surfaces, and the
//! chain right on them.

use alloc::string::ToString;
use alloc::vec;
use alloc::vec::Vec;

use glam::DVec3;

use super::{
    agrees_with_fine_surface, agrees_with_oracle_and_parity, assert_watertight, imported_cube,
    in_box, queries, random_star, random_torus,
};
use crate::esc::chain::{EscError, EscSolid, Stats};
use crate::esc::examples::Example;
use crate::esc::pn::{DEFAULT_CREASE_ANGLE, PnSurface, angle_degrees, pn_normals, pn_patch};
use crate::mesh::Mesh;
use crate::mesh::angle_weighted_normals;
use crate::testutil::Rng;
#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

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
