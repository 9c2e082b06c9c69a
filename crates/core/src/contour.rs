//! Marching squares: the zero contour of a sampled field as polylines with the solid (`f > 0`) on
//! their left, so closed loops around material run counter-clockwise and holes clockwise.
//!
//! The segment rule is derived, not tabulated: walk a cell's edges counter-clockwise; an edge that goes
//! from inside to outside starts a segment and one that goes from outside to inside ends one. A cell
//! has zero, one or two of each. With two (a saddle), the function at the cell centre decides: inside,
//! the material connects through the middle and each start pairs with the next end counter-clockwise;
//! outside, with the previous one. Because neighbouring cells walk their shared edge in opposite
//! directions, an edge that ends a segment in one cell starts one in the next, and segments chain into
//! polylines by edge id alone.

use alloc::vec;
use alloc::vec::Vec;

use glam::{DVec2, DVec3};

use crate::inverse::Forward;
use crate::math::illinois;
use crate::{Axis, Solid2, Solid3};

/// A regular grid of `nx × ny` samples over the box `[min, max]` (corners included).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Grid2 {
    min: DVec2,
    max: DVec2,
    nx: usize,
    ny: usize,
}

impl Grid2 {
    /// A grid of `nx × ny` samples over `[min, max]`; counts below 2 are raised to 2.
    #[must_use]
    pub fn new(min: DVec2, max: DVec2, nx: usize, ny: usize) -> Self {
        Self {
            min,
            max,
            nx: nx.max(2),
            ny: ny.max(2),
        }
    }

    /// Samples along x (at least 2).
    #[must_use]
    pub fn nx(&self) -> usize {
        self.nx
    }

    /// Samples along y (at least 2).
    #[must_use]
    pub fn ny(&self) -> usize {
        self.ny
    }

    /// The x coordinates of the sample columns.
    #[must_use]
    pub fn xs(&self) -> Vec<f64> {
        lin(self.min.x, self.max.x, self.nx)
    }

    /// The y coordinates of the sample rows.
    #[must_use]
    pub fn ys(&self) -> Vec<f64> {
        lin(self.min.y, self.max.y, self.ny)
    }

    /// The position of sample `(i, j)`.
    #[must_use]
    pub fn point(&self, i: usize, j: usize) -> DVec2 {
        let t = DVec2::new(
            i as f64 / (self.nx - 1) as f64,
            j as f64 / (self.ny - 1) as f64,
        );
        self.min + (self.max - self.min) * t
    }
}

fn lin(a: f64, b: f64, n: usize) -> Vec<f64> {
    (0..n)
        .map(|i| a + (b - a) * (i as f64 / (n - 1) as f64))
        .collect()
}

/// One piece of the zero contour.
#[derive(Clone, Debug, PartialEq)]
pub struct Polyline {
    /// The vertices, in order, with `f > 0` on the left. A closed loop does not repeat its first
    /// vertex at the end.
    pub points: Vec<DVec2>,
    /// Whether the last vertex connects back to the first. Open polylines end on the grid's border.
    pub closed: bool,
}

impl Polyline {
    /// The signed area (shoelace) of the closed polygon through the points: positive for a
    /// counter-clockwise loop, that is, for a loop around material.
    #[must_use]
    pub fn signed_area(&self) -> f64 {
        let n = self.points.len();
        (0..n)
            .map(|k| self.points[k].perp_dot(self.points[(k + 1) % n]))
            .sum::<f64>()
            * 0.5
    }

    /// The length of the polyline, with the closing segment of a closed one.
    #[must_use]
    pub fn length(&self) -> f64 {
        let open: f64 = self.points.windows(2).map(|w| w[0].distance(w[1])).sum();
        match (self.closed, self.points.first(), self.points.last()) {
            (true, Some(a), Some(b)) => open + a.distance(*b),
            _ => open,
        }
    }
}

/// The area and perimeter of a region bounded by zero contours (a 2D solid's), exact for the
/// polylines (the shoelace sum, the divergence theorem in the plane), so as near the solid as
/// their resolution: holes, walked clockwise, count negative. Open pieces (ended on a grid's
/// border) bound nothing: they are left out, and counted.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Measure {
    /// The area inside.
    pub area: f64,
    /// The total length of the closed loops.
    pub perimeter: f64,
    /// How many open pieces were left out.
    pub open: usize,
}

impl Measure {
    /// The measurements of the region `lines` bound.
    #[must_use]
    pub fn of(lines: &[Polyline]) -> Self {
        lines.iter().fold(Self::default(), |m, line| {
            if line.closed {
                Self {
                    area: m.area + line.signed_area(),
                    perimeter: m.perimeter + line.length(),
                    open: m.open,
                }
            } else {
                Self {
                    open: m.open + 1,
                    ..m
                }
            }
        })
    }
}

/// The zero contour of a patch solid, `resolution` cells per side of its domain with one cell of
/// margin, vertices refined to `|f| ≤ accuracy`: [`forward_contour`] where the solid is a space
/// mapping certified injective, [`sampled_contour`] otherwise (regular grids, folds).
#[must_use]
pub fn solid_contour(solid: &Solid2, resolution: usize, accuracy: f64) -> Vec<Polyline> {
    forward_contour(solid, resolution, accuracy)
        .unwrap_or_else(|| sampled_contour(solid, resolution, accuracy))
}

