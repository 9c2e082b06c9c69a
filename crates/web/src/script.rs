//! The Script mode: a PLaSM script runs (in the page's worker), and what its top-level
//! expressions give is drawn in the 3D view: surfaces shaded with their triangles' edges, curves
//! as thin tubes, points as small spheres, one colour per result.

use bezsolid_core::mesh::exchange::ExportFormat;
use bezsolid_core::model::ModelFile;
use bezsolid_plasm::mesh::{Geometry, embed};
use bezsolid_plasm::{Complex, Interp, scripts};
use glam::DVec3;
use serde_json::json;

use crate::camera::OrbitView;
use crate::color::Rgba;
use crate::error::Error;
use crate::freeform::octahedron;
use crate::scene::{MeshVertex, Scene, next_generation};
use crate::view3d::prism;

/// Floats per vertex of a drawing: position, normal, straight RGBA.
pub const FLOATS_PER_VERTEX: usize = 10;
/// The most face triangles drawn; a larger result is drawn without them (its edges and curves
/// stay) and the report says so.
pub const MAX_FACES: usize = 600_000;
/// The most edges of faces drawn as a wireframe.
pub const MAX_EDGES: usize = 20_000;
/// The most curve segments drawn as tubes (beyond, the rest is left out and the report says so).
pub const MAX_SEGMENTS: usize = 100_000;
/// Curves of at most this many vertices show them as dots, and at most this many dots are drawn
/// in all.
pub const MAX_CURVE_DOTS: usize = 400;
/// The most dots on curves drawn, over all results.
pub const MAX_DOTS: usize = 4_000;
/// The most points drawn as spheres.
pub const MAX_POINTS: usize = 5_000;

/// Colours of the results, in turn: surfaces take them light, curves dark.
const PALETTE: [[f32; 3]; 6] = [
    [0.86, 0.55, 0.30],
    [0.22, 0.42, 0.78],
    [0.20, 0.60, 0.38],
    [0.62, 0.32, 0.70],
    [0.80, 0.30, 0.28],
    [0.18, 0.58, 0.62],
];
const EDGE_COLOR: Rgba = [0.16, 0.17, 0.2, 1.0];

/// The script shown when there is none: the paper's Fig. 1.
#[must_use]
pub fn default_script() -> String {
    scripts::example("4.4").map_or_else(String::new, scripts::Example::source)
}

/// A run's drawing and its report.
#[derive(Clone, Debug)]
pub struct Drawing {
    /// [`FLOATS_PER_VERTEX`] floats per vertex, three vertices per triangle.
    pub floats: Vec<f32>,
    /// The report, JSON: `error` (`null` or `{line, column, kind, message}`), `warnings` and
    /// `values` (each `{line, column, text}`; values also `drawn`), counts of `complexes`,
    /// `triangles`, `segments`, `points` and `steps`, and `left_out` (what was too large to draw,
    /// in words, or `null`).
    pub report: String,
}

/// Runs `script` and draws its results.
#[must_use]
pub fn run(script: &str) -> Drawing {
    let mut interp = Interp::new();
    let run = interp.run(script);
    let complexes: Vec<&Complex> = run.shown.iter().filter_map(|s| s.value.as_pol()).collect();
    let (floats, counts, left_out) = draw(&complexes);
    let place = |span: bezsolid_plasm::Span| (span.line, span.col);
    let report = json!({
        "error": run.error.as_ref().map(|e| json!({
            "line": e.span.line,
            "column": e.span.col,
            "kind": format!("{:?}", e.kind),
            "message": e.message,
        })),
        "warnings": run.warnings.iter().map(|w| {
            let (line, column) = place(w.span);
            json!({"line": line, "column": column, "message": w.message})
        }).collect::<Vec<_>>(),
        "values": run.shown.iter().map(|s| {
            let (line, column) = place(s.span);
            json!({
                "line": line,
                "column": column,
                "text": s.value.to_string(),
                "drawn": s.value.as_pol().is_some(),
                "patch": is_surface_map(s),
                "volume": is_solid_map(s),
            })
        }).collect::<Vec<_>>(),
        "complexes": complexes.len(),
        "triangles": counts[0],
        "segments": counts[1],
        "points": counts[2],
        "steps": run.steps,
        "left_out": left_out,
    });
    Drawing {
        floats,
        report: report.to_string(),
    }
}

