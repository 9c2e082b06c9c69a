//! A space-mapped Bézier leaf in HyperFun: the inverse map written in the language itself.
//!
//! `f(x)` is the largest clipped `S_ξ(u) & F_s(u)` over the preimages `u` of `x` in the closed
//! parameter box (`S(u) = x`), and where `x` has none the negative continuation: `S_ξ & F_s` at the
//! root of the polynomial map extended past the box, forced negative (the first paper's §3.3.2 and
//! DESIGN §5, as `eval` computes it). The file finds the preimages as `eval` does on its fast
//! path, with HyperFun's arrays, loops and conditionals:
//!
//! - a table of seeds over the parameter box with their images (constants, computed here by the
//!   forward map), the nearest seed found by a loop;
//! - Newton's method from the nearest seed and from every seed whose image lies within a radius
//!   that bounds how far a seed's image can be from a preimage's (the net's Lipschitz bound along
//!   each axis times the seed spacing): `S` and its Jacobian by loops over the control points with
//!   the Bernstein basis and its derivatives written out per axis, each step by Cramer's rule,
//!   stopped at a root by the same tolerances as `eval` (relative to the net's extent);
//! - the largest clipped value over the roots in the box; where the map is certified injective
//!   the first root is the only one and ends the search.
//!
//! Where the map is certified injective the value is `eval`'s to rounding; where it folds the seeds
//! are denser (three per degree along each axis), which finds the roots that `eval`'s atlas finds
//! except within rounding of a fold.

// Axes index the net's counts, the seed tables and the names at once.
#![allow(clippy::needless_range_loop)]

use alloc::boxed::Box;
use alloc::format;
use alloc::string::String;
use alloc::vec::Vec;
use core::fmt::Write as _;

use super::{basis_term, num};
use crate::dim::Control;
use crate::dim::{Dim, Dimension};
use crate::inverse::Forward;
use crate::solid::Solid;
use crate::tensor::Tensor;

/// The most seeds one leaf's table holds.
const MAX_SEEDS: usize = 4096;

/// Newton steps from a seed towards a root in the box.
const ROOT_STEPS: usize = 40;

/// A positive number below any determinant or value the file meets, and one above any squared
/// distance: exponents whose digits after the first are zeros, which HyperFun's scanner reads
/// right (it misreads `1e-15` as `1e-5`; see [`super::num`]).
const TINY: &str = "1e-300";
const HUGE: &str = "1e300";

/// Newton steps towards the continuation's root past the box.
const CONTINUATION_STEPS: usize = 30;

/// A space-mapped Bézier leaf as its export needs it, whatever its dimension.
pub(super) struct MappedLeaf {
    /// Control points per axis.
    dims: Vec<usize>,
    /// The control points' spatial coordinates, one list per coordinate, in storage order (the
    /// last axis fastest).
    spatial: Vec<Vec<f64>>,
    /// The control points' ξ in the same order.
    xi: Vec<f64>,
    /// Whether the map is certified injective (one preimage at most).
    injective: bool,
    /// The net's extent: the unit of residuals.
    scale: f64,
    /// The seeds' parameters, one list per axis.
    seeds: Vec<Vec<f64>>,
    /// The seeds' images, one list per coordinate.
    images: Vec<Vec<f64>>,
    /// A seed whose image is farther than this from the point is not the nearest seed of any of
    /// its preimages.
    radius: f64,
}

/// The parts of a space-mapped solid; `None` for a regular grid (which has a closed form).
pub(super) fn mapped_leaf<const D: usize>(s: &Solid<D>) -> Option<MappedLeaf>
where
    Dim<D>: Dimension<D>,
{
    let map = s.inverse()?;
    Some(mapped_net(s.net(), map.injective()))
}