/// The zero contour of `S_ξ` alone, unclipped, over the patch's parameter square grown by
/// `margin` on every side (the polynomials extend past it; `resolution` cells per side), mapped
/// forward through `(S_x, S_y)`: the curve that functional clipping cuts (the first paper's Figs.
/// 3 and 5, left). Pieces that leave the grown square end on its border (open polylines);
/// vertices are refined to `|S_ξ| ≤ accuracy`. Where the net folds, the curve of every sheet.
#[must_use]
pub fn unclipped_contour(
    solid: &Solid2,
    resolution: usize,
    margin: f64,
    accuracy: f64,
) -> Vec<Polyline> {
    let n = resolution.max(1);
    let m = unclipped_margin(margin);
    let grid = Grid2::new(DVec2::splat(-m), DVec2::splat(1.0 + m), n + 1, n + 1);
    let xi = solid.xi_net();
    let values = xi.eval_grid([&grid.xs(), &grid.ys()]);
    let net = solid.net();
    mapped_forward(
        contour(&grid, &values, |p| xi.eval([p.x, p.y]), accuracy),
        |p| net.eval([p.x, p.y]).truncate(),
    )
}

/// [`unclipped_contour`] of a piecewise patch: the zero contour of `S_ξ` over the global
/// parameter square grown by `margin` (each cell's polynomial over its share of it, the outer
/// cells' extended past it), `resolution` cells per side of each cell, mapped forward through the
/// cells' `(S_x, S_y)`.
#[must_use]
pub fn unclipped_piecewise_contour(
    solid: &crate::piecewise::Piecewise2,
    resolution: usize,
    margin: f64,
    accuracy: f64,
) -> Vec<Polyline> {
    let cells = solid.cells();
    let m = unclipped_margin(margin);
    let n = cells.map(|c| resolution.max(1) * c);
    let grid = Grid2::new(DVec2::splat(-m), DVec2::splat(1.0 + m), n[0] + 1, n[1] + 1);
    let xi = |p: DVec2| solid.eval([p.x, p.y]).z;
    mapped_forward(contour_grid(&grid, xi, accuracy), |p| {
        solid.point([p.x, p.y])
    })
}

/// How often [`forward_piecewise_contour`] checks a vertex against `f`: a sheet's zero line
/// hidden under another is a run of vertices, found when it is this long or longer.
pub const PIECEWISE_CHECK_STRIDE: usize = 8;

/// The zero contour of a moved piecewise patch, traced in its global parameter square (the clipped
/// `S_ξ & F_s(t)`, `resolution` cells per side of each cell, one cell of margin where it is
/// negative) and mapped forward through the cells' `(S_x, S_y)`, vertices refined to
/// `|f| ≤ accuracy` in parameter space. The lines are then checked against `f` itself, the max
/// over the preimages in all cells, at their ends and every [`PIECEWISE_CHECK_STRIDE`]th vertex:
/// `None` when one is off by more than `10·accuracy` (a fold or cells overlapping, where a
/// sheet's zero line lies under another), so that the caller samples `f` instead. Cheap
/// otherwise: a few inverse queries per line.
#[must_use]
pub fn forward_piecewise_contour(
    solid: &crate::piecewise::Piecewise2,
    resolution: usize,
    accuracy: f64,
) -> Option<Vec<Polyline>> {
    let n = solid.cells().map(|c| resolution.max(1) * c);
    let margin = DVec2::new(1.0 / n[0] as f64, 1.0 / n[1] as f64);
    let grid = Grid2::new(-margin, DVec2::ONE + margin, n[0] + 3, n[1] + 3);
    let clipped = |p: DVec2| crate::rfunc::clip(solid.eval([p.x, p.y]).z, [p.x, p.y]);
    let mut lines = contour_grid(&grid, clipped, accuracy);
    let tolerance = 10.0 * accuracy;
    for line in &mut lines {
        let last = line.points.len().saturating_sub(1);
        for (k, p) in line.points.iter_mut().enumerate() {
            *p = solid.point([p.x, p.y]);
            let checked = k % PIECEWISE_CHECK_STRIDE == 0 || k == last;
            // NaN fails the check too.
            let on_f = || solid.f(*p).abs() <= tolerance;
            if checked && !on_f() {
                return None;
            }
        }
    }
    // An orientation-reversing map puts the solid on the right: walk every line backwards.
    let at = |t: [f64; 2]| solid.point(t);
    let (du, dv) = (
        at([0.51, 0.5]) - at([0.49, 0.5]),
        at([0.5, 0.51]) - at([0.5, 0.49]),
    );
    if du.perp_dot(dv) < 0.0 {
        for line in &mut lines {
            line.points.reverse();
        }
    }
    Some(lines)
}

/// The margin an unclipped contour grows the parameter square by: `margin` within `[0, 1]`, 0
/// for a value that is not finite.
fn unclipped_margin(margin: f64) -> f64 {
    if margin.is_finite() {
        margin.clamp(0.0, 1.0)
    } else {
        0.0
    }
}

