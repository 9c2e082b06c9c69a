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

mod draw;
mod piecewise;
mod section;

pub use draw::outline;
use draw::{Pen, contour_shapes, dashed, field_image, normalise, shapes, shapes_of};
use piecewise::frame_piecewise;
pub use piecewise::piecewise_outline;
pub use section::{
    Sectioned, TreeSection, frame_parameter_section, frame_section, parameter_point, plane_axes,
};

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
