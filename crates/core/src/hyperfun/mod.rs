//! HyperFun (`.hf`) export of every model: a regular-grid solid in closed form, a space-mapped one
//! (moved control points) with its inverse map written in HyperFun itself (seeds, Newton's
//! method, the largest clipped value over the preimages: `mapped.rs`), a tree of many solids node
//! by node ([`tree_hf`]). Each export carries its model in comment lines (`with_model`,
//! `model_of`, with the `link` feature), so that it opens back as the model it came from; [`read`] reads any HyperFun
//! program as HyperFun's own interpreter does, and [`field`] meshes one within a box.
//!
//! A regular solid is written as the explicit Bernstein sum in plain HyperFun arithmetic (`+ − * /` and the
//! R-function intersection `&`, which HyperFun defines as `f1 + f2 − sqrt(f1² + f2²)`, the paper's), so
//! it needs no library primitive and is exact: the same polynomial, the same clipping. Numbers are
//! written in Rust's shortest round-trip decimal, so they read back to the same `f64`s.
//!
//! A comment in the file says which library call would be equivalent: `hfBezierVolume(x, l, m, n,
//! bbox, w)`, whose `l, m, n` are control-point counts (degree + 1), whose second and third counts and
//! `w` index run along z and y (in that order), and which clips in world units, `(x1 − x)(x − x0)`, so
//! it matches this file only on a unit box.

use alloc::format;
use alloc::string::String;
use alloc::vec::Vec;
use core::fmt::Write as _;

use glam::{DVec2, DVec3};

use crate::bernstein::binomial;
use crate::{Solid2, Solid3};

#[cfg(test)]
mod agree_tests;
pub mod field;
#[cfg(test)]
mod interp;
mod mapped;
pub mod read;
mod tree;

pub use tree::{MAX_NUMBERS, TreeHfError, tree_hf};

/// How the comment lines that carry an export's model begin: `-- bezsolid model: ` and a part of
/// the model's share link, in lines HyperFun's scanner takes (it refuses a comment past 256
/// characters).
pub const MODEL_MARK: &str = "-- bezsolid model: ";

/// The most characters of the link one comment line carries.
#[cfg(feature = "link")]
const MODEL_LINE: usize = 160;

/// `text` with the model it was exported from in comment lines at its top ([`model_of`] reads it
/// back): the model's share link, so that a HyperFun file opens back as the exact model. A model
/// whose link would pass the link's cap is not carried (the file says so).
#[cfg(feature = "link")]
#[must_use]
pub fn with_model(text: &str, file: &crate::model::ModelFile) -> String {
    let mut out = String::with_capacity(text.len() + 512);
    match crate::link::encode(file) {
        Ok(link) => {
            let _ = writeln!(
                out,
                "-- The bezsolid model this file was exported from (its share link), for \
                 bezsolid to open it back:"
            );
            let chars: Vec<char> = link.chars().collect();
            for line in chars.chunks(MODEL_LINE) {
                let line: String = line.iter().collect();
                let _ = writeln!(out, "{MODEL_MARK}{line}");
            }
        }
        Err(_) => {
            let _ = writeln!(
                out,
                "-- The bezsolid model is too large to be carried here: keep its model file."
            );
        }
    }
    out.push_str(text);
    out
}

/// The model a HyperFun export carries ([`with_model`]): `None` for a file that carries none (a
/// program written for HyperFun, or an export too large to carry its model).
///
/// # Errors
///
/// The link's error where the carried link does not decode (a file edited by hand).
#[cfg(feature = "link")]
pub fn model_of(text: &str) -> Option<Result<crate::model::ModelFile, crate::link::LinkError>> {
    let link: String = text
        .lines()
        .filter_map(|l| l.trim_end().strip_prefix(MODEL_MARK))
        .collect();
    (!link.is_empty()).then(|| crate::link::decode_file(&link))
}

/// A number as a HyperFun literal: negative ones in parentheses, so `a*(-0.5)` parses. Rust writes
/// an `f64` in plain decimal, never with an exponent: HyperFun's scanner misreads a negative
/// exponent of two or more digits (`1e-15` as `1e-5`: the sign goes to the first digit only),
/// while it reads plain digits as meant (to a few units in the last place: it sums them one at a
/// time).
fn num(x: f64) -> String {
    if x < 0.0 {
        format!("({x})")
    } else {
        format!("{x}")
    }
}

/// `expr / d` for a constant `d`, written as a product by `1 / d` where `|d| < 1e-6`: HyperFun
/// refuses any division by less than that ("Division by zero").
fn over(expr: &str, d: f64) -> String {
    if d.abs() >= 1e-6 {
        format!("({expr}) / {}", num(d))
    } else {
        format!("({expr}) * {}", num(1.0 / d))
    }
}

