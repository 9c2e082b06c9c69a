//! The shapes of the 2D view as coloured triangles: contours, dashed lines, the control grid,
//! points and selection laid out by a pen of strokes and discs, the field's colours, and the
//! outline of a patch.

use super::*;

/// The unclipped contour's lines, dashed (the pattern runs on along each line).
pub(super) fn dashed(editor: &Editor, view: &View2, lines: &[Polyline]) -> Vec<ShapeVertex> {
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

pub(super) fn shapes(editor: &Editor, view: &View2, contours: &[Polyline]) -> Vec<ShapeVertex> {
    shapes_of(editor, view, contours, editor.piecewise2().as_ref())
}

/// [`shapes`] with the piecewise patch the editor shows, where it is one, made already.
pub(super) fn shapes_of(
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
pub(super) fn contour_shapes(pen: &mut Pen, editor: &Editor, view: &View2, contours: &[Polyline]) {
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
pub(super) fn normalise(v: f64, range: (f64, f64)) -> f64 {
    if v >= 0.0 {
        v / range.1.max(1e-300)
    } else {
        v / -range.0.min(-1e-300)
    }
}

/// The `w × h` samples `values` (row-major from the bottom) as an image (row 0 at the top).
pub(super) fn field_image(w: usize, h: usize, values: &[f64], range: (f64, f64)) -> FieldImage {
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

/// Turns CSS-pixel strokes and discs into NDC triangles.
pub(super) struct Pen {
    pub(super) out: Vec<ShapeVertex>,
    pub(super) size: DVec2,
    pub(super) dpr: f64,
}

impl Pen {
    pub(super) fn ndc(&self, q: DVec2) -> [f32; 2] {
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