/// The parts of any net as a space mapping (a regular cell of a moved piecewise solid too, whose
/// map is linear and injective).
pub(super) fn mapped_net<const D: usize>(net: &Tensor<Control<D>, D>, injective: bool) -> MappedLeaf
where
    Dim<D>: Dimension<D>,
{
    let dims = net.dims();
    let points: Vec<([f64; D], f64)> = net.points().iter().map(|&c| Dim::<D>::split(c)).collect();
    let spatial: Vec<Vec<f64>> = (0..D)
        .map(|c| points.iter().map(|(x, _)| x[c]).collect())
        .collect();
    let xi = points.iter().map(|&(_, v)| v).collect();
    let (mut lo, mut hi) = ([f64::INFINITY; D], [f64::NEG_INFINITY; D]);
    for (x, _) in &points {
        for c in 0..D {
            lo[c] = lo[c].min(x[c]);
            hi[c] = hi[c].max(x[c]);
        }
    }
    let scale = (0..D)
        .map(|c| (hi[c] - lo[c]).max(lo[c].abs()).max(hi[c].abs()))
        .fold(0.0f64, f64::max);
    // Seeds per axis: a few per degree, more where the map may fold, within the table's cap.
    let per_degree = if injective { 1 } else { 3 };
    let mut grid: [usize; D] = core::array::from_fn(|a| per_degree * (dims[a] - 1) + 2);
    while grid.iter().product::<usize>() > MAX_SEEDS {
        let widest = (0..D).max_by_key(|&a| grid[a]).unwrap_or(0);
        grid[widest] -= 1;
    }
    let count: usize = grid.iter().product();
    let mut seeds: Vec<Vec<f64>> = (0..D).map(|_| Vec::with_capacity(count)).collect();
    let mut images: Vec<Vec<f64>> = (0..D).map(|_| Vec::with_capacity(count)).collect();
    for flat in 0..count {
        let mut rest = flat;
        let mut u = [0.0; D];
        for a in (0..D).rev() {
            u[a] = (rest % grid[a]) as f64 / (grid[a] - 1) as f64;
            rest /= grid[a];
        }
        let e = net.forward(u);
        for a in 0..D {
            seeds[a].push(u[a]);
            images[a].push(e.x[a]);
        }
    }
    // |∂S/∂u_a| ≤ n_a · the longest step between neighbours along a; a preimage's nearest seed
    // is within half a spacing along each axis. Twice that, so that the next seeds are tried too.
    let radius = (0..D)
        .map(|a| {
            let n = dims[a] - 1;
            let stride: usize = dims[a + 1..].iter().product();
            let longest = (0..points.len())
                .filter(|i| (i / stride) % dims[a] < n)
                .map(|i| {
                    let (p, q) = (points[i].0, points[i + stride].0);
                    libm::sqrt((0..D).map(|c| (q[c] - p[c]) * (q[c] - p[c])).sum::<f64>())
                })
                .fold(0.0f64, f64::max);
            n as f64 * longest / (grid[a] - 1) as f64
        })
        .sum::<f64>();
    MappedLeaf {
        dims: dims.to_vec(),
        spatial,
        xi,
        injective,
        scale: scale.max(f64::MIN_POSITIVE),
        seeds,
        images,
        radius,
    }
}

impl MappedLeaf {
    /// How many numbers the export writes for this leaf (its arrays' lengths).
    pub(super) fn numbers(&self) -> usize {
        let d = self.dims.len();
        (d + 1) * self.xi.len() + 2 * d * self.seeds[0].len()
    }
}

