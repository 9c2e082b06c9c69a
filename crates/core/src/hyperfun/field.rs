//! A HyperFun program's solid as a mesh: its field sampled over a box and polygonized (marching
//! cubes, inside `f > 0` as in HyperFun), each crossing found on its edge by the program itself
//! (regula falsi), the solid cut by the box so that the mesh is closed; and its [`section`] by a
//! plane across an axis, the zero contour of the program in the plane. A program has no bounds of
//! its own: the box is the caller's, as HyperFun's polygonizer takes one.

use alloc::vec::Vec;
use core::fmt;

use glam::{DVec2, DVec3};

use super::read::{Evaluator, HfError, Program};
use crate::mesh::Mesh;
use crate::mesh::polygonize::{EdgeRoots, SampleGrid, polygonize};

/// The most operations of the reader one mesh may take over all its points (about a minute).
pub const MAX_MESH_OPERATIONS: u64 = 20_000_000_000;

/// The most cells along the box's longest side (the samples, 8 bytes each, stay under 140 MB).
pub const MAX_RESOLUTION: usize = 256;

/// The most cells along the longer side of a [`section`]'s rectangle (4096² samples, 8 bytes
/// each, 134 MB).
pub const MAX_SECTION_RESOLUTION: usize = 4096;

/// Steps of regula falsi on an edge.
const ROOT_STEPS: usize = 24;

/// How close to a sample, as a fraction of its edge, a vertex may come. A program that is exactly
/// zero at a sample (a ball of radius 1 on a grid through ±1: HyperFun's users write round
/// numbers) would otherwise put the vertices of every edge from that sample on one point, and
/// the triangles between them would have no area; a thousandth of a cell moves the surface by
/// far less than the grid resolves.
const APART: f64 = 1e-3;

/// Why a program has no mesh.
#[derive(Clone, Debug, PartialEq)]
pub enum FieldMeshError {
    /// The program failed at a point (HyperFun's message at its line and position).
    Program {
        /// The point.
        at: [f64; 3],
        /// The program's error.
        error: HfError,
    },
    /// Its value at a point is not a number or not finite.
    NotFinite {
        /// The point.
        at: [f64; 3],
    },
    /// The points together took more than [`MAX_MESH_OPERATIONS`].
    TooMuchWork,
    /// No sample of the box is inside (`f > 0`).
    Empty,
}

impl fmt::Display for FieldMeshError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Program { at, error } => {
                write!(f, "at ({}, {}, {}): {error}", at[0], at[1], at[2])
            }
            Self::NotFinite { at } => write!(
                f,
                "the value at ({}, {}, {}) is not a finite number",
                at[0], at[1], at[2]
            ),
            Self::TooMuchWork => write!(
                f,
                "the program takes more than {MAX_MESH_OPERATIONS} operations over the grid: \
                 mesh it at a lower resolution or in a smaller box"
            ),
            Self::Empty => write!(f, "no point of the grid in the box is inside (f > 0)"),
        }
    }
}

impl core::error::Error for FieldMeshError {}