/// `lines` traced in a parameter square, each point moved by `map`.
fn mapped_forward(mut lines: Vec<Polyline>, map: impl Fn(DVec2) -> DVec2) -> Vec<Polyline> {
    for line in &mut lines {
        for p in &mut line.points {
            *p = map(*p);
        }
    }
    lines
}

/// The zero contour from samples of `f` itself over the solid's domain (for a space mapping, the
/// inverse map at every sample: the reference the forward path is tested against).
#[must_use]
pub fn sampled_contour(solid: &Solid2, resolution: usize, accuracy: f64) -> Vec<Polyline> {
    let grid = sample_grid(solid, resolution);
    let values = solid.f_grid([&grid.xs(), &grid.ys()]);
    contour(&grid, &values, |p: DVec2| solid.f(p), accuracy)
}

/// The grid [`sampled_contour`] samples `f` on: `resolution` cells per side of the solid's domain
/// (widened where a side is too thin for distinct samples) with one cell of margin all round, where
/// `f` is negative, so that every contour closes inside it.
#[must_use]
pub fn sample_grid(solid: &Solid2, resolution: usize) -> Grid2 {
    let (lo, hi) = solid.domain();
    let (lo, hi) = crate::math::sampling_box(lo.to_array(), hi.to_array());
    let (lo, hi) = (DVec2::from_array(lo), DVec2::from_array(hi));
    let resolution = resolution.max(1);
    let cell = (hi - lo) / resolution as f64;
    Grid2::new(lo - cell, hi + cell, resolution + 3, resolution + 3)
}

/// The zero contour of a space mapping certified injective, traced in parameter space (the solid of
/// the same `S_ξ` on the unit square, `resolution` cells per side) and mapped forward through
/// `(S_x, S_y)`: the image of the parameter-space contour is the contour. `None` for a regular grid
/// or a map that may fold.
#[must_use]
pub fn forward_contour(solid: &Solid2, resolution: usize, accuracy: f64) -> Option<Vec<Polyline>> {
    if !solid.inverse()?.injective() {
        return None;
    }
    Some(sheet_contour(solid, resolution, accuracy))
}

/// The parameter-space zero contour mapped forward through `(S_x, S_y)`, whatever the map: for a
/// map certified injective (and for a regular grid) it is the contour ([`forward_contour`]); where
/// the net folds it also holds the zero lines of sheets that lie under others (where `f`, the max
/// over preimages, is decided by another sheet). Cheap (no inverse map), so a live preview of a
/// folded net can draw it.
#[must_use]
pub fn sheet_contour(solid: &Solid2, resolution: usize, accuracy: f64) -> Vec<Polyline> {
    let mut lines = sampled_contour(&solid.in_parameter_space(), resolution, accuracy);
    let net = solid.net();
    for line in &mut lines {
        for p in &mut line.points {
            *p = DVec2::from_array(net.forward(p.to_array()).x);
        }
    }
    // An orientation-reversing map puts the solid on the right: walk every line backwards.
    let e = net.forward([0.5; 2]);
    if e.jac[0][0] * e.jac[1][1] - e.jac[0][1] * e.jac[1][0] < 0.0 {
        for line in &mut lines {
            line.points.reverse();
        }
    }
    lines
}

/// The zero contour of `f` sampled on `grid`; see [`contour`].
pub fn contour_grid(grid: &Grid2, mut f: impl FnMut(DVec2) -> f64, accuracy: f64) -> Vec<Polyline> {
    let mut values = Vec::with_capacity(grid.nx * grid.ny);
    for j in 0..grid.ny {
        for i in 0..grid.nx {
            values.push(f(grid.point(i, j)));
        }
    }
    contour(grid, &values, f, accuracy)
}

