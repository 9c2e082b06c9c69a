//! The program of one space-mapped net: its constant arrays, the preimages' search (Newton from
//! the spline guess, then the nearest seeds), Newton's loop and the negative continuation.

// Axes index the net's counts, the seed tables and the names at once.
#![allow(clippy::needless_range_loop)]

use alloc::boxed::Box;
use alloc::format;
use alloc::string::String;
use alloc::vec::Vec;
use core::fmt::Write as _;

use super::sums::{sum_level, write_guess};
use super::{ESCAPE, HUGE, MappedLeaf, NEAREST_SEEDS, ROOT_STEPS, SEED_ESCAPE, SETTLED_STEP, TINY};
use crate::hyperfun::{basis_term, num};

/// The HyperFun lines of one space-mapped net at the coordinates in array `q`, its names
/// prefixed by `tag`, its arrays added to `arrays`. `cell` is a piecewise solid's cell and cell
/// counts: its clipping is on the global parameter `(cell + u) / cells`.
pub(in crate::hyperfun) fn write_mapped(
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
            leaf.outside_steps(),
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
            leaf.outside_steps(),
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
pub(in crate::hyperfun) struct MappedCode {
    pub(in crate::hyperfun) setup: String,
    pub(in crate::hyperfun) search: String,
    pub(in crate::hyperfun) continuation: String,
    pub(in crate::hyperfun) found: String,
    pub(in crate::hyperfun) best: String,
    pub(in crate::hyperfun) cont: String,
}

impl MappedCode {
    /// The lines of a single solid: `f` is the best value, or the continuation; the variable.
    pub(in crate::hyperfun) fn single(&self, tag: &str, body: &mut String) -> String {
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
pub(in crate::hyperfun) fn indent(text: &str, by: usize) -> String {
    let pad = " ".repeat(by);
    text.lines().fold(String::new(), |mut out, line| {
        let _ = writeln!(out, "{pad}{line}");
        out
    })
}
