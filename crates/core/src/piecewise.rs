//! Piecewise Bézier solids: the first paper's extension (§5) of one solid to "several patches or
//! volumes tied together", where "functional clipping has not to be applied at the shared
//! edges/faces".
//!
//! One global net of `(c_u·n + 1) × (c_v·m + 1) [× (c_w·l + 1)]` control points, indexed like a
//! single net of those counts (the last axis fastest), is cut into `c_u × c_v [× c_w]` cells; cell
//! `(a, b[, c])` is the patch or volume of degree `(n, m[, l])` whose first point is
//! `(a·n, b·m[, c·l])`, so neighbours share their boundary points and the solid is C⁰ across them.
//! With the global parameter `U = (cell + u) / cells` of a cell's local parameter `u`,
//!
//! `f = S_ξ^cell(u) & F_s(U)`
//!
//! clipped on the outer boundary of the grid only. On a regular global grid `U` is the point
//! scaled to the box and the cell is the one `U` falls in (the nearest one outside the box, whose
//! polynomial extends past it); once points move, `f` is the largest value over the preimages of
//! the point in all cells, and where it has none, the largest of the cells' negative
//! continuations (each cell's as a single solid's, [`crate::inverse::InverseMap::outside`]).
//!
//! ```
//! use bezsolid_core::piecewise::Piecewise;
//! use glam::DVec3;
//!
//! // Two bilinear cells side by side over [0, 2] × [0, 1], ξ = 1 everywhere.
//! let points = (0..3)
//!     .flat_map(|i| (0..2).map(move |j| DVec3::new(i as f64, j as f64, 1.0)))
//!     .collect();
//! let solid = Piecewise::<2>::new([2, 1], [1, 1], points).unwrap();
//! // No clipping at the shared edge x = 1, only at the grid's outer boundary.
//! assert!(solid.f(glam::DVec2::new(1.0, 0.5)) > 0.1);
//! assert!(solid.f(glam::DVec2::new(2.0, 0.5)).abs() < 1e-12);
//! ```

use alloc::vec::Vec;
use core::fmt;

use crate::dim::{Control, Dim, Dimension, Point};
use crate::inverse::{Method, QueryStats, Share, Value, solve_jac};
use crate::rfunc::{clip, clip_with_gradient};
use crate::solid::{Solid, SolidError, odometer, point_bounds, regular_box};
use crate::tensor::{Tensor, multi_index};
use crate::{INVERSE_ACCURACY, MAX_DEGREE};

/// The most cells along one axis.
pub const MAX_CELLS: usize = 16;
/// The most cells in all.
pub const MAX_CELL_COUNT: usize = 256;
/// The most control points of a piecewise net.
pub const MAX_POINTS: usize = 1 << 16;

/// Why a piecewise solid could not be built.
#[derive(Clone, Debug, PartialEq)]
pub enum PiecewiseError {
    /// `cells` or `degree` has another length than the solid's dimension.
    Dimension {
        /// The length of `cells`.
        cells: usize,
        /// The length of `degree`.
        degree: usize,
    },
    /// A count of cells along an axis is 0 or above [`MAX_CELLS`].
    Cells {
        /// The axis (0 for u).
        axis: usize,
        /// The count given.
        got: usize,
    },
    /// More cells in all than [`MAX_CELL_COUNT`].
    CellCount {
        /// The product of the counts.
        got: usize,
    },
    /// A cell's degree along an axis is 0 or above [`MAX_DEGREE`].
    Degree {
        /// The axis.
        axis: usize,
        /// The degree given.
        got: usize,
    },
    /// The number of points is not `Π (cells·degree + 1)`.
    Count {
        /// The points given.
        got: usize,
        /// The points the cells and degree ask for.
        want: usize,
    },
    /// A control point has another number of coordinates than `[x, y, ξ]` or `[x, y, z, ξ]`.
    Point {
        /// Its index in the net.
        index: usize,
        /// The numbers it has.
        got: usize,
        /// The numbers a point of this dimension has.
        want: usize,
    },
    /// A control point is not valid (not finite, or too large).
    Solid(SolidError),
}

impl fmt::Display for PiecewiseError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Dimension { cells, degree } => write!(
                f,
                "a piecewise solid's \"cells\" and \"degree\" each have 2 numbers (a patch) or 3 \
                 (a volume), the same; these have {cells} and {degree}"
            ),
            Self::Cells { axis, got } => write!(
                f,
                "{got} cells along axis {}: a piecewise solid has 1 to {MAX_CELLS} cells along \
                 each axis",
                axis_name(*axis)
            ),
            Self::CellCount { got } => write!(
                f,
                "{got} cells: a piecewise solid has at most {MAX_CELL_COUNT} cells in all"
            ),
            Self::Degree { axis, got } => write!(
                f,
                "degree {got} along axis {}: a cell's degree is 1 to {MAX_DEGREE} along each axis",
                axis_name(*axis)
            ),
            Self::Count { got, want } => write!(
                f,
                "{got} control points: these cells and degree take {want} (cells · degree + 1 \
                 along each axis, multiplied)"
            ),
            Self::Point { index, got, want } => write!(
                f,
                "control point {index} has {got} numbers; each has {want} (x, y{}, ξ)",
                if *want == 4 { ", z" } else { "" }
            ),
            Self::Solid(e) => e.fmt(f),
        }
    }
}

impl core::error::Error for PiecewiseError {}

fn axis_name(axis: usize) -> &'static str {
    ["u", "v", "w"].get(axis).copied().unwrap_or("?")
}

