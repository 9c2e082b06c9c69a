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

use crate::args;
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

/// `bezsolid esc`'s arguments.
#[derive(clap::Args)]
pub(crate) struct EscArgs {
    #[command(subcommand)]
    command: Option<EscCommand>,
}

#[derive(clap::Subcommand)]
enum EscCommand {
    /// Point-in-solid for the solid bounded by the PN triangles of a closed triangle mesh.
    #[command(
        after_help = "Example:\n  bezsolid esc classify example:torus --points points.csv -o inside.txt"
    )]
    Classify {
        /// A mesh file (OBJ or STL), example:NAME, or a free-form model file or link.
        #[arg(value_name = "MESH")]
        mesh: Option<String>,
        #[command(flatten)]
        options: EscOptions,
    },
    /// The same for A OP B (OP one of union, intersection, difference), or `complement A`.
    #[command(
        after_help = "Examples:\n  bezsolid esc bool a.obj union example:torus --points points.csv\n  \
                            bezsolid esc bool complement a.obj --points points.csv"
    )]
    Bool {
        /// A OP B, or complement A.
        #[arg(value_name = "A OP B")]
        operands: Vec<String>,
        #[command(flatten)]
        options: EscOptions,
    },
    /// The same for an expression of many solids.
    #[command(
        long_about = "The same for an expression of many solids: names, | union, & \
                      intersection, - difference, ! complement, brackets (! binds tightest, then \
                      &, then | and - left to right).",
        after_help = "Example:\n  bezsolid esc expr '!(A|B)-C' A=a.obj B=example:torus C=c.stl --points points.csv"
    )]
    Expr {
        /// The expression.
        #[arg(value_name = "EXPR")]
        expr: Option<String>,
        /// The solids, each NAME=SOLID (a mesh file, example:NAME, or a free-form model file or
        /// link).
        #[arg(value_name = "NAME=SOLID")]
        solids: Vec<String>,
        #[command(flatten)]
        options: EscOptions,
    },
}

/// The options every `esc` command takes.
#[derive(clap::Args)]
struct EscOptions {
    /// The points, one `x,y,z` a line.
    #[arg(long, value_name = "FILE.csv")]
    points: Option<String>,
    /// Where the values go [default: stdout].
    #[arg(short = 'o', long = "output", value_name = "OUT")]
    output: Option<String>,
    /// An edge whose faces turn by more than DEG degrees stays sharp; 180 rounds every edge
    /// [default: 50].
    #[arg(long, value_name = "DEG")]
    crease: Option<f64>,
}

impl EscOptions {
    /// `--crease DEG`: the angle between neighbouring faces past which an edge stays sharp.
    fn crease(&self) -> Result<f64> {
        let degrees = self
            .crease
            .unwrap_or(bezsolid_core::esc::DEFAULT_CREASE_ANGLE);
        if !bezsolid_core::esc::pn::valid_crease_angle(degrees) {
            bail!(bezsolid_core::esc::EscError::CreaseAngle { degrees });
        }
        Ok(degrees)
    }

    /// The points, which `cmd` needs.
    fn points(&self, cmd: &str) -> Result<Points> {
        Points::open(
            args::required(cmd, self.points.as_deref(), "--points FILE.csv")?,
            3,
        )
    }
}

pub(crate) fn run(args: &EscArgs) -> Result<()> {
    match &args.command {
        Some(EscCommand::Classify { mesh, options }) => classify(mesh.as_deref(), options),
        Some(EscCommand::Bool { operands, options }) => boolean(operands, options),
        Some(EscCommand::Expr {
            expr,
            solids,
            options,
        }) => expression(expr.as_deref(), solids, options),
        None => bail!("esc: which command? usage: {USAGE}"),
    }
}

fn classify(mesh: Option<&str>, options: &EscOptions) -> Result<()> {
    let mesh = args::model("esc classify", mesh, USAGE)?;
    let solid = load_solid(mesh, options.crease()?)?;
    let points = options.points("esc classify")?;
    let mut stats = Stats::default();
    write_values(points, options.output.as_deref(), |q| {
        solid.value(q, &mut stats)
    })
}

fn boolean(operands: &[String], options: &EscOptions) -> Result<()> {
    // `complement A` or `A complement`.
    let unary = match operands {
        [c, a] | [a, c] if is_complement(c) => Some(a),
        [c, _, extra, ..] if is_complement(c) => {
            bail!("esc bool: unexpected argument {extra}: a complement takes one solid")
        }
        _ => None,
    };
    if let Some(a) = unary {
        let solid = load_solid(a, options.crease()?)?;
        let points = options.points("esc bool")?;
        let mut stats = Stats::default();
        return write_values(points, options.output.as_deref(), |q| {
            1 - i32::from(solid.value(q, &mut stats) == 1)
        });
    }
    // A OP B.
    let (a, op, b) = match operands {
        [a, op, b] => (a, op, b),
        [_, _, _, extra, ..] => bail!("esc bool: unexpected argument {extra}"),
        _ => bail!("esc bool: expected A OP B or complement A; usage: {USAGE}"),
    };
    let op = Op::from_name(op).with_context(|| {
        format!(
            "esc bool: unknown operation `{op}`; use union, intersection or difference \
             (or `complement A`)"
        )
    })?;
    let crease = options.crease()?;
    let solids = [load_solid(a, crease)?, load_solid(b, crease)?];
    let points = options.points("esc bool")?;
    let expr = Expr::binary(op, Expr::Solid(0), Expr::Solid(1));
    let mut stats = Stats::default();
    write_values(points, options.output.as_deref(), |q| {
        expr.value(&mut |i| i32::from(solids[i].value(q, &mut stats) == 1))
    })
}

fn expression(text: Option<&str>, named: &[String], options: &EscOptions) -> Result<()> {
    let Some(text) = text else {
        bail!("esc expr: which expression? usage: {USAGE}");
    };
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
    let crease = options.crease()?;
    let solids = paths
        .iter()
        .zip(&used)
        .map(|(path, &used)| used.then(|| load_solid(path, crease)).transpose())
        .collect::<Result<Vec<_>>>()?;
    let points = options.points("esc expr")?;
    let mut stats = Stats::default();
    write_values(points, options.output.as_deref(), |q| {
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
