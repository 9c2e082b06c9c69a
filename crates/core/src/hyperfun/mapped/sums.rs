//! The evaluations the program repeats: `S`, `S_ξ` and the Jacobian as sums factored along the
//! axes, and the spline guess of the continuation.

use alloc::format;
use alloc::string::String;
use alloc::vec::Vec;
use core::fmt::Write as _;

use super::{Guess, MappedLeaf};
use crate::hyperfun::num;
use crate::inverse::tps::Kernel;

/// The loop of axis `a` of the factored sums ([`super::write_mapped`]'s `eval`): accumulators
/// `{tag}z{a}v{c}` (the value of coordinate `c`, `0` for ξ) and `{tag}z{a}g{b}{c}` (its partial
/// along axis `b ≥ a`), summed over the axis's control points; the innermost axis reads the net at
/// the running index `{tag}ix`.
pub(super) fn sum_level(out: &mut String, leaf: &MappedLeaf, tag: &str, a: usize) {
    let d = leaf.dims.len();
    let axes = ["u", "v", "w"];
    let pad = "  ".repeat(a + 1);
    let k = format!("{tag}k{}", axes[a]);
    let (b, dv) = (
        format!("{tag}b{}[{k}]", axes[a]),
        format!("{tag}d{}[{k}]", axes[a]),
    );
    let mut zero = Vec::new();
    for c in 0..=d {
        zero.push(format!("{tag}z{a}v{c} = 0;"));
    }
    for g in a..d {
        for c in 1..=d {
            zero.push(format!("{tag}z{a}g{g}{c} = 0;"));
        }
    }
    let _ = writeln!(out, "{pad}{}", zero.join(" "));
    if a + 1 == d {
        // The innermost axis unrolled (its basis at constant indices): no loop test or counter
        // per control point.
        for kk in 1..=leaf.dims[a] {
            let (b, dv) = (
                format!("{tag}b{}[{kk}]", axes[a]),
                format!("{tag}d{}[{kk}]", axes[a]),
            );
            for c in 1..=d {
                let _ = writeln!(
                    out,
                    "{pad}{tag}z{a}v{c} = {tag}z{a}v{c} + {b} * {tag}p{c}[{tag}ix];\n\
                     {pad}{tag}z{a}g{a}{c} = {tag}z{a}g{a}{c} + {dv} * {tag}p{c}[{tag}ix];"
                );
            }
            let _ = writeln!(
                out,
                "{pad}{tag}z{a}v0 = {tag}z{a}v0 + {b} * {tag}xi[{tag}ix];\n{pad}{tag}ix = {tag}ix + 1;"
            );
        }
        return;
    }
    let _ = writeln!(
        out,
        "{pad}{k} = 1;\n{pad}while ({k} <= {}) loop",
        leaf.dims[a]
    );
    let inner = format!("{pad}  ");
    sum_level(out, leaf, tag, a + 1);
    let next = a + 1;
    for c in 0..=d {
        let _ = writeln!(
            out,
            "{inner}{tag}z{a}v{c} = {tag}z{a}v{c} + {b} * {tag}z{next}v{c};"
        );
    }
    for c in 1..=d {
        let _ = writeln!(
            out,
            "{inner}{tag}z{a}g{a}{c} = {tag}z{a}g{a}{c} + {dv} * {tag}z{next}v{c};"
        );
    }
    for g in next..d {
        for c in 1..=d {
            let _ = writeln!(
                out,
                "{inner}{tag}z{a}g{g}{c} = {tag}z{a}g{g}{c} + {b} * {tag}z{next}g{g}{c};"
            );
        }
    }
    let _ = writeln!(out, "{inner}{k} = {k} + 1;\n{pad}endloop;");
}

/// Lines that set `{tag}h1..{tag}hd` to the spline guess at the point `q`, summed in the order of
/// [`crate::inverse::tps::Spline::eval`].
pub(super) fn write_guess(body: &mut String, g: &Guess, tag: &str, q: &str, d: usize) {
    for c in 1..=d {
        let _ = writeln!(
            body,
            "    {tag}hq{c} = ({q}[{c}] - {}) * {};",
            num(g.centre[c - 1]),
            num(g.inv_scale)
        );
    }
    for a in 0..d {
        let mut sum = num(g.affine[0][a]);
        for c in 0..d {
            let _ = write!(sum, " + {} * {tag}hq{}", num(g.affine[1 + c][a]), c + 1);
        }
        let _ = writeln!(body, "    {tag}h{} = {sum};", a + 1);
    }
    let sites = g.sites[0].len();
    if sites == 0 {
        return;
    }
    let r2 = (1..=d)
        .map(|c| format!("({tag}hs{c}[{tag}hk] - {tag}hq{c}) * ({tag}hs{c}[{tag}hk] - {tag}hq{c})"))
        .collect::<Vec<_>>()
        .join(" + ");
    let _ = writeln!(
        body,
        "    {tag}hk = 1;\n    while ({tag}hk <= {sites}) loop"
    );
    let _ = writeln!(body, "      {tag}hr = {r2};");
    match g.kernel {
        Kernel::ThinPlate => {
            let _ = writeln!(
                body,
                "      if ({tag}hr > 0) then {tag}hp = 0.5 * {tag}hr * log({tag}hr); \
                 else {tag}hp = 0; endif;"
            );
        }
        Kernel::Linear => {
            let _ = writeln!(body, "      {tag}hp = sqrt({tag}hr);");
        }
        Kernel::Cubic => {
            let _ = writeln!(body, "      {tag}hp = {tag}hr * sqrt({tag}hr);");
        }
    }
    for a in 1..=d {
        let _ = writeln!(
            body,
            "      {tag}h{a} = {tag}h{a} + {tag}hw{a}[{tag}hk] * {tag}hp;"
        );
    }
    let _ = writeln!(body, "      {tag}hk = {tag}hk + 1;\n    endloop;");
}
