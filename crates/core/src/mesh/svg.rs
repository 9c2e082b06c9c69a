//! SVG of 2D zero contours: one `<path>` per polyline in world coordinates, y up (the group flips the
//! SVG's y-down axis), closed loops filled with the nonzero rule (loops around material run
//! counter-clockwise and holes clockwise, see [`crate::contour`]).

use alloc::format;
use alloc::string::String;
use core::fmt::Write as _;

use glam::DVec2;

use crate::contour::Polyline;

/// The SVG document of `lines` over the world box `[min, max]`.
///
/// Coordinates are written with Rust's shortest round-trip formatting, so reading them back gives
/// the same `f64`s.
#[must_use]
pub fn contours_svg(lines: &[Polyline], min: DVec2, max: DVec2) -> String {
    let size = max - min;
    // The stroke is a small fraction of the box so that it reads at any scale.
    let stroke = size.max_element() * 0.004;
    let mut out = String::new();
    out.push_str("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    let _ = writeln!(
        out,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"{} {} {} {}\" width=\"800\" height=\"{}\">",
        min.x,
        -max.y,
        size.x,
        size.y,
        libm::round(800.0 * size.y / size.x).clamp(1.0, 1e5),
    );
    out.push_str("<title>bezsolid zero contours</title>\n");
    let _ = writeln!(
        out,
        "<g transform=\"scale(1,-1)\" stroke=\"#111\" stroke-width=\"{stroke}\" stroke-linejoin=\"round\">"
    );
    for line in lines {
        if line.points.is_empty() {
            continue;
        }
        let mut d = String::new();
        for (k, p) in line.points.iter().enumerate() {
            let _ = write!(d, "{}{},{} ", if k == 0 { "M" } else { "L" }, p.x, p.y);
        }
        let (close, fill) = if line.closed {
            ("Z", "fill=\"#cc2921\" fill-opacity=\"0.35\"")
        } else {
            ("", "fill=\"none\"")
        };
        out.push_str(&format!(
            "<path {fill} fill-rule=\"nonzero\" d=\"{}{close}\"/>\n",
            d.trim_end()
        ));
    }
    out.push_str("</g>\n</svg>\n");
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use alloc::vec;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    #[test]
    fn svg_paths_carry_the_exact_points() {
        let square = Polyline {
            points: vec![
                DVec2::new(0.1, 0.1),
                DVec2::new(0.9, 0.1),
                DVec2::new(0.9, 0.3333333333333333),
            ],
            closed: true,
        };
        let open = Polyline {
            points: vec![DVec2::ZERO, DVec2::ONE],
            closed: false,
        };
        let svg = contours_svg(&[square, open], DVec2::ZERO, DVec2::ONE);
        assert!(
            svg.contains("d=\"M0.1,0.1 L0.9,0.1 L0.9,0.3333333333333333Z\""),
            "{svg}"
        );
        assert!(svg.contains("fill=\"none\" fill-rule=\"nonzero\" d=\"M0,0 L1,1\""));
        assert!(svg.contains("viewBox=\"0 -1 1 1\""));
        assert_eq!(svg.matches("<path").count(), 2);
    }
}
