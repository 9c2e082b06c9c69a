//! `bezsolid eval MODEL --points FILE.csv [-o OUT.csv]`: points are read, evaluated and written a
//! line at a time, so that memory does not grow with their number. After a bad line the command
//! stops with its number; the rows of the lines before it have been written.

use anyhow::{Result, anyhow, bail};

use crate::args;
use crate::input::{Lines, MAX_POINTS_BYTES};
use crate::output::Sink;
use crate::progress::Progress;
use anyhow::Context as _;
use bezsolid_core::inverse::Method;
use bezsolid_core::tree::{ModelTree, Tree, TreeValue};
use glam::{DVec2, DVec3};

/// The most points one call evaluates.
const MAX_POINTS: usize = 10_000_000;

/// `bezsolid eval`'s arguments.
#[derive(clap::Args)]
pub(crate) struct EvalArgs {
    #[command(flatten)]
    model: args::Model,
    /// The points: one a line, `x,y` or `x,y,z` as the model is 2D or 3D; blank lines, `#`
    /// comments and a header line are skipped.
    #[arg(long, value_name = "FILE.csv")]
    points: Option<String>,
    /// Where the rows go [default: stdout].
    #[arg(short = 'o', long = "output", value_name = "OUT.csv")]
    output: Option<String>,
    /// How moved points are inverted: paper (the paper's spline guess and Bézier clipping), clip
    /// (Bézier clipping over the whole domain) or fast (seeded Newton) [default: fast].
    #[arg(long, value_name = "METHOD")]
    inverse: Option<String>,
}

pub(crate) fn run(args: &EvalArgs) -> Result<()> {
    let model = args
        .model
        .get("eval", "bezsolid eval MODEL --points FILE.csv")?;
    let points = args::required("eval", args.points.as_deref(), "--points FILE.csv")?;
    let method = match args.inverse.as_deref() {
        None | Some("fast") => Method::Fast,
        Some("paper") => Method::Hybrid,
        Some("clip") => Method::Clipping,
        Some(other) => bail!(
            "eval: --inverse {other}: the inverse map is one of paper (the paper's spline guess \
             and Bézier clipping), clip (Bézier clipping over the whole domain) or fast (the \
             default)"
        ),
    };
    let file = match crate::open(model)? {
        // A HyperFun program (not a bezsolid export): evaluated as HyperFun reads it.
        crate::Opened::Program(program, _) => {
            return hyperfun(model, &program, points, args.output.as_deref());
        }
        crate::Opened::Model(file) => file,
    };
    // One patch or volume, or a tree of many solids (a single solid is a tree of one leaf).
    let tree = file.to_tree().with_context(|| crate::describe(model))?;
    let dim = match tree {
        ModelTree::Plane(_) => 2,
        ModelTree::Space(_) => 3,
    };
    // A map that may fold cuts its atlas for the work to come: about one point per 24 bytes of
    // a file, many where the size is unknown (a pipe).
    let expected = match std::fs::metadata(points).map(|m| m.len()) {
        Ok(len) if len > 0 => usize::try_from(len / 24).unwrap_or(usize::MAX),
        _ => 1 << 16,
    };
    let points = Points::open(points, dim)?;
    let mut out = Sink::create(args.output.as_deref())?;
    match &tree {
        ModelTree::Plane(t) => {
            t.plan(expected);
            out.write(format_args!("x,y,f,preimages\n"))?;
            evaluate(
                t,
                method,
                points,
                &mut out,
                |p| DVec2::new(p[0], p[1]),
                |p, v| format!("{},{},{},{}\n", p[0], p[1], v.f, v.preimages),
            )?;
        }
        ModelTree::Space(t) => {
            t.plan(expected);
            out.write(format_args!("x,y,z,f,preimages\n"))?;
            evaluate(t, method, points, &mut out, DVec3::from_array, |p, v| {
                format!("{},{},{},{},{}\n", p[0], p[1], p[2], v.f, v.preimages)
            })?;
        }
    }
    out.finish()
}

