//! Polygonizing a [`Solid3`]: sample `f` on a grid one half cell past the box on every side (so the
//! outer samples are strictly outside and the mesh is closed), march the cubes, then put each vertex
//! on `f = 0` by a root search along its grid edge, where the volume reduces to a Bézier curve.

use alloc::vec;
use alloc::vec::Vec;
use core::fmt;

use glam::DVec3;

use super::Mesh;
use super::polygonize::{EdgeRoots, SampleGrid, linear_root, polygonize};
use crate::bernstein::{MAX_DEGREE, basis, basis_array};
use crate::rfunc::clip3;
use crate::{Solid3, Volume};

/// The most cells along the longest side of the box.
pub const MAX_RESOLUTION: usize = 512;

/// Why a solid could not be polygonized.
#[derive(Clone, Debug, PartialEq)]
pub enum MeshError {
    /// The resolution is 0 or above [`MAX_RESOLUTION`].
    Resolution {
        /// The resolution given.
        got: usize,
    },
    /// The accuracy is not a positive finite number.
    Accuracy,
}

impl fmt::Display for MeshError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Resolution { got } => {
                write!(f, "resolution {got} is outside 1..={MAX_RESOLUTION}")
            }
            Self::Accuracy => f.write_str("the accuracy must be a positive finite number"),
        }
    }
}

impl core::error::Error for MeshError {}

impl Solid3 {
    /// The sample grid for polygonizing at `resolution` cells along the box's longest side (fewer,
    /// proportionally, along the others, so cells are near cubes), with one extra sample half a cell
    /// outside the box at each end of every axis.
    ///
    /// # Errors
    ///
    /// [`MeshError::Resolution`] for 0 or more than [`MAX_RESOLUTION`].
    pub fn mesh_grid(&self, resolution: usize) -> Result<SampleGrid, MeshError> {
        if resolution == 0 || resolution > MAX_RESOLUTION {
            return Err(MeshError::Resolution { got: resolution });
        }
        let (min, max) = self.domain();
        let size = max - min;
        let cell = size.max_element() / resolution as f64;
        let cells = (size / cell)
            .ceil()
            .max(DVec3::ONE)
            .min(DVec3::splat(resolution as f64));
        let step = size / cells;
        Ok(SampleGrid {
            origin: min - step * 0.5,
            step,
            dims: cells.to_array().map(|c| c as usize + 2),
        })
    }

    /// The closed, outward-oriented triangle mesh of the solid's boundary at `resolution` cells along
    /// the longest side of the box: vertices on `f = 0` to within `accuracy` (in `f`), normals `−∇f`.
    ///
    /// # Errors
    ///
    /// [`MeshError`] for a resolution out of range or a bad accuracy.
    pub fn polygonize(&self, resolution: usize, accuracy: f64) -> Result<Mesh, MeshError> {
        if !(accuracy.is_finite() && accuracy > 0.0) {
            return Err(MeshError::Accuracy);
        }
        let grid = self.mesh_grid(resolution)?;
        let mut roots = SolidRoots::new(self, &grid, accuracy);
        let xs = roots.axis_points(0);
        let ys = roots.axis_points(1);
        let zs = roots.axis_points(2);
        let values = self.f_grid(&xs, &ys, &zs);
        Ok(polygonize(&grid, &values, &mut roots))
    }
}

/// Roots on grid edges of a [`Solid3`]: along an edge two parameters are fixed, so `S_ξ` is a Bézier
/// curve whose coefficients are the net contracted with the two fixed basis rows.
struct SolidRoots<'a> {
    solid: &'a Solid3,
    xi: Volume<f64>,
    grid: SampleGrid,
    /// Parameters of the samples along each axis, and their basis rows.
    params: [Vec<f64>; 3],
    basis: [Vec<f64>; 3],
    accuracy: f64,
}

impl<'a> SolidRoots<'a> {
    fn new(solid: &'a Solid3, grid: &SampleGrid, accuracy: f64) -> Self {
        let xi = solid.xi_volume();
        let (min, max) = solid.domain();
        let degree = xi.degree();
        let degrees = [degree.0, degree.1, degree.2];
        let params: [Vec<f64>; 3] = core::array::from_fn(|axis| {
            (0..grid.dims[axis])
                .map(|a| {
                    (grid.origin[axis] + grid.step[axis] * a as f64 - min[axis])
                        / (max[axis] - min[axis])
                })
                .collect()
        });
        let basis = core::array::from_fn(|axis| {
            let d = degrees[axis] + 1;
            let mut table = vec![0.0; params[axis].len() * d];
            for (row, &t) in table.chunks_exact_mut(d).zip(&params[axis]) {
                basis(degrees[axis], t, row);
            }
            table
        });
        Self {
            solid,
            xi,
            grid: *grid,
            params,
            basis,
            accuracy,
        }
    }