/// The HyperFun lines of one space-mapped net at the coordinates in array `q`, its names
/// prefixed by `tag`, its arrays added to `arrays`. `cell` is a piecewise solid's cell and cell
/// counts: its clipping is on the global parameter `(cell + u) / cells`.
pub(super) fn write_mapped(
    leaf: &MappedLeaf,
    tag: &str,
    q: &str,
    cell: Option<(&[usize], &[usize])>,
    arrays: &mut Vec<(String, usize)>,
) -> MappedCode {
    let mut setup = String::new();
    let body = &mut setup;
    let d = leaf.dims.len();
    let axes = ["u", "v", "w"];
    let seeds = leaf.seeds[0].len();
    let mut array = |name: String, values: &[f64], body: &mut String| {
        arrays.push((name.clone(), values.len()));
        // Array constants are written bare (`-0.5`), as HyperFun's grammar has them.
        let items: Vec<String> = values.iter().map(|&x| format!("{x}")).collect();
        let lines: Vec<String> = items.chunks(8).map(|c| c.join(", ")).collect();
        let _ = writeln!(body, "  {name} = [{}];", lines.join(",\n    "));
    };
    let _ = writeln!(
        body,
        "  -- The inverse map: the preimages u of the point (S(u) = x) by Newton's method from \
         {seeds} seeds over the\n  -- parameter box{}; f is the largest clipped S_xi over them, \
         or with none the negative continuation.",
        if leaf.injective {
            " (the map is certified injective: one preimage at most)"
        } else {
            " (the map may fold)"
        }
    );
    for c in 0..d {
        array(format!("{tag}p{}", c + 1), &leaf.spatial[c], body);
    }
    array(format!("{tag}xi"), &leaf.xi, body);
    for a in 0..d {
        array(format!("{tag}s{}", axes[a]), &leaf.seeds[a], body);
    }
    for c in 0..d {
        array(format!("{tag}i{}", c + 1), &leaf.images[c], body);
    }
    for a in 0..d {
        let n1 = leaf.dims[a];
        arrays.push((format!("{tag}b{}", axes[a]), n1));
        arrays.push((format!("{tag}d{}", axes[a]), n1));
    }

    // S, its Jacobian and S_xi at the parameters {tag}u, {tag}v[, {tag}w].
    let mut eval = String::new();
    for a in 0..d {
        let (t, n) = (format!("{tag}{}", axes[a]), leaf.dims[a] - 1);
        let s = format!("{t}s");
        let _ = writeln!(eval, "  {s} = 1 - {t};");
        for i in 0..=n {
            let _ = writeln!(
                eval,
                "  {tag}b{}[{}] = {};",
                axes[a],
                i + 1,
                term(n, i, &t, &s)
            );
            // d/dt B_i^n = n (B_{i-1}^{n-1} − B_i^{n-1}), the first and last with one term.
            let derivative = if n == 0 {
                String::from("0")
            } else if i == 0 {
                format!("-{n} * ({})", term(n - 1, 0, &t, &s))
            } else if i == n {
                format!("{n} * ({})", term(n - 1, n - 1, &t, &s))
            } else {
                format!(
                    "{n} * ({} - {})",
                    term(n - 1, i - 1, &t, &s),
                    term(n - 1, i, &t, &s)
                )
            };
            let _ = writeln!(eval, "  {tag}d{}[{}] = {derivative};", axes[a], i + 1);
        }
    }
    let mut zero: Vec<String> = (1..=d).map(|c| format!("{tag}x{c}")).collect();
    zero.push(format!("{tag}xv"));
    for a in 1..=d {
        for c in 1..=d {
            zero.push(format!("{tag}j{a}{c}"));
        }
    }
    for z in &zero {
        let _ = writeln!(eval, "  {z} = 0;");
    }
    // One loop per axis over the control points, the last axis innermost.
    let index = |a: usize| format!("{tag}k{}", axes[a]);
    for a in 0..d {
        let pad = "  ".repeat(a + 1);
        let _ = writeln!(eval, "{pad}{} = 1;", index(a));
        let _ = writeln!(eval, "{pad}while ({} <= {}) loop", index(a), leaf.dims[a]);
    }
    let pad = "  ".repeat(d + 1);
    // The flat index: ((ku − 1)·m1 + kv − 1)·l1 + kw.
    let mut flat = format!("{} - 1", index(0));
    for a in 1..d {
        flat = format!("({flat}) * {} + {} - 1", leaf.dims[a], index(a));
    }
    let _ = writeln!(eval, "{pad}{tag}ix = {flat} + 1;");
    let factor = |a: usize, derivative: bool| {
        format!(
            "{tag}{}{}[{}]",
            if derivative { "d" } else { "b" },
            axes[a],
            index(a)
        )
    };
    let product = |along: Option<usize>| {
        (0..d)
            .map(|a| factor(a, along == Some(a)))
            .collect::<Vec<_>>()
            .join(" * ")
    };
    let _ = writeln!(eval, "{pad}{tag}bb = {};", product(None));
    for a in 0..d {
        let _ = writeln!(eval, "{pad}{tag}g{} = {};", a + 1, product(Some(a)));
    }
    for c in 1..=d {
        let _ = writeln!(
            eval,
            "{pad}{tag}x{c} = {tag}x{c} + {tag}bb * {tag}p{c}[{tag}ix];"
        );
    }
    let _ = writeln!(eval, "{pad}{tag}xv = {tag}xv + {tag}bb * {tag}xi[{tag}ix];");
    for a in 1..=d {
        for c in 1..=d {
            let _ = writeln!(
                eval,
                "{pad}{tag}j{a}{c} = {tag}j{a}{c} + {tag}g{a} * {tag}p{c}[{tag}ix];"
            );
        }
    }
    for a in (0..d).rev() {
        let pad = "  ".repeat(a + 1);
        let _ = writeln!(eval, "{pad}  {} = {} + 1;", index(a), index(a));
        let _ = writeln!(eval, "{pad}endloop;");
    }
    // The clipped value at the current parameters.
    let params: Vec<String> = (0..d).map(|a| format!("{tag}{}", axes[a])).collect();
    let clip = params
        .iter()
        .enumerate()
        .map(|(a, t)| match cell {
            None => format!("({t} * (1 - {t}))"),
            Some((at, cells)) => {
                let g = format!("(({} + {t}) / {})", at[a], cells[a]);
                format!("({g} * (1 - {g}))")
            }
        })
        .reduce(|a, b| format!("({a} & {b})"))
        .unwrap_or_default();

    // Newton's method from the parameters in place, at most `{tag}max` steps: `{tag}ok` = 1 at a
    // root (S evaluated there), 0 where it stalls, escapes or meets a singular Jacobian.
    let mut newton = String::new();
    let w = &mut newton;
    let _ = writeln!(w, "  {tag}go = 1; {tag}ok = 0; {tag}set = 0; {tag}it = 0;");
    let _ = writeln!(w, "  while ({tag}go = 1) loop");
    w.push_str(&indent(&eval, 2));
    for c in 1..=d {
        let _ = writeln!(w, "    {tag}r{c} = {tag}x{c} - {q}[{c}];");
    }
    largest_abs(w, "    ", &format!("{tag}res"), &format!("{tag}r"), d);
    let _ = writeln!(
        w,
        "    if ({tag}res <= {} or ({tag}set = 1 and {tag}res <= {})) then",
        num(leaf.scale * 1e-15),
        num(leaf.scale * 1e-9)
    );
    let _ = writeln!(w, "      {tag}ok = 1; {tag}go = 0;");
    let _ = writeln!(w, "    else");
    let _ = writeln!(
        w,
        "      if ({tag}set = 1 or {tag}it >= {tag}max) then {tag}go = 0; else"
    );
    // Cramer's rule for J δ = r, J[row c][column a] = ∂S_c/∂u_a = {tag}j{a}{c}.
    let m = |row: usize, col: usize| format!("{tag}j{col}{row}");
    let r = |row: usize| format!("{tag}r{row}");
    let det = |cols: &[&dyn Fn(usize) -> String]| -> String {
        if d == 2 {
            format!(
                "({} * {} - {} * {})",
                cols[0](1),
                cols[1](2),
                cols[1](1),
                cols[0](2)
            )
        } else {
            let e = |row: usize, col: usize| cols[col - 1](row);
            format!(
                "({a} * ({e22} * {e33} - {e32} * {e23}) - {b} * ({e21} * {e33} - {e31} * {e23}) \
                 + {c} * ({e21} * {e32} - {e31} * {e22}))",
                a = e(1, 1),
                b = e(1, 2),
                c = e(1, 3),
                e21 = e(2, 1),
                e22 = e(2, 2),
                e23 = e(2, 3),
                e31 = e(3, 1),
                e32 = e(3, 2),
                e33 = e(3, 3),
            )
        }
    };
    let columns: Vec<Box<dyn Fn(usize) -> String>> = (1..=d)
        .map(|col| Box::new(move |row: usize| m(row, col)) as Box<dyn Fn(usize) -> String>)
        .collect();
    let refs: Vec<&dyn Fn(usize) -> String> = columns.iter().map(|b| b.as_ref()).collect();
    let _ = writeln!(w, "        {tag}det = {};", det(&refs));
    let _ = writeln!(
        w,
        "        if (abs({tag}det) <= {TINY}) then {tag}go = 0; else"
    );
    // 1 / det without dividing by less than 1e-6 in magnitude, which HyperFun refuses ("Division
    // by zero"): det scaled by 2^20 (exactly) until it is that large, the scale divided by it.
    let _ = writeln!(w, "          {tag}sc = {tag}det; {tag}inv = 1;");
    let _ = writeln!(
        w,
        "          while (abs({tag}sc) < 0.000001) loop\n            \
         {tag}sc = {tag}sc * 1048576; {tag}inv = {tag}inv * 1048576;\n          endloop;"
    );
    let _ = writeln!(w, "          {tag}inv = {tag}inv / {tag}sc;");
    for a in 1..=d {
        let mut with_r = refs.clone();
        with_r[a - 1] = &r;
        let _ = writeln!(w, "          {tag}e{a} = {} * {tag}inv;", det(&with_r));
    }
    for a in 1..=d {
        let t = &params[a - 1];
        let _ = writeln!(w, "          {t} = {t} - {tag}e{a};");
    }
    largest_abs(
        w,
        "          ",
        &format!("{tag}step"),
        &format!("{tag}e"),
        d,
    );
    let _ = writeln!(
        w,
        "          if ({tag}step <= {}) then {tag}set = 1; endif;",
        num(1e-13)
    );
    let escaped: Vec<String> = params.iter().map(|t| format!("abs({t}) >= 8")).collect();
    let _ = writeln!(
        w,
        "          if ({}) then {tag}go = 0; endif;",
        escaped.join(" or ")
    );
    let _ = writeln!(w, "          {tag}it = {tag}it + 1;");
    let _ = writeln!(w, "        endif;\n      endif;\n    endif;\n  endloop;");

    let distance = |k: &str| {
        (1..=d)
            .map(|c| format!("({tag}i{c}[{k}] - {q}[{c}]) * ({tag}i{c}[{k}] - {q}[{c}])"))
            .collect::<Vec<_>>()
            .join(" + ")
    };
    let seed_at = |k: &str| {
        params
            .iter()
            .enumerate()
            .map(|(a, t)| format!("{t} = {tag}s{}[{k}];", axes[a]))
            .collect::<Vec<_>>()
            .join(" ")
    };
    // The nearest seed.
    let mut search = String::new();
    let body = &mut search;
    let _ = writeln!(body, "  {tag}near = 1; {tag}nd = {HUGE}; {tag}n = 1;");
    let _ = writeln!(body, "  while ({tag}n <= {seeds}) loop");
    let _ = writeln!(body, "    {tag}dd = {};", distance(&format!("{tag}n")));
    let _ = writeln!(
        body,
        "    if ({tag}dd < {tag}nd) then {tag}nd = {tag}dd; {tag}near = {tag}n; endif;"
    );
    let _ = writeln!(body, "    {tag}n = {tag}n + 1;\n  endloop;");
    // Newton from the nearest seed (n = 0), then from every seed within the radius.
    let radius = leaf.radius * leaf.radius;
    let _ = writeln!(
        body,
        "  {tag}found = 0; {tag}best = 0; {tag}n = 0; {tag}max = {ROOT_STEPS};"
    );
    let _ = writeln!(body, "  while ({tag}n <= {seeds}) loop");
    let _ = writeln!(body, "    {tag}try = 0;");
    let _ = writeln!(
        body,
        "    if ({tag}n = 0) then {tag}try = 1; {tag}k = {tag}near; else {tag}k = {tag}n; endif;"
    );
    let more = if leaf.injective {
        format!(" and {tag}found = 0")
    } else {
        String::new()
    };
    let _ = writeln!(
        body,
        "    if ({tag}n > 0 and {tag}n /= {tag}near{more}) then\n      \
         {tag}dd = {};\n      if ({tag}dd <= {}) then {tag}try = 1; endif;\n    endif;",
        distance(&format!("{tag}n")),
        num(radius)
    );
    let _ = writeln!(body, "    if ({tag}try = 1) then");
    let _ = writeln!(body, "      {}", seed_at(&format!("{tag}k")));
    body.push_str(&indent(&newton, 4));
    let inside: Vec<String> = params
        .iter()
        .map(|t| format!("{t} >= {} and {t} <= {}", num(-1e-12), num(1.0 + 1e-12)))
        .collect();
    let _ = writeln!(
        body,
        "      if ({tag}ok = 1 and {}) then",
        inside.join(" and ")
    );
    // On the box's boundary within rounding: clamped, and S_xi taken there (as eval does).
    let _ = writeln!(body, "        {tag}cl = 0;");
    for t in &params {
        let _ = writeln!(
            body,
            "        if ({t} < 0) then {t} = 0; {tag}cl = 1; endif;\n        \
             if ({t} > 1) then {t} = 1; {tag}cl = 1; endif;"
        );
    }
    let _ = writeln!(body, "        if ({tag}cl = 1) then");
    body.push_str(&indent(&eval, 8));
    let _ = writeln!(body, "        endif;");
    let _ = writeln!(body, "        {tag}val = {tag}xv & {clip};");
    let _ = writeln!(
        body,
        "        if ({tag}found = 0 or {tag}val > {tag}best) then {tag}best = {tag}val; endif;"
    );
    let _ = writeln!(body, "        {tag}found = 1;");
    let _ = writeln!(body, "      endif;\n    endif;");
    let _ = writeln!(body, "    {tag}n = {tag}n + 1;\n  endloop;");
    // No preimage: the continuation past the box, from the nearest seed.
    let mut continuation = String::new();
    let body = &mut continuation;
    let _ = writeln!(
        body,
        "    {} {tag}max = {CONTINUATION_STEPS};",
        seed_at(&format!("{tag}near"))
    );
    body.push_str(&indent(&newton, 2));
    let _ = writeln!(body, "    if ({tag}ok = 0) then");
    let _ = writeln!(body, "      {}", seed_at(&format!("{tag}near")));
    body.push_str(&indent(&eval, 4));
    let _ = writeln!(body, "    endif;");
    let _ = writeln!(body, "    {tag}cont = {tag}xv & {clip};");
    let _ = writeln!(
        body,
        "    -- Outside the image f is negative.\n    if ({tag}cont >= 0) then {tag}cont = -{tag}cont - {TINY}; endif;"
    );
    MappedCode {
        setup,
        search,
        continuation,
        found: format!("{tag}found"),
        best: format!("{tag}best"),
        cont: format!("{tag}cont"),
    }
}

