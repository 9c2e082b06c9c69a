//! The colours the views share: straight RGBA, and the diverging scale of the defining function.

/// An RGBA colour, components in `[0, 1]`, not premultiplied.
pub type Rgba = [f32; 4];

/// The selected control point, in every view.
pub const SELECT_COLOR: Rgba = [1.0, 0.62, 0.0, 1.0];

/// The diverging colour scale of the field (the idea of the paper's Fig. 7): `t = −1` blue, `0`
/// white, `+1` red; `t` is clamped to `[−1, 1]`.
#[must_use]
pub fn diverging(t: f64) -> Rgba {
    const BLUE: [f64; 3] = [0.16, 0.36, 0.78];
    const WHITE: [f64; 3] = [0.97, 0.97, 0.97];
    const RED: [f64; 3] = [0.80, 0.16, 0.13];
    let t = if t.is_nan() { 0.0 } else { t.clamp(-1.0, 1.0) };
    let (end, s) = if t < 0.0 { (BLUE, -t) } else { (RED, t) };
    // A slight ease so that values near zero are visibly tinted.
    let s = s.powf(0.6);
    let c = |k: usize| (WHITE[k] + (end[k] - WHITE[k]) * s) as f32;
    [c(0), c(1), c(2), 1.0]
}