    fn axis_points(&self, axis: usize) -> Vec<f64> {
        (0..self.grid.dims[axis])
            .map(|a| self.grid.origin[axis] + self.grid.step[axis] * a as f64)
            .collect()
    }

    /// The coefficients of `S_ξ` along `axis` through sample `lower` (the other two parameters fixed).
    fn line(&self, axis: usize, lower: [usize; 3]) -> [f64; MAX_DEGREE + 1] {
        let (n, m, l) = self.xi.degree();
        let dims = [n + 1, m + 1, l + 1];
        let ones = [1.0; MAX_DEGREE + 1];
        // Basis rows of the two fixed parameters, and ones along the edge's own axis.
        let rows: [&[f64]; 3] = core::array::from_fn(|ax| {
            if ax == axis {
                &ones[..dims[ax]]
            } else {
                &self.basis[ax][lower[ax] * dims[ax]..(lower[ax] + 1) * dims[ax]]
            }
        });
        let pts = self.xi.points();
        let mut out = [0.0; MAX_DEGREE + 1];
        for (i, &wi) in rows[0].iter().enumerate() {
            for (j, &wj) in rows[1].iter().enumerate() {
                let wij = wi * wj;
                let base = (i * dims[1] + j) * dims[2];
                for (k, &wk) in rows[2].iter().enumerate() {
                    out[[i, j, k][axis]] += pts[base + k] * (wij * wk);
                }
            }
        }
        out
    }
}

impl EdgeRoots for SolidRoots<'_> {
    fn root(&mut self, axis: usize, lower: [usize; 3], f0: f64, f1: f64) -> f64 {
        let coef = self.line(axis, lower);
        let degree = [self.xi.degree().0, self.xi.degree().1, self.xi.degree().2][axis];
        let (t0, t1) = (
            self.params[axis][lower[axis]],
            self.params[axis][lower[axis] + 1],
        );
        let p = |ax: usize| self.params[ax][lower[ax]];
        let g = |t: f64| {
            let s = t0 + (t1 - t0) * t;
            let b = basis_array(degree, s);
            let value: f64 = coef[..=degree].iter().zip(&b).map(|(c, b)| c * b).sum();
            let mut uvw = [p(0), p(1), p(2)];
            uvw[axis] = s;
            clip3(value, uvw[0], uvw[1], uvw[2])
        };
        illinois(g, f0, f1, self.accuracy)
    }

    fn normal(&mut self, p: DVec3) -> DVec3 {
        -self.solid.f_with_gradient(p).1.normalize_or_zero()
    }

    fn centre(&mut self, mean: DVec3, lo: DVec3, hi: DVec3) -> DVec3 {
        // Newton steps along the gradient, kept in the cube.
        let mut p = mean;
        for _ in 0..8 {
            let (f, g) = self.solid.f_with_gradient(p);
            let g2 = g.length_squared();
            if f.abs() <= self.accuracy || g2 == 0.0 || !g2.is_finite() {
                break;
            }
            p = (p - g * (f / g2)).clamp(lo, hi);
        }
        p
    }
}

/// A root of `g` on `[0, 1]` where `g(0) = f0` and `g(1) = f1` have opposite signs (`≤ 0` and `> 0`),
/// by the Illinois variant of regula falsi, until `|g| ≤ accuracy`; at most 64 steps.
fn illinois(g: impl Fn(f64) -> f64, f0: f64, f1: f64, accuracy: f64) -> f64 {
    let (mut a, mut b, mut fa, mut fb) = (0.0, 1.0, f0, f1);
    let mut side = 0i8;
    let mut t = linear_root(fa, fb);
    for _ in 0..64 {
        let ft = g(t);
        if ft.abs() <= accuracy || !ft.is_finite() {
            break;
        }
        if (ft > 0.0) == (fb > 0.0) {
            b = t;
            fb = ft;
            if side == 1 {
                fa *= 0.5;
            }
            side = 1;
        } else {
            a = t;
            fa = ft;
            if side == -1 {
                fb *= 0.5;
            }
            side = -1;
        }
        if b - a <= f64::EPSILON {
            break;
        }
        t = a + (b - a) * linear_root(fa, fb);
    }
    t
}

