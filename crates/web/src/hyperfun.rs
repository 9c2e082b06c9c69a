//! The HyperFun mode: a HyperFun program (a model file of kind `hyperfun`: the program's text and
//! the box it is drawn in) meshed as HyperFun evaluates it and drawn shaded in the 3D view, its
//! field cut by a plane for the section under the editor, its mesh exported and measured. Every
//! function takes the model file (or link) as the page keeps it, and runs in a worker.

use bezsolid_core::hyperfun::field::{self, FieldMeshError};
use bezsolid_core::hyperfun::read::{HfError, Program};
use bezsolid_core::mesh::Mesh;
use bezsolid_core::mesh::exchange::ExportFormat;
use bezsolid_core::model::ModelFile;
use glam::DVec3;
use serde_json::{Value, json};

use crate::error::Error;
use crate::scene::MeshVertex;
use crate::script::{Drawing, FLOATS_PER_VERTEX};

/// The most samples along a section's longer side.
pub const MAX_SECTION_SAMPLES: usize = 1024;
/// The colour of a program's solid in the 3D view.
const COLOR: [f32; 4] = [0.86, 0.55, 0.30, 1.0];

/// The program and box of a HyperFun model file or link.
///
/// # Errors
///
/// A text that is no model file or link, or not of kind `hyperfun`, or a bad box.
pub fn read(text: &str) -> Result<(String, [[f64; 3]; 2]), Error> {
    let file = crate::freeform::read_file(text)?;
    let (program, bounds) = file.to_hyperfun().map_err(Error::from)?;
    Ok((program.to_string(), bounds))
}

/// The model file (JSON) of `program` in `bounds` (`[x0, y0, z0, x1, y1, z1]`).
///
/// # Errors
///
/// A box that is not six numbers, finite, low below high on each axis, or a program too long.
pub fn model_json(program: &str, bounds: &[f64]) -> Result<String, Error> {
    let file = file_of(program, bounds)?;
    Ok(serde_json::to_string_pretty(&file).unwrap_or_default())
}

/// The share link's fragment of `program` in `bounds` (as [`model_json`]).
///
/// # Errors
///
/// As [`model_json`], or a program too long for a link (save the model file instead).
pub fn link(program: &str, bounds: &[f64]) -> Result<String, Error> {
    bezsolid_core::link::encode(&file_of(program, bounds)?).map_err(Error::from)
}

/// The program and box of a model file or link of kind `hyperfun`, JSON `{program, box}`
/// (`box` as six numbers), or `None` for any other text.
#[must_use]
pub fn program_of(text: &str) -> Option<String> {
    let (program, [lo, hi]) = read(text).ok()?;
    let bounds: Vec<f64> = lo.iter().chain(&hi).copied().collect();
    Some(json!({"program": program, "box": bounds}).to_string())
}

/// Whether `text` is one of bezsolid's HyperFun exports that carries its model (it opens as
/// that model).
#[must_use]
pub fn carries_model(text: &str) -> bool {
    bezsolid_core::hyperfun::model_of(text).is_some()
}

fn file_of(program: &str, bounds: &[f64]) -> Result<ModelFile, Error> {
    let [x0, y0, z0, x1, y1, z1] = bounds else {
        return Err(Error::new(format!(
            "a box is six numbers x0, y0, z0, x1, y1, z1, not {}",
            bounds.len()
        )));
    };
    let file = ModelFile::from_hyperfun(program, Some([[*x0, *y0, *z0], [*x1, *y1, *z1]]));
    file.to_hyperfun().map_err(Error::from)?;
    Ok(file)
}

/// A program's error for the page: HyperFun's message at its line and position, and the point
/// where an evaluation failed.
fn error_json(error: &FieldMeshError) -> Value {
    match error {
        FieldMeshError::Program { at, error } => {
            let mut e = hf_error_json(error);
            e["at"] = json!(at);
            e
        }
        other => json!({"line": null, "column": null, "message": other.to_string()}),
    }
}

fn hf_error_json(e: &HfError) -> Value {
    json!({"line": e.line, "column": e.position, "message": e.message})
}

/// The program of a model, parsed, and its box; or the report of why not (JSON, `error` set).
fn parse(text: &str) -> Result<(Program, DVec3, DVec3), Result<Value, Error>> {
    let (source, [lo, hi]) = read(text).map_err(Err)?;
    let program = Program::parse(&source).map_err(|e| Ok(json!({"error": hf_error_json(&e)})))?;
    Ok((program, DVec3::from_array(lo), DVec3::from_array(hi)))
}