/// `C(n, i)·t^i·(1 − t)^(n − i)` for the parameter named `t` (and `1 − t` named `s`), by repeated
/// products.
fn basis_term(n: usize, i: usize, t: &str, s: &str) -> String {
    let mut factors: Vec<String> = Vec::with_capacity(n + 1);
    let c = binomial(n, i);
    if c != 1.0 {
        factors.push(num(c));
    }
    factors.extend((0..i).map(|_| String::from(t)));
    factors.extend((0..n - i).map(|_| String::from(s)));
    factors.join("*")
}

/// Lines that define the parameter `t` of axis `k` (1-based `x[k]`) over `[lo, hi]`, `1 − t` and the
/// basis values `{t}0..{t}n`.
fn axis_lines(out: &mut String, t: &str, k: usize, lo: f64, hi: f64, n: usize) {
    let _ = writeln!(
        out,
        "  {t} = {};",
        over(&format!("x[{k}] - {}", num(lo)), hi - lo)
    );
    let _ = writeln!(out, "  {t}s = 1 - {t};");
    for i in 0..=n {
        let _ = writeln!(
            out,
            "  b{t}{i} = {};",
            basis_term(n, i, t, &format!("{t}s"))
        );
    }
}

fn header(out: &mut String, what: &str) {
    let _ = writeln!(out, "-- {what}, exported by bezsolid.");
    let _ = writeln!(
        out,
        "-- f = S_xi(u, v[, w]) & F_b(u) & F_b(v)[ & F_b(w)], F_b(t) = t(1 - t): the explicit Bernstein"
    );
    let _ = writeln!(
        out,
        "-- sum of the control points' xi over the parameters (a scaling of x), clipped to the box."
    );
}

/// A 2D model's HyperFun export ([`solid2_hf`], or [`tree_hf`] of a 2D model: a prism along z)
/// bounded to the slab `0 ≤ z ≤ height`: `my_model = f & (x[3]·(height − x[3]))`, the slab's
/// strip intersected by HyperFun's `&` (the R-function, as the domain's box clips). `None` for a
/// height that is not positive and finite, or a text that is not a 2D export of this module.
#[must_use]
pub fn extruded(text: &str, height: f64) -> Option<String> {
    const PRISM: &str = "x[3] is unused (a prism along z)";
    if !(height.is_finite() && height > 0.0 && text.contains(PRISM)) {
        return None;
    }
    let start = text.rfind("\n  my_model = ")? + "\n  my_model = ".len();
    let end = start + text[start..].find(";\n}")?;
    let expr = &text[start..end];
    let h = num(height);
    let body = text[..start].replace(
        PRISM,
        &format!("x[3] bounds the extrusion from z = 0 to z = {height}"),
    );
    Some(format!("{body}({expr}) & (x[3] * ({h} - x[3]));\n}}\n"))
}

/// The HyperFun model of a 2D solid: a function of `x[1], x[2]` (HyperFun models are 3D, so `x[3]` is
/// unused and the solid is a prism along z). A space-mapped one is written with its inverse map
/// ([`tree_hf`] of the solid alone).
///
/// # Errors
///
/// [`TreeHfError::TooLarge`] for a space-mapped solid past [`MAX_NUMBERS`] (none within the
/// model's caps).
pub fn solid2_hf(solid: &Solid2) -> Result<String, TreeHfError> {
    if solid.is_space_mapped() {
        return tree_hf(&crate::model::ModelFile::from_solid2(solid));
    }
    let [n, m] = solid.degree();
    let (min, max): (DVec2, DVec2) = solid.domain();
    let mut out = String::new();
    header(
        &mut out,
        &format!("A Bezier patch solid of degree ({n}, {m})"),
    );
    let _ = writeln!(
        out,
        "-- HyperFun has no 2D patch primitive; x[3] is unused (a prism along z)."
    );
    let _ = writeln!(out, "my_model(x[3], a[1])\n{{");
    axis_lines(&mut out, "u", 1, min.x, max.x, n);
    axis_lines(&mut out, "v", 2, min.y, max.y, m);
    let xi = solid.xi_net();
    let mut rows = Vec::with_capacity(n + 1);
    for i in 0..=n {
        let terms: Vec<String> = (0..=m)
            .map(|j| format!("bv{j}*{}", num(xi[[i, j]])))
            .collect();
        rows.push(format!("bu{i}*({})", terms.join(" + ")));
    }
    let _ = writeln!(out, "  sxi = {};", rows.join("\n    + "));
    let _ = writeln!(out, "  my_model = sxi & ((u*us) & (v*vs));\n}}");
    #[cfg(feature = "link")]
    let out = with_model(&out, &crate::model::ModelFile::from_solid2(solid));
    Ok(out)
}