/// The mesh of `program`'s solid within the box `[lo, hi]`, `res` cells along the box's longest
/// side (from 1 to [`MAX_RESOLUTION`], clamped), cut by the box. `progress(done, total)` is told of each layer of samples.
///
/// # Errors
///
/// [`FieldMeshError`]: the program's error or a value that is not finite at a point, work past
/// [`MAX_MESH_OPERATIONS`], or no inside sample.
pub fn mesh(
    program: &Program,
    lo: DVec3,
    hi: DVec3,
    res: usize,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<Mesh, FieldMeshError> {
    let extent = hi - lo;
    let step = extent.max_element() / res.clamp(1, MAX_RESOLUTION) as f64;
    let count = |e: f64| (libm::ceil(e / step) as usize).max(1) + 1;
    let dims = [count(extent.x), count(extent.y), count(extent.z)];
    let step = DVec3::new(
        extent.x / (dims[0] - 1) as f64,
        extent.y / (dims[1] - 1) as f64,
        extent.z / (dims[2] - 1) as f64,
    );
    let grid = SampleGrid {
        origin: lo,
        step,
        dims,
    };
    let mut field = Sampler::new(program);
    let mut values = Vec::with_capacity(dims[0] * dims[1] * dims[2]);
    let mut inside = false;
    for c in 0..dims[2] {
        for b in 0..dims[1] {
            for a in 0..dims[0] {
                let p = grid.point(a, b, c);
                let mut v = field.at(p)?;
                // The box cuts the solid: its outer samples are outside.
                let rim = a == 0
                    || b == 0
                    || c == 0
                    || a + 1 == dims[0]
                    || b + 1 == dims[1]
                    || c + 1 == dims[2];
                if rim && v > 0.0 {
                    v = -f64::MIN_POSITIVE;
                }
                inside |= v > 0.0;
                values.push(v);
            }
        }
        progress(c + 1, dims[2]);
    }
    if !inside {
        return Err(FieldMeshError::Empty);
    }
    let mut roots = Roots {
        field: &mut field,
        grid,
    };
    let mesh = polygonize(&grid, &values, &mut roots);
    match field.failed {
        Some(e) => Err(e),
        None => Ok(mesh),
    }
}

/// The section of `program`'s solid by the plane across `axis` (0 for x, 1 for y, 2 for z) at
/// `at`, within the box `[lo, hi]`: the zero contour of the program in the plane, sampled on a
/// grid of `res` cells along the longer side of the box's rectangle in the plane (from 1 to
/// [`MAX_SECTION_RESOLUTION`], clamped; along the shorter side as many as keep its cells no
/// larger), each vertex refined on the program until `|f| <= accuracy`.
///
/// The lines are in the plane's two coordinates, ordered as [`crate::tree::plane_axes`] orders
/// them (`y, z` across x, `x, z` across y, `x, y` across z), with `f > 0` on their left; a line
/// that leaves the box's rectangle ends on its border. `at` need not be within `[lo, hi]` along
/// `axis`. A rectangle that is empty or not finite in the plane gives no lines.
///
/// # Errors
///
/// [`FieldMeshError`]: the program's error or a value that is not finite at a point, or work
/// past [`MAX_MESH_OPERATIONS`] (the first of them stops the sampling).
pub fn section(
    program: &Program,
    axis: usize,
    at: f64,
    lo: DVec3,
    hi: DVec3,
    res: usize,
    accuracy: f64,
) -> Result<Vec<crate::contour::Polyline>, FieldMeshError> {
    section_field(program, axis, at, lo, hi, res, accuracy).map(|s| s.lines)
}

/// A program's field in a plane ([`section_field`]): its samples and its zero contour.
#[derive(Clone, Debug, PartialEq)]
pub struct Section {
    /// Samples along the plane's first coordinate.
    pub nx: usize,
    /// Samples along its second.
    pub ny: usize,
    /// The rectangle's low corner, in the plane's coordinates.
    pub lo: DVec2,
    /// Its high corner.
    pub hi: DVec2,
    /// The program's values at the samples, row by row from `lo` (`values[j·nx + i]`).
    pub values: Vec<f64>,
    /// The zero contour, as [`section`] gives it.
    pub lines: Vec<crate::contour::Polyline>,
}

/// [`section`] with the samples the contour was found from: the field over the plane, for a
/// picture of it. A rectangle that is empty or not finite gives no samples and no lines.
///
/// # Errors
///
/// As [`section`].
pub fn section_field(
    program: &Program,
    axis: usize,
    at: f64,
    lo: DVec3,
    hi: DVec3,
    res: usize,
    accuracy: f64,
) -> Result<Section, FieldMeshError> {
    use crate::contour::{Grid2, contour};
    let [a, b] = crate::tree::plane_axes(axis);
    let (lo, hi) = (DVec2::new(lo[a], lo[b]), DVec2::new(hi[a], hi[b]));
    let mut out = Section {
        nx: 0,
        ny: 0,
        lo,
        hi,
        values: Vec::new(),
        lines: Vec::new(),
    };
    if !(lo.is_finite() && hi.is_finite() && lo.x < hi.x && lo.y < hi.y) {
        return Ok(out);
    }
    let res = res.clamp(1, MAX_SECTION_RESOLUTION);
    let side = (hi - lo).max_element();
    let samples = |e: f64| (libm::ceil(e / side * res as f64) as usize).max(1) + 1;
    (out.nx, out.ny) = (samples(hi.x - lo.x), samples(hi.y - lo.y));
    let grid = Grid2::new(lo, hi, out.nx, out.ny);
    let mut sampler = Sampler::new(program);
    let mut failed = None;
    let mut value = |q: DVec2| {
        let mut p = DVec3::splat(at);
        (p[a], p[b]) = (q.x, q.y);
        // After the first failure no point is evaluated: its error is the answer.
        match failed.is_none().then(|| sampler.at(p)) {
            Some(Ok(v)) => v,
            Some(Err(e)) => {
                failed = Some(e);
                -1.0
            }
            None => -1.0,
        }
    };
    out.values.reserve(out.nx * out.ny);
    for j in 0..out.ny {
        for i in 0..out.nx {
            out.values.push(value(grid.point(i, j)));
        }
    }
    out.lines = contour(&grid, &out.values, &mut value, accuracy);
    match failed {
        Some(e) => Err(e),
        None => Ok(out),
    }
}

/// A program's values at points for a mesh or a section, their work counted together against
/// [`MAX_MESH_OPERATIONS`].
pub struct Sampler<'p> {
    run: Evaluator<'p>,
    work: u64,
    /// The first failure while refining an edge (where the polygonizer cannot be told).
    failed: Option<FieldMeshError>,
}