/// The solid of a HyperFun model meshed at `resolution` cells along the box's longest side,
/// drawn: [`FLOATS_PER_VERTEX`] floats a vertex (shaded, one colour), and the report, JSON:
/// `error` (`null`, or `{line, column, message}` with `at` the point where an evaluation failed;
/// `line` is `null` for an error of no line), `triangles`, `cells` and `dimension` (the size of
/// the program's `x`: a program of `x[2]` is drawn through the box along z).
/// A box with no inside sample draws nothing, with no error.
///
/// # Errors
///
/// A text that is no HyperFun model file or link (the program's own errors are in the report).
pub fn draw(
    text: &str,
    resolution: usize,
    mut progress: impl FnMut(usize, usize),
) -> Result<Drawing, Error> {
    let (program, lo, hi) = match parse(text) {
        Ok(p) => p,
        Err(report) => return Ok(report_only(report?)),
    };
    let cells = resolution.clamp(1, field::MAX_RESOLUTION);
    let mesh = match field::mesh(&program, lo, hi, cells, &mut progress) {
        Ok(mesh) => mesh,
        Err(FieldMeshError::Empty) => Mesh::default(),
        Err(e) => return Ok(report_only(json!({"error": error_json(&e)}))),
    };
    let floats = shaded(&mesh);
    let report = json!({
        "error": null,
        "triangles": mesh.triangle_count(),
        "cells": cells,
        "dimension": program.dims()[0],
    });
    Ok(Drawing {
        floats,
        report: report.to_string(),
    })
}

fn report_only(report: Value) -> Drawing {
    Drawing {
        floats: Vec::new(),
        report: report.to_string(),
    }
}

/// Corners whose face turns further than this from their vertex's mean normal keep their face's
/// normal (a crease: a block's edge, a difference's rim) rather than a smooth one.
const CREASE_COS: f64 = 0.77; // cos 40°

/// The triangles of `mesh`, shaded: smooth (each vertex's normal the area-weighted mean of its
/// faces') but for corners across a crease, which take their face's.
fn shaded(mesh: &Mesh) -> Vec<f32> {
    let mut mean = vec![DVec3::ZERO; mesh.positions.len()];
    let faces: Vec<DVec3> = (0..mesh.triangles.len())
        .map(|t| {
            let [a, b, c] = mesh.corners(t);
            let n = (b - a).cross(c - a);
            for &i in &mesh.triangles[t] {
                mean[i as usize] += n;
            }
            n.normalize_or_zero()
        })
        .collect();
    let mut floats = Vec::with_capacity(mesh.triangles.len() * 3 * FLOATS_PER_VERTEX);
    for (t, face) in faces.iter().enumerate() {
        for &i in &mesh.triangles[t] {
            let smooth = mean[i as usize].normalize_or_zero();
            let n = if smooth.dot(*face) >= CREASE_COS {
                smooth
            } else {
                *face
            };
            let v = MeshVertex {
                position: mesh.positions[i as usize].as_vec3().to_array(),
                normal: n.as_vec3().to_array(),
                color: COLOR,
            };
            floats.extend(v.position.iter().chain(&v.normal).chain(&v.color));
        }
    }
    floats
}