/// The HyperFun model of a 3D solid: the explicit Bernstein sum, with the equivalent
/// `hfBezierVolume` call in a comment; a space-mapped one with its inverse map ([`tree_hf`] of
/// the solid alone).
///
/// # Errors
///
/// [`TreeHfError::TooLarge`] for a space-mapped solid past [`MAX_NUMBERS`] (none within the
/// model's caps).
pub fn solid3_hf(solid: &Solid3) -> Result<String, TreeHfError> {
    if solid.is_space_mapped() {
        return tree_hf(&crate::model::ModelFile::from_solid3(solid));
    }
    let [n, m, l] = solid.degree();
    let (min, max): (DVec3, DVec3) = solid.domain();
    let xi = solid.xi_net();
    let at = |i: usize, j: usize, k: usize| xi.points()[(i * (m + 1) + j) * (l + 1) + k];
    let mut out = String::new();
    header(
        &mut out,
        &format!("A Bezier volume solid of degree ({n}, {m}, {l})"),
    );
    let _ = writeln!(
        out,
        "-- The HyperFun library primitive for this is hfBezierVolume(x, {}, {}, {}, bbox, w): its counts",
        n + 1,
        l + 1,
        m + 1
    );
    let _ = writeln!(
        out,
        "-- are control points per axis (degree + 1) along x, z, y in that order, with w indexed"
    );
    let _ = writeln!(
        out,
        "-- [i*{}*{} + kz*{} + jy]; it clips in world units, (x1 - x)(x - x0), so it equals this",
        l + 1,
        m + 1,
        m + 1
    );
    let _ = writeln!(out, "-- model only on a unit box. With:");
    let _ = writeln!(
        out,
        "--   bbox = [{}, {}, {}, {}, {}, {}];",
        min.x, min.y, min.z, max.x, max.y, max.z
    );
    let mut w = Vec::with_capacity((n + 1) * (m + 1) * (l + 1));
    for i in 0..=n {
        for k in 0..=l {
            for j in 0..=m {
                w.push(format!("{}", at(i, j, k)));
            }
        }
    }
    let lines: Vec<String> = w.chunks(8).map(|chunk| chunk.join(", ")).collect();
    for (c, line) in lines.iter().enumerate() {
        let lead = if c == 0 { "--   w = [" } else { "--        " };
        let tail = if c + 1 == lines.len() { "];" } else { "," };
        let _ = writeln!(out, "{lead}{line}{tail}");
    }
    let _ = writeln!(out, "my_model(x[3], a[1])\n{{");
    axis_lines(&mut out, "u", 1, min.x, max.x, n);
    axis_lines(&mut out, "v", 2, min.y, max.y, m);
    axis_lines(&mut out, "w", 3, min.z, max.z, l);
    let mut slabs = Vec::with_capacity(n + 1);
    for i in 0..=n {
        let mut rows = Vec::with_capacity(m + 1);
        for j in 0..=m {
            let terms: Vec<String> = (0..=l)
                .map(|k| format!("bw{k}*{}", num(at(i, j, k))))
                .collect();
            rows.push(format!("bv{j}*({})", terms.join(" + ")));
        }
        slabs.push(format!("bu{i}*({})", rows.join("\n      + ")));
    }
    let _ = writeln!(out, "  sxi = {};", slabs.join("\n    + "));
    let _ = writeln!(out, "  my_model = sxi & (((u*us) & (v*vs)) & (w*ws));\n}}");
    #[cfg(feature = "link")]
    let out = with_model(&out, &crate::model::ModelFile::from_solid3(solid));
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::ModelSolid;
    use crate::presets::Preset;
    use crate::testutil::Rng;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    /// The file `text` at the point `x`, by the tests' HyperFun interpreter.
    fn run_hf(text: &str, x: [f64; 3]) -> f64 {
        super::interp::eval(text, x)
    }

    #[test]
    fn exported_volumes_evaluate_to_f() {
        let mut rng = Rng::new(60);
        for preset in [Preset::Blob, Preset::Ring, Preset::Fish] {
            let ModelSolid::Volume(solid) = preset.solid() else {
                panic!()
            };
            let text = solid3_hf(&solid).unwrap();
            assert!(text.contains("hfBezierVolume"));
            let (min, max) = solid.domain();
            for _ in 0..50 {
                let t = DVec3::new(
                    rng.range(-0.2, 1.2),
                    rng.range(-0.2, 1.2),
                    rng.range(-0.2, 1.2),
                );
                let p = min + (max - min) * t;
                let got = run_hf(&text, p.to_array());
                let want = solid.f(p);
                assert!(
                    (got - want).abs() <= 1e-12 * (1.0 + want.abs()),
                    "{preset:?} at {p}: {got} vs {want}"
                );
            }
        }
    }

    #[test]
    fn exported_patches_evaluate_to_f() {
        let mut rng = Rng::new(61);
        let solid = Solid2::regular(
            [3, 2],
            DVec2::new(-1.0, 2.0),
            DVec2::new(0.5, 3.0),
            |[_, _]| rng.range(-1.0, 1.0),
        )
        .unwrap();
        let text = solid2_hf(&solid).unwrap();
        for _ in 0..50 {
            let p = DVec2::new(rng.range(-1.2, 0.7), rng.range(1.8, 3.2));
            let got = run_hf(&text, [p.x, p.y, rng.range(-5.0, 5.0)]);
            let want = solid.f(p);
            assert!(
                (got - want).abs() <= 1e-12 * (1.0 + want.abs()),
                "{p}: {got} vs {want}"
            );
        }
    }
}
