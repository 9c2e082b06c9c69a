//! The 2D view's picture, as data: the field sampled over the view and coloured on the diverging
//! scale ([`FieldImage`]), the zero contour, the control grid, points and selection as coloured
//! triangles ([`ShapeVertex`], laid out by a pen of strokes and discs): everything but the GPU
//! upload, tested natively.

use bezsolid_core::Patch;
use bezsolid_core::contour::{
    Grid2, Polyline, contour, forward_piecewise_contour, sheet_contour, solid_contour,
    unclipped_contour, unclipped_piecewise_contour,
};
use bezsolid_core::rfunc::clip2;
use bezsolid_core::tree::Tree;
use glam::{DVec2, DVec3};

use crate::color::{Rgba, SELECT_COLOR, diverging};
use crate::editor::Editor;
use crate::view2d::{POINT_RADIUS, View2};

/// Samples of the field along the view's longer side (the texture is filtered up to the canvas).
const FIELD_SAMPLES: usize = 320;
/// Accuracy to which contour vertices are refined onto f = 0, relative to the largest |f| sampled.
pub const CONTOUR_ACCURACY: f64 = 1e-9;
/// Cells per side of the parameter-space mesh that draws a space mapping's field (mapped forward).
const MAPPED_MESH_CELLS: usize = 96;
/// Cells per side of the parameter square in which a space mapping's contour is traced.
const MAPPED_CONTOUR_CELLS: usize = 192;
/// Samples along each boundary curve of the domain's outline.
const OUTLINE_SAMPLES: usize = 64;

const CONTOUR_COLOR: Rgba = [0.06, 0.06, 0.08, 1.0];
/// The unclipped contour of `S_ξ`: dashed, a dark violet apart from the solid's black.
const UNCLIPPED_COLOR: Rgba = [0.32, 0.12, 0.45, 0.95];
/// How far past the domain (in parameters) it is traced: the polynomial's own zero set goes on
/// where the clipping stops the solid.
const UNCLIPPED_MARGIN: f64 = 0.5;
/// Its dashes and gaps, in CSS pixels.
const DASH: f64 = 7.0;
const GAP: f64 = 5.0;
const GRID_COLOR: Rgba = [0.18, 0.2, 0.24, 0.75];
const BOX_COLOR: Rgba = [0.3, 0.32, 0.36, 0.6];
const OUTLINE_COLOR: Rgba = [0.08, 0.08, 0.1, 1.0];

/// One vertex of the overlay geometry: a position in normalised device coordinates and a colour.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShapeVertex {
    /// x, y in `[−1, 1]`, y up.
    pub position: [f32; 2],
    /// Straight (not premultiplied) RGBA.
    pub color: Rgba,
}

impl ShapeVertex {
    /// Bytes of one vertex: 6 little-endian `f32`.
    pub const SIZE: usize = 24;

    /// Appends the vertex's bytes, in the layout of the shape pipeline (`float32x2`, `float32x4`).
    pub fn write(&self, out: &mut Vec<u8>) {
        for x in self.position.iter().chain(&self.color) {
            out.extend_from_slice(&x.to_le_bytes());
        }
    }
}

/// The function field as an image covering the whole view: row 0 at the top, RGBA8.
#[derive(Clone, Debug, PartialEq)]
pub struct FieldImage {
    /// Columns.
    pub width: u32,
    /// Rows.
    pub height: u32,
    /// `width · height · 4` bytes.
    pub rgba: Vec<u8>,
}

/// Everything one redraw needs.
#[derive(Clone, Debug)]
pub struct Frame {
    /// Drawn first, filtered to the whole target.
    pub field: FieldImage,
    /// Drawn over the field, as a triangle list with alpha blending.
    pub shapes: Vec<ShapeVertex>,
    /// The zero contour in world coordinates (what the black line shows).
    pub contours: Vec<Polyline>,
    /// The lowest and highest `f` sampled inside the domain box (full blue and full red; the
    /// legend's ends).
    pub range: (f64, f64),
    /// The net may fold: the contour shows the zero lines of every sheet (see
    /// [`frame`]).
    pub folded: bool,
    /// The zero contour of `S_ξ` alone in world coordinates, when the view shows it
    /// ([`View2::set_unclipped`]; none for a model of many solids).
    pub unclipped: Vec<Polyline>,
    /// A volume's true section drawn instead of its control slice ([`frame_section`]): the axis
    /// across which its plane lies (0 for x), where, and the area inside.
    pub section: Option<(usize, f64, f64)>,
    /// The section is across the parameters ([`frame_parameter_section`]): its axis is u, v or
    /// w, where it lies a parameter, its area a fraction of the parameter square.
    pub section_in_parameters: bool,
}

impl Frame {
    /// A frame of a plane's field, its contour and shapes: not folded, no section.
    fn plain(
        field: FieldImage,
        shapes: Vec<ShapeVertex>,
        contours: Vec<Polyline>,
        range: (f64, f64),
        unclipped: Vec<Polyline>,
    ) -> Self {
        Self {
            field,
            shapes,
            contours,
            range,
            folded: false,
            unclipped,
            section: None,
            section_in_parameters: false,
        }
    }
}

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

/// The unclipped contour of the editor's patch when `view` shows it, `accuracy` in `S_ξ`.
fn unclipped(editor: &Editor, view: &View2, accuracy: f64) -> Vec<Polyline> {
    if view.unclipped() {
        unclipped_contour(
            editor.solid(),
            MAPPED_CONTOUR_CELLS,
            UNCLIPPED_MARGIN,
            accuracy,
        )
    } else {
        Vec::new()
    }
}