/// The section of a HyperFun model's field by the plane across `axis` (0 x, 1 y, 2 z) at `at`,
/// within the box: `samples` along the box's longer side in the plane. The report, JSON: `error`
/// (as [`draw`]'s), `nx`, `ny` (the samples across and up), `lo` and `hi` (the plane's corners, in
/// its two coordinates: `y, z` across x, `x, z` across y, `x, y` across z) and `segments`; the
/// data: the `nx · ny` values row by row from `lo`, then each segment of the zero contour as four
/// numbers (`u0, v0, u1, v1`).
///
/// # Errors
///
/// A text that is no HyperFun model file or link, or an axis other than 0, 1 and 2.
pub fn section(
    text: &str,
    axis: usize,
    at: f64,
    samples: usize,
) -> Result<(Vec<f64>, String), Error> {
    if axis > 2 {
        return Err(Error::new(format!(
            "axis {axis}: the axes are 0 (x), 1 (y) and 2 (z)"
        )));
    }
    let (program, lo, hi) = match parse(text) {
        Ok(p) => p,
        Err(report) => return Ok((Vec::new(), report?.to_string())),
    };
    let n = samples.clamp(2, MAX_SECTION_SAMPLES);
    let side = (hi - lo).max_element();
    let accuracy = side * 1e-6;
    let cut = match field::section_field(&program, axis, at, lo, hi, n - 1, accuracy) {
        Ok(cut) => cut,
        Err(e) => return Ok((Vec::new(), json!({"error": error_json(&e)}).to_string())),
    };
    let field::Section {
        nx,
        ny,
        lo: lo2,
        hi: hi2,
        values,
        lines,
    } = cut;
    let mut data = values;
    let mut segments = 0;
    for line in &lines {
        let pts = &line.points;
        let ends = if line.closed {
            pts.len()
        } else {
            pts.len().saturating_sub(1)
        };
        for k in 0..ends {
            let (p, q) = (pts[k], pts[(k + 1) % pts.len()]);
            data.extend([p.x, p.y, q.x, q.y]);
            segments += 1;
        }
    }
    let report = json!({
        "error": null,
        "nx": nx,
        "ny": ny,
        "lo": [lo2.x, lo2.y],
        "hi": [hi2.x, hi2.y],
        "segments": segments,
    });
    Ok((data, report.to_string()))
}

/// The mesh of a HyperFun model's solid at `resolution` cells along the box's longest side.
///
/// # Errors
///
/// The program's error (HyperFun's message at its line and position), a value that is not
/// finite, work past the cap, or nothing inside the box.
pub fn mesh(
    text: &str,
    resolution: usize,
    mut progress: impl FnMut(usize, usize),
) -> Result<Mesh, Error> {
    let (source, [lo, hi]) = read(text)?;
    let program = Program::parse(&source).map_err(|e| Error::new(e.to_string()))?;
    if !(1..=field::MAX_RESOLUTION).contains(&resolution) {
        return Err(Error::new(format!(
            "resolution {resolution} is outside 1 to {} for a HyperFun program",
            field::MAX_RESOLUTION
        )));
    }
    field::mesh(
        &program,
        DVec3::from_array(lo),
        DVec3::from_array(hi),
        resolution,
        &mut progress,
    )
    .map_err(|e| Error::new(e.to_string()))
}

/// A mesh file of a HyperFun model's solid (see [`mesh`]).
///
/// # Errors
///
/// As [`mesh`], or the format's writer.
pub fn export(
    text: &str,
    format: ExportFormat,
    resolution: usize,
    progress: impl FnMut(usize, usize),
) -> Result<Vec<u8>, Error> {
    let mesh = mesh(text, resolution, progress)?;
    Ok(format.write(&mesh, "bezsolid-hyperfun")?)
}

