//! `bezsolid esc classify MESH --points FILE.csv [-o OUT]`,
//! `bezsolid esc bool A OP B --points FILE.csv [-o OUT]`, `bezsolid esc bool complement A …` and
//! `bezsolid esc expr "EXPR" NAME=SOLID… --points FILE.csv [-o OUT]`: point-in-solid and Booleans
//! of the solids bounded by PN triangles over closed triangle meshes (the second paper), one `0` or
//! `1` per point. A free-form model file or share link stands for its whole result wherever a mesh
//! goes.

use anyhow::{Context, Result, bail};
use bezsolid_core::esc::Boolean;
use bezsolid_core::esc::Example;
use bezsolid_core::esc::bool::is_name;
use bezsolid_core::esc::{EscSolid, Stats};
use bezsolid_core::esc::{Expr, Op};
use bezsolid_core::mesh::{MAX_FILE_BYTES, read};
use bezsolid_core::model::MAX_OPERANDS;
use glam::DVec3;

use crate::args::Args;
use crate::eval::Points;
use crate::output::Sink;

pub(crate) const USAGE: &str = "bezsolid esc classify MESH --points FILE.csv [-o OUT] | \
     bezsolid esc bool A OP B --points FILE.csv [-o OUT] (OP: union, intersection, difference) | \
     bezsolid esc bool complement A --points FILE.csv [-o OUT] | \
     bezsolid esc expr \"EXPR\" NAME=SOLID... --points FILE.csv [-o OUT] \
     (EXPR: names, | union, & intersection, - difference, ! complement, brackets); \
     every command takes --crease DEG (edges sharper than DEG degrees stay sharp; default 50)";

/// The names `complement` goes by on the command line.
fn is_complement(word: &str) -> bool {
    matches!(word, "complement" | "not" | "!")
}

pub(crate) fn run(args: &[String]) -> Result<()> {
    match args.first().map(String::as_str) {
        Some("classify") => classify(&args[1..]),
        Some("bool") => boolean(&args[1..]),
        Some("expr") => expression(&args[1..]),
        Some(other) => bail!("esc: unknown command `{other}`; usage: {USAGE}"),
        None => bail!("esc: which command? usage: {USAGE}"),
    }
}

fn classify(args: &[String]) -> Result<()> {
    let args = Args::parse("esc classify", args, &["--points", "--output", "--crease"])?;
    let mesh = args.model(USAGE)?;
    let solid = load_solid(mesh, crease(&args)?)?;
    let points = Points::open(args.required("--points", "--points FILE.csv")?, 3)?;
    let mut stats = Stats::default();
    write_values(points, args.value("--output"), |q| {
        solid.value(q, &mut stats)
    })
}

fn boolean(args: &[String]) -> Result<()> {
    // `complement A` or `A complement`, then the options.
    let unary = match args {
        [c, a, rest @ ..] if is_complement(c) => Some((a, rest)),
        [a, c, rest @ ..]
            if is_complement(c) && rest.first().is_none_or(|r| r.starts_with('-')) =>
        {
            Some((a, rest))
        }
        _ => None,
    };
    if let Some((a, rest)) = unary {
        let args = Args::parse("esc bool", rest, &["--points", "--output", "--crease"])?;
        if let Ok(extra) = args.model("") {
            bail!("esc bool: unexpected argument {extra}: a complement takes one solid");
        }
        let solid = load_solid(a, crease(&args)?)?;
        let points = Points::open(args.required("--points", "--points FILE.csv")?, 3)?;
        let mut stats = Stats::default();
        return write_values(points, args.value("--output"), |q| {
            1 - i32::from(solid.value(q, &mut stats) == 1)
        });
    }
    // A OP B, then the options.
    let [a, op, b, rest @ ..] = args else {
        bail!("esc bool: expected A OP B or complement A; usage: {USAGE}");
    };
    let op = Op::from_name(op).with_context(|| {
        format!(
            "esc bool: unknown operation `{op}`; use union, intersection or difference \
             (or `complement A`)"
        )
    })?;
    let args = Args::parse("esc bool", rest, &["--points", "--output", "--crease"])?;
    if let Ok(extra) = args.model("") {
        bail!("esc bool: unexpected argument {extra}");
    }
    let crease = crease(&args)?;
    let solids = [load_solid(a, crease)?, load_solid(b, crease)?];
    let points = Points::open(args.required("--points", "--points FILE.csv")?, 3)?;
    let expr = Expr::binary(op, Expr::Solid(0), Expr::Solid(1));
    let mut stats = Stats::default();
    write_values(points, args.value("--output"), |q| {
        expr.value(&mut |i| i32::from(solids[i].value(q, &mut stats) == 1))
    })
}