/// The triangles that draw `complexes`, the counts of face triangles, segments and points drawn,
/// and what was left out, if anything.
#[must_use]
pub fn draw(complexes: &[&Complex]) -> (Vec<f32>, [usize; 3], Option<String>) {
    let geometries: Vec<Geometry> = complexes.iter().map(|c| Geometry::of([*c])).collect();
    let bounds = geometries
        .iter()
        .filter_map(Geometry::bounds)
        .reduce(|(a, b), (c, d)| (a.min(c), b.max(d)));
    let Some((lo, hi)) = bounds else {
        return (Vec::new(), [0; 3], None);
    };
    let size = (hi - lo).length().max(1e-9);
    let faces: usize = geometries.iter().map(|g| g.mesh.triangles.len()).sum();
    let edges: usize = geometries.iter().map(|g| g.edges.len()).sum();
    let mut left_out = Vec::new();
    let show_faces = faces <= MAX_FACES;
    if !show_faces {
        left_out.push(format!(
            "{faces} triangles (past {MAX_FACES}): only edges and curves"
        ));
    }
    let show_edges = edges <= MAX_EDGES;
    if !show_edges && faces > 0 {
        left_out.push(format!("the wireframe of {edges} edges (past {MAX_EDGES})"));
    }
    let mut out: Vec<MeshVertex> = Vec::new();
    let mut counts = [0usize; 3];
    let (mut segments_left, mut points_left, mut dots_left) = (MAX_SEGMENTS, MAX_POINTS, MAX_DOTS);
    for (k, g) in geometries.iter().enumerate() {
        let [r, gr, b] = PALETTE[k % PALETTE.len()];
        let light: Rgba = [r, gr, b, 1.0];
        let dark: Rgba = [r * 0.7, gr * 0.7, b * 0.7, 1.0];
        if show_faces {
            for t in &g.mesh.triangles {
                for &i in t {
                    out.push(MeshVertex {
                        position: g.mesh.positions[i as usize].as_vec3().to_array(),
                        normal: g.mesh.normals[i as usize].as_vec3().to_array(),
                        color: light,
                    });
                }
            }
            counts[0] += g.mesh.triangles.len();
        }
        if show_edges || !show_faces {
            let take = g.edges.len().min(segments_left);
            for [a, b] in &g.edges[..take] {
                prism(&mut out, *a, *b, size * 0.0012, EDGE_COLOR);
            }
            segments_left -= take;
        }
        let take = g.segments.len().min(segments_left);
        for [a, b] in &g.segments[..take] {
            prism(&mut out, *a, *b, size * 0.0035, dark);
        }
        counts[1] += take;
        segments_left -= take;
        // A curve's vertices show its parametrization (Script 3.1's three maps of one arc).
        let c = complexes[k];
        if c.order == 2 && c.point_count() <= MAX_CURVE_DOTS.min(dots_left) {
            for i in 0..c.point_count() {
                octahedron(&mut out, embed(c.point(i)), size * 0.007, dark);
            }
            dots_left -= c.point_count();
        }
        let take = g.points.len().min(points_left);
        for p in &g.points[..take] {
            octahedron(&mut out, *p, size * 0.009, dark);
        }
        counts[2] += take;
        points_left -= take;
    }
    let segments: usize = geometries.iter().map(|g| g.segments.len()).sum();
    if counts[1] < segments {
        left_out.push(format!("{} of {segments} segments", segments - counts[1]));
    }
    let points: usize = geometries.iter().map(|g| g.points.len()).sum();
    if counts[2] < points {
        left_out.push(format!("{} of {points} points", points - counts[2]));
    }
    let mut floats = Vec::with_capacity(out.len() * FLOATS_PER_VERTEX);
    for v in &out {
        floats.extend(v.position.iter().chain(&v.normal).chain(&v.color));
    }
    let left_out = (!left_out.is_empty()).then(|| left_out.join("; "));
    (floats, counts, left_out)
}

/// A mesh file of a script's results: `"obj"` (faces, lines and points) or the triangles as
/// `"stl"`, `"ply"`, `"3mf"` or `"glb"`.
///
/// # Errors
///
/// The script's error, or a script that draws nothing (or no triangles, for all but OBJ).
pub fn export(script: &str, format: ExportFormat) -> Result<Vec<u8>, Error> {
    let mut interp = Interp::new();
    let run = interp.run(script);
    if let Some(e) = run.error {
        return Err(Error::new(e.to_string()));
    }
    let complexes: Vec<&Complex> = run.shown.iter().filter_map(|s| s.value.as_pol()).collect();
    if complexes.is_empty() {
        return Err("the script draws nothing: no top-level expression gives a complex".into());
    }
    let no_triangles = || "the script draws no triangles (only curves or points): export OBJ";
    if let Some(format) = format.plain() {
        return bezsolid_plasm::mesh::export(complexes, format).map_err(|_| no_triangles().into());
    }
    let mesh = bezsolid_plasm::mesh::Geometry::of(complexes).mesh;
    if mesh.triangles.is_empty() {
        return Err(no_triangles().into());
    }
    Ok(format.write(&mesh, "bezsolid-script")?)
}

