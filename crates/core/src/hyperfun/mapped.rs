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
use crate::inverse::tps::Kernel;
use crate::inverse::{Forward, InverseMap};
use crate::solid::Solid;
use crate::tensor::Tensor;

/// The most seeds one leaf's table holds.
const MAX_SEEDS: usize = 4096;

/// Newton steps from a seed towards a root in the box (as many as eval's fast path takes).
const ROOT_STEPS: usize = 12;

/// The seeds an injective map tries where Newton from the guess fails: the nearest few to the
/// point, among those within the radius (the others cannot be a preimage's nearest seed).
const NEAREST_SEEDS: usize = 4;

/// A seed's Newton iterate this far from the box's centre along an axis (in parameters) has left
/// for a root past the box: the seed is dropped.
const SEED_ESCAPE: f64 = 2.0;

/// The continuation's Newton escapes where eval's does (`|u| ≥ 8`).
const ESCAPE: f64 = 8.0;

/// A Newton step this short has settled (the residual is checked once more), as in `eval`. Past
/// the box (the continuation, `|u|` up to 8) the polynomial's terms cancel and a root may never
/// settle to this: `eval` then takes the spline guess, and the file does the same unless its own
/// rounding, which differs, lets it settle (a few points in a thousand far outside a net, both
/// values negative).
const SETTLED_STEP: f64 = 1e-13;

/// A positive number below any determinant or value the file meets, and one above any squared
/// distance: exponents whose digits after the first are zeros, which HyperFun's scanner reads
/// right (it misreads `1e-15` as `1e-5`; see [`super::num`]).
const TINY: &str = "1e-300";
const HUGE: &str = "1e300";

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
    /// Where the continuation's Newton starts: the inverse map's spline guess, as `eval` starts
    /// it ([`crate::inverse::InverseMap::outside`]); `None` for a cell that is a linear map (no
    /// inverse map), whose continuation starts at the nearest seed and converges in one step.
    guess: Option<Guess>,
    /// The continuation's Newton steps at most: `eval`'s.
    outside_steps: usize,
    /// The control points' bounding box, per coordinate: it holds the image.
    bounds: Vec<(f64, f64)>,
}

/// A spline guess's numbers ([`crate::inverse::tps::Spline::parts`]), one list per coordinate.
struct Guess {
    kernel: Kernel,
    centre: Vec<f64>,
    inv_scale: f64,
    /// The normalised sites, one list per coordinate.
    sites: Vec<Vec<f64>>,
    /// The sites' weights, one list per parameter.
    weights: Vec<Vec<f64>>,
    /// Row 0 the constant, row `1 + c` the coefficients of coordinate `c`.
    affine: Vec<Vec<f64>>,
}

impl Guess {
    fn of<const D: usize>(map: &InverseMap<D>) -> Self {
        let parts = map.spline().parts();
        Self {
            kernel: parts.kernel,
            centre: parts.centre.to_vec(),
            inv_scale: parts.inv_scale,
            sites: (0..D)
                .map(|c| parts.sites.iter().map(|s| s[c]).collect())
                .collect(),
            weights: (0..D)
                .map(|a| parts.weights.iter().map(|w| w[a]).collect())
                .collect(),
            affine: parts.affine.iter().map(|row| row.to_vec()).collect(),
        }
    }
}

/// The parts of a space-mapped solid; `None` for a regular grid (which has a closed form).
pub(super) fn mapped_leaf<const D: usize>(s: &Solid<D>) -> Option<MappedLeaf>
where
    Dim<D>: Dimension<D>,
{
    Some(mapped_net(s.net(), Some(s.inverse()?)))
}