fn expression(args: &[String]) -> Result<()> {
    let Some((text, rest)) = args.split_first() else {
        bail!("esc expr: which expression? usage: {USAGE}");
    };
    // NAME=SOLID operands, then the options.
    let split = rest
        .iter()
        .position(|a| a.starts_with('-') && a.len() > 1)
        .unwrap_or(rest.len());
    let (named, options) = rest.split_at(split);
    let args = Args::parse("esc expr", options, &["--points", "--output", "--crease"])?;
    if let Ok(extra) = args.model("") {
        bail!("esc expr: unexpected argument {extra} after the options");
    }
    if named.is_empty() {
        bail!("esc expr: no solids: give them as NAME=SOLID, e.g. A=a.obj B=example:torus");
    }
    if named.len() > MAX_OPERANDS {
        bail!(
            "esc expr: {} solids; at most {MAX_OPERANDS} are taken",
            named.len()
        );
    }
    let mut names: Vec<&str> = Vec::with_capacity(named.len());
    let mut paths = Vec::with_capacity(named.len());
    for arg in named {
        let Some((name, solid)) = arg.split_once('=').filter(|(n, _)| is_name(n)) else {
            bail!(
                "esc expr: `{arg}` is not NAME=SOLID (a name is a letter or _, then letters, \
                 digits or _)"
            );
        };
        if names.contains(&name) {
            bail!("esc expr: the name {name} is given twice");
        }
        names.push(name);
        paths.push(solid);
    }
    let expr = Expr::parse(text, &names).with_context(|| format!("esc expr: {text:?}"))?;
    let mut used = vec![false; names.len()];
    mark(&expr, &mut used);
    for (name, used) in names.iter().zip(&used) {
        if !used {
            eprintln!("bezsolid: esc expr: {name} is not in the expression; it is not read");
        }
    }
    let crease = crease(&args)?;
    let solids = paths
        .iter()
        .zip(&used)
        .map(|(path, &used)| used.then(|| load_solid(path, crease)).transpose())
        .collect::<Result<Vec<_>>>()?;
    let points = Points::open(args.required("--points", "--points FILE.csv")?, 3)?;
    let mut stats = Stats::default();
    write_values(points, args.value("--output"), |q| {
        expr.value(&mut |i| {
            solids[i]
                .as_ref()
                .map_or(0, |s| i32::from(s.value(q, &mut stats) == 1))
        })
    })
}

/// Marks every solid `expr` names.
fn mark(expr: &Expr, used: &mut [bool]) {
    match expr {
        Expr::Solid(i) => used[*i] = true,
        Expr::Complement(a) => mark(a, used),
        Expr::Binary(_, a, b) => {
            mark(a, used);
            mark(b, used);
        }
    }
}

/// `--crease DEG`: the angle between neighbouring faces past which an edge stays sharp.
fn crease(args: &Args) -> Result<f64> {
    let degrees = args.number("--crease", bezsolid_core::esc::DEFAULT_CREASE_ANGLE)?;
    if !bezsolid_core::esc::pn::valid_crease_angle(degrees) {
        bail!(bezsolid_core::esc::EscError::CreaseAngle { degrees });
    }
    Ok(degrees)
}

/// A mesh file (OBJ, or STL binary or ASCII) or a built-in example (`example:NAME`), its edges
/// sharp past `crease` degrees; or a free-form model file or share link (its whole result, with
/// the crease angles it says).
fn load_solid(arg: &str, crease: f64) -> Result<Boolean> {
    let is_model = crate::is_link(arg)
        || std::path::Path::new(arg)
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("json"));
    if is_model {
        let file = crate::load_file(arg)?;
        return file.to_boolean().with_context(|| crate::describe(arg));
    }
    let mesh = if let Some(name) = arg.strip_prefix("example:") {
        let names: Vec<&str> = Example::ALL.iter().map(|e| e.name()).collect();
        Example::from_name(name)
            .with_context(|| format!("no example `{name}`; the examples are {}", names.join(", ")))?
            .mesh()
    } else {
        let bytes = crate::input::read_bytes(arg, MAX_FILE_BYTES as u64, "mesh file")?;
        read(&bytes).with_context(|| format!("{arg} is not a usable mesh"))?
    };
    let solid = EscSolid::with_crease_angle(&mesh, crease)
        .with_context(|| format!("{arg} does not bound a solid"))?;
    Ok(Boolean {
        solids: vec![solid],
        expr: Expr::Solid(0),
    })
}

/// One `0` or `1` per point, written as each point is read: `value` is the chain's value there.
fn write_values(
    points: Points,
    out: Option<&str>,
    mut value: impl FnMut(DVec3) -> i32,
) -> Result<()> {
    let mut out = Sink::create(out)?;
    for p in points {
        // A normal chain's value is 0 or 1; anything else would be a bug, reported as outside.
        let v = value(DVec3::from_array(p?));
        out.write(format_args!("{}\n", i32::from(v == 1)))?;
    }
    out.finish()
}