/// Builds the frame of `editor`'s model in `view`: samples the field over the view, colours it,
/// traces the zero contour and lays out the control grid, the points and the selection ring. A
/// space mapping is drawn in parameter space and mapped forward (`frame_mapped`).
#[must_use]
pub fn frame(editor: &Editor, view: &View2) -> Frame {
    if let Some(solid) = editor.piecewise2() {
        return frame_piecewise(editor, view, &solid);
    }
    if editor.solid().is_space_mapped() {
        return frame_mapped(editor, view);
    }
    let (w, h) = field_size(view, FIELD_SAMPLES);
    let (grid, values) = sample_view(editor, view, w, h);
    let (xs, ys) = (grid.xs(), grid.ys());

    // Each sign is scaled to its own extreme, so the whole blue-white-red range is in use and zero
    // stays white whatever the magnitudes.
    // The range is taken inside the domain box: outside it the clipping falls off steeply and
    // would wash out the interior; those samples clamp to full blue.
    let (dmin, dmax) = editor.solid().domain();
    let mut range = (0.0f64, 0.0f64);
    for (b, &y) in ys.iter().enumerate() {
        for (a, &x) in xs.iter().enumerate() {
            if (dmin.x..=dmax.x).contains(&x) && (dmin.y..=dmax.y).contains(&y) {
                let v = values[b * w + a];
                range = (range.0.min(v), range.1.max(v));
            }
        }
    }
    let field = field_image(w, h, &values, range);
    let magnitude = values.iter().fold(f64::MIN_POSITIVE, |m, v| m.max(v.abs()));
    let contours = contour(
        &grid,
        &values,
        |p| editor.solid().f(p),
        CONTOUR_ACCURACY * magnitude,
    );
    let unclipped = unclipped(editor, view, CONTOUR_ACCURACY * magnitude);
    let mut shapes = shapes(editor, view, &contours);
    shapes.extend(dashed(editor, view, &unclipped));
    Frame::plain(field, shapes, contours, range, unclipped)
}

/// Samples of a model of many solids' field along the view's longer side: the whole field where
/// every Bézier part is regular (a polynomial per sample), fewer where a part is space-mapped (an
/// inverse map per sample and part).
pub const TREE_SAMPLES: usize = FIELD_SAMPLES;
/// See [`TREE_SAMPLES`].
pub const TREE_MAPPED_SAMPLES: usize = 120;

/// The frame of a 2D model of many solids: the whole tree's field sampled over the view, its zero
/// contour, and the open Bézier part's control net and points over them (`part`), `long` samples
/// along the view's longer side.
#[must_use]
pub fn frame_tree(editor: &Editor, view: &View2, tree: &Tree<2>, part: bool, long: usize) -> Frame {
    let (w, h) = field_size(view, long);
    let grid = view_grid(editor, view, w, h);
    let (xs, ys) = (grid.xs(), grid.ys());
    tree.plan(w * h);
    let values = tree.f_grid([&xs, &ys]);
    let (field, range, magnitude) = whole_field(w, h, &values);
    let contours = contour(&grid, &values, |p| tree.f(p), CONTOUR_ACCURACY * magnitude);
    let shapes = if part {
        shapes(editor, view, &contours)
    } else {
        let mut pen = Pen {
            out: Vec::new(),
            size: view.size(),
            dpr: view.dpr(),
        };
        contour_shapes(&mut pen, editor, view, &contours);
        pen.out
    };
    Frame::plain(field, shapes, contours, range, Vec::new())
}

/// The frame of a piecewise patch (or a piecewise volume's slice): its field, its zero contour,
/// the global net with the curves its cells meet on, and `S_ξ = 0` unclipped when the view asks.
/// Where points moved, the field and the contour are drawn forward through the cells
/// ([`piecewise_forward`]) unless cells fold over each other, where `f` is sampled over the view
/// ([`piecewise_field`]).
fn frame_piecewise(
    editor: &Editor,
    view: &View2,
    solid: &bezsolid_core::piecewise::Piecewise2,
) -> Frame {
    let forward = (!solid.is_regular())
        .then(|| piecewise_forward(editor, view, solid))
        .flatten();
    let (field, mesh, contours, range, magnitude) = forward.unwrap_or_else(|| {
        let (field, contours, range, magnitude) = piecewise_field(editor, view, solid);
        (field, Vec::new(), contours, range, magnitude)
    });
    let mut shapes = mesh;
    shapes.extend(shapes_of(editor, view, &contours, Some(solid)));
    let unclipped = if view.unclipped() {
        // About as many cells along the longer side as a single patch's curve has.
        let most = solid.cells().into_iter().max().unwrap_or(1);
        unclipped_piecewise_contour(
            solid,
            (MAPPED_CONTOUR_CELLS / most).max(16),
            UNCLIPPED_MARGIN,
            CONTOUR_ACCURACY * magnitude,
        )
    } else {
        Vec::new()
    };
    shapes.extend(dashed(editor, view, &unclipped));
    Frame::plain(field, shapes, contours, range, unclipped)
}