/// A piecewise Bézier solid in `D` dimensions: cells of one global net (see the [module
/// documentation](self)).
#[derive(Clone, Debug, PartialEq)]
pub struct Piecewise<const D: usize>
where
    Dim<D>: Dimension<D>,
{
    cells: [usize; D],
    degree: [usize; D],
    /// The global net's points, the last axis fastest.
    points: Vec<Control<D>>,
    /// The cells as solids of their own, in the order of the net (the last axis fastest).
    parts: Vec<Solid<D>>,
    /// The regular grid's box, or the bounds of the moved net.
    min: [f64; D],
    max: [f64; D],
    regular: bool,
}

/// A piecewise patch.
pub type Piecewise2 = Piecewise<2>;
/// A piecewise volume.
pub type Piecewise3 = Piecewise<3>;

impl<const D: usize> Piecewise<D>
where
    Dim<D>: Dimension<D>,
{
    /// The piecewise solid of `cells` cells of `degree` each, from the global net's `points`
    /// (`Π (cells·degree + 1)` of them, the last axis fastest).
    ///
    /// # Errors
    ///
    /// [`PiecewiseError`] for counts out of range, a wrong number of points or a bad coordinate.
    pub fn new(
        cells: [usize; D],
        degree: [usize; D],
        points: Vec<Control<D>>,
    ) -> Result<Self, PiecewiseError> {
        for axis in 0..D {
            if !(1..=MAX_CELLS).contains(&cells[axis]) {
                return Err(PiecewiseError::Cells {
                    axis,
                    got: cells[axis],
                });
            }
            if !(1..=MAX_DEGREE).contains(&degree[axis]) {
                return Err(PiecewiseError::Degree {
                    axis,
                    got: degree[axis],
                });
            }
        }
        let count: usize = cells.iter().product();
        if count > MAX_CELL_COUNT {
            return Err(PiecewiseError::CellCount { got: count });
        }
        let dims: [usize; D] = core::array::from_fn(|a| cells[a] * degree[a] + 1);
        let want: usize = dims.iter().product();
        if points.len() != want {
            return Err(PiecewiseError::Count {
                got: points.len(),
                want,
            });
        }
        let flat = |index: [usize; D]| (0..D).fold(0, |k, a| k * dims[a] + index[a]);
        let parts = (0..count)
            .map(|k| {
                let cell = multi_index(cells, k);
                let net = Tensor::from_fn(degree, |i| {
                    points[flat(core::array::from_fn(|a| cell[a] * degree[a] + i[a]))]
                })
                .map_err(SolidError::from)?;
                Solid::try_from_net(net)
            })
            .collect::<Result<Vec<_>, _>>()
            .map_err(PiecewiseError::Solid)?;
        let spatial: Vec<[f64; D]> = points.iter().map(|&c| Dim::<D>::split(c).0).collect();
        let (min, max, regular) = match regular_box(dims, &spatial) {
            Some((min, max)) => (min, max, true),
            None => {
                let (min, max) = point_bounds(&spatial);
                (min, max, false)
            }
        };
        Ok(Self {
            cells,
            degree,
            points,
            parts,
            min,
            max,
            regular,
        })
    }

    /// The cells along each axis.
    #[must_use]
    pub fn cells(&self) -> [usize; D] {
        self.cells
    }

    /// Each cell's degree.
    #[must_use]
    pub fn degree(&self) -> [usize; D] {
        self.degree
    }

    /// The global net's points per axis, `cells·degree + 1`.
    #[must_use]
    pub fn dims(&self) -> [usize; D] {
        core::array::from_fn(|a| self.cells[a] * self.degree[a] + 1)
    }

    /// The global net's points, the last axis fastest.
    #[must_use]
    pub fn points(&self) -> &[Control<D>] {
        &self.points
    }

    /// The cell at `cell` as a solid of its own (clipped on its own box: use [`Self::f`] for the
    /// piecewise solid's values), `None` past the cells.
    #[must_use]
    pub fn part(&self, cell: [usize; D]) -> Option<&Solid<D>> {
        if (0..D).any(|a| cell[a] >= self.cells[a]) {
            return None;
        }
        self.parts
            .get((0..D).fold(0, |k, a| k * self.cells[a] + cell[a]))
    }

    /// Says that about `queries` evaluations of `f` are coming (see [`Solid::plan`]): the moved
    /// cells share one map's budget (see [`Share`]), each by the part of the solid's box its own
    /// covers.
    pub fn plan(&self, queries: usize) {
        self.share(1.0, self.load());
        self.plan_cells(queries);
    }

    /// [`Self::plan`] with the cells' shares given before ([`Self::share`]): a tree's leaf.
    pub(crate) fn plan_cells(&self, queries: usize) {
        for part in &self.parts {
            part.plan(queries);
        }
    }

    /// [`Self::plan`] with the work of every query through each cell's map fixed at its share
    /// ([`Solid::fix_query_work`]): a mesh's samples then do not depend on their order.
    pub fn fix_query_work(&self, queries: usize) {
        self.share(1.0, self.load());
        self.fix_cells_query_work(queries);
    }

    /// [`Self::fix_query_work`] with the cells' shares given before ([`Self::share`]).
    pub(crate) fn fix_cells_query_work(&self, queries: usize) {
        for part in &self.parts {
            part.fix_query_work(queries);
        }
    }

    /// The sum of the moved cells' reaches within the solid ([`Self::share`] with `reach` 1): how
    /// many cells a query into the solid's box reaches on average.
    pub(crate) fn load(&self) -> f64 {
        self.cell_reaches().map(|(_, r)| r).sum()
    }

    /// Gives each moved cell the part of a command's work its box covers of the solid's, times
    /// `reach` (the solid's own part of the command), among maps whose reaches sum to `load`.
    pub(crate) fn share(&self, reach: f64, load: f64) {
        for (part, r) in self.cell_reaches() {
            part.share(Share::new(reach * r, load));
        }
    }

    /// The moved cells with the fraction of the solid's box their own box covers.
    fn cell_reaches(&self) -> impl Iterator<Item = (&Solid<D>, f64)> {
        let whole = self.domain();
        let whole = (Dim::<D>::coords(whole.0), Dim::<D>::coords(whole.1));
        self.parts
            .iter()
            .filter(|part| part.is_space_mapped())
            .map(move |part| {
                let (lo, hi) = part.domain();
                (
                    part,
                    box_fraction((Dim::<D>::coords(lo), Dim::<D>::coords(hi)), whole),
                )
            })
    }

    /// Whether the global net is a regular grid (no point moved in space).
    #[must_use]
    pub fn is_regular(&self) -> bool {
        self.regular
    }

    /// The regular grid's box, or the bounds of the moved net's points (which hold its image).
    #[must_use]
    pub fn domain(&self) -> (Point<D>, Point<D>) {
        (Dim::<D>::point(self.min), Dim::<D>::point(self.max))
    }

    /// A single solid as a piecewise one of one cell: the same function (a single cell is
    /// clipped on its own parameter, which is then the global one).
    ///
    /// # Errors
    ///
    /// None for a solid of a degree a cell takes (every solid's); the type is [`Self::new`]'s.
    pub fn from_solid(solid: &Solid<D>) -> Result<Self, PiecewiseError> {
        Self::new([1; D], solid.degree(), solid.net().points().to_vec())
    }

    /// `S(t)` with its `ξ` at global parameter `t` (in the unit box; past it, the nearest cell's
    /// polynomial extended): the cell's net at its local parameter.
    #[must_use]
    pub fn eval(&self, t: [f64; D]) -> Control<D> {
        let (k, u) = self.locate(t);
        self.parts[k].net().eval(u)
    }

    /// The point `S(t)` in space of global parameter `t` ([`Self::eval`] without `ξ`).
    #[must_use]
    pub fn point(&self, t: [f64; D]) -> Point<D> {
        Dim::<D>::point(Dim::<D>::split(self.eval(t)).0)
    }

    /// The solid with one more cell along `axis`, after the last: the last cells mirrored across
    /// the face they end on, so that the net goes on as it was made. With `B` the index of that
    /// face along the axis and the other indices fixed, the new points are
    /// `P_{B+k} = 2·P_B − P_{B−k}` in space (on a regular grid: the grid's spacing, continued) and
    /// `ξ_{B+k} = ξ_{B−k}` (the solid's mirror image), `k = 1..=degree`.
    ///
    /// # Errors
    ///
    /// [`PiecewiseError::Dimension`] for an axis past the solid's, [`PiecewiseError::Cells`] or
    /// [`PiecewiseError::CellCount`] past the caps, [`PiecewiseError::Solid`] where a mirrored
    /// point is past the largest coordinate.
    pub fn with_cell_added(&self, axis: usize) -> Result<Self, PiecewiseError> {
        self.check_axis(axis)?;
        let mut cells = self.cells;
        cells[axis] += 1;
        let dims = self.dims();
        let n = self.degree[axis];
        let mut new_dims = dims;
        new_dims[axis] += n;
        let boundary = dims[axis] - 1;
        let old = |index: [usize; D]| self.points[(0..D).fold(0, |k, a| k * dims[a] + index[a])];
        let count: usize = new_dims.iter().product();
        let points = (0..count)
            .map(|k| {
                let index = multi_index(new_dims, k);
                let i = index[axis];
                if i <= boundary {
                    return old(index);
                }
                let mut face = index;
                face[axis] = boundary;
                let mut mirror = index;
                mirror[axis] = 2 * boundary - i;
                let (b, _) = Dim::<D>::split(old(face));
                let (m, xi) = Dim::<D>::split(old(mirror));
                Dim::<D>::control(core::array::from_fn(|c| 2.0 * b[c] - m[c]), xi)
            })
            .collect();
        Self::new(cells, self.degree, points)
    }

    /// The solid without its last cells along `axis` (the inverse of [`Self::with_cell_added`]).
    ///
    /// # Errors
    ///
    /// [`PiecewiseError::Dimension`] for an axis past the solid's, [`PiecewiseError::Cells`]
    /// (`got: 0`) where the axis has one cell.
    pub fn with_cell_removed(&self, axis: usize) -> Result<Self, PiecewiseError> {
        self.check_axis(axis)?;
        let mut cells = self.cells;
        cells[axis] -= 1;
        if cells[axis] == 0 {
            return Err(PiecewiseError::Cells { axis, got: 0 });
        }
        let dims = self.dims();
        let keep = cells[axis] * self.degree[axis] + 1;
        let points = self
            .points
            .iter()
            .enumerate()
            .filter(|&(k, _)| multi_index(dims, k)[axis] < keep)
            .map(|(_, &p)| p)
            .collect();
        Self::new(cells, self.degree, points)
    }

    fn check_axis(&self, axis: usize) -> Result<(), PiecewiseError> {
        if axis < D {
            Ok(())
        } else {
            Err(PiecewiseError::Dimension {
                cells: axis + 1,
                degree: D,
            })
        }
    }

    /// The global parameter of local parameter `u` of cell number `k`.
    fn global(&self, k: usize, u: [f64; D]) -> [f64; D] {
        let cell = multi_index(self.cells, k);
        core::array::from_fn(|a| (cell[a] as f64 + u[a]) / self.cells[a] as f64)
    }

    /// The cell of global parameter `t` (the nearest outside the unit box) and its local parameter.
    fn locate(&self, t: [f64; D]) -> (usize, [f64; D]) {
        let mut k = 0;
        let mut u = [0.0; D];
        for a in 0..D {
            let n = self.cells[a];
            let s = t[a] * n as f64;
            // NaN and anything past the box fall to the first or last cell.
            let cell = if s >= n as f64 {
                n - 1
            } else if s >= 0.0 {
                s as usize
            } else {
                0
            };
            k = k * n + cell;
            u[a] = s - cell as f64;
        }
        (k, u)
    }

    /// `f(p)` (see the [module documentation](self)) with the number of preimages of `p` (a point
    /// on a face two cells share counts once) and the global parameter it was taken at; the
    /// preimages of moved cells are found by `method`.
    #[must_use]
    pub fn evaluate(&self, p: Point<D>, method: Method) -> Value<D> {
        self.evaluate_cell(Dim::<D>::coords(p), method).0
    }

    /// [`Self::evaluate`] with the cell that gave `f`, its local parameter there, and the sign
    /// `f` has against the cell's clipped value (−1 where the continuation forced it negative).
    fn evaluate_cell(&self, p: [f64; D], method: Method) -> (Value<D>, usize, [f64; D], f64) {
        if self.regular {
            let t: [f64; D] =
                core::array::from_fn(|c| (p[c] - self.min[c]) / (self.max[c] - self.min[c]));
            let (k, u) = self.locate(t);
            let xi = Dim::<D>::split(self.parts[k].net().eval(u)).1;
            let value = Value {
                f: clip(xi, t),
                preimages: usize::from(t.iter().all(|x| (0.0..=1.0).contains(x))),
                u: t,
                exhausted: false,
            };
            return (value, k, u, 1.0);
        }
        let mut stats = QueryStats::default();
        // The best value, its global parameter, its cell and local parameter.
        let mut best: Option<(f64, [f64; D], usize, [f64; D])> = None;
        let mut seen: Vec<[f64; D]> = Vec::new();
        for (k, part) in self.parts.iter().enumerate() {
            if !near_box(part, p) {
                continue;
            }
            let roots = match part.inverse() {
                None => {
                    let u = Dim::<D>::coords(part.to_param(Dim::<D>::point(p)));
                    if u.iter().all(|x| (0.0..=1.0).contains(x)) {
                        alloc::vec![u]
                    } else {
                        Vec::new()
                    }
                }
                Some(map) => {
                    // Each cell's query has its own budget (its share of the command's).
                    let mut own = QueryStats::default();
                    let roots = map.preimages(part.net(), p, method, INVERSE_ACCURACY, &mut own);
                    stats.exhausted |= own.exhausted;
                    roots
                }
            };
            for u in roots {
                let t = self.global(k, u);
                let f = clip(Dim::<D>::split(part.net().eval(u)).1, t);
                if best.is_none_or(|(b, ..)| f > b) {
                    best = Some((f, t, k, u));
                }
                if seen
                    .iter()
                    .all(|s| (0..D).any(|c| (s[c] - t[c]).abs() > 1e-9))
                {
                    seen.push(t);
                }
            }
        }
        if let Some((f, t, k, u)) = best {
            let value = Value {
                f,
                preimages: seen.len(),
                u: t,
                exhausted: stats.exhausted,
            };
            return (value, k, u, 1.0);
        }
        // No preimage in any cell: the largest of the cells' negative continuations.
        let (f, t, k, u, sign) = self
            .parts
            .iter()
            .enumerate()
            .map(|(k, part)| {
                let u = match part.inverse() {
                    None => Dim::<D>::coords(part.to_param(Dim::<D>::point(p))),
                    Some(map) => map.outside(part.net(), p, &mut QueryStats::default()),
                };
                let t = self.global(k, u);
                let f = clip(Dim::<D>::split(part.net().eval(u)).1, t);
                // Negative outside the image, as a single solid's continuation is.
                if f < 0.0 {
                    (f, t, k, u, 1.0)
                } else {
                    (-f - f64::MIN_POSITIVE, t, k, u, -1.0)
                }
            })
            .fold((f64::NEG_INFINITY, [0.5; D], 0, [0.5; D], 1.0), |a, b| {
                if b.0 > a.0 { b } else { a }
            });
        let value = Value {
            f,
            preimages: 0,
            u: t,
            exhausted: stats.exhausted,
        };
        (value, k, u, sign)
    }

    /// The defining function: positive inside, negative outside (preimages of moved cells by
    /// [`Method::Fast`]).
    #[must_use]
    pub fn f(&self, p: Point<D>) -> f64 {
        self.evaluate(p, Method::Fast).f
    }

    /// `f(p)` and its gradient, through the cell and preimage that give `f`.
    #[must_use]
    pub fn f_with_gradient(&self, p: Point<D>) -> (f64, Point<D>) {
        let (v, k, u, sign) = self.evaluate_cell(Dim::<D>::coords(p), Method::Fast);
        let part = &self.parts[k];
        let (s, ds) = part.net().eval_with_gradient(u);
        let xi = Dim::<D>::split(s).1;
        // ∂S_ξ/∂U = cells · ∂S_ξ/∂u.
        let dxi: [f64; D] =
            core::array::from_fn(|c| Dim::<D>::split(ds[c]).1 * self.cells[c] as f64);
        let (f, g) = clip_with_gradient(xi, dxi, v.u);
        let g: [f64; D] = if self.regular {
            core::array::from_fn(|c| g[c] / (self.max[c] - self.min[c]))
        } else {
            // ∇_p f = J^{-T} ∇_u f, ∇_u f = ∇_U f / cells.
            let jt: [[f64; D]; D] =
                core::array::from_fn(|r| core::array::from_fn(|c| Dim::<D>::split(ds[r]).0[c]));
            let gu: [f64; D] = core::array::from_fn(|c| g[c] / self.cells[c] as f64);
            solve_jac(&transpose(jt), gu).unwrap_or([0.0; D])
        };
        let g = g.map(|x| {
            if x.is_nan() {
                0.0
            } else {
                (sign * x).clamp(-f64::MAX, f64::MAX)
            }
        });
        (if self.regular { f } else { v.f }, Dim::<D>::point(g))
    }

    /// `f` at every point of the grid `axes[0] × axes[1] × …`, the first axis fastest (as
    /// [`Solid::f_grid`] orders it).
    #[must_use]
    pub fn f_grid(&self, axes: [&[f64]; D]) -> Vec<f64> {
        let lens = axes.map(<[f64]>::len);
        odometer(lens)
            .map(|at| self.f(Dim::<D>::point(core::array::from_fn(|c| axes[c][at[c]]))))
            .collect()
    }
}

