//! True sections of volumes in the 2D view: the field and contour on a plane across a Bézier
//! volume, a piecewise volume or a model of many solids, in space or in the volume's parameters.

use super::*;

pub use bezsolid_core::tree::plane_axes;

/// A volume a true section cuts: a single Bézier volume, or a piecewise one (its global
/// parameter is the section's parameter).
pub trait Sectioned {
    /// `f` at `p`.
    fn f(&self, p: DVec3) -> f64;
    /// `f` on the grid `axes[0] × axes[1] × axes[2]`, the first axis fastest.
    fn f_grid(&self, axes: [&[f64]; 3]) -> Vec<f64>;
    /// Says that about `queries` evaluations are coming.
    fn plan(&self, _queries: usize) {}
    /// Whether points moved in space (an inverse map per sample).
    fn mapped(&self) -> bool;
    /// The regular grid's box, or the moved net's bounds.
    fn domain(&self) -> (DVec3, DVec3);
    /// The point `S(u)` in space of parameter `u`.
    fn point(&self, u: [f64; 3]) -> DVec3;
}

impl Sectioned for bezsolid_core::Solid3 {
    fn f(&self, p: DVec3) -> f64 {
        bezsolid_core::Solid3::f(self, p)
    }
    fn f_grid(&self, axes: [&[f64]; 3]) -> Vec<f64> {
        bezsolid_core::Solid3::f_grid(self, axes)
    }
    fn plan(&self, queries: usize) {
        bezsolid_core::Solid3::plan(self, queries);
    }
    fn mapped(&self) -> bool {
        self.is_space_mapped()
    }
    fn domain(&self) -> (DVec3, DVec3) {
        bezsolid_core::Solid3::domain(self)
    }
    fn point(&self, u: [f64; 3]) -> DVec3 {
        use bezsolid_core::inverse::Forward;
        DVec3::from_array(self.net().forward(u).x)
    }
}

impl Sectioned for bezsolid_core::piecewise::Piecewise3 {
    fn f(&self, p: DVec3) -> f64 {
        bezsolid_core::piecewise::Piecewise3::f(self, p)
    }
    fn f_grid(&self, axes: [&[f64]; 3]) -> Vec<f64> {
        bezsolid_core::piecewise::Piecewise3::f_grid(self, axes)
    }
    fn plan(&self, queries: usize) {
        bezsolid_core::piecewise::Piecewise3::plan(self, queries);
    }
    fn mapped(&self) -> bool {
        !self.is_regular()
    }
    fn domain(&self) -> (DVec3, DVec3) {
        bezsolid_core::piecewise::Piecewise3::domain(self)
    }
    fn point(&self, u: [f64; 3]) -> DVec3 {
        bezsolid_core::piecewise::Piecewise3::point(self, u)
    }
}

/// A model of many solids in space as a true section cuts it: the tree, the box the section
/// spans, and whether a Bézier part of it is space-mapped (then sampled more coarsely). Its
/// parameter is its box's, `lo + u·(hi − lo)`.
#[derive(Clone, Copy, Debug)]
pub struct TreeSection<'a> {
    /// The tree.
    pub tree: &'a Tree<3>,
    /// The box the section spans.
    pub bounds: (DVec3, DVec3),
    /// Whether a Bézier part of it is space-mapped.
    pub mapped: bool,
}

impl Sectioned for TreeSection<'_> {
    fn f(&self, p: DVec3) -> f64 {
        self.tree.f(p)
    }
    fn f_grid(&self, axes: [&[f64]; 3]) -> Vec<f64> {
        self.tree.f_grid(axes)
    }
    fn plan(&self, queries: usize) {
        self.tree.plan(queries);
    }
    fn mapped(&self) -> bool {
        self.mapped
    }
    fn domain(&self) -> (DVec3, DVec3) {
        self.bounds
    }
    fn point(&self, u: [f64; 3]) -> DVec3 {
        let (lo, hi) = self.bounds;
        lo + DVec3::from_array(u) * (hi - lo)
    }
}