/// The sampled field of a piecewise patch over the view, with its zero contour, the colour range
/// and the largest `|f|`: `f` at every sample (the inverse map of every cell near it where points
/// moved). Where points moved, the field outside the net's image (no preimage in any cell, where
/// the continuation only keeps `f` negative) is drawn full blue, as a single space-mapped patch's
/// is.
fn piecewise_field(
    editor: &Editor,
    view: &View2,
    solid: &bezsolid_core::piecewise::Piecewise2,
) -> (FieldImage, Vec<Polyline>, (f64, f64), f64) {
    use bezsolid_core::inverse::Method;
    let long = if solid.is_regular() {
        TREE_SAMPLES
    } else {
        TREE_MAPPED_SAMPLES
    };
    let (w, h) = field_size(view, long);
    let grid = view_grid(editor, view, w, h);
    let (xs, ys) = (grid.xs(), grid.ys());
    // The moved cells share the frame's budget (see `Share`).
    solid.plan(w * h);
    let samples: Vec<(f64, bool)> = ys
        .iter()
        .flat_map(|&y| xs.iter().map(move |&x| DVec2::new(x, y)))
        .map(|p| {
            let v = solid.evaluate(p, Method::Fast);
            (v.f, solid.is_regular() || v.preimages > 0)
        })
        .collect();
    // The colour range is taken inside the domain (as a single patch's is): far outside, the
    // clipping falls off steeply and would wash out the interior.
    let (dmin, dmax) = solid.domain();
    let in_domain = |k: usize| {
        let p = DVec2::new(xs[k % w], ys[k / w]);
        p.cmpge(dmin).all() && p.cmple(dmax).all()
    };
    let values: Vec<f64> = samples.iter().map(|s| s.0).collect();
    let (_, _, magnitude) = whole_field(w, h, &values);
    let range = samples
        .iter()
        .enumerate()
        .filter(|&(k, s)| s.1 && s.0.is_finite() && in_domain(k))
        .map(|(_, s)| s)
        .fold((0.0f64, 0.0f64), |r, s| (r.0.min(s.0), r.1.max(s.0)));
    let outside = range.0.min(-f64::MIN_POSITIVE) * 2.0;
    let shown: Vec<f64> = samples
        .iter()
        .map(|&(f, image)| if image { f } else { outside })
        .collect();
    let field = field_image(w, h, &shown, range);
    let contours = contour(&grid, &values, |p| solid.f(p), CONTOUR_ACCURACY * magnitude);
    (field, contours, range, magnitude)
}

/// A moved piecewise patch's field drawn forward, as a single moved patch's is: each cell's
/// parameter grid mapped through its `(S_x, S_y)` and coloured by the globally clipped `S_ξ` (no
/// inverse map; the mesh, over a flat full-blue field image), with the contour traced in the
/// global parameter square and mapped forward ([`forward_piecewise_contour`], every vertex
/// checked against `f`), the colour range and the largest `|f|`. `None` where that check fails
/// (cells folding over each other): the caller samples `f` itself.
#[allow(clippy::type_complexity)]
fn piecewise_forward(
    editor: &Editor,
    view: &View2,
    solid: &bezsolid_core::piecewise::Piecewise2,
) -> Option<(FieldImage, Vec<ShapeVertex>, Vec<Polyline>, (f64, f64), f64)> {
    let [cu, cv] = solid.cells();
    let per_cell = (MAPPED_MESH_CELLS / cu.max(cv)).max(8);
    let local: Vec<f64> = (0..=per_cell).map(|k| k as f64 / per_cell as f64).collect();
    let mut sheets = Vec::with_capacity(cu * cv);
    for b in 0..cv {
        for a in 0..cu {
            let part = solid.part([a, b])?;
            let net = part.net().eval_grid([&local, &local]);
            let side = per_cell + 1;
            let values = net
                .iter()
                .enumerate()
                .map(|(k, p)| {
                    let t = DVec2::new(
                        (a as f64 + local[k % side]) / cu as f64,
                        (b as f64 + local[k / side]) / cv as f64,
                    );
                    clip2(p.z, t.x, t.y)
                })
                .collect();
            sheets.push(Sheet {
                screen: net
                    .iter()
                    .map(|p| view.part_to_screen(editor, p.truncate()))
                    .collect(),
                values,
                cells: [per_cell; 2],
            });
        }
    }
    let (field, mesh, range, magnitude) = forward_field(view, &sheets);
    let contours = forward_piecewise_contour(
        solid,
        (MAPPED_CONTOUR_CELLS / cu.max(cv)).max(16),
        CONTOUR_ACCURACY * magnitude,
    )?;
    Some((field, mesh, contours, range, magnitude))
}

/// Field samples `(w, h)` of the view with `long` along its longer side.
fn field_size(view: &View2, long: usize) -> (usize, usize) {
    let aspect = view.size().x / view.size().y;
    if aspect >= 1.0 {
        (long, ((long as f64 / aspect).round() as usize).max(2))
    } else {
        (((long as f64 * aspect).round() as usize).max(2), long)
    }
}

/// The field image of `w × h` samples coloured over their whole finite range, with that range and
/// the largest finite `|f|` (what a contour's accuracy is relative to).
fn whole_field(w: usize, h: usize, values: &[f64]) -> (FieldImage, (f64, f64), f64) {
    let finite = || values.iter().filter(|v| v.is_finite());
    let range = finite().fold((0.0f64, 0.0f64), |r, &v| (r.0.min(v), r.1.max(v)));
    let magnitude = finite().fold(f64::MIN_POSITIVE, |m, v| m.max(v.abs()));
    (field_image(w, h, values, range), range, magnitude)
}

/// The texel centres of a `w × h` image of the view: where the field is sampled, so that the
/// filtered texture and the contour agree.
fn view_grid(editor: &Editor, view: &View2, w: usize, h: usize) -> Grid2 {
    let (vmin, vmax) = view.view_box(editor);
    let texel = (vmax - vmin) / DVec2::new(w as f64, h as f64);
    Grid2::new(vmin + texel * 0.5, vmax - texel * 0.5, w, h)
}