/// `bezsolid eval` of a HyperFun program (`x,y,z,f` rows): its `my_model` (else its first body),
/// read and evaluated as HyperFun's interpreter reads and evaluates it; a refusal or an error at a
/// point is HyperFun's message at its line and position.
fn hyperfun(
    path: &str,
    program: &bezsolid_core::hyperfun::read::Program,
    points: &str,
    output: Option<&str>,
) -> Result<()> {
    let path = crate::describe(path);
    let mut run = program.evaluator();
    let mut points = Points::open(points, 3)?;
    let mut out = Sink::create(output)?;
    out.write(format_args!("x,y,z,f\n"))?;
    let mut progress = Progress::new("evaluating", out.is_stdout());
    let mut count = 0usize;
    while let Some(p) = points.next() {
        let p = p?;
        count += 1;
        let f = run.eval(&p, &[]).map_err(|e| {
            anyhow!(
                "{path}: at point {count} ({}, {}, {}): {e}",
                p[0],
                p[1],
                p[2]
            )
        })?;
        out.write(format_args!("{},{},{},{f}\n", p[0], p[1], p[2]))?;
        if count.is_multiple_of(256) {
            let (read, len) = points.progress();
            progress.at(read, len);
        }
    }
    progress.finish();
    out.finish()
}

/// Points of `dim` (2 or 3) coordinates read from a file, one per line, comma-separated. Blank
/// lines and `#` comments are skipped; a first line that is not numbers is taken as a header.
/// Each point comes as `[x, y, z]` (`z` is 0 for two coordinates), or as the error of its line.
pub(crate) struct Points {
    lines: Lines,
    path: String,
    dim: usize,
    line: Vec<u8>,
    /// The number of the line last read (from 1).
    no: usize,
    /// Whether no line but blank ones and comments has come yet.
    first: bool,
    count: usize,
}

impl Points {
    /// The points of the file `path`, read up to [`MAX_POINTS_BYTES`].
    ///
    /// # Errors
    ///
    /// When the file cannot be opened.
    pub(crate) fn open(path: &str, dim: usize) -> Result<Self> {
        Ok(Self {
            lines: crate::input::open(path, MAX_POINTS_BYTES, "points file")?,
            path: path.into(),
            dim,
            line: Vec::new(),
            no: 0,
            first: true,
            count: 0,
        })
    }

    /// The next point, `None` at the end of the file. Errors of a line start with the path.
    fn next_point(&mut self) -> Result<Option<[f64; 3]>> {
        let dim = self.dim;
        loop {
            if !self.lines.next_into(&mut self.line)? {
                return Ok(None);
            }
            self.no += 1;
            let (no, path) = (self.no, &self.path);
            let line = std::str::from_utf8(&self.line)
                .map_err(|_| anyhow!("cannot read {path}: stream did not contain valid UTF-8"))?
                .trim();
            if line.is_empty() || line.starts_with('#') {
                continue;
            }
            let mut values = [0.0; 3];
            let mut found = 0;
            let mut numbers = true;
            for field in line.split(',') {
                let Ok(v) = field.trim().parse::<f64>() else {
                    numbers = false;
                    break;
                };
                if let Some(slot) = values.get_mut(found) {
                    *slot = v;
                }
                found += 1;
            }
            let first = std::mem::replace(&mut self.first, false);
            if !numbers {
                if first {
                    continue;
                }
                bail!("{path}: line {no}: not {dim} numbers: {line:?}");
            }
            if found != dim {
                bail!("{path}: line {no}: expected {dim} coordinates, found {found}");
            }
            if !values.iter().all(|v| v.is_finite()) {
                bail!("{path}: line {no}: coordinates must be finite numbers");
            }
            if self.count == MAX_POINTS {
                bail!("{path}: more than {MAX_POINTS} points");
            }
            self.count += 1;
            return Ok(Some(values));
        }
    }
}

