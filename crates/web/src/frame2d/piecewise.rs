//! Piecewise patches in the 2D view: the field sampled over the view or drawn forward through the
//! cells, and the curves the cells meet on.

use super::*;

/// The frame of a piecewise patch (or a piecewise volume's slice): its field, its zero contour,
/// the global net with the curves its cells meet on, and `S_ξ = 0` unclipped when the view asks.
/// Where points moved, the field and the contour are drawn forward through the cells
/// ([`piecewise_forward`]) unless cells fold over each other, where `f` is sampled over the view
/// ([`piecewise_field`]).
pub(super) fn frame_piecewise(
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