/// `f` sampled at the texel centres of a `w × h` image of the view, with the grid.
fn sample_view(editor: &Editor, view: &View2, w: usize, h: usize) -> (Grid2, Vec<f64>) {
    let grid = view_grid(editor, view, w, h);
    let values = editor.solid().f_grid([&grid.xs(), &grid.ys()]);
    (grid, values)
}

/// The frame of a space mapping. The inverse map at every pixel would cost a Newton solve per
/// pixel; instead a parameter-space mesh of the patch is mapped forward (`S(u, v)`, exact at its
/// vertices) and coloured by the clipped `S_ξ`, drawn in increasing `f` so that where the net
/// folds the larger value (the max over preimages) is on top. Outside the image `f` is negative
/// everywhere; it is drawn flat full blue: proving that a point has no preimage takes Bézier
/// clipping over the whole domain (40 ms for a coarse 96-pixel image of a 16×16 net, natively).
/// The contour is traced in parameter space and mapped forward.
///
/// Where the net may fold (no injectivity certificate) the exact contour would need the inverse
/// map at every sample, seconds per frame at degree 15: the live view draws the zero lines of
/// every sheet ([`sheet_contour`]) and [`Frame::folded`] says so. Exports use the exact `f`.
fn frame_mapped(editor: &Editor, view: &View2) -> Frame {
    let injective = editor.solid().inverse().is_some_and(|m| m.injective());
    let cells = MAPPED_MESH_CELLS;
    let ts: Vec<f64> = (0..=cells).map(|k| k as f64 / cells as f64).collect();
    let net = editor.solid().net().eval_grid([&ts, &ts]);
    let side = cells + 1;
    let fs: Vec<f64> = net
        .iter()
        .enumerate()
        .map(|(k, p)| clip2(p.z, ts[k % side], ts[k / side]))
        .collect();
    let points = net.iter().map(|p| view.to_screen(editor, p.truncate()));
    let sheet = Sheet {
        screen: points.collect(),
        values: fs,
        cells: [cells; 2],
    };
    let (field, mesh, range, magnitude) = forward_field(view, &[sheet]);
    let accuracy = CONTOUR_ACCURACY * magnitude;
    let contours = if injective {
        solid_contour(editor.solid(), MAPPED_CONTOUR_CELLS, accuracy)
    } else {
        sheet_contour(editor.solid(), MAPPED_CONTOUR_CELLS, accuracy)
    };
    let unclipped = unclipped(editor, view, accuracy);
    let mut drawn = mesh;
    drawn.extend(shapes(editor, view, &contours));
    drawn.extend(dashed(editor, view, &unclipped));
    Frame {
        field,
        shapes: drawn,
        contours,
        range,
        folded: !injective,
        unclipped,
        section: None,
        section_in_parameters: false,
    }
}

/// A sheet of the forward-drawn field: a `(cells + 1)`-point grid over a parameter box (the
/// first axis fastest), each point on the screen with the clipped `S_ξ` there.
struct Sheet {
    screen: Vec<DVec2>,
    values: Vec<f64>,
    cells: [usize; 2],
}

/// The field of a space mapping drawn forward: each sheet's grid cells as two triangles coloured
/// by their values, all drawn in increasing `f` so that where sheets overlap (a fold, cells of a
/// piecewise patch lying over each other) the larger value, the max over preimages, is on top.
/// Outside the sheets `f` is negative everywhere: the 2 × 2 field image under them is flat full
/// blue. With the colour range and the largest `|f|`.
fn forward_field(
    view: &View2,
    sheets: &[Sheet],
) -> (FieldImage, Vec<ShapeVertex>, (f64, f64), f64) {
    let all = || sheets.iter().flat_map(|s| s.values.iter().copied());
    let range = all().fold((0.0f64, 0.0f64), |r, v| (r.0.min(v), r.1.max(v)));
    let magnitude = all().fold(f64::MIN_POSITIVE, |m, v| m.max(v.abs()));
    let (w, h) = (2, 2);
    let field = field_image(w, h, &vec![range.0.min(-1e-300); w * h], range);
    let mut triangles: Vec<(f64, usize, [usize; 3])> = Vec::new();
    for (k, sheet) in sheets.iter().enumerate() {
        let [cu, cv] = sheet.cells;
        let side = cu + 1;
        for b in 0..cv {
            for a in 0..cu {
                let i = b * side + a;
                for tri in [[i, i + 1, i + side + 1], [i, i + side + 1, i + side]] {
                    let top = tri
                        .iter()
                        .map(|&v| sheet.values[v])
                        .fold(f64::NEG_INFINITY, f64::max);
                    triangles.push((top, k, tri));
                }
            }
        }
    }
    triangles.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut pen = Pen {
        out: Vec::with_capacity(triangles.len() * 3),
        size: view.size(),
        dpr: view.dpr(),
    };
    for (_, k, tri) in &triangles {
        let sheet = &sheets[*k];
        for &i in tri {
            pen.out.push(ShapeVertex {
                position: pen.ndc(sheet.screen[i]),
                color: diverging(normalise(sheet.values[i], range)),
            });
        }
    }
    (field, pen.out, range, magnitude)
}

