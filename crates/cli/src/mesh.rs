//! `bezsolid mesh MODEL [--res N] -o OUT.{stl,obj,ply,3mf,glb} [--accuracy A] [--box X0,Y0,Z0,X1,Y1,Z1]
//! [--threads T] [--stats]`: the closed boundary mesh of a volume solid, of a 3D tree of many solids (within
//! its bounds, or within the box, cut by it), or of the result of a free-form model. A volume
//! solid or a tree is meshed on `T` threads (default: every core), the same mesh as on one. With
//! `--stats` (and then `-o` may be left out) the mesh's volume, area and bounding box are printed on
//! stdout.

use anyhow::{Context, Result, bail};

use crate::args;
use crate::progress::Progress;
use bezsolid_core::esc::draw::MAX_RESOLUTION as ESC_MAX_RESOLUTION;
use bezsolid_core::mesh::MAX_RESOLUTION;
use bezsolid_core::mesh::exchange::ExportFormat;
use bezsolid_core::model::{ModelSolid, SolidSpec};
use bezsolid_core::tree::{ModelTree, TreeMeshError};

/// The threads a volume or a tree is meshed on.
fn pool(threads: usize) -> Result<rayon::ThreadPool> {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .context("cannot start the threads")
}

/// The most threads `--threads` may ask for.
const MAX_THREADS: usize = 256;

/// `bezsolid mesh`'s arguments.
#[derive(clap::Args)]
pub(crate) struct MeshArgs {
    #[command(flatten)]
    model: args::Model,
    /// The mesh file; its extension says the format: .stl, .obj, .ply, .3mf or .glb. May be left
    /// out with --stats.
    #[arg(short = 'o', long = "output", value_name = "OUT")]
    output: Option<String>,
    /// Cells along the longest side of the model's box, or of each part's where parts lie far
    /// apart [default: 64; at most 512].
    #[arg(long, value_name = "N")]
    res: Option<usize>,
    /// Vertices are refined until |f| <= A [default: 1e-9].
    #[arg(long, value_name = "A")]
    accuracy: Option<f64>,
    /// The box a tree is meshed within, and cut by; needed by one that may be unbounded (a
    /// half-space, a cylinder) and by a HyperFun program (a model file of kind hyperfun gives its
    /// own).
    #[arg(long = "box", value_name = "X0,Y0,Z0,X1,Y1,Z1")]
    region: Option<String>,
    /// Threads to mesh on (the same mesh as on one) [default: every core].
    #[arg(long, value_name = "T")]
    threads: Option<usize>,
    /// Print `volume: V`, `area: A` and `bbox: X0 Y0 Z0 X1 Y1 Z1` of the mesh on stdout.
    #[arg(long)]
    stats: bool,
}

pub(crate) fn run(args: &MeshArgs) -> Result<()> {
    let model = args
        .model
        .get("mesh", "bezsolid mesh MODEL --res N -o OUT.stl")?;
    let stats = args.stats;
    let out = match args.output.as_deref() {
        Some(out) => Some(out),
        None if stats => None,
        None => Some(args::required(
            "mesh",
            None::<&str>,
            "-o OUT.stl, OUT.obj or OUT.ply",
        )?),
    };
    let res = args.res.unwrap_or(64);
    let accuracy = args.accuracy.unwrap_or(1e-9);
    let cores = std::thread::available_parallelism().map_or(1, std::num::NonZero::get);
    let threads = args.threads.unwrap_or(cores);
    if !(1..=MAX_THREADS).contains(&threads) {
        bail!("--threads {threads} is outside 1..={MAX_THREADS}");
    }
    let format = match out {
        Some(out) => match ExportFormat::of_path(out) {
            Some(format) => Some((out, format)),
            None => bail!("mesh: {out} should end in .stl, .obj or .ply, or in .3mf or .glb"),
        },
        None => None,
    };
    if !(1..=MAX_RESOLUTION).contains(&res) {
        bail!("--res {res} is outside 1..={MAX_RESOLUTION}");
    }
    let file = match crate::open(model)? {
        crate::Opened::Program(program, bounds) => {
            let mesh = hyperfun(model, &program, res, args.region.as_deref(), bounds)?;
            return finish(model, &mesh, format, stats, res);
        }
        crate::Opened::Model(file) => file,
    };
    let mut progress = Progress::new("meshing", false);
    let live = progress.live();
    let mut step = |done: usize, total: usize| progress.steps(done, total);
    // The mesh, and how many evaluations ran out of their work budget.
    let (mesh, exhausted) = if let SolidSpec::Esc { .. } = file.solid {
        // A free-form model: the surface of its result, vertices on the PN surfaces (exact, so
        // --accuracy does not apply).
        if res > ESC_MAX_RESOLUTION {
            bail!("--res {res} is outside 1..={ESC_MAX_RESOLUTION} for a free-form model");
        }
        let boolean = file.to_boolean().with_context(|| crate::describe(model))?;
        if !boolean.is_bounded() {
            bail!(
                "{}: the result is unbounded (a complement holds everything outside its solids): \
                 intersect it with a bounded solid to mesh it",
                crate::describe(model)
            );
        }
        let mesh = boolean.surface_in_steps(res, &mut step);
        if mesh.triangles.is_empty() {
            bail!("mesh: the result is empty");
        }
        (mesh, 0)
    } else if file.solid.is_tree() {
        let region = args::bounds::<3>("--box", args.region.as_deref())?;
        let ModelTree::Space(tree) = file.to_tree().with_context(|| crate::describe(model))? else {
            bail!("mesh polygonizes 3D models; for a 2D tree use `bezsolid contour`");
        };
        // Reported in rounds of cells when the bar may be drawn, else in one.
        let mesh = pool(threads)?.install(|| {
            if live {
                tree.polygonize_in_steps(res, accuracy, region, &mut step)
                    .map(|(mesh, _)| mesh)
            } else {
                tree.polygonize(res, accuracy, region)
            }
        });
        let mesh = match mesh {
            Err(TreeMeshError::Unbounded) => bail!(
                "{}: the model may be unbounded (a half-space, a cylinder, a morph past 0..1 or a \
                 blend of a space-mapped solid): mesh it within --box X0,Y0,Z0,X1,Y1,Z1",
                crate::describe(model)
            ),
            other => other.with_context(|| crate::describe(model))?,
        };
        (mesh, 0)
    } else {
        let solid = file.to_solid().with_context(|| crate::describe(model))?;
        let ModelSolid::Volume(solid) = solid else {
            bail!("mesh polygonizes volume (3D) models; for a patch use `bezsolid contour`");
        };
        let mesh =
            pool(threads)?.install(|| solid.polygonize_in_steps(res, accuracy, &mut step))?;
        (mesh, solid.exhausted())
    };
    progress.finish();
    crate::warn_exhausted(exhausted);
    finish(model, &mesh, format, stats, res)
}