/// Whether a value is a surface made by `MAP` of a map of two parameters into at least three
/// coordinates: one that may become a Bézier patch solid.
fn is_surface_map(s: &bezsolid_plasm::Shown) -> bool {
    matches!((s.value.as_pol(), &s.map), (Some(p), Some(m)) if p.order == 3 && p.dim >= 3 && m.domain.dim == 2)
}

/// Whether a value is a solid made by `MAP` of a map of three parameters into three coordinates
/// (tetrahedra in space): one that may become a Bézier volume solid.
fn is_solid_map(s: &bezsolid_plasm::Shown) -> bool {
    matches!((s.value.as_pol(), &s.map), (Some(p), Some(m)) if p.order == 4 && p.dim == 3 && m.domain.dim == 3)
}

/// What a value is, in words, for a refusal: "a curve", "a surface in 2 coordinates", ….
fn what_it_is(s: &bezsolid_plasm::Shown) -> String {
    let Some(p) = s.value.as_pol() else {
        return "not a drawing (no complex)".into();
    };
    let what = match p.order {
        1 => "points",
        2 => "a curve",
        3 => "a surface",
        4 => "a solid",
        _ => "a complex of cells of more than three dimensions",
    };
    let made = match &s.map {
        Some(m) => format!(
            ", made by MAP of a map of {} parameter{}",
            m.domain.dim,
            if m.domain.dim == 1 { "" } else { "s" }
        ),
        None => ", not made by MAP".into(),
    };
    format!("{what} in {} coordinates{made}", p.dim)
}

/// Runs `script` and gives its top-level value number `index` if `fits` takes it (else why not:
/// `wanted`, and what the value is), with the interpreter to sample its map in, the map, and the
/// box of the map's domain (its first `D` coordinates).
fn mapped<const D: usize>(
    script: &str,
    index: usize,
    fits: fn(&bezsolid_plasm::Shown) -> bool,
    wanted: &str,
) -> Result<(Interp, bezsolid_plasm::MapOf, [f64; D], [f64; D]), Error> {
    let mut interp = Interp::new();
    let run = interp.run(script);
    if let Some(e) = run.error {
        return Err(Error::new(e.to_string()));
    }
    let shown = run
        .shown
        .get(index)
        .ok_or_else(|| Error::new(format!("the script has no top-level value {index}")))?;
    if !fits(shown) {
        return Err(Error::new(format!(
            "that value is {}, not {wanted}",
            what_it_is(shown)
        )));
    }
    let map = shown.map.clone().ok_or("no map")?;
    let d = &map.domain;
    let (mut lo, mut hi) = ([f64::INFINITY; D], [f64::NEG_INFINITY; D]);
    for i in 0..d.point_count() {
        for k in 0..D {
            lo[k] = lo[k].min(d.point(i)[k]);
            hi[k] = hi[k].max(d.point(i)[k]);
        }
    }
    Ok((interp, map, lo, hi))
}

/// The first three coordinates of `f` at the point of the domain's box `[lo, hi]` of parameters
/// `t` (in the unit box), or `None` (the first error kept in `failure`).
fn sample<const D: usize>(
    interp: &mut Interp,
    f: &bezsolid_plasm::Value,
    (lo, hi): ([f64; D], [f64; D]),
    t: [f64; D],
    failure: &mut Option<String>,
) -> Option<DVec3> {
    let at: [f64; D] = core::array::from_fn(|k| lo[k] + (hi[k] - lo[k]) * t[k]);
    match interp.call(f, &at).map(|p| p.as_point()) {
        Ok(Some(p)) if p.len() >= 3 => Some(DVec3::new(p[0], p[1], p[2])),
        Ok(_) => None,
        Err(e) => {
            failure.get_or_insert(e.to_string());
            None
        }
    }
}

