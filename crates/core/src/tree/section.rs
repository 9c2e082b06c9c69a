//! Boundaries in the plane: the zero contour of a 2D tree, and the true section of a 3D tree by
//! a plane across an axis.

use alloc::vec::Vec;

use glam::DVec2;

use super::mesh::{Field, GRID_SHIFT, Region, TreeMeshError, region};
use super::{Step, Tree};
use crate::contour::{Grid2, Polyline, contour};
use crate::dim::{Dim, Dimension};

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
        let grid = plane_grid(DVec2::from_array(lo), DVec2::from_array(hi), resolution);
        let mut field = Field::new(self, clip);
        let lines = self.plane_contour(
            &grid,
            &mut field,
            |q| q,
            accuracy,
            |xs, ys| self.f_grid([xs, ys]),
        );
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
        let grid = plane_grid(
            DVec2::new(lo[a], lo[b]),
            DVec2::new(hi[a], hi[b]),
            resolution,
        );
        let place = |q: [f64; 2]| {
            let mut p = [at; 3];
            p[a] = q[0];
            p[b] = q[1];
            p
        };
        let mut field = Field::new(self, clip);
        Ok(
            self.plane_contour(&grid, &mut field, place, accuracy, |us, vs| {
                // The plane's grid as a grid of space with one sample across the axis: its first
                // axis (a) is the fastest, as the plane's grid has it.
                let across = [at];
                let mut axes: [&[f64]; 3] = [&across; 3];
                axes[a] = us;
                axes[b] = vs;
                self.f_grid(axes)
            }),
        )
    }
}

/// The grid of a contour over `[lo, hi]` in a plane: `resolution` cells a side with a cell of
/// margin, shifted off the lattice by [`GRID_SHIFT`] of a cell.
fn plane_grid(lo: DVec2, hi: DVec2, resolution: usize) -> Grid2 {
    let cell = (hi - lo) / resolution as f64;
    let shift = cell * GRID_SHIFT;
    Grid2::new(
        lo - cell + shift,
        hi + cell + shift,
        resolution + 3,
        resolution + 3,
    )
}

impl<const D: usize> Tree<D>
where
    Dim<D>: Dimension<D>,
{
    /// The zero contour of `field` on the plane's `grid`, placed in space by `place`, vertices
    /// refined to `|f| ≤ accuracy`: planned for the grid's samples, taken tile by tile by pruned
    /// programs ([`Tiles`]), or by `f_grid` (the tree's grid evaluation over the grid's two
    /// coordinate lists) where no tile leaves anything out.
    fn plane_contour(
        &self,
        grid: &Grid2,
        field: &mut Field<'_, D>,
        place: impl Fn([f64; 2]) -> [f64; D] + Copy,
        accuracy: f64,
        f_grid: impl FnOnce(&[f64], &[f64]) -> Vec<f64>,
    ) -> Vec<Polyline> {
        let (xs, ys) = (grid.xs(), grid.ys());
        self.plan(xs.len() * ys.len());
        if let Some(tiles) = Tiles::new(self, grid, place) {
            let values = tiles.values(field, grid, place);
            return contour(
                grid,
                &values,
                |q| field.f_by(tiles.program_at(grid, q), place(q.to_array())),
                accuracy,
            );
        }
        let values: Vec<f64> = f_grid(&xs, &ys)
            .into_iter()
            .enumerate()
            .map(|(k, f)| field.clipped(f, place([xs[k % xs.len()], ys[k / xs.len()]])))
            .collect();
        contour(grid, &values, |q| field.f(place(q.to_array())), accuracy)
    }
}

/// The cells per side of the tiles a plane's grid is cut into, each sampled by the tree's program
/// pruned over its box.
const TILE: usize = 16;

/// A plane's grid cut into tiles of [`TILE`] cells a side, each with the tree's program pruned
/// over its box (see [`Tree::pruned_of`]): the operands that cannot decide a sign there left
/// out, so that a model of many solids side by side samples the few near each tile, not all of
/// them (a section of 200 folded volumes evaluated every one at every sample). A pruned program
/// has the tree's signs and zero set in its tile, so the contour is the tree's.
struct Tiles {
    across: [usize; 2],
    programs: Vec<Option<Vec<Step>>>,
}

impl Tiles {
    /// The tiles of `grid`, placed in the tree's space by `place`; `None` where no tile leaves
    /// anything out (the tree's own grid evaluation is the faster then).
    fn new<const D: usize>(
        tree: &Tree<D>,
        grid: &Grid2,
        place: impl Fn([f64; 2]) -> [f64; D],
    ) -> Option<Self>
    where
        Dim<D>: Dimension<D>,
    {
        let cells = [grid.nx() - 1, grid.ny() - 1];
        let across = cells.map(|n| n.div_ceil(TILE));
        let mut leaves = Vec::with_capacity(tree.leaves.len());
        let mut programs = Vec::with_capacity(across[0] * across[1]);
        for tj in 0..across[1] {
            for ti in 0..across[0] {
                let (i0, j0) = (ti * TILE, tj * TILE);
                let (i1, j1) = ((i0 + TILE).min(cells[0]), (j0 + TILE).min(cells[1]));
                let (a, b) = (grid.point(i0, j0), grid.point(i1, j1));
                let (pa, pb) = (place([a.x, a.y]), place([b.x, b.y]));
                let lo = core::array::from_fn(|c| pa[c].min(pb[c]));
                let hi = core::array::from_fn(|c| pa[c].max(pb[c]));
                tree.leaf_ranges(lo, hi, &mut leaves);
                programs.push(tree.pruned_of(&leaves));
            }
        }
        programs
            .iter()
            .any(Option::is_some)
            .then_some(Self { across, programs })
    }

    /// The program of the tile of sample `(i, j)` (the tile whose cells hold it first).
    fn program(&self, i: usize, j: usize) -> Option<&[Step]> {
        let ti = (i / TILE).min(self.across[0] - 1);
        let tj = (j / TILE).min(self.across[1] - 1);
        self.programs[tj * self.across[0] + ti].as_deref()
    }

    /// The program of the tile whose closed box holds the point `p` of the plane.
    fn program_at(&self, grid: &Grid2, p: DVec2) -> Option<&[Step]> {
        let (a, b) = (grid.point(0, 0), grid.point(grid.nx() - 1, grid.ny() - 1));
        let cell = |x: f64, lo: f64, hi: f64, n: usize| {
            // Truncation is the floor of a positive number (and NaN goes to the first cell).
            let t = (x - lo) / (hi - lo) * (n - 1) as f64;
            if t > 0.0 { (t as usize).min(n - 2) } else { 0 }
        };
        self.program(
            cell(p.x, a.x, b.x, grid.nx()),
            cell(p.y, a.y, b.y, grid.ny()),
        )
    }

    /// `f` at every sample of `grid` (row-major), each by its tile's program.
    fn values<const D: usize>(
        &self,
        field: &mut Field<'_, D>,
        grid: &Grid2,
        place: impl Fn([f64; 2]) -> [f64; D],
    ) -> Vec<f64>
    where
        Dim<D>: Dimension<D>,
    {
        let mut values = Vec::with_capacity(grid.nx() * grid.ny());
        for j in 0..grid.ny() {
            for i in 0..grid.nx() {
                let q = grid.point(i, j);
                values.push(field.f_by(self.program(i, j), place([q.x, q.y])));
            }
        }
        values
    }
}