/// The parts of any net as a space mapping with its inverse map, or without one a regular cell of
/// a moved piecewise solid (whose map is linear and injective).
pub(super) fn mapped_net<const D: usize>(
    net: &Tensor<Control<D>, D>,
    map: Option<&InverseMap<D>>,
) -> MappedLeaf
where
    Dim<D>: Dimension<D>,
{
    let injective = map.is_none_or(InverseMap::injective);
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
    // is within half a spacing along each axis. Twice that where the map may fold, so that the
    // next seeds are tried too.
    let reach = if injective { 0.5 } else { 1.0 };
    let radius = reach
        * (0..D)
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
        guess: map.map(Guess::of),
        bounds: (0..D).map(|c| (lo[c], hi[c])).collect(),
        // As `InverseMap::outside`: 30 steps where the map is injective, else 8 (within a query
        // budget that a single point never exhausts).
        outside_steps: if injective { 30 } else { 8 },
    }
}

impl MappedLeaf {
    /// How many numbers the export writes for this leaf (its arrays' lengths).
    pub(super) fn numbers(&self) -> usize {
        let d = self.dims.len();
        let guess = self.guess.as_ref().map_or(0, |g| 2 * d * g.sites[0].len());
        (d + 1) * self.xi.len() + 2 * d * self.seeds[0].len() + guess
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
    if let Some(g) = &leaf.guess
        && !g.sites[0].is_empty()
    {
        for c in 0..d {
            array(format!("{tag}hs{}", c + 1), &g.sites[c], body);
        }
        for a in 0..d {
            array(format!("{tag}hw{}", a + 1), &g.weights[a], body);
        }
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
    // S, S_xi and the Jacobian by sums factored along the axes, the last innermost: each level
    // sums the level inside it against its axis's basis (the value) and the basis's derivative
    // (its own partial), and carries the inner partials against the basis: about 2D + 1 products
    // per control point instead of D² + 3D + 1.
    let _ = writeln!(eval, "  {tag}ix = 1;");
    sum_level(&mut eval, leaf, tag, 0);
    for c in 1..=d {
        let _ = writeln!(eval, "  {tag}x{c} = {tag}z0v{c};");
    }
    let _ = writeln!(eval, "  {tag}xv = {tag}z0v0;");
    for a in 1..=d {
        for c in 1..=d {
            let _ = writeln!(eval, "  {tag}j{a}{c} = {tag}z0g{}{c};", a - 1);
        }
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
        "    if (({tag}res <= {} and {tag}it < {tag}max) or ({tag}set = 1 and {tag}res <= {})) then",
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
        num(SETTLED_STEP)
    );
    let escaped: Vec<String> = params
        .iter()
        .map(|t| format!("abs({t}) >= {tag}esc"))
        .collect();
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
    // A root Newton reached in the closed box: clamped onto it within rounding (S_xi taken there,
    // as eval does), its clipped value the best so far.
    let inside: Vec<String> = params
        .iter()
        .map(|t| format!("{t} >= {} and {t} <= {}", num(-1e-12), num(1.0 + 1e-12)))
        .collect();
    let inside = inside.join(" and ");
    let mut accept = String::new();
    let _ = writeln!(accept, "{tag}cl = 0;");
    for t in &params {
        let _ = writeln!(
            accept,
            "if ({t} < 0) then {t} = 0; {tag}cl = 1; endif;\n\
             if ({t} > 1) then {t} = 1; {tag}cl = 1; endif;"
        );
    }
    let _ = writeln!(accept, "if ({tag}cl = 1) then");
    accept.push_str(&indent(&eval, 0));
    let _ = writeln!(accept, "endif;");
    let _ = writeln!(accept, "{tag}val = {tag}xv & {clip};");
    let _ = writeln!(
        accept,
        "if ({tag}found = 0 or {tag}val > {tag}best) then {tag}best = {tag}val; endif;"
    );
    let _ = writeln!(accept, "{tag}found = 1;");

    // The seeds: the nearest one, then every one within the radius (an injective map stops at
    // its first root).
    let mut seeded = String::new();
    let body = &mut seeded;
    let _ = writeln!(body, "{tag}near = 1; {tag}nd = {HUGE}; {tag}n = 1;");
    let _ = writeln!(body, "while ({tag}n <= {seeds}) loop");
    let _ = writeln!(body, "  {tag}dd = {};", distance(&format!("{tag}n")));
    let _ = writeln!(
        body,
        "  if ({tag}dd < {tag}nd) then {tag}nd = {tag}dd; {tag}near = {tag}n; endif;"
    );
    let _ = writeln!(body, "  {tag}n = {tag}n + 1;\nendloop;");
    let radius = leaf.radius * leaf.radius;
    let _ = writeln!(
        body,
        "{tag}n = 0; {tag}max = {ROOT_STEPS}; {tag}esc = {};",
        num(SEED_ESCAPE)
    );
    let _ = writeln!(body, "while ({tag}n <= {seeds}) loop");
    let _ = writeln!(body, "  {tag}try = 0;");
    let _ = writeln!(
        body,
        "  if ({tag}n = 0) then {tag}try = 1; {tag}k = {tag}near; else {tag}k = {tag}n; endif;"
    );
    let more = if leaf.injective {
        format!(" and {tag}found = 0")
    } else {
        String::new()
    };
    let _ = writeln!(
        body,
        "  if ({tag}n > 0 and {tag}n /= {tag}near{more}) then\n    \
         {tag}dd = {};\n    if ({tag}dd <= {}) then {tag}try = 1; endif;\n  endif;",
        distance(&format!("{tag}n")),
        num(radius)
    );
    let _ = writeln!(body, "  if ({tag}try = 1) then");
    let _ = writeln!(body, "    {}", seed_at(&format!("{tag}k")));
    body.push_str(&indent(&newton, 2));
    let _ = writeln!(body, "    if ({tag}ok = 1 and {inside}) then");
    body.push_str(&indent(&accept, 6));
    let _ = writeln!(body, "    endif;\n  endif;");
    let _ = writeln!(body, "  {tag}n = {tag}n + 1;\nendloop;");

    // An injective map's seeds: the few nearest to the point (within the radius), nearest first,
    // until one reaches the root.
    let mut nearest = String::new();
    let body = &mut nearest;
    let _ = writeln!(body, "{tag}prev = -1; {tag}tries = 0;");
    let _ = writeln!(
        body,
        "while ({tag}tries < {NEAREST_SEEDS} and {tag}found = 0) loop"
    );
    let _ = writeln!(
        body,
        "  {tag}near = 0; {tag}nd = {}; {tag}n = 1;",
        num(radius)
    );
    let _ = writeln!(body, "  while ({tag}n <= {seeds}) loop");
    let _ = writeln!(body, "    {tag}dd = {};", distance(&format!("{tag}n")));
    let _ = writeln!(
        body,
        "    if ({tag}dd > {tag}prev and {tag}dd <= {tag}nd) then {tag}nd = {tag}dd; {tag}near = {tag}n; endif;"
    );
    let _ = writeln!(body, "    {tag}n = {tag}n + 1;\n  endloop;");
    let _ = writeln!(
        body,
        "  if ({tag}near = 0) then {tag}tries = {NEAREST_SEEDS}; else"
    );
    let _ = writeln!(
        body,
        "    {tag}prev = {tag}nd; {tag}tries = {tag}tries + 1; {} {tag}max = {ROOT_STEPS}; {tag}esc = {};",
        seed_at(&format!("{tag}near")),
        num(SEED_ESCAPE)
    );
    body.push_str(&indent(&newton, 2));
    let _ = writeln!(body, "    if ({tag}ok = 1 and {inside}) then");
    body.push_str(&indent(&accept, 6));
    let _ = writeln!(body, "    endif;\n  endif;\nendloop;");

    // Where the continuation's Newton starts (`{tag}h1..`): the spline guess, or a linear cell's
    // first seed (its Newton converges in one step from anywhere).
    let mut guess = String::new();
    match &leaf.guess {
        Some(g) => write_guess(&mut guess, g, tag, q, d),
        None => {
            for a in 0..d {
                let _ = writeln!(guess, "  {tag}h{} = {tag}s{}[1];", a + 1, axes[a]);
            }
        }
    }
    let start: Vec<String> = (0..d)
        .map(|a| format!("{} = {tag}h{};", params[a], a + 1))
        .collect();
    let start = start.join(" ");
    // The continuation at the parameters Newton reached (`{tag}ok = 1`, S evaluated there), else
    // at the guess: negative outside the image, as eval forces it.
    let mut negative = String::new();
    let _ = writeln!(negative, "if ({tag}ok = 0) then");
    let _ = writeln!(negative, "  {start}");
    negative.push_str(&indent(&eval, 0));
    let _ = writeln!(negative, "endif;");
    let _ = writeln!(negative, "{tag}cont = {tag}xv & {clip};");
    let _ = writeln!(
        negative,
        "-- Outside the image f is negative.\nif ({tag}cont >= 0) then {tag}cont = -{tag}cont - {TINY}; endif;\n\
         {tag}cdone = 1;"
    );

    let mut search = String::new();
    let mut continuation = String::new();
    let _ = writeln!(search, "  {tag}found = 0; {tag}best = 0; {tag}cdone = 0;");
    if leaf.injective {
        // Newton from the guess first, as eval's continuation runs it: a root in the box is the
        // preimage (one at most); a root past the box is the continuation's, and the point has
        // no preimage (the certified map does not fold back into the box); only where Newton
        // fails, and the point lies in the net's bounding box (which holds the image), do the
        // seeds search.
        search.push_str(&guess);
        let _ = writeln!(
            search,
            "  {start} {tag}max = {}; {tag}esc = {};",
            leaf.outside_steps,
            num(ESCAPE)
        );
        search.push_str(&indent(&newton, 0));
        let _ = writeln!(search, "  if ({tag}ok = 1 and {inside}) then");
        search.push_str(&indent(&accept, 4));
        let _ = writeln!(search, "  else\n    if ({tag}ok = 1) then");
        search.push_str(&indent(&negative, 6));
        let in_box: Vec<String> = (0..d)
            .map(|c| {
                let (lo, hi) = leaf.bounds[c];
                format!(
                    "{q}[{}] >= {} and {q}[{}] <= {}",
                    c + 1,
                    num(lo),
                    c + 1,
                    num(hi)
                )
            })
            .collect();
        let _ = writeln!(search, "    else\n      if ({}) then", in_box.join(" and "));
        search.push_str(&indent(&nearest, 8));
        let _ = writeln!(search, "      endif;\n    endif;\n  endif;");
        // Newton from the guess failed: eval's continuation is at the guess itself.
        let _ = writeln!(continuation, "    if ({tag}cdone = 0) then");
        let _ = writeln!(continuation, "      {tag}ok = 0;");
        continuation.push_str(&indent(&negative, 6));
        let _ = writeln!(continuation, "    endif;");
    } else {
        search.push_str(&indent(&seeded, 2));
        continuation.push_str(&indent(&guess, 2));
        let _ = writeln!(
            continuation,
            "    {start} {tag}max = {}; {tag}esc = {};",
            leaf.outside_steps,
            num(ESCAPE)
        );
        continuation.push_str(&indent(&newton, 2));
        continuation.push_str(&indent(&negative, 4));
    }
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

/// The loop of axis `a` of the factored sums ([`write_mapped`]'s `eval`): accumulators
/// `{tag}z{a}v{c}` (the value of coordinate `c`, `0` for ξ) and `{tag}z{a}g{b}{c}` (its partial
/// along axis `b ≥ a`), summed over the axis's control points; the innermost axis reads the net at
/// the running index `{tag}ix`.
fn sum_level(out: &mut String, leaf: &MappedLeaf, tag: &str, a: usize) {
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
fn write_guess(body: &mut String, g: &Guess, tag: &str, q: &str, d: usize) {
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