/// The model file of a patch solid equal to the surface of the top-level value number `index` of
/// `script` (see [`bezsolid_core::blend::fit_patch`]): its map over the box of its domain, with
/// `(x, y, ξ)` its first three coordinates. A surface blended from Bézier curves thus becomes a
/// net to edit point by point in the Bézier mode. Also gives the degree.
///
/// # Errors
///
/// The script's error, a value that is not such a surface, or a map that is no polynomial of
/// degree at most 16 in each parameter.
pub fn patch_model(script: &str, index: usize) -> Result<(String, [usize; 2]), Error> {
    let (mut interp, map, lo, hi) = mapped::<2>(
        script,
        index,
        is_surface_map,
        "a surface made by MAP of a map of two parameters into at least three coordinates",
    )?;
    let mut failure = None;
    let patch = bezsolid_core::blend::fit_patch(&mut |u, v| {
        sample(&mut interp, &map.f, (lo, hi), [u, v], &mut failure)
    })
    .map_err(|e| failure.clone().unwrap_or_else(|| e.to_string()))?;
    let degree = patch.degree();
    let solid = bezsolid_core::Solid2::try_from_net(patch).map_err(Error::from)?;
    let json = serde_json::to_string_pretty(&ModelFile::from_solid2(&solid)).unwrap_or_default();
    Ok((json, degree))
}

/// ξ of every control point of a volume made from a script's solid: the Bézier mode's value for a
/// new net of two points per axis ([`crate::editor::dome`], 1/4), positive everywhere, so that
/// the volume solid is the whole image of its box: the solid the script's `MAP` draws.
#[must_use]
pub fn volume_xi() -> f64 {
    crate::editor::dome([0; 3], [1; 3])
}

/// The model file of a volume solid equal to the solid of the top-level value number `index` of
/// `script`: the tensor Bézier volume of its map over the box of its domain (see
/// [`bezsolid_core::blend::fit_volume`]: a solid blended from Bézier or Hermite surfaces, as
/// `Bezier:S3:<…>` makes one, is such a volume exactly), `(x, y, z)` its three coordinates and ξ
/// [`volume_xi`] everywhere, so that the solid is the map's image. The parameters `(u, v, w)`
/// are the map's first, second and third. Also gives the degree.
///
/// # Errors
///
/// The script's error, a value that is not such a solid (a curve, a surface, a plane drawing),
/// or a map that is no polynomial of degree at most 16 in each parameter.
pub fn volume_model(script: &str, index: usize) -> Result<(String, [usize; 3]), Error> {
    let (mut interp, map, lo, hi) = mapped::<3>(
        script,
        index,
        is_solid_map,
        "a solid made by MAP of a map of three parameters into three coordinates",
    )?;
    let mut failure = None;
    let volume = bezsolid_core::blend::fit_volume(&mut |u, v, w| {
        sample(&mut interp, &map.f, (lo, hi), [u, v, w], &mut failure)
    })
    .map_err(|e| failure.clone().unwrap_or_else(|| e.to_string()))?;
    let degree = volume.degree();
    let xi = volume_xi();
    let net = volume.map(|p| p.extend(xi));
    let solid = bezsolid_core::Solid3::try_from_net(net).map_err(Error::from)?;
    let json = serde_json::to_string_pretty(&ModelFile::from_solid3(&solid)).unwrap_or_default();
    Ok((json, degree))
}

/// The script of a model file or link (`None` for one that is not a script, or unreadable).
#[must_use]
pub fn script_of(text: &str) -> Option<String> {
    let file = crate::freeform::read_file(text).ok()?;
    file.to_script().ok().map(str::to_string)
}

/// The model file of a script (JSON).
#[must_use]
pub fn model_json(script: &str) -> String {
    serde_json::to_string_pretty(&ModelFile::from_plasm(script)).unwrap_or_default()
}

/// The share link's fragment of a script.
///
/// # Errors
///
/// A script too long for a link (save the model file instead).
pub fn link(script: &str) -> Result<String, Error> {
    bezsolid_core::link::encode(&ModelFile::from_plasm(script)).map_err(Error::from)
}

/// The Script mode's view: the last drawing and an orbit camera.
#[derive(Clone, Debug, Default)]
pub struct ScriptView {
    orbit: OrbitView,
    vertices: Vec<MeshVertex>,
    bounds: Option<(DVec3, DVec3)>,
    generation: u64,
}

