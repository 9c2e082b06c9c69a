//! Built-in closed solids for tests, benchmarks and the page: an icosphere, a torus and a blob.
//! Each is a closed, consistently outward-oriented 2-manifold with unit vertex normals, made by
//! code (no data files) and the same on every run.

use alloc::collections::BTreeMap;
use alloc::vec::Vec;
use core::f64::consts::TAU;

use glam::DVec3;

use crate::mesh::Mesh;
use crate::mesh::angle_weighted_normals;

/// The most subdivision levels of [`icosphere`]: 6 gives 81 920 triangles.
pub const MAX_SUBDIVISIONS: u32 = 6;

/// The most segments along either direction of [`torus`] (so its indices fit `u32` comfortably).
pub const MAX_TORUS_SEGMENTS: usize = 4096;

/// The built-in solids.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Example {
    /// The unit sphere as [`icosphere`]`(3)`: 1280 triangles.
    Icosphere,
    /// A ring as [`torus`]`(1.0, 0.4, 32, 16)`: 1024 triangles.
    Torus,
    /// An organic, asymmetric star-shaped solid, [`blob`]: 5120 triangles.
    Blob,
}

impl Example {
    /// Every example, in the order of their names.
    pub const ALL: [Example; 3] = [Self::Icosphere, Self::Torus, Self::Blob];

    /// The example's name: `icosphere`, `torus` or `blob`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Icosphere => "icosphere",
            Self::Torus => "torus",
            Self::Blob => "blob",
        }
    }

    /// The example of a name (as [`Example::name`] gives it), if there is one.
    #[must_use]
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|e| e.name() == name)
    }

    /// The example's mesh.
    #[must_use]
    pub fn mesh(self) -> Mesh {
        match self {
            Self::Icosphere => icosphere(3),
            Self::Torus => torus(1.0, 0.4, 32, 16),
            Self::Blob => blob(),
        }
    }
}

