//! Boundaries in the plane: the zero contour of a 2D tree, and the true section of a 3D tree by
//! a plane across an axis.

use alloc::vec::Vec;

use glam::DVec2;

use super::Tree;
use super::mesh::{Field, GRID_SHIFT, Region, TreeMeshError, region};
use crate::contour::{Grid2, Polyline, contour};

impl Tree<2> {
    /// The zero contour of the solid, solid on the left, from a grid of `resolution` cells per
    /// side of its bounds (or of `region`, cut by it) with a cell of margin, vertices refined to
    /// `|f| ≤ accuracy`. An empty solid has no lines.
    ///
    /// # Errors
    ///
    /// [`TreeMeshError`]: no bounds and no region, a bad region, resolution or accuracy; no
    /// line where the solid has an inside point ([`TreeMeshError::Lost`]).
    pub fn contour(
        &self,
        resolution: usize,
        accuracy: f64,
        region: Option<([f64; 2], [f64; 2])>,
    ) -> Result<Vec<Polyline>, TreeMeshError> {
        let Some(Region { lo, hi, clip }) =
            self::region(self.bounds(), region, resolution, accuracy)?
        else {
            return Ok(Vec::new());
        };
        let (lo, hi) = (DVec2::from_array(lo), DVec2::from_array(hi));
        let cell = (hi - lo) / resolution as f64;
        let shift = cell * GRID_SHIFT;
        let grid = Grid2::new(
            lo - cell + shift,
            hi + cell + shift,
            resolution + 3,
            resolution + 3,
        );
        let mut field = Field::new(self, clip);
        // The samples as a grid (the Bézier leaves axis at a time), the roots point by point.
        let (xs, ys) = (grid.xs(), grid.ys());
        self.plan(xs.len() * ys.len());
        let values: Vec<f64> = self
            .f_grid([&xs, &ys])
            .into_iter()
            .enumerate()
            .map(|(k, f)| field.clipped(f, [xs[k % xs.len()], ys[k / xs.len()]]))
            .collect();
        let lines = contour(&grid, &values, |p| field.f(p.to_array()), accuracy);
        // Never an empty success where the solid has an inside point.
        if let (true, Some((p, f))) = (lines.is_empty(), self.inside_point(region)) {
            return Err(TreeMeshError::Lost {
                at: [p.x, p.y, 0.0],
                f,
                resolution,
            });
        }
        Ok(lines)
    }
}

/// The two axes of the plane across `axis` (0 for x), in order: `(y, z)` across x, `(x, z)`
/// across y, `(x, y)` across z: the coordinates of [`Tree::section`]'s lines.
#[must_use]
pub fn plane_axes(axis: usize) -> [usize; 2] {
    match axis {
        0 => [1, 2],
        1 => [0, 2],
        _ => [0, 1],
    }
}

impl Tree<3> {
    /// The true section of the solid by the plane `p[axis] = at`: the zero contour of `f` on the
    /// plane, solid on the left, in the plane's coordinates (the other two axes in order: `(y, z)`
    /// across x, `(x, z)` across y, `(x, y)` across z), from a grid of `resolution` cells per side
    /// of the bounds (or of `region`, cut by it) with a cell of margin, vertices refined to
    /// `|f| ≤ accuracy`. The loops' signed areas add up to the section's area.
    ///
    /// # Errors
    ///
    /// [`TreeMeshError`]: no bounds and no region, a bad region, resolution or accuracy, an axis
    /// past z, or a plane that misses the box ([`TreeMeshError::Plane`]).
    pub fn section(
        &self,
        axis: usize,
        at: f64,
        resolution: usize,
        accuracy: f64,
        region: Option<([f64; 3], [f64; 3])>,
    ) -> Result<Vec<Polyline>, TreeMeshError> {
        if axis > 2 || !at.is_finite() {
            return Err(TreeMeshError::Region);
        }
        // The box the model fills (or the one given) must hold the plane.
        if let Some((lo, hi)) = region.or(self.bounds())
            && lo[axis] <= hi[axis]
            && !(lo[axis]..=hi[axis]).contains(&at)
        {
            return Err(TreeMeshError::Plane {
                axis,
                at,
                lo: lo[axis],
                hi: hi[axis],
            });
        }
        let Some(Region { lo, hi, clip }) =
            self::region(self.bounds(), region, resolution, accuracy)?
        else {
            return Ok(Vec::new());
        };
        let [a, b] = plane_axes(axis);
        let (plo, phi) = (DVec2::new(lo[a], lo[b]), DVec2::new(hi[a], hi[b]));
        let cell = (phi - plo) / resolution as f64;
        let shift = cell * GRID_SHIFT;
        let grid = Grid2::new(
            plo - cell + shift,
            phi + cell + shift,
            resolution + 3,
            resolution + 3,
        );
        let (us, vs) = (grid.xs(), grid.ys());
        self.plan(us.len() * vs.len());
        let place = |q: [f64; 2]| {
            let mut p = [at; 3];
            p[a] = q[0];
            p[b] = q[1];
            p
        };
        let mut field = Field::new(self, clip);
        // The plane's grid as a grid of space with one sample across the axis: its first axis
        // (a) is the fastest, as the plane's grid has it.
        let across = [at];
        let mut axes: [&[f64]; 3] = [&across; 3];
        axes[a] = &us;
        axes[b] = &vs;
        let values: Vec<f64> = self
            .f_grid(axes)
            .into_iter()
            .enumerate()
            .map(|(k, f)| field.clipped(f, place([us[k % us.len()], vs[k / us.len()]])))
            .collect();
        Ok(contour(
            &grid,
            &values,
            |q| field.f(place(q.to_array())),
            accuracy,
        ))
    }
}