impl ScriptView {
    /// An empty view.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Shows a drawing ([`FLOATS_PER_VERTEX`] floats per vertex), framing it unless the camera
    /// was moved since the last framing, or `refit`.
    ///
    /// # Errors
    ///
    /// Data that is not whole triangles of vertices.
    pub fn set_drawing(&mut self, floats: &[f32], refit: bool) -> Result<(), Error> {
        let per_triangle = 3 * FLOATS_PER_VERTEX;
        if !floats.len().is_multiple_of(per_triangle) {
            return Err(Error::new(format!(
                "a drawing of {} floats is not whole triangles",
                floats.len()
            )));
        }
        self.vertices = floats
            .chunks_exact(FLOATS_PER_VERTEX)
            .map(|v| MeshVertex {
                position: [v[0], v[1], v[2]],
                normal: [v[3], v[4], v[5]],
                color: [v[6], v[7], v[8], v[9]],
            })
            .collect();
        self.bounds = self
            .vertices
            .iter()
            .map(|v| DVec3::from_array(v.position.map(f64::from)))
            .fold(None, |b, p| match b {
                None => Some((p, p)),
                Some((lo, hi)) => Some((lo.min(p), hi.max(p))),
            });
        self.generation = next_generation();
        if refit || !self.orbit.moved() {
            self.fit();
        }
        Ok(())
    }

    /// Triangles drawn.
    #[must_use]
    pub fn triangle_count(&self) -> usize {
        self.vertices.len() / 3
    }

    fn extent_box(&self) -> (DVec3, DVec3) {
        self.bounds.unwrap_or((DVec3::splat(-1.0), DVec3::ONE))
    }

    /// Frames the drawing.
    pub fn fit(&mut self) {
        let (lo, hi) = self.extent_box();
        self.orbit.fit(lo, hi);
    }

    /// The viewport's size in CSS pixels.
    pub fn resize(&mut self, width: f64, height: f64) {
        let bounds = self.extent_box();
        self.orbit.resize(width, height, bounds);
    }

    /// The camera and its gestures.
    pub fn orbit(&mut self) -> &mut OrbitView {
        &mut self.orbit
    }

    /// Everything one redraw needs.
    #[must_use]
    pub fn scene(&self) -> Scene<'_> {
        let (lo, hi) = self.extent_box();
        let extent = (hi - lo).length().max(1e-9);
        self.orbit
            .scene(&self.vertices, &[], self.generation, extent)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn report(d: &Drawing) -> serde_json::Value {
        serde_json::from_str(&d.report).expect("JSON")
    }

    #[test]
    fn every_example_draws_and_reports() {
        for e in scripts::EXAMPLES {
            let d = run(&e.source());
            let r = report(&d);
            assert!(r["error"].is_null(), "{}: {}", e.id, r["error"]);
            assert!(!d.floats.is_empty() && d.floats.len().is_multiple_of(3 * FLOATS_PER_VERTEX));
            assert!(r["complexes"].as_u64().unwrap_or(0) >= 1);
            assert!(r["left_out"].is_null());
            let mut view = ScriptView::new();
            view.set_drawing(&d.floats, true).expect("whole triangles");
            assert_eq!(
                view.triangle_count() * 3 * FLOATS_PER_VERTEX,
                d.floats.len()
            );
            assert!(!view.scene().opaque.is_empty());
        }
        // Fig. 1: the surface's 800 triangles and the four curves' 32 segments each.
        let r = report(&run(&default_script()));
        assert_eq!(
            (r["triangles"].as_u64(), r["segments"].as_u64()),
            (Some(800), Some(128))
        );
        assert_eq!(r["warnings"].as_array().map(Vec::len), Some(5));
    }

    #[test]
    fn errors_are_reported_with_what_came_before() {
        // `Choose` is the prelude's now: an unknown name fails the first line.
        let d = run("Chooze:<1,1>;\n1 + 2;\nMAP:(CONS:<S1, S1>):(Domain:4);\n<1,2> + 1;\n");
        let r = report(&d);
        assert_eq!(r["error"]["line"], 1);
        assert!(d.floats.is_empty());
        let d = run("1 + 2;\nMAP:(CONS:<S1, S1>):(Domain:4);\n<1,2> + 1;\n");
        let r = report(&d);
        assert_eq!(
            (r["error"]["line"].as_u64(), r["error"]["column"].as_u64()),
            (Some(3), Some(7))
        );
        assert_eq!(r["values"][0]["text"], "3");
        assert_eq!(r["values"][1]["drawn"], true);
        assert_eq!(r["segments"], 4);
        assert!(!d.floats.is_empty(), "what came before the error is drawn");
    }