impl<'p> Sampler<'p> {
    /// A sampler of `program`, no work done yet.
    #[must_use]
    pub fn new(program: &'p Program) -> Self {
        Self {
            run: program.evaluator(),
            work: 0,
            failed: None,
        }
    }

    /// The program's value at `p`.
    ///
    /// # Errors
    ///
    /// The program's error there, a value that is not finite, or the work of all points so far
    /// past [`MAX_MESH_OPERATIONS`].
    pub fn at(&mut self, p: DVec3) -> Result<f64, FieldMeshError> {
        let at = p.to_array();
        let v = self
            .run
            .eval(&at, &[])
            .map_err(|error| FieldMeshError::Program { at, error })?;
        self.work = self.work.saturating_add(self.run.operations());
        if self.work > MAX_MESH_OPERATIONS {
            return Err(FieldMeshError::TooMuchWork);
        }
        if v.is_finite() {
            Ok(v)
        } else {
            Err(FieldMeshError::NotFinite { at })
        }
    }
}

/// Edge roots by regula falsi (Illinois) on the program; an edge to a rim sample (forced outside
/// by the box's cut) by linear interpolation.
struct Roots<'f, 'p> {
    field: &'f mut Sampler<'p>,
    grid: SampleGrid,
}

impl EdgeRoots for Roots<'_, '_> {
    fn vertex(&mut self, axis: usize, lower: [usize; 3], f0: f64, f1: f64) -> (f64, DVec3) {
        let (t, normal) = self.root(axis, lower, f0, f1);
        (t.clamp(APART, 1.0 - APART), normal)
    }
}