/// One net's lines: `setup` (its constant arrays), `search` (sets `found` to 1 where the point has
/// a preimage, `best` to the largest clipped value over them) and `continuation` (sets `cont` to
/// the negative continuation; it needs `search` run before it).
pub(super) struct MappedCode {
    pub(super) setup: String,
    pub(super) search: String,
    pub(super) continuation: String,
    pub(super) found: String,
    pub(super) best: String,
    pub(super) cont: String,
}

impl MappedCode {
    /// The lines of a single solid: `f` is the best value, or the continuation; the variable.
    pub(super) fn single(&self, tag: &str, body: &mut String) -> String {
        body.push_str(&self.setup);
        body.push_str(&self.search);
        let _ = writeln!(
            body,
            "  if ({} = 1) then {tag}f = {}; else",
            self.found, self.best
        );
        body.push_str(&indent(&self.continuation, 2));
        let _ = writeln!(body, "    {tag}f = {};\n  endif;", self.cont);
        format!("{tag}f")
    }
}

/// Lines that set `var` to the largest `|{of}1|`, …, `|{of}d|`, indented by `pad`.
fn largest_abs(w: &mut String, pad: &str, var: &str, of: &str, d: usize) {
    let _ = writeln!(w, "{pad}{var} = abs({of}1);");
    for c in 2..=d {
        let _ = writeln!(
            w,
            "{pad}if (abs({of}{c}) > {var}) then {var} = abs({of}{c}); endif;"
        );
    }
}

/// `B_i^n(t)` written out ([`basis_term`], with `1` for degree zero).
fn term(n: usize, i: usize, t: &str, s: &str) -> String {
    let b = basis_term(n, i, t, s);
    if b.is_empty() { String::from("1") } else { b }
}

/// `text` with every line indented by `by` more spaces.
pub(super) fn indent(text: &str, by: usize) -> String {
    let pad = " ".repeat(by);
    text.lines().fold(String::new(), |mut out, line| {
        let _ = writeln!(out, "{pad}{line}");
        out
    })
}