/// The frame of a volume's true section by the plane `p[axis] = at` (in space): `f` itself sampled
/// over the view in the plane's coordinates ([`plane_axes`]), its zero contour refined on `f`,
/// and the area inside; no control points (the section is not edited: the control slice is). A
/// space-mapped volume is sampled more coarsely (an inverse map per sample).
#[must_use]
pub fn frame_section(
    editor: &Editor,
    view: &View2,
    volume: &(impl Sectioned + ?Sized),
    axis: usize,
    at: f64,
) -> Frame {
    let (grid, w, h) = section_grid(editor, view, volume);
    let (us, vs) = (grid.xs(), grid.ys());
    let [a, b] = plane_axes(axis);
    let place = |q: DVec2| {
        let mut p = [at; 3];
        p[a] = q.x;
        p[b] = q.y;
        DVec3::from_array(p)
    };
    // The plane's grid as a grid of space with one sample across the axis (its first axis the
    // fastest, as the plane's grid has it).
    let across = [at];
    let mut axes: [&[f64]; 3] = [&across; 3];
    axes[a] = &us;
    axes[b] = &vs;
    volume.plan(w * h);
    let values = volume.f_grid(axes);
    let mut frame = section_frame(editor, view, (&grid, w, h), &values, |q| volume.f(place(q)));
    let area = frame
        .contours
        .iter()
        .filter(|l| l.closed)
        .map(Polyline::signed_area)
        .sum();
    frame.section = Some((axis, at, area));
    frame
}

/// The frame of a volume's section across its parameters: the plane `u[axis] = t` of the
/// parameter box, shown over the volume's box in the plane's axes ([`plane_axes`]: parameter
/// `(u_a, u_b)` at `lo + u·(hi − lo)`), `f` at the points `S(u)` of that surface in space
/// (exactly: through the inverse map where the points moved), its zero contour, and the part of
/// the parameter square inside (as the area, a fraction); no control points. On a regular grid
/// it is the section by the plane `p[axis] = lo + t·(hi − lo)`.
#[must_use]
pub fn frame_parameter_section(
    editor: &Editor,
    view: &View2,
    volume: &(impl Sectioned + ?Sized),
    axis: usize,
    t: f64,
) -> Frame {
    let (grid, w, h) = section_grid(editor, view, volume);
    let [a, b] = plane_axes(axis);
    let (lo, hi) = volume.domain();
    let f_at = |q: DVec2| volume.f(parameter_point(volume, axis, t, q));
    volume.plan(w * h);
    let (xs, ys) = (grid.xs(), grid.ys());
    let values: Vec<f64> = ys
        .iter()
        .flat_map(|&y| xs.iter().map(move |&x| DVec2::new(x, y)))
        .map(f_at)
        .collect();
    let mut frame = section_frame(editor, view, (&grid, w, h), &values, f_at);
    let square = (hi[a] - lo[a]) * (hi[b] - lo[b]);
    let area: f64 = frame
        .contours
        .iter()
        .filter(|l| l.closed)
        .map(Polyline::signed_area)
        .sum();
    frame.section = Some((axis, t, area / square));
    frame.section_in_parameters = true;
    frame
}

/// The point `S(u)` in space of the view point `q` of a section across the parameters
/// ([`frame_parameter_section`]): `u[axis] = t`, the other two parameters `q` over the volume's
/// box in the plane's axes.
#[must_use]
pub fn parameter_point(volume: &(impl Sectioned + ?Sized), axis: usize, t: f64, q: DVec2) -> DVec3 {
    let [a, b] = plane_axes(axis);
    let (lo, hi) = volume.domain();
    let mut u = [t; 3];
    u[a] = (q.x - lo[a]) / (hi[a] - lo[a]);
    u[b] = (q.y - lo[b]) / (hi[b] - lo[b]);
    volume.point(u)
}

/// The sample grid of a section of `volume` over the view, `w × h`: coarser for a space-mapped
/// volume (an inverse map per sample).
fn section_grid(
    editor: &Editor,
    view: &View2,
    volume: &(impl Sectioned + ?Sized),
) -> (Grid2, usize, usize) {
    let long = if volume.mapped() {
        TREE_MAPPED_SAMPLES
    } else {
        FIELD_SAMPLES
    };
    let (w, h) = field_size(view, long);
    (view_grid(editor, view, w, h), w, h)
}

/// A section's frame from `values` sampled on `grid` (`w × h`): the field, its zero contour
/// refined on `f`, drawn; no control points.
fn section_frame(
    editor: &Editor,
    view: &View2,
    (grid, w, h): (&Grid2, usize, usize),
    values: &[f64],
    f: impl Fn(DVec2) -> f64,
) -> Frame {
    let (field, range, magnitude) = whole_field(w, h, values);
    let contours = contour(grid, values, f, CONTOUR_ACCURACY * magnitude);
    let mut pen = Pen {
        out: Vec::new(),
        size: view.size(),
        dpr: view.dpr(),
    };
    contour_shapes(&mut pen, editor, view, &contours);
    Frame::plain(field, pen.out, contours, range, Vec::new())
}