/// What a HyperFun model's solid measures on its mesh (see [`mesh`]), JSON as the other modes'
/// measures ([`crate::document::headless::mesh_measure`]).
///
/// # Errors
///
/// As [`mesh`], or an empty mesh.
pub fn measure(
    text: &str,
    resolution: usize,
    progress: impl FnMut(usize, usize),
) -> Result<String, Error> {
    crate::document::headless::mesh_measure(&mesh(text, resolution, progress)?, resolution)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec2;

    const BALL: &str = "my_model(x[3], a[1]) { my_model = 4 - x[1]^2 - x[2]^2 - x[3]^2; }";

    fn model(program: &str) -> String {
        model_json(program, &[-3.0, -3.0, -3.0, 3.0, 3.0, 3.0]).unwrap()
    }

    #[test]
    fn a_ball_is_drawn_closed_and_measured_near_its_volume() {
        let text = model(BALL);
        let d = draw(&text, 32, |_, _| {}).unwrap();
        let report: Value = serde_json::from_str(&d.report).unwrap();
        assert!(report["error"].is_null(), "{report}");
        let triangles = report["triangles"].as_u64().unwrap() as usize;
        assert!(triangles > 500);
        assert_eq!(d.floats.len(), triangles * 3 * FLOATS_PER_VERTEX);
        let m: Value = serde_json::from_str(&measure(&text, 48, |_, _| {}).unwrap()).unwrap();
        let exact = 4.0 / 3.0 * core::f64::consts::PI * 8.0;
        let volume = m["volume"].as_f64().unwrap();
        assert!((volume - exact).abs() < 0.02 * exact, "{volume} vs {exact}");
        let obj = export(&text, ExportFormat::Obj, 16, |_, _| {}).unwrap();
        let back = bezsolid_core::mesh::Format::Obj.read(&obj).unwrap();
        assert!(back.check_closed_manifold().is_ok());
    }

    #[test]
    fn errors_come_at_their_line_and_place() {
        let text = model("my_model(x[3], a[1])\n{\n  s = 1;\n  my_model = s;\n}");
        let d = draw(&text, 16, |_, _| {}).unwrap();
        let report: Value = serde_json::from_str(&d.report).unwrap();
        assert_eq!(report["error"]["line"], 3, "{report}");
        assert_eq!(report["error"]["message"], "Left bracket expected");
        assert!(d.floats.is_empty());
        // A run-time error: where it happened.
        let text = model("my_model(x[3], a[1]) { d = x[1] - x[1]; my_model = 1 / d; }");
        let report: Value =
            serde_json::from_str(&draw(&text, 8, |_, _| {}).unwrap().report).unwrap();
        assert_eq!(report["error"]["message"], "Division by zero", "{report}");
        assert!(report["error"]["at"].is_array());
        // Not a HyperFun model at all: an error of the call.
        assert!(draw("{}", 8, |_, _| {}).is_err());
        assert!(mesh(&text, 8, |_, _| {}).is_err());
    }

    #[test]
    fn nothing_inside_draws_nothing_without_error() {
        let text = model("my_model(x[3], a[1]) { my_model = -1; }");
        let report: Value =
            serde_json::from_str(&draw(&text, 8, |_, _| {}).unwrap().report).unwrap();
        assert!(report["error"].is_null());
        assert_eq!(report["triangles"], 0);
        assert!(measure(&text, 8, |_, _| {}).is_err());
    }

    #[test]
    fn the_section_of_a_ball_is_its_circle() {
        let text = model(BALL);
        let (data, report) = section(&text, 2, 1.0, 64).unwrap();
        let report: Value = serde_json::from_str(&report).unwrap();
        let (nx, ny) = (
            report["nx"].as_u64().unwrap() as usize,
            report["ny"].as_u64().unwrap() as usize,
        );
        assert_eq!((nx, ny), (64, 64));
        let segments = report["segments"].as_u64().unwrap() as usize;
        assert!(segments > 20);
        assert_eq!(data.len(), nx * ny + 4 * segments);
        // z = 1 cuts the ball of radius 2 in a circle of radius √3.
        for s in data[nx * ny..].chunks(4) {
            let r = DVec2::new(s[0], s[1]).length();
            assert!((r - 3f64.sqrt()).abs() < 1e-4, "{r}");
        }
        // The centre's value is the field's there: 4 − 1 = 3 (the middle sample, on a grid of
        // 64 from −3 to 3, is near it).
        assert!(data[32 * nx + 32] > 2.9);
        // Above the ball: no contour, every value negative.
        let (data, _) = section(&text, 0, 2.5, 16).unwrap();
        assert!(data.iter().all(|&v| v < 0.0));
        assert!(section(&text, 3, 0.0, 16).is_err());
    }

    #[test]
    fn models_and_links_carry_the_program_and_its_box() {
        let json = model_json(BALL, &[-1.0, -2.0, -3.0, 1.0, 2.0, 3.0]).unwrap();
        let back: Value = serde_json::from_str(&program_of(&json).unwrap()).unwrap();
        assert_eq!(back["program"], BALL);
        assert_eq!(back["box"], json!([-1.0, -2.0, -3.0, 1.0, 2.0, 3.0]));
        let fragment = link(BALL, &[-1.0, -2.0, -3.0, 1.0, 2.0, 3.0]).unwrap();
        assert_eq!(program_of(&fragment), program_of(&json));
        assert!(model_json(BALL, &[1.0, 0.0, 0.0, 0.0, 1.0, 1.0]).is_err());
        assert!(model_json(BALL, &[0.0; 5]).is_err());
        assert!(program_of(r#"{"format": "bezsolid", "version": 1, "solid": {"kind": "plasm", "script": "1;"}}"#).is_none());
        assert!(!carries_model(BALL));
    }
}