/// Writes `mesh` where `format` says and prints its figures with `--stats`.
fn finish(
    model: &str,
    mesh: &bezsolid_core::mesh::Mesh,
    format: Option<(&str, ExportFormat)>,
    stats: bool,
    res: usize,
) -> Result<()> {
    if let Some((out, format)) = format {
        let bytes = format.write(mesh, &title(model))?;
        std::fs::write(out, bytes).with_context(|| format!("cannot write {out}"))?;
        eprintln!(
            "bezsolid: {} triangles, {} vertices written to {out}",
            mesh.triangle_count(),
            mesh.positions.len()
        );
    }
    if stats {
        print_stats(mesh, res);
    }
    Ok(())
}

/// The mesh of a HyperFun program (not a bezsolid export) within the box it needs (a program has
/// no bounds of its own), cut by it: `--box`, else the box its model file gives (`default`).
fn hyperfun(
    path: &str,
    program: &bezsolid_core::hyperfun::read::Program,
    res: usize,
    region: Option<&str>,
    default: Option<([f64; 3], [f64; 3])>,
) -> Result<bezsolid_core::mesh::Mesh> {
    use bezsolid_core::hyperfun::field;
    let path = crate::describe(path);
    let Some((lo, hi)) = args::bounds::<3>("--box", region)?.or(default) else {
        bail!(
            "{path}: a HyperFun program has no bounds of its own: mesh it within \
             --box X0,Y0,Z0,X1,Y1,Z1"
        );
    };
    if res > field::MAX_RESOLUTION {
        bail!(
            "--res {res} is outside 1..={} for a HyperFun program",
            field::MAX_RESOLUTION
        );
    }
    let mut progress = Progress::new("meshing", false);
    let mesh = field::mesh(
        program,
        glam::DVec3::from_array(lo),
        glam::DVec3::from_array(hi),
        res,
        &mut |done, total| progress.steps(done, total),
    )
    .map_err(|e| anyhow::anyhow!("{path}: {e}"))?;
    progress.finish();
    Ok(mesh)
}

/// The model's name in the files that keep one (3MF, GLB): the preset's, or the model file's name
/// without its extensions; a link's is "bezsolid".
fn title(model: &str) -> String {
    if let Some(preset) = model.strip_prefix("preset:") {
        return preset.to_string();
    }
    if crate::is_link(model) {
        return "bezsolid".to_string();
    }
    let name = std::path::Path::new(model)
        .file_name()
        .and_then(|n| n.to_str())
        .unwrap_or("bezsolid");
    let stem = name.split('.').next().unwrap_or(name);
    if stem.is_empty() { name } else { stem }.to_string()
}

/// `--stats`: the mesh's volume, area and box on stdout, one `name: value` line each; what they
/// are measured on (the mesh at `res`) on stderr.
fn print_stats(mesh: &bezsolid_core::mesh::Mesh, res: usize) {
    let m = mesh.measure();
    println!("volume: {}", m.volume);
    println!("area: {}", m.area);
    println!(
        "bbox: {} {} {} {} {} {}",
        m.min.x, m.min.y, m.min.z, m.max.x, m.max.y, m.max.z
    );
    eprintln!(
        "bezsolid: measured on the mesh of {} triangles at --res {res} (exact for the mesh; \
         a finer --res comes nearer the solid)",
        mesh.triangle_count()
    );
}
