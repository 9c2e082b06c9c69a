//! Shells of a mesh: turned to face out of the solid or into a cavity, and refused when they cross.

use alloc::string::ToString;

use glam::DVec3;

use super::{agrees_with_oracle_and_parity, in_box, queries};
use crate::esc::chain::{EscError, EscSolid, Stats};
use crate::mesh::Mesh;
use crate::mesh::ShellError;
use crate::mesh::angle_weighted_normals;
use crate::testutil::Rng;
#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

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