impl Points {
    /// The bytes read so far, and the file's length where it is known.
    pub(crate) fn progress(&self) -> (u64, Option<u64>) {
        self.lines.progress()
    }
}

impl Iterator for Points {
    type Item = Result<[f64; 3]>;

    fn next(&mut self) -> Option<Self::Item> {
        self.next_point().transpose()
    }
}

/// The CSV's rows, `x,y[,z],f,preimages` per point. On a regular grid the map is a scaling, so a
/// point has one preimage inside the (closed) domain box and none outside; a space mapping counts
/// the parameter points in the closed unit box that map to it (several where it folds); a tree
/// sums them over its Bézier leaves.
fn evaluate<const D: usize>(
    tree: &Tree<D>,
    method: Method,
    mut points: Points,
    out: &mut Sink,
    point: impl Fn([f64; 3]) -> bezsolid_core::Point<D>,
    row: impl Fn([f64; 3], TreeValue) -> String,
) -> Result<()>
where
    bezsolid_core::Dim<D>: bezsolid_core::Dimension<D>,
{
    let (mut count, mut exhausted) = (0usize, 0usize);
    let mut progress = Progress::new("evaluating", out.is_stdout());
    while let Some(p) = points.next() {
        let p = p?;
        let v = tree.evaluate_by(point(p), method);
        (count, exhausted) = (count + 1, exhausted + usize::from(v.exhausted));
        out.write(format_args!("{}", row(p, v)))?;
        if count % 256 == 0 {
            let (read, len) = points.progress();
            progress.at(read, len);
        }
    }
    progress.finish();
    if exhausted > 0 {
        eprintln!(
            "bezsolid: warning: the net folds over itself so often that {exhausted} of {count} points \
             reached the work limit of a query; their preimages may be incomplete"
        );
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: impl AsRef<[u8]>, dim: usize) -> Result<Vec<Vec<f64>>> {
        static FILES: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
        let path = std::env::temp_dir().join(format!(
            "bezsolid-points-{}-{}",
            std::process::id(),
            FILES.fetch_add(1, std::sync::atomic::Ordering::Relaxed)
        ));
        std::fs::write(&path, text)?;
        let points: Result<Vec<[f64; 3]>> =
            Points::open(path.to_str().unwrap_or(""), dim)?.collect();
        std::fs::remove_file(&path)?;
        Ok(points?.into_iter().map(|p| p[..dim].to_vec()).collect())
    }

    #[test]
    fn points_parse_with_header_comments_and_errors() {
        let pts = parse("x,y\n# c\n0.5, 0.25\n\n1,2\n", 2).unwrap();
        assert_eq!(pts, vec![vec![0.5, 0.25], vec![1.0, 2.0]]);
        let pts = parse("\r\n  # c\r\n1,2,3\r\n-0,1e-300, 4 ", 3).unwrap();
        assert_eq!(pts, vec![vec![1.0, 2.0, 3.0], vec![-0.0, 1e-300, 4.0]]);
        for (text, dim, says) in [
            ("1,2,3\n", 2, "line 1: expected 2 coordinates, found 3"),
            ("1,2\nx,y\n", 2, "line 2: not 2 numbers: \"x,y\""),
            ("# h\n\n1,NaN\n", 2, "line 3: coordinates must be finite"),
            ("1,inf\n", 2, "line 1: coordinates must be finite"),
            (
                "x,y,z\n1,2,3,4\n",
                3,
                "line 2: expected 3 coordinates, found 4",
            ),
        ] {
            let e = format!("{:#}", parse(text, dim).unwrap_err());
            assert!(e.contains(says), "{text:?}: {e}");
        }
        let e = parse(b"1,2\n\xff,3\n", 2).unwrap_err().to_string();
        assert!(e.ends_with(": stream did not contain valid UTF-8"), "{e}");
    }
}