/// The zero contour of `f` from its samples `values` on `grid` (row-major: `values[j·nx + i]` at
/// [`Grid2::point`]`(i, j)`).
///
/// `f` itself is called at the centres of saddle cells and to refine every vertex on its cell edge
/// until `|f| ≤ accuracy` (Illinois regula falsi, at most 100 steps: a function that is not continuous
/// along the edge gets the best point found).
///
/// # Panics
///
/// If `values.len() != grid.nx · grid.ny`.
pub fn contour(
    grid: &Grid2,
    values: &[f64],
    mut f: impl FnMut(DVec2) -> f64,
    accuracy: f64,
) -> Vec<Polyline> {
    let (nx, ny) = (grid.nx, grid.ny);
    assert_eq!(values.len(), nx * ny, "one sample per grid point");
    let horizontal = (nx - 1) * ny;
    let edge_count = horizontal + nx * (ny - 1);
    let h = |i: usize, j: usize| j * (nx - 1) + i;
    let v = |i: usize, j: usize| horizontal + j * nx + i;
    let inside = |i: usize, j: usize| values[j * nx + i] > 0.0;

    const NONE: u32 = u32::MAX;
    let mut next = vec![NONE; edge_count];
    let mut has_pred = vec![false; edge_count];
    for j in 0..ny - 1 {
        for i in 0..nx - 1 {
            let corners = [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)];
            let ins = corners.map(|(a, b)| inside(a, b));
            if ins.iter().all(|&x| x) || ins.iter().all(|&x| !x) {
                continue;
            }
            let edges = [h(i, j), v(i + 1, j), h(i, j + 1), v(i, j)];
            let mut starts = [0usize; 2];
            let mut ends = [0usize; 2];
            let (mut ns, mut ne) = (0, 0);
            for k in 0..4 {
                match (ins[k], ins[(k + 1) % 4]) {
                    (true, false) => {
                        starts[ns] = k;
                        ns += 1;
                    }
                    (false, true) => {
                        ends[ne] = k;
                        ne += 1;
                    }
                    _ => {}
                }
            }
            let mut link = |s: usize, e: usize| {
                next[edges[s]] = edges[e] as u32;
                has_pred[edges[e]] = true;
            };
            if ns == 1 {
                link(starts[0], ends[0]);
            } else {
                let centre = (grid.point(i, j) + grid.point(i + 1, j + 1)) * 0.5;
                let step = if f(centre) > 0.0 { 1 } else { 3 };
                for &s in &starts[..2] {
                    let mut k = (s + step) % 4;
                    while !ends[..2].contains(&k) {
                        k = (k + step) % 4;
                    }
                    link(s, k);
                }
            }
        }
    }

    // The endpoints of an edge id, for vertex refinement.
    let ends_of = |e: usize| -> (DVec2, DVec2, f64, f64) {
        let ((i0, j0), (i1, j1)) = if e < horizontal {
            let (i, j) = (e % (nx - 1), e / (nx - 1));
            ((i, j), (i + 1, j))
        } else {
            let k = e - horizontal;
            let (i, j) = (k % nx, k / nx);
            ((i, j), (i, j + 1))
        };
        (
            grid.point(i0, j0),
            grid.point(i1, j1),
            values[j0 * nx + i0],
            values[j1 * nx + i1],
        )
    };
    let mut vertex = |e: usize| {
        let (a, b, fa, fb) = ends_of(e);
        refine(&mut f, a, b, fa, fb, accuracy)
    };

    let mut visited = vec![false; edge_count];
    let mut lines = Vec::new();
    // Open chains first (they start on the border, where no cell leads in), then the loops.
    for pass_open in [true, false] {
        for start in 0..edge_count {
            if next[start] == NONE || visited[start] || (pass_open && has_pred[start]) {
                continue;
            }
            let mut points = Vec::new();
            let mut e = start;
            let closed = loop {
                visited[e] = true;
                points.push(vertex(e));
                let n = next[e];
                if n == NONE {
                    break false;
                }
                e = n as usize;
                if e == start {
                    break true;
                }
                if visited[e] {
                    // Cannot happen for a consistent chain; end the piece rather than loop.
                    break false;
                }
            };
            lines.push(Polyline { points, closed });
        }
    }
    lines
}

/// A zero of `f` on the segment `[a, b]` where `fa`, `fb` have opposite signs.
fn refine(
    f: &mut impl FnMut(DVec2) -> f64,
    a: DVec2,
    b: DVec2,
    fa: f64,
    fb: f64,
    accuracy: f64,
) -> DVec2 {
    a.lerp(b, illinois(|t| f(a.lerp(b, t)), fa, fb, accuracy))
}