#[cfg(test)]
mod tests {
    use super::*;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    /// A ball of radius `r` (in parameter units) about the middle of the box `[min, max]`: in degree 2
    /// the Bernstein coefficients of `(t − ½)²` are `(¼, −¼, ¼)`, so `S_ξ = r² − |t − ½|²` exactly.
    fn ball(r: f64, min: DVec3, max: DVec3) -> Solid3 {
        let c = [0.25, -0.25, 0.25];
        Solid3::regular((2, 2, 2), min, max, |i, j, k| r * r - c[i] - c[j] - c[k]).unwrap()
    }

    #[test]
    fn ball_mesh_is_closed_accurate_and_its_volume_converges() {
        let (min, max) = (DVec3::new(-1.0, 0.0, 2.0), DVec3::new(1.0, 2.0, 4.0));
        let r = 0.4;
        let solid = ball(r, min, max);
        // The box is a 2-cube: the ball's radius in space is 2r.
        let exact = 4.0 / 3.0 * core::f64::consts::PI * (2.0 * r).powi(3);
        let centre = (min + max) / 2.0;
        let mut last_error = f64::INFINITY;
        for res in [8, 16, 32, 64] {
            let accuracy = 1e-10;
            let mesh = solid.polygonize(res, accuracy).unwrap();
            mesh.check_closed_manifold().unwrap();
            assert_eq!(mesh.euler_characteristic(), 2);
            for (p, n) in mesh.positions.iter().zip(&mesh.normals) {
                assert!(solid.f(*p).abs() <= accuracy, "f = {} at {p}", solid.f(*p));
                assert!((n.length() - 1.0).abs() < 1e-12);
                // On a ball the outward normal is the radial direction.
                assert!(n.dot((*p - centre).normalize()) > 1.0 - 1e-9);
            }
            let error = (mesh.volume() - exact).abs() / exact;
            assert!(
                error < 0.6 * last_error,
                "res {res}: error {error} after {last_error}"
            );
            last_error = error;
        }
        assert!(last_error < 2e-3, "{last_error}");
    }

    #[test]
    fn a_solid_cut_by_the_box_is_closed_by_the_box_faces() {
        // ξ = 0.5 everywhere: the whole box is inside; the mesh is the box itself, vertices on its faces.
        let solid = Solid3::regular(
            (1, 2, 1),
            DVec3::ZERO,
            DVec3::new(2.0, 1.0, 1.0),
            |_, _, _| 0.5,
        )
        .unwrap();
        let mesh = solid.polygonize(10, 1e-12).unwrap();
        mesh.check_closed_manifold().unwrap();
        assert_eq!(mesh.euler_characteristic(), 2);
        // Marching cubes bevels the box's edges: a prism of section (h/2)²/2 along each of them.
        let h = 0.2;
        let bevel = 16.0 * (h / 2.0) * (h / 2.0) / 2.0;
        // (The corners, where three bevels meet, give a little back.)
        assert!(
            (mesh.volume() - (2.0 - bevel)).abs() < 0.01,
            "{}",
            mesh.volume()
        );
        for p in &mesh.positions {
            let on_face = p.x.abs() < 1e-9
                || (p.x - 2.0).abs() < 1e-9
                || p.y.abs() < 1e-9
                || (p.y - 1.0).abs() < 1e-9
                || p.z.abs() < 1e-9
                || (p.z - 1.0).abs() < 1e-9;
            assert!(on_face, "{p}");
        }
    }

    #[test]
    fn bad_arguments_are_typed_errors() {
        let solid = ball(0.3, DVec3::ZERO, DVec3::ONE);
        assert_eq!(
            solid.polygonize(0, 1e-6),
            Err(MeshError::Resolution { got: 0 })
        );
        assert_eq!(
            solid.polygonize(MAX_RESOLUTION + 1, 1e-6),
            Err(MeshError::Resolution {
                got: MAX_RESOLUTION + 1
            })
        );
        for accuracy in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            assert_eq!(solid.polygonize(8, accuracy), Err(MeshError::Accuracy));
        }
        // An empty solid is an empty mesh, not an error.
        let empty = Solid3::regular((1, 1, 1), DVec3::ZERO, DVec3::ONE, |_, _, _| -1.0).unwrap();
        assert_eq!(empty.polygonize(8, 1e-6).unwrap().triangle_count(), 0);
    }

    #[test]
    fn cells_are_near_cubes_in_a_long_box() {
        let solid = ball(0.3, DVec3::ZERO, DVec3::new(4.0, 1.0, 0.5));
        let grid = solid.mesh_grid(40).unwrap();
        assert_eq!(grid.dims, [42, 12, 7]);
        assert!((grid.step.x - 0.1).abs() < 1e-12 && grid.step.max_element() <= 0.1 + 1e-12);
    }
}