    #[test]
    fn exports_parse_back() {
        let src = scripts::example("4.6").expect("4.6").source();
        let obj = String::from_utf8(export(&src, ExportFormat::Obj).expect("obj")).expect("text");
        assert_eq!(obj.lines().filter(|l| l.starts_with("f ")).count(), 392);
        let stl = export(&src, ExportFormat::Stl).expect("stl");
        assert_eq!(
            u32::from_le_bytes(stl[80..84].try_into().expect("4 bytes")),
            392
        );
        let arc = scripts::example("3.3").expect("3.3").source();
        assert!(
            export(&arc, ExportFormat::Stl).is_err_and(|e| e.message().contains("no triangles"))
        );
        assert!(
            String::from_utf8(export(&arc, ExportFormat::Obj).expect("obj"))
                .is_ok_and(|t| t.contains("\nl 1 2\n"))
        );
        assert!(
            export("1;", ExportFormat::Obj).is_err_and(|e| e.message().contains("draws nothing"))
        );
        assert!(
            export("1 +;", ExportFormat::Obj)
                .is_err_and(|e| e.message().starts_with("line 1, column 3"))
        );
    }

    #[test]
    fn scripts_travel_in_model_files_and_links() {
        let src = default_script();
        assert_eq!(script_of(&model_json(&src)).as_deref(), Some(src.as_str()));
        let fragment = link(&src).expect("a link");
        assert_eq!(
            script_of(&format!("http://x/#{}", &fragment[1..])).as_deref(),
            Some(src.as_str())
        );
        assert!(script_of("{\"format\":\"bezsolid\"}").is_none());
        assert!(
            script_of(&crate::freeform::model_json(
                &crate::freeform::FreeForm::new().model_file()
            ))
            .is_none()
        );
    }

    #[test]
    fn a_blended_surface_becomes_a_patch_solid() {
        let src = default_script();
        let d = run(&src);
        let r = report(&d);
        assert_eq!(r["values"][0]["patch"], true);
        assert_eq!(r["values"][1]["patch"], false, "a curve is no surface");
        let (json, degree) = patch_model(&src, 0).expect("a patch");
        assert_eq!(degree, [3, 3]);
        let file: ModelFile = serde_json::from_str(&json).expect("a model file");
        let bezsolid_core::model::ModelSolid::Patch(solid) = file.to_solid().expect("a solid")
        else {
            panic!("a patch");
        };
        // The net interpolates the boundary curves: its corners are the curves' ends.
        let p = solid.net();
        assert!((p[[0, 0]] - DVec3::ZERO).length() < 1e-9);
        assert!((p[[3, 0]] - DVec3::new(10.0, 0.0, 0.0)).length() < 1e-9);
        assert!((p[[0, 3]] - DVec3::new(0.0, 6.0, 0.0)).length() < 1e-9);
        assert!((p[[3, 3]] - DVec3::new(10.0, 6.0, -1.0)).length() < 1e-9);
        // A plane grid has no third coordinate; a curve is not a surface.
        let grids = scripts::example("4.8").expect("4.8").source();
        assert!(patch_model(&grids, 0).is_err());
        assert!(patch_model(&src, 1).is_err());
        // Hermite surfaces are cubic too.
        let hermite = scripts::example("4.6").expect("4.6").source();
        assert_eq!(patch_model(&hermite, 0).expect("a patch").1, [3, 3]);
    }

    /// Scripts 4.5 and 4.8 (the curves `c1`, `c2` and `grid1`), then `added`.
    fn after_4_8(added: &str) -> String {
        format!("{}\n{}\n{added}", scripts::S4_5.text, scripts::S4_8.text)
    }

    /// The volume of a model file, checked to be one with ξ = [`volume_xi`] everywhere.
    fn volume_of(json: &str) -> bezsolid_core::Solid3 {
        let file: ModelFile = serde_json::from_str(json).expect("a model file");
        let bezsolid_core::model::ModelSolid::Volume(solid) = file.to_solid().expect("a solid")
        else {
            panic!("a volume");
        };
        assert!(solid.net().points().iter().all(|p| p.w == volume_xi()));
        solid
    }

