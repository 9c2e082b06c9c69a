//! Simplicial complexes: what `interval`, `QUOTE` and products make and `MAP` maps.

use std::fmt;

use crate::meter::{Charge, buffer_bytes, rc_bytes};

/// A simplicial complex: points of one dimension and cells of one order (1 vertex for points, 2
/// for segments, 3 for triangles, 4 for tetrahedra), both flat.
///
/// Its bytes (as made by [`Complex::new`], or cloned) count against the memory budget of a run
/// until it is dropped.
#[derive(Debug)]
pub struct Complex {
    /// Coordinates per point.
    pub dim: usize,
    /// `dim` coordinates per point.
    pub points: Vec<f64>,
    /// Vertices per cell: the cells' dimension plus one.
    pub order: usize,
    /// `order` point indices per cell.
    pub cells: Vec<u32>,
    /// Its bytes, as counted when it was made.
    _held: Charge,
}

impl PartialEq for Complex {
    fn eq(&self, other: &Complex) -> bool {
        (self.dim, self.order) == (other.dim, other.order)
            && self.points == other.points
            && self.cells == other.cells
    }
}

impl Clone for Complex {
    fn clone(&self) -> Complex {
        Complex::new(
            self.dim,
            self.points.clone(),
            self.order,
            self.cells.clone(),
        )
    }
}

/// Why a complex cannot be made.
#[derive(Clone, Debug, PartialEq)]
pub enum ComplexError {
    /// More cells (or points) than the limit.
    TooMany {
        /// How many the operation would make.
        count: u128,
        /// The limit.
        limit: usize,
    },
    /// A product past four vertices per cell (past tetrahedra), or of points of too many
    /// coordinates.
    Dimension(usize),
}

impl fmt::Display for ComplexError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ComplexError::TooMany { count, limit } => {
                write!(f, "{count} cells, past the limit of {limit}")
            }
            ComplexError::Dimension(d) => write!(
                f,
                "a product of dimension {d}: cells of at most 3 dimensions (tetrahedra) are \
                 supported"
            ),
        }
    }
}

impl Complex {
    /// A complex of `points` (`dim` coordinates each) and `cells` (`order` point indices each).
    pub fn new(dim: usize, points: Vec<f64>, order: usize, cells: Vec<u32>) -> Complex {
        let held = Charge::new(Complex::bytes(points.capacity(), cells.capacity()));
        Complex {
            dim,
            points,
            order,
            cells,
            _held: held,
        }
    }

    /// Bytes of a complex of `coordinates` numbers and `indices` point indices: its `Rc`, its
    /// coordinates and its cells.
    pub(crate) const fn bytes(coordinates: usize, indices: usize) -> usize {
        rc_bytes::<Complex>()
            .saturating_add(buffer_bytes::<f64>(coordinates))
            .saturating_add(buffer_bytes::<u32>(indices))
    }

    /// Points.
    pub fn point_count(&self) -> usize {
        self.points.len().checked_div(self.dim).unwrap_or(0)
    }

    /// Cells.
    pub fn cell_count(&self) -> usize {
        self.cells.len().checked_div(self.order).unwrap_or(0)
    }

    /// Point `i`'s coordinates.
    pub fn point(&self, i: usize) -> &[f64] {
        &self.points[i * self.dim..(i + 1) * self.dim]
    }

    /// Cell `i`'s point indices.
    pub fn cell(&self, i: usize) -> &[u32] {
        &self.cells[i * self.order..(i + 1) * self.order]
    }

    /// The one-dimensional complex of `QUOTE`: a segment for each positive length and a gap for
    /// each negative one, from 0.
    pub fn quote(lengths: &[f64]) -> Complex {
        let mut points = Vec::new();
        let mut cells = Vec::new();
        let mut pos = 0.0;
        let mut last: Option<(f64, u32)> = None;
        for &d in lengths {
            if d > 0.0 {
                let a = match last {
                    Some((x, i)) if x == pos => i,
                    _ => {
                        points.push(pos);
                        (points.len() - 1) as u32
                    }
                };
                points.push(pos + d);
                let b = (points.len() - 1) as u32;
                cells.extend([a, b]);
                last = Some((pos + d, b));
            }
            pos += d.abs();
        }
        Complex::new(1, points, 2, cells)
    }

    /// `[a, b]` in `n` equal segments.
    pub fn interval(a: f64, b: f64, n: usize) -> Complex {
        let points = (0..=n)
            .map(|k| {
                if k == n {
                    b
                } else {
                    a + (b - a) * k as f64 / n as f64
                }
            })
            .collect();
        Complex::new(
            1,
            points,
            2,
            (0..n as u32).flat_map(|k| [k, k + 1]).collect(),
        )
    }

    /// The cells a product would have, without making it.
    pub fn product_count(&self, other: &Complex) -> u128 {
        let (k, l) = (self.order - 1, other.order - 1);
        self.cell_count() as u128 * other.cell_count() as u128 * binomial(k + l, k)
    }