/// The part of the box `whole` that the box `part` (within it) covers, by volume; an axis along
/// which `whole` is flat counts 1.
fn box_fraction<const D: usize>(part: ([f64; D], [f64; D]), whole: ([f64; D], [f64; D])) -> f64 {
    (0..D)
        .map(|c| {
            let side = whole.1[c] - whole.0[c];
            let own = (part.1[c].min(whole.1[c]) - part.0[c].max(whole.0[c])).max(0.0);
            if side > 0.0 {
                (own / side).min(1.0)
            } else {
                1.0
            }
        })
        .product()
}

/// The columns of `m` as rows.
fn transpose<const D: usize>(m: [[f64; D]; D]) -> [[f64; D]; D] {
    core::array::from_fn(|r| core::array::from_fn(|c| m[c][r]))
}

/// Whether `p` lies in the bounds of `part`'s control points, grown by a little (the image of a
/// Bézier cell lies in the hull of its points).
fn near_box<const D: usize>(part: &Solid<D>, p: [f64; D]) -> bool
where
    Dim<D>: Dimension<D>,
{
    let (lo, hi) = part.domain();
    let (lo, hi) = (Dim::<D>::coords(lo), Dim::<D>::coords(hi));
    (0..D).all(|c| {
        let pad = 1e-9
            * (hi[c] - lo[c])
                .abs()
                .max(lo[c].abs())
                .max(hi[c].abs())
                .max(1.0);
        p[c] >= lo[c] - pad && p[c] <= hi[c] + pad
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testutil::Rng;
    use alloc::string::ToString;
    use alloc::vec;
    use glam::{DVec2, DVec3, DVec4};
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    /// The Bernstein polynomial `B_i^n(t)`, written out (the test's own).
    fn bernstein(n: usize, i: usize, t: f64) -> f64 {
        let mut binomial = 1.0;
        for k in 0..i {
            binomial = binomial * (n - k) as f64 / (k + 1) as f64;
        }
        binomial * t.powi(i as i32) * (1.0 - t).powi((n - i) as i32)
    }

    /// `a & b = a + b − √(a² + b²)`.
    fn and(a: f64, b: f64) -> f64 {
        a + b - (a * a + b * b).sqrt()
    }

    /// `S^cell(u)` of the global net `points` (last axis fastest) by the sum over the cell's points.
    fn cell_sum<const D: usize>(
        dims: [usize; D],
        degree: [usize; D],
        points: &[Vec<f64>],
        cell: [usize; D],
        u: [f64; D],
    ) -> Vec<f64> {
        let mut out = vec![0.0; D + 1];
        for flat in 0..degree.iter().map(|d| d + 1).product() {
            let i = multi_index(degree.map(|d| d + 1), flat);
            let w: f64 = (0..D).map(|a| bernstein(degree[a], i[a], u[a])).product();
            let g = (0..D).fold(0, |k, a| k * dims[a] + cell[a] * degree[a] + i[a]);
            for (o, x) in out.iter_mut().zip(&points[g]) {
                *o += w * x;
            }
        }
        out
    }

    /// DESIGN's formula for a regular grid over `[min, max]`: the cell `U` falls in (nearest
    /// outside), its polynomial at the local parameter, clipped by `F_s(U)` left to right.
    fn expected<const D: usize>(
        cells: [usize; D],
        degree: [usize; D],
        points: &[Vec<f64>],
        (min, max): ([f64; D], [f64; D]),
        p: [f64; D],
    ) -> f64 {
        let dims: [usize; D] = core::array::from_fn(|a| cells[a] * degree[a] + 1);
        let t: [f64; D] = core::array::from_fn(|a| (p[a] - min[a]) / (max[a] - min[a]));
        let cell: [usize; D] = core::array::from_fn(|a| {
            ((t[a] * cells[a] as f64).floor().max(0.0) as usize).min(cells[a] - 1)
        });
        let u: [f64; D] = core::array::from_fn(|a| t[a] * cells[a] as f64 - cell[a] as f64);
        let xi = cell_sum(dims, degree, points, cell, u)[D];
        let strip = |x: f64| x * (1.0 - x);
        let fs = (1..D).fold(strip(t[0]), |f, a| and(f, strip(t[a])));
        and(xi, fs)
    }

    fn regular_points<const D: usize>(
        rng: &mut Rng,
        dims: [usize; D],
        (min, max): ([f64; D], [f64; D]),
    ) -> Vec<Vec<f64>> {
        (0..dims.iter().product())
            .map(|k| {
                let i = multi_index(dims, k);
                let mut p: Vec<f64> = (0..D)
                    .map(|a| min[a] + (max[a] - min[a]) * i[a] as f64 / (dims[a] - 1) as f64)
                    .collect();
                p.push(rng.range(-1.0, 1.0));
                p
            })
            .collect()
    }

    fn piecewise2(cells: [usize; 2], degree: [usize; 2], points: &[Vec<f64>]) -> Piecewise2 {
        let pts = points
            .iter()
            .map(|p| DVec3::new(p[0], p[1], p[2]))
            .collect();
        Piecewise::new(cells, degree, pts).unwrap()
    }

    fn piecewise3(cells: [usize; 3], degree: [usize; 3], points: &[Vec<f64>]) -> Piecewise3 {
        let pts = points
            .iter()
            .map(|p| DVec4::new(p[0], p[1], p[2], p[3]))
            .collect();
        Piecewise::new(cells, degree, pts).unwrap()
    }

    #[test]
    fn a_regular_piecewise_solid_is_its_cells_polynomials_clipped_on_the_outer_box_only() {
        let mut rng = Rng::new(7);
        for _ in 0..20 {
            let cells = [rng.int(1, 4), rng.int(1, 4)];
            let degree = [rng.int(1, 4), rng.int(1, 4)];
            let bx = (
                [rng.range(-2.0, 0.0), rng.range(-2.0, 0.0)],
                [rng.range(0.5, 3.0), rng.range(0.5, 3.0)],
            );
            let dims = [cells[0] * degree[0] + 1, cells[1] * degree[1] + 1];
            let points = regular_points(&mut rng, dims, bx);
            let solid = piecewise2(cells, degree, &points);
            assert!(solid.is_regular());
            for _ in 0..200 {
                let p = [0, 1].map(|a| {
                    let w = bx.1[a] - bx.0[a];
                    rng.range(bx.0[a] - 0.2 * w, bx.1[a] + 0.2 * w)
                });
                let want = expected(cells, degree, &points, bx, p);
                let got = solid.f(DVec2::from_array(p));
                assert!(
                    (got - want).abs() <= 1e-12 * want.abs().max(1.0),
                    "{got} {want}"
                );
            }
        }
        for _ in 0..10 {
            let cells = [rng.int(1, 3), rng.int(1, 3), rng.int(1, 3)];
            let degree = [rng.int(1, 3), rng.int(1, 3), rng.int(1, 3)];
            let bx = ([-1.0, 0.0, 0.5], [1.0, 2.0, 1.5]);
            let dims = core::array::from_fn(|a| cells[a] * degree[a] + 1);
            let points = regular_points(&mut rng, dims, bx);
            let solid = piecewise3(cells, degree, &points);
            for _ in 0..200 {
                let p = [0, 1, 2].map(|a| rng.range(bx.0[a] - 0.3, bx.1[a] + 0.3));
                let want = expected(cells, degree, &points, bx, p);
                let got = solid.f(DVec3::from_array(p));
                assert!(
                    (got - want).abs() <= 1e-12 * want.abs().max(1.0),
                    "{got} {want}"
                );
            }
        }
    }

    #[test]
    fn shared_faces_are_not_clipped_and_the_solid_is_continuous_across_them() {
        // ξ = 1 everywhere on two cells along u: positive on the shared edge, where a single
        // cell's clipping would give 0.
        let points = (0..3)
            .flat_map(|i| (0..2).map(move |j| vec![f64::from(i), f64::from(j), 1.0]))
            .collect::<Vec<_>>();
        let solid = piecewise2([2, 1], [1, 1], &points);
        let on_edge = solid.f(DVec2::new(1.0, 0.5));
        assert!(on_edge > 0.1, "{on_edge}");
        let alone = solid.part([0, 0]).unwrap().f(DVec2::new(1.0, 0.5));
        assert!(
            alone.abs() < 1e-12,
            "a cell alone is clipped at its edge: {alone}"
        );
        // Random cubic cells: values on both sides of every shared face agree to first order.
        let mut rng = Rng::new(11);
        let cells = [3, 2, 2];
        let degree = [3, 2, 3];
        let bx = ([0.0; 3], [3.0, 2.0, 2.0]);
        let dims = core::array::from_fn(|a| cells[a] * degree[a] + 1);
        let points = regular_points(&mut rng, dims, bx);
        let solid = piecewise3(cells, degree, &points);
        for _ in 0..300 {
            let axis = rng.int(0, 2);
            let mut p = [0, 1, 2].map(|a| rng.range(0.05, bx.1[a] - 0.05));
            p[axis] = rng.int(1, cells[axis] - 1) as f64;
            let h = 1e-9;
            let (mut lo, mut hi) = (p, p);
            lo[axis] -= h;
            hi[axis] += h;
            let (a, b) = (
                solid.f(DVec3::from_array(lo)),
                solid.f(DVec3::from_array(hi)),
            );
            assert!((a - b).abs() < 1e-6, "a jump of {} across a face", a - b);
        }
    }

    #[test]
    fn one_cell_is_the_single_solid_regular_or_moved() {
        let mut rng = Rng::new(3);
        for moved in [false, true] {
            let points: Vec<DVec3> = (0..4)
                .flat_map(|i| (0..3).map(move |j| (i, j)))
                .map(|(i, j)| {
                    let wobble = if moved { 0.15 } else { 0.0 };
                    DVec3::new(
                        f64::from(i) / 3.0 + wobble * rng.range(-1.0, 1.0),
                        f64::from(j) / 2.0 + wobble * rng.range(-1.0, 1.0),
                        rng.range(-1.0, 1.0),
                    )
                })
                .collect();
            let piecewise = Piecewise::<2>::new([1, 1], [3, 2], points.clone()).unwrap();
            let single = Solid::try_from_net(Tensor::try_new([3, 2], points).unwrap()).unwrap();
            assert_eq!(piecewise.is_regular(), !moved);
            for _ in 0..200 {
                let p = DVec2::new(rng.range(-0.3, 1.3), rng.range(-0.3, 1.3));
                let (a, b) = (piecewise.f(p), single.f(p));
                assert!((a - b).abs() <= 1e-9 * a.abs().max(1.0), "{p}: {a} {b}");
            }
        }
    }

    #[test]
    fn a_cell_added_mirrors_the_last_across_their_face_and_removing_it_gives_the_solid_back() {
        let mut rng = Rng::new(19);
        // One cell and its mirror: the solid is symmetric about the face they share (the clipping
        // x(1 − x) of the global parameter is symmetric too), patches and volumes.
        for _ in 0..10 {
            let degree = [rng.int(1, 4), rng.int(1, 4)];
            let bx = ([rng.range(-2.0, 0.0), 0.0], [rng.range(0.5, 2.0), 1.0]);
            let points = regular_points(&mut rng, degree.map(|d| d + 1), bx);
            let one = piecewise2([1, 1], degree, &points);
            let axis = rng.int(0, 1);
            let two = one.with_cell_added(axis).unwrap();
            assert_eq!(two.cells()[axis], 2);
            assert!(two.is_regular(), "a regular grid goes on with its spacing");
            let (lo, hi) = two.domain();
            let width = bx.1[axis] - bx.0[axis];
            assert!((hi[axis] - (bx.1[axis] + width)).abs() < 1e-12);
            assert!((lo[axis] - bx.0[axis]).abs() < 1e-12);
            for _ in 0..100 {
                let p = DVec2::new(rng.range(lo.x, hi.x), rng.range(lo.y, hi.y));
                let mut q = p;
                q[axis] = 2.0 * bx.1[axis] - p[axis];
                let (a, b) = (two.f(p), two.f(q));
                assert!((a - b).abs() < 1e-12, "{p} {q}: {a} {b}");
            }
            assert_eq!(two.with_cell_removed(axis).unwrap(), one);
        }
        // Moved volumes of many cells: every new point is the mirror of one of the last cells
        // across the face, and removing the cell gives the net back.
        for _ in 0..10 {
            let cells = [rng.int(1, 3), rng.int(1, 3), rng.int(1, 3)];
            let degree = [rng.int(1, 3), rng.int(1, 3), rng.int(1, 3)];
            let dims: [usize; 3] = core::array::from_fn(|a| cells[a] * degree[a] + 1);
            let mut points = regular_points(&mut rng, dims, ([0.0; 3], [1.0; 3]));
            for p in &mut points {
                for x in &mut p[..3] {
                    *x += rng.range(-0.02, 0.02);
                }
            }
            let solid = piecewise3(cells, degree, &points);
            let axis = rng.int(0, 2);
            let grown = solid.with_cell_added(axis).unwrap();
            let new_dims = grown.dims();
            assert_eq!(new_dims[axis], dims[axis] + degree[axis]);
            let b = dims[axis] - 1;
            let at = |dims: [usize; 3], i: [usize; 3]| (i[0] * dims[1] + i[1]) * dims[2] + i[2];
            for k in 0..grown.points().len() {
                let i = multi_index(new_dims, k);
                let got = grown.points()[k];
                if i[axis] <= b {
                    assert_eq!(got, solid.points()[at(dims, i)]);
                    continue;
                }
                let (mut face, mut mirror) = (i, i);
                face[axis] = b;
                mirror[axis] = 2 * b - i[axis];
                let (f, m) = (
                    solid.points()[at(dims, face)],
                    solid.points()[at(dims, mirror)],
                );
                let want = (2.0 * f - m).truncate().extend(m.w);
                assert!((got - want).abs().max_element() < 1e-12, "{got} {want}");
            }
            assert_eq!(grown.with_cell_removed(axis).unwrap(), solid);
        }
    }

    #[test]
    fn cells_are_added_and_removed_within_the_caps() {
        let points = regular_points(&mut Rng::new(2), [2, 2], ([0.0; 2], [1.0; 2]));
        let mut solid = piecewise2([1, 1], [1, 1], &points);
        assert_eq!(
            solid.with_cell_removed(0),
            Err(PiecewiseError::Cells { axis: 0, got: 0 })
        );
        for _ in 1..MAX_CELLS {
            solid = solid.with_cell_added(1).unwrap();
        }
        assert_eq!(
            solid.with_cell_added(1),
            Err(PiecewiseError::Cells {
                axis: 1,
                got: MAX_CELLS + 1
            })
        );
        assert!(matches!(
            solid.with_cell_added(2),
            Err(PiecewiseError::Dimension { .. })
        ));
    }

    #[test]
    fn specs_spell_piecewise_solids_and_single_ones_as_one_cell() {
        use crate::model::SolidSpec;
        let mut rng = Rng::new(23);
        let points = regular_points(&mut rng, [4, 3, 3], ([0.0; 3], [1.0; 3]));
        let solid = piecewise3([3, 1, 2], [1, 2, 1], &points);
        let spec = SolidSpec::from_piecewise(&solid);
        assert_eq!(spec.to_piecewise::<3>().unwrap().unwrap(), solid);
        assert!(spec.to_piecewise::<2>().is_none());
        let patch = crate::Solid2::fig9();
        let spec = crate::model::ModelFile::from_solid2(&patch).solid;
        let one = spec.to_piecewise::<2>().unwrap().unwrap();
        assert_eq!(one, Piecewise::from_solid(&patch).unwrap());
        for _ in 0..100 {
            let p = DVec2::new(rng.range(-0.2, 1.2), rng.range(-0.2, 1.2));
            assert!((one.f(p) - patch.f(p)).abs() < 1e-12);
        }
    }

    #[test]
    fn moved_points_give_the_largest_value_over_the_preimages_in_all_cells() {
        let mut rng = Rng::new(5);
        let cells = [2, 2];
        let degree = [2, 2];
        let dims = [5, 5];
        let mut points = regular_points(&mut rng, dims, ([0.0, 0.0], [2.0, 2.0]));
        // Move every point a little: each cell's map stays injective.
        for p in &mut points {
            p[0] += rng.range(-0.08, 0.08);
            p[1] += rng.range(-0.08, 0.08);
        }
        let solid = piecewise2(cells, degree, &points);
        assert!(!solid.is_regular());
        for _ in 0..300 {
            let cell = [rng.int(0, 1), rng.int(0, 1)];
            let u = [rng.range(0.02, 0.98), rng.range(0.02, 0.98)];
            let s = cell_sum(dims, degree, &points, cell, u);
            let t = [0, 1].map(|a| (cell[a] as f64 + u[a]) / 2.0);
            let want = and(s[2], and(t[0] * (1.0 - t[0]), t[1] * (1.0 - t[1])));
            let v = solid.evaluate(DVec2::new(s[0], s[1]), Method::Clipping);
            assert!((v.f - want).abs() < 1e-9, "{} {want}", v.f);
            assert!(v.preimages >= 1);
        }
        // Far outside: negative, no preimage.
        let v = solid.evaluate(DVec2::new(5.0, -3.0), Method::Fast);
        assert!(v.f < 0.0 && v.preimages == 0);
    }

    #[test]
    fn where_cells_overlap_the_larger_value_wins() {
        // Two bilinear cells along u; the shared column pushed past the far end folds the first
        // cell over the second.
        let column = |x: f64, xi: f64| [vec![x, 0.0, xi], vec![x, 1.0, xi]];
        let points: Vec<Vec<f64>> = [column(0.0, 1.0), column(3.0, 0.2), column(2.0, -0.5)]
            .into_iter()
            .flatten()
            .collect();
        let solid = piecewise2([2, 1], [1, 1], &points);
        // x = 2.5, y = 0.5: in the first cell at u = 5/6, in the second at u = 1/2.
        let p = DVec2::new(2.5, 0.5);
        let v = solid.evaluate(p, Method::Clipping);
        assert_eq!(v.preimages, 2);
        let first = and(
            1.0 + (0.2 - 1.0) * 5.0 / 6.0,
            and(5.0 / 12.0 * 7.0 / 12.0, 0.25),
        );
        let second = and(0.2 + (-0.5 - 0.2) * 0.5, and(0.75 * 0.25, 0.25));
        assert!(
            (v.f - first.max(second)).abs() < 1e-9,
            "{} {first} {second}",
            v.f
        );
        assert!((solid.f(p) - v.f).abs() < 1e-9);
    }

    #[test]
    fn bad_nets_are_refused_with_what_is_wrong() {
        let p = |n: usize| vec![DVec3::ZERO; n];
        let e = |r: Result<Piecewise2, PiecewiseError>| r.unwrap_err();
        assert_eq!(
            e(Piecewise::new([2, 1], [1, 1], p(4))),
            PiecewiseError::Count { got: 4, want: 6 }
        );
        assert_eq!(
            e(Piecewise::new([0, 1], [1, 1], p(2))),
            PiecewiseError::Cells { axis: 0, got: 0 }
        );
        assert_eq!(
            e(Piecewise::new([1, 17], [1, 1], p(36))),
            PiecewiseError::Cells { axis: 1, got: 17 }
        );
        assert_eq!(
            e(Piecewise::new([1, 1], [1, 0], p(2))),
            PiecewiseError::Degree { axis: 1, got: 0 }
        );
        assert_eq!(
            Piecewise::<3>::new([8, 8, 8], [1, 1, 1], vec![DVec4::ZERO; 729]).unwrap_err(),
            PiecewiseError::CellCount { got: 512 }
        );
        let mut nan = p(4);
        nan[2].z = f64::NAN;
        assert_eq!(
            e(Piecewise::new([1, 1], [1, 1], nan)),
            PiecewiseError::Solid(SolidError::NonFinite)
        );
        assert!(
            e(Piecewise::new([1, 1], [1, 1], p(3)))
                .to_string()
                .contains("take 4")
        );
    }
}
#[cfg(test)]
mod gradient_tests {
    use super::*;
    use crate::testutil::Rng;
    use glam::DVec3;

    #[test]
    fn gradients_match_finite_differences() {
        let mut rng = Rng::new(2);
        for moved in [false, true] {
            let spec = crate::testutil::random_piecewise3(&mut rng, moved);
            let crate::model::SolidSpec::Piecewise {
                cells,
                degree,
                points,
            } = spec
            else {
                unreachable!()
            };
            let pts = points
                .iter()
                .map(|p| glam::DVec4::new(p[0], p[1], p[2], p[3]))
                .collect();
            let s = Piecewise::<3>::new(
                [cells[0], cells[1], cells[2]],
                [degree[0], degree[1], degree[2]],
                pts,
            )
            .unwrap();
            let (lo, hi) = s.domain();
            for _ in 0..200 {
                let p = DVec3::new(
                    rng.range(lo.x, hi.x),
                    rng.range(lo.y, hi.y),
                    rng.range(lo.z, hi.z),
                );
                let (_, g) = s.f_with_gradient(p);
                let h = 1e-6;
                let fd = DVec3::new(
                    s.f(p + DVec3::X * h) - s.f(p - DVec3::X * h),
                    s.f(p + DVec3::Y * h) - s.f(p - DVec3::Y * h),
                    s.f(p + DVec3::Z * h) - s.f(p - DVec3::Z * h),
                ) / (2.0 * h);
                assert!(
                    (g - fd).length() < 1e-4 * fd.length().max(1.0),
                    "{moved} {p}: {g} against {fd}"
                );
            }
        }
    }
}