    /// The script's map of its top-level value `index` at `t`, and the volume's point there.
    fn both_at(
        src: &str,
        index: usize,
        solid: &bezsolid_core::Solid3,
        t: [f64; 3],
    ) -> (DVec3, DVec3) {
        let mut interp = Interp::new();
        let run = interp.run(src);
        let f = run.shown[index].map.as_ref().expect("a map").f.clone();
        let p = interp
            .call(&f, &t)
            .expect("defined")
            .as_point()
            .expect("a point");
        (DVec3::from_slice(&p), solid.net().eval(t).truncate())
    }

    #[test]
    fn a_solid_blended_from_hermite_surfaces_becomes_a_volume_exactly() {
        // After Fig. 4: grid1 (the plane quarter ring between c1 and c2) and the same grid lifted to
        // z = 1, blended by Bezier:S3 into a slab: cubic along the curves, linear across them and up.
        let src = after_4_8(
            "DEF a1 = CubicHermite:S1:<<1,0,1>,<0,1,1>,<0,3,0>,<-3,0,0>>;\n\
             DEF a2 = CubicHermite:S1:<<0.5,0,1>,<0,0.5,1>,<0,1,0>,<-1,0,0>>;\n\
             DEF top = CubicHermite:S2:<a1,a2,d,d>;\n\
             DEF Slab = Bezier:S3:<grid1, top>;\n\
             MAP:Slab:(Domain:8 * Domain:4 * Domain:2);\n",
        );
        let r = report(&run(&src));
        assert!(r["error"].is_null(), "{}", r["error"]);
        assert_eq!(
            (&r["values"][0]["volume"], &r["values"][0]["patch"]),
            (&serde_json::json!(true), &serde_json::json!(false))
        );
        let (json, degree) = volume_model(&src, 0).expect("a volume");
        assert_eq!(degree, [3, 1, 1]);
        let solid = volume_of(&json);
        // The net's corners are the map's values at the domain's corners.
        let [n, m, l] = degree;
        for (i, j, k) in (0..8).map(|c| (c & 1, (c >> 1) & 1, c >> 2)) {
            let t = [i as f64, j as f64, k as f64];
            let (want, _) = both_at(&src, 0, &solid, t);
            let corner = solid.net()[[i * n, j * m, k * l]].truncate();
            assert!(
                (corner - want).length() < 1e-12,
                "corner {t:?}: {corner} vs {want}"
            );
        }
        // Along the edges, on the faces and inside, the volume is the map.
        for t in [
            [0.3, 0.0, 0.0],
            [1.0, 0.7, 1.0],
            [0.0, 1.0, 0.45],
            [0.25, 0.5, 0.0],
            [0.81, 0.33, 0.62],
        ] {
            let (want, got) = both_at(&src, 0, &solid, t);
            assert!((got - want).length() < 1e-12, "{t:?}: {got} vs {want}");
        }
        // The solid is the slab: inside at the map's image of the middle, not in the ring's hole
        // or above it.
        let (middle, _) = both_at(&src, 0, &solid, [0.5, 0.5, 0.5]);
        assert!(solid.f(middle) > 0.0);
        assert!(solid.f(DVec3::new(0.1, 0.1, 0.5)) < 0.0);
        assert!(solid.f(DVec3::new(0.5, 0.5, 1.5)) < 0.0);
        // Script 4.7's surface over grid1: a lens, cubic both ways.
        let lens = after_4_8(
            "DEF Surf3 = CubicHermite:S2:<c1,c2,<1,1,1>,<-1,-1,-1>>;\n\
             MAP:(Bezier:S3:<grid1, Surf3>):(Domain:6 * Domain:6 * Domain:2);\n",
        );
        let (json, degree) = volume_model(&lens, 0).expect("a volume");
        assert_eq!(degree, [3, 3, 1]);
        let solid = volume_of(&json);
        for t in [
            [0.0, 0.0, 0.0],
            [1.0, 1.0, 1.0],
            [0.2, 0.9, 0.5],
            [0.5, 0.5, 1.0],
        ] {
            let (want, got) = both_at(&lens, 0, &solid, t);
            assert!((got - want).length() < 1e-12, "{t:?}: {got} vs {want}");
        }
    }