/// The unclipped contour's lines, dashed (the pattern runs on along each line).
fn dashed(editor: &Editor, view: &View2, lines: &[Polyline]) -> Vec<ShapeVertex> {
    let mut pen = Pen {
        out: Vec::new(),
        size: view.size(),
        dpr: view.dpr(),
    };
    for line in lines {
        let mut pts: Vec<DVec2> = line
            .points
            .iter()
            .map(|&p| view.part_to_screen(editor, p))
            .collect();
        if line.closed && !pts.is_empty() {
            pts.push(pts[0]);
        }
        // Where along the pattern (dash then gap) the line is.
        let mut phase = 0.0;
        for w in pts.windows(2) {
            let (a, b) = (w[0], w[1]);
            let len = (b - a).length();
            if !len.is_finite() || len <= 0.0 {
                continue;
            }
            let mut at = 0.0;
            while at < len {
                let (on, left) = if phase < DASH {
                    (true, DASH - phase)
                } else {
                    (false, DASH + GAP - phase)
                };
                let step = left.min(len - at);
                if on {
                    pen.segment(
                        a.lerp(b, at / len),
                        a.lerp(b, (at + step) / len),
                        2.0,
                        UNCLIPPED_COLOR,
                    );
                }
                at += step;
                phase = (phase + step) % (DASH + GAP);
            }
        }
    }
    pen.out
}

fn shapes(editor: &Editor, view: &View2, contours: &[Polyline]) -> Vec<ShapeVertex> {
    shapes_of(editor, view, contours, editor.piecewise2().as_ref())
}

/// [`shapes`] with the piecewise patch the editor shows, where it is one, made already.
fn shapes_of(
    editor: &Editor,
    view: &View2,
    contours: &[Polyline],
    pieces: Option<&bezsolid_core::piecewise::Piecewise2>,
) -> Vec<ShapeVertex> {
    let scale = editor.xi_scale();
    let mut pen = Pen {
        out: Vec::new(),
        size: view.size(),
        dpr: view.dpr(),
    };
    let patch = editor.solid().net();
    // The domain's outline: the patch's four boundary curves (the box of a regular grid); a
    // piecewise patch's, and the curves its cells meet on.
    let lines = match pieces {
        Some(solid) => piecewise_outline(solid),
        None => outline(patch).to_vec(),
    };
    for line in lines {
        for w in line.windows(2) {
            pen.segment(
                view.part_to_screen(editor, w[0]),
                view.part_to_screen(editor, w[1]),
                1.25,
                BOX_COLOR,
            );
        }
    }
    let [n, m] = editor.solid().degree();
    let selected = editor.selected().map(|(i, j)| i * (m + 1) + j);
    let at = |i: usize, j: usize| view.part_to_screen(editor, patch[[i, j]].truncate());
    for i in 0..=n {
        for j in 0..=m {
            if i < n {
                pen.segment(at(i, j), at(i + 1, j), 1.5, GRID_COLOR);
            }
            if j < m {
                pen.segment(at(i, j), at(i, j + 1), 1.5, GRID_COLOR);
            }
        }
    }
    contour_shapes(&mut pen, editor, view, contours);
    for (k, p) in patch.points().iter().enumerate() {
        let q = view.part_to_screen(editor, p.truncate());
        if selected == Some(k) {
            pen.disc(q, POINT_RADIUS + 5.0, SELECT_COLOR);
        }
        pen.disc(q, POINT_RADIUS + 1.5, OUTLINE_COLOR);
        pen.disc(q, POINT_RADIUS, diverging(p.z / scale));
    }
    pen.out
}

/// The zero contour's lines.
fn contour_shapes(pen: &mut Pen, editor: &Editor, view: &View2, contours: &[Polyline]) {
    for line in contours {
        let pts: Vec<DVec2> = line
            .points
            .iter()
            .map(|&p| view.to_screen(editor, p))
            .collect();
        let count = if line.closed {
            pts.len()
        } else {
            pts.len().saturating_sub(1)
        };
        for k in 0..count {
            pen.segment(pts[k], pts[(k + 1) % pts.len()], 2.5, CONTOUR_COLOR);
        }
        for &p in &pts {
            pen.disc(p, 1.25, CONTOUR_COLOR);
        }
    }
}

/// `v` on the colour scale's `[−1, 1]`: each sign scaled to its own extreme of `range`.
fn normalise(v: f64, range: (f64, f64)) -> f64 {
    if v >= 0.0 {
        v / range.1.max(1e-300)
    } else {
        v / -range.0.min(-1e-300)
    }
}

/// The `w × h` samples `values` (row-major from the bottom) as an image (row 0 at the top).
fn field_image(w: usize, h: usize, values: &[f64], range: (f64, f64)) -> FieldImage {
    let mut rgba = Vec::with_capacity(w * h * 4);
    for row in (0..h).rev() {
        for &v in &values[row * w..(row + 1) * w] {
            rgba.extend(diverging(normalise(v, range)).map(|c| (c * 255.0).round() as u8));
        }
    }
    FieldImage {
        width: w as u32,
        height: h as u32,
        rgba,
    }
}

/// The four boundary curves of a patch in the plane, `S(u, 0)`, `S(1, v)`, `S(u, 1)`, `S(0, v)`, as
/// polylines in world coordinates.
#[must_use]
pub fn outline(patch: &Patch<DVec3>) -> [Vec<DVec2>; 4] {
    let t = |k: usize| k as f64 / OUTLINE_SAMPLES as f64;
    let curve = |f: &dyn Fn(f64) -> (f64, f64)| -> Vec<DVec2> {
        (0..=OUTLINE_SAMPLES)
            .map(|k| {
                let (u, v) = f(t(k));
                patch.eval([u, v]).truncate()
            })
            .collect()
    };
    [
        curve(&|s| (s, 0.0)),
        curve(&|s| (1.0, s)),
        curve(&|s| (1.0 - s, 1.0)),
        curve(&|s| (0.0, 1.0 - s)),
    ]
}