impl Roots<'_, '_> {
    /// Where the surface crosses the edge, as a fraction of it, and no normal.
    fn root(&mut self, axis: usize, lower: [usize; 3], f0: f64, f1: f64) -> (f64, DVec3) {
        let linear = |f0: f64, f1: f64| {
            let t = f0 / (f0 - f1);
            if t.is_finite() {
                t.clamp(0.0, 1.0)
            } else {
                0.5
            }
        };
        let mut upper = lower;
        upper[axis] += 1;
        let dims = self.grid.dims;
        let rim = |i: [usize; 3]| (0..3).any(|k| i[k] == 0 || i[k] + 1 == dims[k]);
        if self.field.failed.is_some() || rim(lower) || rim(upper) {
            return (linear(f0, f1), DVec3::ZERO);
        }
        let p0 = self.grid.point(lower[0], lower[1], lower[2]);
        let p1 = self.grid.point(upper[0], upper[1], upper[2]);
        let (mut a, mut fa, mut b, mut fb) = (0.0, f0, 1.0, f1);
        let mut side = 0;
        for _ in 0..ROOT_STEPS {
            let t = (a * fb - b * fa) / (fb - fa);
            if !t.is_finite() {
                break;
            }
            let ft = match self.field.at(p0.lerp(p1, t)) {
                Ok(v) => v,
                Err(e) => {
                    self.field.failed = Some(e);
                    break;
                }
            };
            if ft == 0.0 {
                return (t, DVec3::ZERO);
            }
            // The root stays between the ends whose values differ in sign (f ≤ 0 against f > 0).
            if (ft > 0.0) == (fb > 0.0) {
                (b, fb) = (t, ft);
                if side == 1 {
                    fa *= 0.5;
                }
                side = 1;
            } else {
                (a, fa) = (t, ft);
                if side == -1 {
                    fb *= 0.5;
                }
                side = -1;
            }
            if b - a <= 1e-12 {
                break;
            }
        }
        (linear(fa, fb) * (b - a) + a, DVec3::ZERO)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    const BALL: &str = "my_model(x[3], a[1]) { my_model = 1 - x[1]^2 - x[2]^2 - x[3]^2; }";

    #[test]
    fn a_sections_lines_lie_on_the_program_s_zero_set_in_the_planes_coordinates() {
        let program = Program::parse(BALL).unwrap();
        let (lo, hi) = (DVec3::splat(-2.0), DVec3::splat(2.0));
        // Through the centre, the unit circle, counter-clockwise around the disc.
        let lines = section(&program, 2, 0.0, lo, hi, 64, 1e-12).unwrap();
        assert_eq!(lines.len(), 1, "{lines:?}");
        assert!(lines[0].closed);
        assert!(lines[0].points.len() > 100);
        for p in &lines[0].points {
            assert!((p.length() - 1.0).abs() < 1e-9, "{p}");
        }
        let area = lines[0].signed_area();
        assert!((area - core::f64::consts::PI).abs() < 2e-3, "{area}");
        // Across x at 0.6: the circle of radius 0.8 in (y, z); the box's x extent is not needed.
        let thin = section(
            &program,
            0,
            0.6,
            DVec3::new(0.0, -1.0, -1.0),
            DVec3::new(0.1, 1.0, 1.0),
            64,
            1e-12,
        )
        .unwrap();
        assert_eq!(thin.len(), 1);
        for p in &thin[0].points {
            assert!((p.length() - 0.8).abs() < 1e-9, "{p}");
        }
        // Above the ball, or in an empty rectangle, nothing.
        assert_eq!(section(&program, 2, 2.0, lo, hi, 64, 1e-12), Ok(Vec::new()));
        let flat = DVec3::new(2.0, -2.0, -2.0);
        assert_eq!(
            section(&program, 2, 0.0, lo, flat, 64, 1e-12),
            Ok(Vec::new())
        );
    }

    #[test]
    fn a_section_says_the_programs_first_error() {
        let program = Program::parse("my_model(x[3], a[1]) { my_model = 1 / x[1]; }").unwrap();
        let err = section(
            &program,
            2,
            0.0,
            DVec3::splat(-1.0),
            DVec3::splat(1.0),
            4,
            1e-9,
        )
        .unwrap_err();
        assert!(
            matches!(&err, FieldMeshError::Program { at, .. } if at[0] == 0.0),
            "{err:?}"
        );
    }

    #[test]
    fn a_program_zero_at_samples_meshes_without_degenerate_triangles() {
        // Radius 1 on a grid of step 1/3 through ±1: six samples lie on the surface.
        let program = Program::parse(BALL).unwrap();
        let mesh = mesh(
            &program,
            DVec3::splat(-2.0),
            DVec3::splat(2.0),
            12,
            &mut |_, _| {},
        )
        .unwrap();
        mesh.check_closed_manifold().unwrap();
        let volume = mesh.volume();
        let exact = 4.0 / 3.0 * core::f64::consts::PI;
        assert!((volume - exact).abs() < 0.08 * exact, "{volume}");
    }
}