    #[test]
    fn a_bezier_blend_of_bezier_patches_gives_their_control_points() {
        // Fig. 1's Surf1 over a flat floor at z = -2: Bezier:S3 of two Bézier surfaces. The net is
        // the floor's (elevated to bicubic) under Surf1's, whose points are Script 4.4's.
        let src = format!(
            "{}\n{}\n{}\n\
             DEF Floor = Bezier:S2:<Bezier:S1:<<0,0,-2>,<10,0,-2>>, Bezier:S1:<<0,6,-2>,<10,6,-2>>>;\n\
             DEF Body = Bezier:S3:<Floor, Surf1>;\n\
             MAP:Body:(Intervals:1:10 * Intervals:1:10 * Intervals:1:2);\n",
            scripts::S4_2.text,
            scripts::S4_3.text,
            scripts::S4_4.text
        );
        let r = report(&run(&src));
        assert!(r["error"].is_null(), "{}", r["error"]);
        assert_eq!(r["values"][0]["volume"], false, "Surf1 is a surface");
        assert_eq!(r["values"][1]["volume"], true);
        let (json, degree) = volume_model(&src, 1).expect("a volume");
        assert_eq!(degree, [3, 3, 1]);
        let solid = volume_of(&json);
        let p = |i: usize, j: usize, k: usize| solid.net()[[i, j, k]].truncate();
        for (got, want) in [
            (p(0, 0, 1), [0.0, 0.0, 0.0]),
            (p(3, 0, 1), [10.0, 0.0, 0.0]),
            (p(1, 2, 1), [7.0, 5.0, -1.0]),
            (p(2, 2, 1), [8.0, 5.0, 1.0]),
            (p(3, 3, 1), [10.0, 6.0, -1.0]),
            (p(0, 0, 0), [0.0, 0.0, -2.0]),
            (p(1, 1, 0), [10.0 / 3.0, 2.0, -2.0]),
            (p(3, 3, 0), [10.0, 6.0, -2.0]),
        ] {
            assert!(
                (got - DVec3::from_array(want)).length() < 1e-9,
                "{got} vs {want:?}"
            );
        }
        for t in [[0.1, 0.2, 0.3], [0.9, 0.5, 0.75], [1.0, 0.0, 0.5]] {
            let (want, got) = both_at(&src, 1, &solid, t);
            assert!((got - want).length() < 1e-11, "{t:?}: {got} vs {want}");
        }
    }

    #[test]
    fn what_is_not_a_polynomial_solid_has_no_volume() {
        let fig1 = default_script();
        let refusal =
            |src: &str, index: usize| volume_model(src, index).expect_err("refused").to_string();
        assert!(refusal(&fig1, 0).contains("a surface in 3 coordinates"));
        assert!(refusal(&fig1, 1).contains("a curve in 3 coordinates"));
        let grids = scripts::example("4.8").expect("4.8").source();
        assert!(refusal(&grids, 0).contains("a surface in 2 coordinates"));
        let flat = "MAP:<S1, S2>:(Domain:2 * Domain:2 * Domain:2);";
        assert!(refusal(flat, 0).contains("a solid in 2 coordinates"));
        assert!(refusal("1 + 2;", 0).contains("not a drawing"));
        assert!(refusal("1 + 2;", 3).contains("no top-level value 3"));
        let twisted = "MAP:<S1, S2, SIN ~ (K:30 * S3)>:(Domain:2 * Domain:2 * Domain:2);";
        assert!(refusal(twisted, 0).contains("not a polynomial"));
        assert!(refusal("1 +;", 0).starts_with("line 1, column 3"));
        // A patch is no volume either way round.
        assert!(patch_model(flat, 0).is_err_and(|e| e.to_string().contains("a solid")));
    }

    #[test]
    fn exported_solids_face_outward() {
        // A mirrored map turns the domain's cells inside out; the file's faces still point out.
        let src =
            "MAP:<S1, S2, K:0 - S3>:(interval:<0,1>:2 * interval:<0,1>:2 * interval:<0,1>:2);";
        for format in [ExportFormat::Stl, ExportFormat::Ply, ExportFormat::Obj] {
            let raw = format
                .plain()
                .expect("a plain format")
                .parse(&export(src, format).expect("a file"))
                .expect("parses back");
            let mesh = bezsolid_core::mesh::Mesh {
                positions: raw.positions,
                normals: Vec::new(),
                triangles: raw.triangles,
            };
            assert!(
                (mesh.volume() - 1.0).abs() < 1e-6,
                "{format}: {}",
                mesh.volume()
            );
        }
    }

    #[test]
    fn plane_drawings_are_seen_from_above() {
        let d = run(&scripts::example("4.8").expect("4.8").source());
        let mut view = ScriptView::new();
        view.set_drawing(&d.floats, true).expect("whole triangles");
        assert!(view.orbit().camera().pitch > 1.5);
        assert!(view.set_drawing(&[0.0; 7], false).is_err());
    }
}