/// The boundary curves of a piecewise patch and the curves its cells meet on, each cell's
/// 64 segments long (as a single patch's outline).
#[must_use]
pub fn piecewise_outline(solid: &bezsolid_core::piecewise::Piecewise2) -> Vec<Vec<DVec2>> {
    let [cu, cv] = solid.cells();
    let curve = |cells: usize, at: &dyn Fn(f64) -> [f64; 2]| -> Vec<DVec2> {
        let n = OUTLINE_SAMPLES * cells;
        (0..=n)
            .map(|k| solid.point(at(k as f64 / n as f64)))
            .collect()
    };
    let mut lines = Vec::new();
    for a in 0..=cu {
        let u = a as f64 / cu as f64;
        lines.push(curve(cv, &|s| [u, s]));
    }
    for b in 0..=cv {
        let v = b as f64 / cv as f64;
        lines.push(curve(cu, &|s| [s, v]));
    }
    lines
}

/// Turns CSS-pixel strokes and discs into NDC triangles.
struct Pen {
    out: Vec<ShapeVertex>,
    size: DVec2,
    dpr: f64,
}

impl Pen {
    fn ndc(&self, q: DVec2) -> [f32; 2] {
        let t = q / self.size;
        [(t.x * 2.0 - 1.0) as f32, (1.0 - t.y * 2.0) as f32]
    }

    fn triangle(&mut self, a: DVec2, b: DVec2, c: DVec2, color: Rgba) {
        for p in [a, b, c] {
            self.out.push(ShapeVertex {
                position: self.ndc(p),
                color,
            });
        }
    }

    /// A straight stroke `width` CSS pixels wide (at least one device pixel).
    fn segment(&mut self, a: DVec2, b: DVec2, width: f64, color: Rgba) {
        let d = b - a;
        let len = d.length();
        if len <= 0.0 || !len.is_finite() {
            return;
        }
        let half = width.max(1.0 / self.dpr) * 0.5;
        let nrm = DVec2::new(-d.y, d.x) / len * half;
        self.triangle(a - nrm, b - nrm, b + nrm, color);
        self.triangle(a - nrm, b + nrm, a + nrm, color);
    }