/// The zero contours of a [`Solid3`] on the plane where the coordinate `axis` is `at` (the paper's
/// Fig. 11 stack is several of these): polylines in the plane's coordinates, the other two axes in
/// increasing order (`(y, z)` for [`Axis::U`], `(x, z)` for [`Axis::V`], `(x, y)` for [`Axis::W`]),
/// solid on the left, from a grid of `resolution` cells along the longer side of the section with a
/// cell of margin, vertices refined to `|f| ≤ accuracy`.
///
/// Returns no lines for a resolution below 2 or a bad accuracy, and for a plane that misses the box.
#[must_use]
pub fn cross_section(
    solid: &Solid3,
    axis: Axis,
    at: f64,
    resolution: usize,
    accuracy: f64,
) -> Vec<Polyline> {
    let a = axis.index();
    let (b, d) = crate::tensor::other_axes(a);
    let (min, max) = solid.domain();
    let in_box = (min[a]..=max[a]).contains(&at);
    let (min, max) = crate::math::sampling_box(min.to_array(), max.to_array());
    let (min, max) = (DVec3::from_array(min), DVec3::from_array(max));
    if resolution < 2 || !accuracy.is_finite() || accuracy <= 0.0 || !in_box {
        return Vec::new();
    }
    let (lo, hi) = (DVec2::new(min[b], min[d]), DVec2::new(max[b], max[d]));
    let size = hi - lo;
    let cell = size.max_element() / resolution as f64;
    let cells = (size / cell).ceil().max(DVec2::ONE);
    let step = size / cells;
    let grid = Grid2::new(
        lo - step,
        hi + step,
        cells.x as usize + 3,
        cells.y as usize + 3,
    );
    let lift = |p: DVec2| {
        let mut q = DVec3::ZERO;
        q[a] = at;
        q[b] = p.x;
        q[d] = p.y;
        q
    };
    contour_grid(&grid, |p| solid.f(lift(p)), accuracy)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testutil::Rng;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    fn disc(c: DVec2, r: f64) -> impl Fn(DVec2) -> f64 {
        move |p| r * r - (p - c).length_squared()
    }

    /// `S_ξ = 0` unclipped: on the net's zero set, and running on to the domain's border where
    /// clipping closes the solid's contour inside it (a patch of ξ > 0 across one side).
    #[test]
    fn unclipped_contours_lie_on_s_xi_and_reach_the_border_the_clipping_cuts() {
        // ξ = 1 − 2v over [0, 2] × [0, 1] with a bump: S_ξ = 0 crosses the whole square.
        let solid = Solid2::regular([2, 2], DVec2::ZERO, DVec2::new(2.0, 1.0), |[i, j]| {
            1.0 - j as f64 + if (i, j) == (1, 1) { 0.3 } else { 0.0 }
        })
        .unwrap();
        let unclipped = unclipped_contour(&solid, 64, 0.25, 1e-12);
        assert_eq!(unclipped.len(), 1);
        let line = &unclipped[0];
        assert!(!line.closed, "the curve leaves the grown square");
        for p in &line.points {
            let t = [p.x / 2.0, p.y];
            let xi = solid.xi_net().eval(t);
            assert!(xi.abs() <= 1e-9, "S_ξ = {xi} at {p}");
        }
        // It runs on past the box, x ∈ [0, 2], to the grown square's sides x = −0.5 and 2.5.
        let ends = [line.points[0], line.points[line.points.len() - 1]];
        assert!(
            ends.iter()
                .all(|e| (e.x + 0.5).abs() < 1e-9 || (e.x - 2.5).abs() < 1e-9),
            "{ends:?}"
        );
        // The clipped solid's contour is one closed loop inside the box instead.
        let clipped = solid_contour(&solid, 64, 1e-12);
        assert!(clipped.iter().all(|l| l.closed));
        // A moved net: the curve is mapped forward through (S_x, S_y).
        let mut moved = solid.clone();
        moved.set_point([1, 1], DVec2::new(1.2, 0.6)).unwrap();
        for line in unclipped_contour(&moved, 64, 0.0, 1e-12) {
            for p in &line.points {
                let v = moved.evaluate(*p, crate::inverse::Method::Clipping);
                let xi = moved.xi_net().eval(v.u);
                assert!(xi.abs() <= 1e-7, "S_ξ = {xi} at {p}");
            }
        }
    }

    /// A piecewise patch's `S_ξ = 0` unclipped: one cell is the single patch's curve; two cells
    /// (the first mirrored) give a curve on each cell's polynomial, across their shared edge, on
    /// past the outer boundary only.
    #[test]
    fn unclipped_piecewise_contours_lie_on_each_cells_s_xi() {
        use crate::piecewise::Piecewise2;
        let solid = Solid2::regular([2, 2], DVec2::ZERO, DVec2::new(2.0, 1.0), |[i, j]| {
            1.0 - j as f64 + if (i, j) == (1, 1) { 0.3 } else { 0.0 }
        })
        .unwrap();
        let one = Piecewise2::from_solid(&solid).unwrap();
        let (a, b) = (
            unclipped_contour(&solid, 64, 0.25, 1e-12),
            unclipped_piecewise_contour(&one, 64, 0.25, 1e-12),
        );
        assert_eq!(a.len(), b.len());
        for (a, b) in a.iter().zip(&b) {
            assert_eq!(a.points.len(), b.points.len());
            for (p, q) in a.points.iter().zip(&b.points) {
                assert!((*p - *q).length() < 1e-9, "{p} {q}");
            }
        }
        let two = one.with_cell_added(0).unwrap();
        let lines = unclipped_piecewise_contour(&two, 64, 0.25, 1e-12);
        assert_eq!(lines.len(), 1, "one curve across the shared edge x = 2");
        let line = &lines[0];
        for p in &line.points {
            let t = [p.x / 4.0, p.y];
            let xi = two.eval(t).z;
            assert!(xi.abs() <= 1e-9, "S_ξ = {xi} at {p}");
        }
        let xs = line.points.iter().map(|p| p.x);
        let (lo, hi) = xs.fold((f64::MAX, f64::MIN), |(l, h), x| (l.min(x), h.max(x)));
        assert!(
            (lo + 1.0).abs() < 1e-9 && (hi - 5.0).abs() < 1e-9,
            "{lo} {hi}"
        );
    }

    /// A moved piecewise patch: the contour traced in the global parameters and mapped forward
    /// lies on `f` (the max over every cell's preimages) at every vertex, checked or not, and
    /// bounds the area the sampled contour of `f` does; where a cell folds over the other and
    /// hides the first one's zero line, the check refuses it.
    #[test]
    fn forward_piecewise_contours_lie_on_f_and_folds_are_refused() {
        use crate::piecewise::Piecewise2;
        let grid_point = |i: usize, j: usize, x: f64| {
            let (u, v) = (i as f64 / 4.0, j as f64 / 2.0);
            let xi = 0.25 - (u - 0.55).powi(2) - 0.8 * (v - 0.5).powi(2);
            DVec3::new(x, j as f64 / 2.0, xi)
        };
        let mut points: Vec<DVec3> = (0..5)
            .flat_map(|i| (0..3).map(move |j| (i, j)))
            .map(|(i, j)| grid_point(i, j, i as f64 / 2.0))
            .collect();
        // The middle point of the shared edge moved out in space.
        points[2 * 3 + 1] += DVec3::new(0.2, 0.15, 0.0);
        let solid = Piecewise2::new([2, 1], [2, 2], points.clone()).unwrap();
        assert!(!solid.is_regular());
        let lines = forward_piecewise_contour(&solid, 48, 1e-10).unwrap();
        assert_eq!(lines.len(), 1);
        assert!(lines[0].closed);
        for p in &lines[0].points {
            assert!(solid.f(*p).abs() < 1e-7, "f = {} at {p}", solid.f(*p));
        }
        let (lo, hi) = solid.domain();
        let box_grid = Grid2::new(lo - DVec2::splat(0.1), hi + DVec2::splat(0.1), 160, 90);
        let sampled = contour_grid(&box_grid, |p| solid.f(p), 1e-10);
        let area = |lines: &[Polyline]| lines.iter().map(Polyline::signed_area).sum::<f64>();
        let (a, b) = (area(&lines), area(&sampled));
        assert!(a > 0.0 && (a - b).abs() < 0.01 * b, "{a} {b}");
        // The second cell folded back over the first with S_ξ high: the first cell's zero line
        // lies under it.
        let folded: Vec<DVec3> = (0..5)
            .flat_map(|i| (0..3).map(move |j| (i, j)))
            .map(|(i, j)| {
                let x = if i <= 2 {
                    i as f64 / 2.0
                } else {
                    2.0 - i as f64 / 2.0
                };
                let xi = [-1.0, 1.0, 5.0, 5.0, 5.0][i];
                DVec3::new(x, j as f64 / 2.0, xi)
            })
            .collect();
        let solid = Piecewise2::new([2, 1], [2, 2], folded).unwrap();
        assert!(forward_piecewise_contour(&solid, 48, 1e-10).is_none());
    }

    /// A square with a square hole (walked clockwise) and an open piece: the area is the ring's,
    /// the perimeter both loops', the open piece left out and counted.
    #[test]
    fn contours_are_measured_by_the_shoelace_sum() {
        let square = |lo: f64, hi: f64| {
            vec![
                DVec2::new(lo, lo),
                DVec2::new(hi, lo),
                DVec2::new(hi, hi),
                DVec2::new(lo, hi),
            ]
        };
        let mut hole = square(1.0, 2.0);
        hole.reverse();
        let lines = [
            Polyline {
                points: square(0.0, 4.0),
                closed: true,
            },
            Polyline {
                points: hole,
                closed: true,
            },
            Polyline {
                points: vec![DVec2::ZERO, DVec2::new(0.0, 9.0)],
                closed: false,
            },
        ];
        let m = Measure::of(&lines);
        assert!((m.area - 15.0).abs() < 1e-12, "{}", m.area);
        assert!((m.perimeter - 20.0).abs() < 1e-12, "{}", m.perimeter);
        assert_eq!(m.open, 1);
        assert!((lines[2].length() - 9.0).abs() < 1e-12);
    }

    #[test]
    fn contour_circle_is_one_closed_ccw_loop_on_the_zero_set() {
        let mut rng = Rng::new(40);
        for _ in 0..20 {
            let c = DVec2::new(rng.range(0.3, 0.7), rng.range(0.3, 0.7));
            let r = rng.range(0.1, 0.25);
            let accuracy = 1e-10;
            let n = rng.int(8, 80);
            let f = disc(c, r);
            let lines = contour_grid(&Grid2::new(DVec2::ZERO, DVec2::ONE, n, n + 3), &f, accuracy);
            assert_eq!(lines.len(), 1, "one loop for a circle");
            let line = &lines[0];
            assert!(line.closed);
            assert!(line.points.len() >= 4);
            for p in &line.points {
                assert!(f(*p).abs() <= accuracy, "|f| = {} at {p}", f(*p).abs());
            }
            // Material on the left: counter-clockwise, with about the disc's area.
            let area = line.signed_area();
            let exact = core::f64::consts::PI * r * r;
            assert!(
                area > 0.0 && (area - exact).abs() < 0.2 * exact,
                "area {area} vs {exact}"
            );
        }
    }

    #[test]
    fn contour_hole_runs_clockwise() {
        let ring = |p: DVec2| {
            let d = (p - DVec2::splat(0.5)).length();
            (0.4 - d).min(d - 0.2)
        };
        let lines = contour_grid(&Grid2::new(DVec2::ZERO, DVec2::ONE, 50, 50), ring, 1e-12);
        assert_eq!(lines.len(), 2);
        let mut areas: Vec<f64> = lines.iter().map(Polyline::signed_area).collect();
        areas.sort_by(f64::total_cmp);
        assert!(areas[0] < 0.0 && areas[1] > 0.0, "{areas:?}");
        assert!(lines.iter().all(|l| l.closed));
    }

    #[test]
    fn contour_open_where_it_meets_the_border() {
        // A half-plane x < 0.4 cuts the box from bottom to top.
        let lines = contour_grid(
            &Grid2::new(DVec2::ZERO, DVec2::ONE, 11, 7),
            |p| 0.4 - p.x,
            1e-12,
        );
        assert_eq!(lines.len(), 1);
        let line = &lines[0];
        assert!(!line.closed);
        // Material (x < 0.4) on the left means walking upwards.
        assert!(line.points[0].y < line.points[line.points.len() - 1].y);
        assert!(line.points.iter().all(|p| (p.x - 0.4).abs() < 1e-12));
    }

    #[test]
    fn contour_saddle_follows_the_cell_centre() {
        // Samples of a saddle on a single cell: inside at (0,0) and (1,1). The bilinear interpolant
        // (1 − 2x)(1 − 2y) is 0 at the centre; lifted by 0.1 the material joins through the middle,
        // lowered by 0.1 it splits. Each case has its own exact pair of segments.
        let grid = Grid2::new(DVec2::ZERO, DVec2::ONE, 2, 2);
        let values = [1.0, -1.0, -1.0, 1.0];
        let bilinear = |p: DVec2| (1.0 - 2.0 * p.x) * (1.0 - 2.0 * p.y);
        // Segments as rounded (thousandths) endpoint pairs, sorted, for exact comparison.
        let segments = |lift: f64| {
            let mut s: Vec<[[i64; 2]; 2]> = contour(&grid, &values, |p| bilinear(p) + lift, 1e-13)
                .iter()
                .map(|l| {
                    assert!(!l.closed && l.points.len() == 2);
                    let r = |p: DVec2| [(p.x * 1e3).round() as i64, (p.y * 1e3).round() as i64];
                    [r(l.points[0]), r(l.points[1])]
                })
                .collect();
            s.sort_unstable();
            s
        };
        // Roots of the lifted interpolant on the edges: (1 − 2t) = ∓0.1 → t = 0.55 or 0.45.
        // Joined: the segments cut off the outside corners (1,0) and (0,1), material on the left.
        assert_eq!(
            segments(0.1),
            [[[450, 1000], [0, 550]], [[550, 0], [1000, 450]]]
        );
        // Split: they cut off the inside corners (0,0) and (1,1).
        assert_eq!(
            segments(-0.1),
            [[[450, 0], [0, 450]], [[550, 1000], [1000, 550]]]
        );
    }

    #[test]
    fn contour_checkerboard_of_saddles_counts_loops() {
        // cos(πx)·cos(πy) + c on [0, 4]², sampled on the integer lattice only, so that every cell is
        // a saddle. Lowered (c < 0), the bumps at even-sum points separate: the centre bump and the
        // four at (1±1, …) inside the border close into counter-clockwise loops. Lifted (c > 0), the
        // bumps join and the dips around the four interior odd-sum points become clockwise holes.
        let field = |c: f64| {
            move |p: DVec2| {
                (core::f64::consts::PI * p.x).cos() * (core::f64::consts::PI * p.y).cos() + c
            }
        };
        let grid = Grid2::new(DVec2::ZERO, DVec2::splat(4.0), 5, 5);
        let split = contour_grid(&grid, field(-0.2), 1e-12);
        let bumps: Vec<&Polyline> = split.iter().filter(|l| l.closed).collect();
        assert_eq!(bumps.len(), 5);
        assert!(
            bumps.iter().all(|l| l.signed_area() > 0.0),
            "bumps run counter-clockwise"
        );
        let joined = contour_grid(&grid, field(0.2), 1e-12);
        let holes: Vec<&Polyline> = joined.iter().filter(|l| l.closed).collect();
        assert_eq!(holes.len(), 4);
        assert!(
            holes.iter().all(|l| l.signed_area() < 0.0),
            "holes run clockwise"
        );
    }

    #[test]
    fn contour_of_fig9_solid_is_one_loop() {
        let s = crate::Solid2::fig9();
        let grid = Grid2::new(DVec2::splat(-0.2), DVec2::splat(1.2), 97, 97);
        let values = s.f_grid([&grid.xs(), &grid.ys()]);
        let lines = contour(&grid, &values, |p| s.f(p), 1e-9);
        assert_eq!(lines.len(), 1);
        assert!(lines[0].closed && lines[0].signed_area() > 0.0);
        assert!(lines[0].points.iter().all(|p| s.f(*p).abs() <= 1e-9));
    }

    #[test]
    fn ring_cross_sections_have_a_hole_across_and_two_discs_along() {
        let crate::model::ModelSolid::Volume(ring) = crate::presets::Preset::Ring.solid() else {
            panic!("the ring is a volume")
        };
        let accuracy = 1e-10;
        let lift = |axis: Axis, at: f64, p: DVec2| match axis {
            Axis::U => DVec3::new(at, p.x, p.y),
            Axis::V => DVec3::new(p.x, at, p.y),
            Axis::W => DVec3::new(p.x, p.y, at),
        };
        // Across the axis: an annulus, the outer loop counter-clockwise, the hole clockwise.
        let flat = cross_section(&ring, Axis::W, 0.0, 64, accuracy);
        assert_eq!(flat.len(), 2);
        let mut areas: Vec<f64> = flat.iter().map(Polyline::signed_area).collect();
        areas.sort_by(f64::total_cmp);
        assert!(areas[0] < 0.0 && areas[1] > 0.0 && areas[1] > -areas[0]);
        // Along it (through the axis): the tube cut twice, two discs.
        for axis in [Axis::U, Axis::V] {
            let cut = cross_section(&ring, axis, 0.0, 64, accuracy);
            assert_eq!(cut.len(), 2, "{axis:?}");
            for line in &cut {
                assert!(line.closed && line.signed_area() > 0.0);
                for p in &line.points {
                    assert!(ring.f(lift(axis, 0.0, *p)).abs() <= accuracy);
                }
            }
        }
        for line in &flat {
            for p in &line.points {
                assert!(ring.f(lift(Axis::W, 0.0, *p)).abs() <= accuracy);
            }
        }
        // Planes that miss the box, and bad arguments, give nothing.
        assert!(cross_section(&ring, Axis::W, 5.0, 64, accuracy).is_empty());
        assert!(cross_section(&ring, Axis::W, f64::NAN, 64, accuracy).is_empty());
        assert!(cross_section(&ring, Axis::W, 0.0, 1, accuracy).is_empty());
        assert!(cross_section(&ring, Axis::W, 0.0, 64, f64::NAN).is_empty());
    }

    #[test]
    fn a_net_whose_points_share_one_x_has_closed_contours() {
        // The box is 2.2e-308 wide beside x = 3.9e-11: below rounding, so a grid over it alone has
        // no width and its margin cannot close the contour.
        let patch = crate::Patch::from_fn([2, 2], |[i, j]| {
            DVec3::new(
                3.9e-11 + 1.1e-308 * i as f64,
                j as f64 / 2.0,
                1.0 - (j as f64 - 1.0).abs(),
            )
        })
        .unwrap();
        let solid = Solid2::try_from_net(patch).unwrap();
        for res in [2, 7, 16, 64] {
            for line in solid_contour(&solid, res, 1e-9) {
                assert!(line.closed, "{res}: {line:?}");
                assert!(line.points.iter().all(|p| p.is_finite()));
            }
        }
    }

    /// Distance from `p` to the nearest segment of any line.
    fn distance_to(lines: &[Polyline], p: DVec2) -> f64 {
        let mut best = f64::INFINITY;
        for line in lines {
            let n = line.points.len();
            let segments = if line.closed { n } else { n - 1 };
            for k in 0..segments {
                let (a, b) = (line.points[k], line.points[(k + 1) % n]);
                let t = ((p - a).dot(b - a) / (b - a).length_squared()).clamp(0.0, 1.0);
                let t = if t.is_finite() { t } else { 0.0 };
                best = best.min((a + (b - a) * t).distance(p));
            }
        }
        best
    }

    #[test]
    fn forward_contour_is_the_inverse_contour() {
        let mut rng = Rng::new(91);
        let mut checked = 0;
        for _ in 0..6 {
            let patch = crate::inverse::tests::warped_patch(&mut rng, [3, 3], 0.1);
            let solid = Solid2::try_from_net(patch).unwrap();
            let Some(forward) = forward_contour(&solid, 96, 1e-12) else {
                continue;
            };
            checked += 1;
            let sampled = sampled_contour(&solid, 96, 1e-12);
            // Features below a cell are the grid's to resolve or miss: compare the rest.
            let cell = (solid.domain().1 - solid.domain().0).max_element() / 96.0;
            let big = |ls: Vec<Polyline>| -> Vec<Polyline> {
                ls.into_iter()
                    .filter(|l| !l.closed || l.signed_area().abs() > cell * cell)
                    .collect()
            };
            let (forward, sampled) = (big(forward), big(sampled));
            let info = |ls: &[Polyline]| -> Vec<(usize, bool, f64)> {
                ls.iter()
                    .map(|l| (l.points.len(), l.closed, l.signed_area()))
                    .collect()
            };
            assert_eq!(
                forward.len(),
                sampled.len(),
                "{:?} vs {:?}",
                info(&forward),
                info(&sampled)
            );
            // Vertices exactly on f = 0 as the inverse map sees it.
            for p in forward.iter().flat_map(|l| &l.points) {
                let v = solid.evaluate(*p, crate::inverse::Method::Clipping);
                assert!(v.f.abs() < 1e-9, "f = {} at {p}", v.f);
            }
            // Hausdorff distance between the two polylines: both have their vertices on the curve,
            // on different grids; between vertices each is a chord, and where the clipping makes a
            // corner (where the zero set of S_ξ meets the domain's edge, at any angle) each cuts it
            // within a cell or two.
            let hausdorff = forward
                .iter()
                .flat_map(|l| &l.points)
                .map(|&p| distance_to(&sampled, p))
                .chain(
                    sampled
                        .iter()
                        .flat_map(|l| &l.points)
                        .map(|&p| distance_to(&forward, p)),
                )
                .fold(0.0, f64::max);
            assert!(
                hausdorff < 2.0 * cell,
                "Hausdorff {hausdorff} vs cell {cell}"
            );
            // The solid on the left: the same signed area.
            let area = |ls: &[Polyline]| ls.iter().map(Polyline::signed_area).sum::<f64>();
            assert!(
                (area(&forward) - area(&sampled)).abs() < 0.01 * area(&sampled).abs().max(1e-3)
            );
        }
        assert!(checked >= 4, "{checked}");
    }
}