    /// Whether [`Complex::product`] would make the product, without making it.
    ///
    /// # Errors
    ///
    /// As [`Complex::product`].
    pub(crate) fn product_fits(&self, other: &Complex, limit: usize) -> Result<(), ComplexError> {
        let (k, l) = (self.order - 1, other.order - 1);
        if k + l > 3 {
            return Err(ComplexError::Dimension(k + l));
        }
        let count = self.product_count(other);
        let points = self.point_count() as u128 * other.point_count() as u128;
        // Coordinates, too: a product of points of many coordinates is as large as many cells.
        let coordinates = points * (self.dim + other.dim) as u128 / 16;
        let most = count.max(points).max(coordinates);
        if most > limit as u128 {
            return Err(ComplexError::TooMany { count: most, limit });
        }
        Ok(())
    }

    /// The bytes that making the product takes at most: the product's, and a copy of the cells of
    /// both.
    pub(crate) fn product_bytes(&self, other: &Complex) -> u128 {
        let (k, l) = (self.order - 1, other.order - 1);
        let points = self.point_count() as u128 * other.point_count() as u128;
        let coordinates = points * (self.dim + other.dim) as u128;
        let indices = self.product_count(other) * (k + l + 1) as u128;
        let copies = (self.cells.len() + other.cells.len()) as u128;
        Complex::bytes(0, 0) as u128 + coordinates * 8 + (indices + copies) * 4
    }

    /// The product of two complexes (`A * B`): points are pairs (coordinates concatenated), and
    /// each product of a `k`-cell and an `l`-cell is split into the `C(k+l, k)` simplices of the
    /// staircase triangulation, which agree on shared faces. Cells of full dimension are turned
    /// to positive orientation (counter-clockwise triangles in the plane).
    ///
    /// # Errors
    ///
    /// [`ComplexError::TooMany`] past `limit` cells or points, [`ComplexError::Dimension`] past
    /// tetrahedra.
    pub fn product(&self, other: &Complex, limit: usize) -> Result<Complex, ComplexError> {
        self.product_fits(other, limit)?;
        let (k, l) = (self.order - 1, other.order - 1);
        let count = self.product_count(other);
        let dim = self.dim + other.dim;
        let points = self.point_count() as u128 * other.point_count() as u128;
        let m = other.point_count();
        let mut pts = Vec::with_capacity(points as usize * dim);
        for i in 0..self.point_count() {
            for j in 0..m {
                pts.extend_from_slice(self.point(i));
                pts.extend_from_slice(other.point(j));
            }
        }
        // Each monotone lattice path from (0, 0) to (k, l) is one simplex.
        let mut paths = Vec::new();
        staircase(k, l, &mut Vec::new(), &mut paths);
        let order = k + l + 1;
        let mut cells = Vec::with_capacity(count as usize * order);
        let sorted = |c: &Complex| -> Vec<u32> {
            let mut cells = c.cells.clone();
            for cell in cells.chunks_mut(c.order) {
                cell.sort_unstable();
            }
            cells
        };
        let (cells_a, cells_b) = (sorted(self), sorted(other));
        for ca in cells_a.chunks(self.order) {
            for cb in cells_b.chunks(other.order) {
                for path in &paths {
                    for &(i, j) in path {
                        cells.push(ca[i] * m as u32 + cb[j]);
                    }
                }
            }
        }
        let mut out = Complex::new(dim, pts, order, cells);
        out.orient();
        Ok(out)
    }

    /// Turns cells of full dimension to positive orientation.
    fn orient(&mut self) {
        if self.order != self.dim + 1 || !(3..=4).contains(&self.order) {
            return;
        }
        let dim = self.dim;
        for c in 0..self.cell_count() {
            let cell = self.cell(c);
            let at = |a: usize, d: usize| self.points[cell[a] as usize * dim + d];
            let e = |a: usize, d: usize| at(a, d) - at(0, d);
            let det = if self.order == 3 {
                e(1, 0) * e(2, 1) - e(1, 1) * e(2, 0)
            } else {
                e(1, 0) * (e(2, 1) * e(3, 2) - e(2, 2) * e(3, 1))
                    - e(1, 1) * (e(2, 0) * e(3, 2) - e(2, 2) * e(3, 0))
                    + e(1, 2) * (e(2, 0) * e(3, 1) - e(2, 1) * e(3, 0))
            };
            if det < 0.0 {
                let o = self.order;
                self.cells.swap(c * o + 1, c * o + 2);
            }
        }
    }
}

fn staircase(
    k: usize,
    l: usize,
    path: &mut Vec<(usize, usize)>,
    out: &mut Vec<Vec<(usize, usize)>>,
) {
    let (i, j) = path.last().copied().unwrap_or((0, 0));
    if path.is_empty() {
        path.push((0, 0));
    }
    if i == k && j == l {
        out.push(path.clone());
    } else {
        if i < k {
            path.push((i + 1, j));
            staircase(k, l, path, out);
            path.pop();
        }
        if j < l {
            path.push((i, j + 1));
            staircase(k, l, path, out);
            path.pop();
        }
    }
}

fn binomial(n: usize, k: usize) -> u128 {
    (0..k).fold(1u128, |acc, i| acc * (n - i) as u128 / (i + 1) as u128)
}