    /// A filled disc, with enough sides to look round at its size.
    fn disc(&mut self, c: DVec2, r: f64, color: Rgba) {
        let sides = ((r * self.dpr * 2.0) as usize).clamp(6, 40);
        let at = |k: usize| {
            let a = core::f64::consts::TAU * k as f64 / sides as f64;
            c + DVec2::new(a.cos(), a.sin()) * r
        };
        for k in 0..sides {
            self.triangle(c, at(k), at(k + 1), color);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use bezsolid_core::Solid2;
    use bezsolid_core::model::{ModelFile, SolidSpec};
    use bezsolid_core::tree::ModelTree;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    /// The switch draws `S_ξ = 0` unclipped, dashed, beside the solid's contour, regular or
    /// space-mapped: its pieces are the core's, its dashes add triangles, and off it draws none.
    #[test]
    fn the_unclipped_contour_is_drawn_dashed_when_the_view_asks() {
        let editor = Editor::new(Solid2::fig9());
        let mut view = View2::new();
        view.sync(&editor);
        let plain = frame(&editor, &view);
        assert!(plain.unclipped.is_empty());
        view.set_unclipped(true);
        let with = frame(&editor, &view);
        assert!(
            !with.unclipped.is_empty(),
            "fig9's S_ξ = 0 runs past its box"
        );
        assert_eq!(with.contours.len(), plain.contours.len());
        assert!(with.shapes.len() > plain.shapes.len() + 6 * with.unclipped.len());
        // Each vertex on S_ξ = 0 (fig9 is regular: its parameters are the scaled point).
        for line in &with.unclipped {
            for &p in &line.points {
                let t = editor.solid().to_param(p);
                let xi = editor.solid().xi_net().eval([t.x, t.y]);
                assert!(xi.abs() < 1e-6, "S_ξ = {xi} at {p}");
            }
        }
        let mut moved = editor.solid().clone();
        moved.set_point([1, 1], DVec2::new(0.4, 0.45)).unwrap();
        let editor = Editor::new(moved);
        let mapped = frame(&editor, &view);
        assert!(!mapped.unclipped.is_empty() && mapped.shapes.len() > 100);
    }

    /// A piecewise volume (a dome volume with a cell added along u, a point of the face the
    /// cells share moved in space): its slice is drawn as the piecewise patch it is, its section
    /// and the probe are of the piecewise solid, not of the global net read as one volume.
    #[test]
    fn a_piecewise_model_is_drawn_sliced_and_cut_as_the_piecewise_solid() {
        let mut editor = Editor::new(Solid2::fig9());
        editor.new_volume(4, 4, 4).unwrap();
        let mut parts = crate::parts::Parts::of_editor(&mut editor).unwrap();
        parts.add_cell(0, &mut editor).unwrap();
        // Point (3, 1, 2) lies on the face u = 1/2 of the global net: move it out in space.
        let index = (3 * 4 + 1) * 4 + 2;
        editor.begin_volume_drag(index);
        let p = editor.volume().unwrap().net().points()[index];
        assert!(editor.drag_volume_to(Some(p.truncate() + DVec3::new(0.15, -0.1, 0.05)), None));
        editor.end_drag();
        parts.sync(&editor);
        let pieces = editor.piecewise3().unwrap();
        assert!(!pieces.is_regular());
        editor.set_slice(bezsolid_core::Axis::W, 2).unwrap();
        let slice = editor.piecewise2().unwrap();
        let mut view = View2::new();
        let (lo, hi) = pieces.domain();
        view.set_scene(Some((lo.truncate(), hi.truncate())));
        view.sync(&editor);
        let drawn = frame(&editor, &view);
        assert!(!drawn.contours.is_empty());
        let mut off_single = 0.0f64;
        for line in &drawn.contours {
            for &q in &line.points {
                assert!(slice.f(q).abs() < 1e-6, "f = {} at {q}", slice.f(q));
                off_single = off_single.max(editor.solid().f(q).abs());
            }
        }
        assert!(
            off_single > 1e-3,
            "the global net as one patch is another contour"
        );
        // Outside the moved net's image (a corner of the view, past the points' bounds): full
        // blue, as a single space-mapped patch is drawn.
        let blue = crate::color::diverging(-1.0).map(|c| (c * 255.0).round() as u8);
        assert_eq!(drawn.field.rgba[..4], blue);
        // S_ξ = 0 unclipped, dashed, beside it.
        view.set_unclipped(true);
        let with = frame(&editor, &view);
        assert!(!with.unclipped.is_empty());
        assert!(with.shapes.len() > drawn.shapes.len() + 6 * with.unclipped.len());
        view.set_unclipped(false);
        let q = view.to_screen(&editor, DVec2::new(0.5, 0.5));
        assert_eq!(view.probe(&editor, q), slice.f(view.to_world(&editor, q)));
        // The outline: the boundary and the curve the two cells meet on, from corner to corner of
        // their shared edge.
        let lines = piecewise_outline(&slice);
        assert_eq!(lines.len(), 3 + 2);
        let shared = &lines[1];
        let net = editor.solid().net();
        let ends = [shared[0], shared[shared.len() - 1]];
        assert!((ends[0] - net[[3, 0]].truncate()).length() < 1e-12);
        assert!((ends[1] - net[[3, 3]].truncate()).length() < 1e-12);
        // The true section by z = at, on f of the piecewise volume.
        let at = (lo.z + hi.z) / 2.0;
        let section = frame_section(&editor, &view, &pieces, 2, at);
        assert!(!section.contours.is_empty());
        for line in &section.contours {
            for &q in &line.points {
                let f = pieces.f(DVec3::new(q.x, q.y, at));
                assert!(f.abs() < 1e-6, "f = {f} at {q}");
            }
        }
        // Across the parameters: f at the piecewise map's points of the global parameter plane.
        let across = frame_parameter_section(&editor, &view, &pieces, 2, 0.5);
        assert!(!across.contours.is_empty());
        for line in &across.contours {
            for &q in &line.points {
                let f = pieces.f(parameter_point(&pieces, 2, 0.5, q));
                assert!(f.abs() < 1e-6, "f = {f} at {q}");
            }
        }
    }

    /// A model of many solids cut across space: the contour is of the whole tree's `f` on the
    /// plane (a volume and a sphere beside it, overlapping), not of the open part alone.
    #[test]
    fn a_section_of_a_model_of_many_solids_cuts_the_whole_model() {
        let mut editor = Editor::new(Solid2::fig9());
        editor.new_volume(4, 4, 4).unwrap();
        let mut parts = crate::parts::Parts::of_editor(&mut editor).unwrap();
        parts
            .add(crate::outline::NewNode::Sphere, &mut editor)
            .unwrap();
        parts.select(&[0], &mut editor).unwrap();
        let bezsolid_core::tree::ModelTree::Space(tree) = parts.tree(&editor).unwrap() else {
            unreachable!()
        };
        let (lo, hi) = tree.bounds().unwrap();
        let bounds = (DVec3::from_array(lo), DVec3::from_array(hi));
        let whole = TreeSection {
            tree: &tree,
            bounds,
            mapped: false,
        };
        let mut view = View2::new();
        view.set_scene(Some((bounds.0.truncate(), bounds.1.truncate())));
        view.sync(&editor);
        let at = 0.5;
        let cut = frame_section(&editor, &view, &whole, 2, at);
        for line in &cut.contours {
            for &q in &line.points {
                let f = tree.f(DVec3::new(q.x, q.y, at));
                assert!(f.abs() < 1e-6, "f = {f} at {q}");
            }
        }
        // The sphere (centre (1, 0.5, 0.5), radius 0.4) reaches past the volume's box, x ≤ 1.
        let reach = |frame: &Frame| {
            frame
                .contours
                .iter()
                .flat_map(|l| l.points.iter().map(|p| p.x))
                .fold(f64::MIN, f64::max)
        };
        assert!((reach(&cut) - 1.4).abs() < 1e-3, "{}", reach(&cut));
        let part = frame_section(&editor, &view, editor.volume().unwrap(), 2, at);
        assert!(reach(&part) < 1.0, "the open part alone");
        let (whole_area, part_area) = (cut.section.unwrap().2, part.section.unwrap().2);
        assert!(whole_area > part_area + 0.1, "{whole_area} {part_area}");
    }

    /// `volume` in an editor and a view that frames its box.
    fn framed(volume: &bezsolid_core::Solid3) -> (Editor, View2) {
        let mut editor = Editor::new(Solid2::fig9());
        editor.set_volume(volume.clone());
        let mut view = View2::new();
        let (lo, hi) = volume.domain();
        view.set_scene(Some((lo.truncate(), hi.truncate())));
        view.sync(&editor);
        (editor, view)
    }

    fn fish() -> bezsolid_core::Solid3 {
        let bezsolid_core::model::ModelSolid::Volume(fish) =
            bezsolid_core::presets::Preset::Fish.solid()
        else {
            unreachable!()
        };
        fish
    }

    /// A volume's true section: its contour on `f = 0` of the plane, its area the core's section's,
    /// no control points drawn; the view frames the plane's box.
    #[test]
    fn a_true_section_is_the_contour_of_f_on_the_plane() {
        let fish = fish();
        let (editor, view) = framed(&fish);
        let section = frame_section(&editor, &view, &fish, 2, 0.1);
        let (axis, at, area) = section.section.unwrap();
        assert_eq!((axis, at), (2, 0.1));
        assert!(!section.contours.is_empty());
        for line in &section.contours {
            for q in &line.points {
                let f = fish.f(DVec3::new(q.x, q.y, 0.1));
                assert!(f.abs() < 1e-6, "f = {f} at {q}");
            }
        }
        let ModelTree::Space(tree) = ModelFile::from_solid3(&fish).to_tree().unwrap() else {
            unreachable!()
        };
        let core: f64 = tree
            .section(2, 0.1, 256, 1e-10, None)
            .unwrap()
            .iter()
            .filter(|l| l.closed)
            .map(Polyline::signed_area)
            .sum();
        assert!((area - core).abs() < 0.01 * core, "{area} against {core}");
        // Only the contour: no control points (discs) over the field.
        let slice = frame(&editor, &view);
        assert!(section.shapes.len() < slice.shapes.len());
    }

    /// A section across the parameters: on a regular grid it is the section by the matching
    /// plane in space (its part of the parameter square the space section's area over the box's
    /// face); on a moved volume its contour lies on `f(S(u)) = 0`.
    #[test]
    fn a_section_across_the_parameters_is_f_at_the_points_of_the_parameter_plane() {
        let fish = fish();
        let (editor, view) = framed(&fish);
        let (lo, hi) = fish.domain();
        let t = 0.6;
        let across = frame_parameter_section(&editor, &view, &fish, 2, t);
        assert!(across.section_in_parameters);
        let (axis, at, part) = across.section.unwrap();
        assert_eq!((axis, at), (2, t));
        assert!(part > 0.05 && part < 1.0, "{part}");
        let space = frame_section(&editor, &view, &fish, 2, lo.z + t * (hi.z - lo.z));
        let (_, _, area) = space.section.unwrap();
        let face = (hi.x - lo.x) * (hi.y - lo.y);
        assert!(
            (part * face - area).abs() < 1e-4 * area,
            "{part} of {face} against {area}"
        );

        let mut moved = fish.clone();
        moved
            .set_point([3, 2, 1], DVec3::new(0.4, 0.3, 0.2))
            .unwrap();
        moved
            .set_point([5, 1, 2], DVec3::new(1.3, -0.2, 0.6))
            .unwrap();
        assert!(moved.inverse().is_some());
        let (editor, view) = framed(&moved);
        let across = frame_parameter_section(&editor, &view, &moved, 2, 0.5);
        assert!(!across.contours.is_empty());
        for line in &across.contours {
            for &q in line.points.iter().step_by(5) {
                let p = parameter_point(&moved, 2, 0.5, q);
                let f = moved.f(p);
                assert!(f.abs() < 1e-6, "f = {f} at {p}");
            }
        }
    }

    /// Two discs apart and the paper's patch between them: the view shows the whole field, three
    /// pieces of contour on f = 0 of the whole tree, red inside and blue outside.
    #[test]
    fn a_2d_model_of_many_solids_is_drawn_whole() {
        let disc = |x: f64| SolidSpec::Circle {
            center: [x, 0.5],
            radius: 0.3,
        };
        let patch = ModelFile::from_solid2(&Solid2::fig9()).solid;
        let spec = SolidSpec::Union {
            of: vec![disc(-1.0), patch, disc(2.0)],
        };
        let ModelTree::Plane(tree) = ModelFile::from_spec(spec).to_tree().unwrap() else {
            panic!("2D")
        };
        let editor = Editor::new(Solid2::fig9());
        let mut view = View2::new();
        view.resize(800.0, 400.0, 1.0);
        let (lo, hi) = tree.bounds().unwrap();
        view.set_scene(Some((DVec2::from_array(lo), DVec2::from_array(hi))));
        let frame = frame_tree(&editor, &view, &tree, false, 200);
        assert!(frame.range.0 < 0.0 && frame.range.1 > 0.0);
        assert_eq!(frame.contours.len(), 3, "two discs and the patch's solid");
        let magnitude = frame.range.0.abs().max(frame.range.1);
        for line in &frame.contours {
            for &p in &line.points {
                assert!(tree.f(p).abs() <= 1e-8 * magnitude, "{p} is on f = 0");
            }
        }
        // The discs' centres are inside (red), a point between them outside (blue).
        let texel = |p: DVec2| {
            let q = view.to_screen(&editor, p) / view.size();
            let (w, h) = (frame.field.width as f64, frame.field.height as f64);
            let (x, y) = ((q.x * w) as usize, (q.y * h) as usize);
            let k = (y * frame.field.width as usize + x) * 4;
            [frame.field.rgba[k], frame.field.rgba[k + 2]]
        };
        for c in [DVec2::new(-1.0, 0.5), DVec2::new(2.0, 0.5)] {
            let [r, b] = texel(c);
            assert!(r > b, "inside is red at {c}");
        }
        let [r, b] = texel(DVec2::new(1.5, 0.5));
        assert!(b > r, "outside is blue");
    }
}