/// The unit sphere centred at the origin, from an icosahedron whose triangles are each split into
/// four, `subdivisions` times (capped at [`MAX_SUBDIVISIONS`]): `20·4ⁿ` triangles and `10·4ⁿ + 2`
/// vertices, all on the sphere, with normals equal to the positions. Midpoints are shared between
/// the two triangles of an edge, so the mesh is closed.
#[must_use]
pub fn icosphere(subdivisions: u32) -> Mesh {
    // The icosahedron with corners (0, ±1, ±φ) and their cyclic permutations; faces counter-clockwise
    // seen from outside.
    let phi = (1.0 + crate::math::sqrt(5.0)) / 2.0;
    let corners = [
        (-1.0, phi, 0.0),
        (1.0, phi, 0.0),
        (-1.0, -phi, 0.0),
        (1.0, -phi, 0.0),
        (0.0, -1.0, phi),
        (0.0, 1.0, phi),
        (0.0, -1.0, -phi),
        (0.0, 1.0, -phi),
        (phi, 0.0, -1.0),
        (phi, 0.0, 1.0),
        (-phi, 0.0, -1.0),
        (-phi, 0.0, 1.0),
    ];
    let mut positions: Vec<DVec3> = corners
        .iter()
        .map(|&(x, y, z)| DVec3::new(x, y, z).normalize())
        .collect();
    let mut triangles: Vec<[u32; 3]> = Vec::from([
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ]);
    for _ in 0..subdivisions.min(MAX_SUBDIVISIONS) {
        // The midpoint of each undirected edge, made once.
        let mut midpoints: BTreeMap<(u32, u32), u32> = BTreeMap::new();
        let mut midpoint = |a: u32, b: u32| {
            *midpoints.entry((a.min(b), a.max(b))).or_insert_with(|| {
                let p = (positions[a as usize] + positions[b as usize]).normalize();
                positions.push(p);
                positions.len() as u32 - 1
            })
        };
        let mut finer = Vec::with_capacity(4 * triangles.len());
        for &[a, b, c] in &triangles {
            let (ab, bc, ca) = (midpoint(a, b), midpoint(b, c), midpoint(c, a));
            finer.extend([[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]);
        }
        triangles = finer;
    }
    Mesh {
        normals: positions.clone(),
        positions,
        triangles,
    }
}

/// A torus around the z axis: the circle of radius `major` in the xy plane swept by a tube of
/// radius `minor` (it bounds a solid without self-intersection for `0 < minor < major`). A grid of
/// `around` segments around the axis by `tube` segments around the tube (each clamped to
/// `3..=`[`MAX_TORUS_SEGMENTS`]), each quad split into two triangles; normals are the analytic
/// outward ones.
#[must_use]
pub fn torus(major: f64, minor: f64, around: usize, tube: usize) -> Mesh {
    let around = around.clamp(3, MAX_TORUS_SEGMENTS);
    let tube = tube.clamp(3, MAX_TORUS_SEGMENTS);
    let mut positions = Vec::with_capacity(around * tube);
    let mut normals = Vec::with_capacity(around * tube);
    for i in 0..around {
        let theta = TAU * i as f64 / around as f64;
        let (st, ct) = (libm::sin(theta), libm::cos(theta));
        for j in 0..tube {
            let phi = TAU * j as f64 / tube as f64;
            let (sp, cp) = (libm::sin(phi), libm::cos(phi));
            let n = DVec3::new(cp * ct, cp * st, sp);
            positions.push(DVec3::new(major * ct, major * st, 0.0) + minor * n);
            normals.push(n);
        }
    }
    // Vertex (i, j) is at index i·tube + j. ∂p/∂θ × ∂p/∂φ points outward, so the quad
    // (i, j) → (i + 1, j) → (i + 1, j + 1) → (i, j + 1) is counter-clockwise seen from outside.
    let index = |i: usize, j: usize| ((i % around) * tube + j % tube) as u32;
    let mut triangles = Vec::with_capacity(2 * around * tube);
    for i in 0..around {
        for j in 0..tube {
            let (a, b) = (index(i, j), index(i + 1, j));
            let (c, d) = (index(i + 1, j + 1), index(i, j + 1));
            triangles.extend([[a, b, c], [a, c, d]]);
        }
    }
    Mesh {
        positions,
        normals,
        triangles,
    }
}

/// The blob's radius in the direction of the unit vector `p`: smooth bumps of total amplitude at
/// most 0.4 around 1, so the radius stays in [0.6, 1.4] and the surface is a radial graph over the
/// sphere (star-shaped from the origin, so without self-intersection). No symmetry of the sphere
/// maps it onto itself.
fn blob_radius(p: DVec3) -> f64 {
    1.0 + 0.22 * libm::sin(3.0 * p.x + 0.5) * libm::sin(2.0 * p.y + 1.0) * libm::cos(2.0 * p.z)
        + 0.12 * libm::sin(5.0 * p.y - p.z)
        + 0.06 * libm::cos(4.0 * p.x + 3.0 * p.z + 0.3)
}

/// An organic closed solid of 5120 triangles: [`icosphere`]`(4)` with each vertex moved along its
/// ray from the origin to radius `r(p) ∈ [0.6, 1.4]`, a sum of smooth bumps; normals by
/// [`angle_weighted_normals`]. Scaling the corners of a triangle by positive factors along their
/// rays keeps its orientation as seen from the origin, so the blob stays closed and outward.
#[must_use]
pub fn blob() -> Mesh {
    let mut mesh = icosphere(4);
    for p in &mut mesh.positions {
        *p *= blob_radius(*p);
    }
    mesh.normals = angle_weighted_normals(&mesh.positions, &mesh.triangles);
    mesh
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;
    use crate::mesh::validate;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    fn assert_solid(mesh: &Mesh, euler: i64) {
        mesh.check_closed_manifold().unwrap();
        validate(&mesh.positions, &mesh.triangles).unwrap();
        assert_eq!(mesh.euler_characteristic(), euler);
        assert!(mesh.volume() > 0.0);
        assert_eq!(mesh.normals.len(), mesh.positions.len());
        for n in &mesh.normals {
            assert!((n.length() - 1.0).abs() < 1e-12);
        }
        // Vertex normals point to the same side as the triangles around them (loosely: a coarse
        // torus's analytic normals lean away from its flat triangles).
        let computed = angle_weighted_normals(&mesh.positions, &mesh.triangles);
        for (n, c) in mesh.normals.iter().zip(&computed) {
            assert!(n.dot(*c) > 0.5, "{n} {c}");
        }
    }

    #[test]
    fn examples_are_closed_outward_solids() {
        for (example, euler) in Example::ALL.into_iter().zip([2, 0, 2]) {
            assert_solid(&example.mesh(), euler);
        }
    }

    #[test]
    fn examples_round_trip_their_names() {
        for example in Example::ALL {
            assert_eq!(Example::from_name(example.name()), Some(example));
        }
        assert_eq!(Example::from_name("cube"), None);
        assert_eq!(Example::Icosphere.mesh().triangles.len(), 1280);
        assert_eq!(Example::Torus.mesh().triangles.len(), 1024);
        assert_eq!(Example::Blob.mesh().triangles.len(), 5120);
    }

    #[test]
    fn examples_icosphere_counts_and_lies_on_the_unit_sphere() {
        for n in 0..=4 {
            let mesh = icosphere(n);
            assert_eq!(mesh.triangles.len(), 20 * 4usize.pow(n));
            assert_eq!(mesh.positions.len(), 10 * 4usize.pow(n) + 2);
            assert_solid(&mesh, 2);
        }
        let mesh = icosphere(3);
        assert_eq!(mesh.triangles.len(), 1280);
        assert_eq!(mesh.positions.len(), 642);
        for (p, n) in mesh.positions.iter().zip(&mesh.normals) {
            assert!((p.length() - 1.0).abs() < 1e-12);
            assert_eq!(p, n);
        }
        // The volume approaches the ball's from below.
        let ball = 4.0 / 3.0 * core::f64::consts::PI;
        assert!(mesh.volume() < ball && mesh.volume() > 0.97 * ball);
        assert_eq!(
            icosphere(100).triangles.len(),
            20 * 4usize.pow(MAX_SUBDIVISIONS)
        );
    }

    #[test]
    fn examples_torus_has_the_right_shape() {
        let (major, minor) = (1.0, 0.4);
        let mesh = torus(major, minor, 32, 16);
        assert_eq!(mesh.positions.len(), 512);
        for (p, n) in mesh.positions.iter().zip(&mesh.normals) {
            // The distance to the core circle is the minor radius, along the normal.
            let core = DVec3::new(p.x, p.y, 0.0).normalize() * major;
            assert!(((*p - core).length() - minor).abs() < 1e-12);
            assert!((*p - core - *n * minor).length() < 1e-12);
        }
        // 2π²Rr², approached from below by the inscribed polyhedron.
        let exact = 2.0 * core::f64::consts::PI.powi(2) * major * minor * minor;
        assert!(mesh.volume() < exact && mesh.volume() > 0.95 * exact);
        assert_solid(&torus(2.0, 0.5, 1, 0), 0);
    }

    #[test]
    fn examples_blob_is_generic_and_within_its_radii() {
        let a = blob();
        assert_eq!(a, blob());
        for p in &a.positions {
            assert!((0.6..=1.4).contains(&p.length()));
        }
        // Not symmetric under x → −x, y → −y or z → −z: the mirrored vertices are not vertices.
        for flip in [
            DVec3::new(-1.0, 1.0, 1.0),
            DVec3::new(1.0, -1.0, 1.0),
            DVec3::new(1.0, 1.0, -1.0),
        ] {
            let mirrored = a
                .positions
                .iter()
                .filter(|&&p| a.positions.iter().any(|&q| (q - p * flip).length() < 1e-9))
                .count();
            assert!(mirrored < a.positions.len() / 2, "{mirrored}");
        }
        let lo = a.positions.iter().fold(DVec3::INFINITY, |m, &p| m.min(p));
        let hi = a
            .positions
            .iter()
            .fold(DVec3::NEG_INFINITY, |m, &p| m.max(p));
        assert!((hi + lo).length() > 0.05, "{lo} {hi}");
    }
}
