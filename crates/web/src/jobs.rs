//! The worker's protocol: the jobs the page hands its Web Worker ([`Job`], JSON as the page sends
//! it) and what they make ([`Done`]), run by [`run`] and carried as bytes by [`run_bytes`], so that
//! the worker itself is a few lines of transport and every job is tested natively.
//!
//! A result travels as one buffer: a little-endian `u32` header length, the header (JSON: the
//! payload's element type, and `approximate` or `report` where the job gives them), zeros up to a
//! multiple of 8 bytes, then the payload's little-endian elements.

use serde::{Deserialize, Serialize};

use bezsolid_core::Axis;
use bezsolid_core::mesh::Share;
use bezsolid_core::mesh::exchange::ExportFormat;

use crate::error::Error;

/// A job, as the page posts it (`{"kind": "surface", "model": …, "resolution": 64}`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case")]
pub enum Job {
    /// The surface a volume model is drawn with: six `f32` per vertex. With `share: [k, n]`,
    /// share `k` of `n` of it, for a page that makes it in `n` workers: the shares' floats, one
    /// after another, are the surface's.
    Surface {
        /// A model file or link.
        model: String,
        /// Cells along the longest side.
        resolution: usize,
        /// `[k, n]`: share `k` (from 0) of `n`; none for the whole.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        share: Option<[usize; 2]>,
    },
    /// A mesh file of a volume model.
    Mesh {
        /// A model file or link.
        model: String,
        /// `stl`, `obj`, `ply`, `3mf` or `glb`.
        format: ExportFormat,
        /// Cells along the longest side.
        resolution: usize,
    },
    /// The zero contour of each slice of a volume across an axis: six `f64` per segment, with a
    /// progress report after each slice. With `share: [k, n]`, the slices of share `k` of `n`:
    /// the shares' segments, one after another, are the stack's.
    Stack {
        /// A model file or link.
        model: String,
        /// 0 (u), 1 (v) or 2 (w).
        #[serde(with = "axis_index")]
        axis: Axis,
        /// `[k, n]`: share `k` (from 0) of `n`; none for the whole.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        share: Option<[usize; 2]>,
    },
    /// What a model's solid measures, JSON ([`crate::document::headless::measure_in_steps`]):
    /// a 3D model's mesh at `resolution` (the mesh export's), a 2D model's contour (the SVG
    /// export's), with a progress report on the way.
    Measure {
        /// A model file or link.
        model: String,
        /// Cells along the longest side of a 3D model's mesh.
        resolution: usize,
    },
    /// The SVG of a patch model's contours.
    Svg {
        /// A model file or link.
        model: String,
    },
    /// The HyperFun model of a model (a model of many solids as its tree).
    Hf {
        /// A model file or link.
        model: String,
    },
    /// The surface of a free-form model's result: six `f32` per vertex.
    EscSurface {
        /// A free-form model file or link.
        model: String,
        /// Cells along the longest side.
        resolution: usize,
    },
    /// A mesh file of a free-form model's result, with a progress report after each layer of
    /// samples.
    EscMesh {
        /// A free-form model file or link.
        model: String,
        /// `stl`, `obj`, `ply`, `3mf` or `glb`.
        format: ExportFormat,
        /// Cells along the longest side.
        resolution: usize,
    },
    /// A script's run: its drawing (`f32` vertices) and its report (JSON).
    Plasm {
        /// The script.
        script: String,
    },
    /// A mesh file of a script's results.
    PlasmMesh {
        /// The script (named `model` as the page sends it).
        model: String,
        /// `obj`, `stl`, `ply`, `3mf` or `glb`.
        format: ExportFormat,
    },
    /// The Bézier net of a script's surface: a patch model file.
    PlasmPatch {
        /// The script.
        script: String,
        /// Which top-level value.
        index: usize,
    },
    /// The Bézier net of a script's solid: a volume model file.
    PlasmVolume {
        /// The script.
        script: String,
        /// Which top-level value.
        index: usize,
    },
    /// A HyperFun program's drawing (`f32` vertices) and its report (JSON), with a progress
    /// report after each layer of samples ([`crate::hyperfun::draw`]).
    HyperfunDraw {
        /// A HyperFun model file or link (the program and its box).
        model: String,
        /// Cells along the box's longest side.
        resolution: usize,
    },
    /// A HyperFun program's field in a plane and its zero contour (`f64`), and the report
    /// ([`crate::hyperfun::section`]).
    HyperfunSection {
        /// A HyperFun model file or link.
        model: String,
        /// The plane's normal: 0 (x), 1 (y) or 2 (z).
        axis: usize,
        /// Where the plane cuts its axis.
        at: f64,
        /// Samples along the plane's longer side.
        samples: usize,
    },
    /// A mesh file of a HyperFun program's solid, with a progress report after each layer.
    HyperfunMesh {
        /// A HyperFun model file or link.
        model: String,
        /// `stl`, `obj`, `ply`, `3mf` or `glb`.
        format: ExportFormat,
        /// Cells along the box's longest side.
        resolution: usize,
    },
    /// What a HyperFun program's solid measures, JSON, on its mesh.
    HyperfunMeasure {
        /// A HyperFun model file or link.
        model: String,
        /// Cells along the box's longest side.
        resolution: usize,
    },
}

/// An axis on the wire: its number, 0 (u), 1 (v) or 2 (w), as the page numbers axes.
mod axis_index {
    use bezsolid_core::Axis;
    use serde::{Deserialize, Deserializer, Serializer, de::Error as _};

    pub(super) fn serialize<S: Serializer>(axis: &Axis, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_u64(axis.index() as u64)
    }

    pub(super) fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Axis, D::Error> {
        let n = u64::deserialize(d)?;
        usize::try_from(n)
            .ok()
            .and_then(Axis::from_index)
            .ok_or_else(|| D::Error::custom("axes are 0 (u), 1 (v) and 2 (w)"))
    }
}

/// A job's `share: [k, n]` (none: the whole).
fn share_of(share: Option<[usize; 2]>) -> Result<Share, Error> {
    let Some([k, n]) = share else {
        return Ok(Share::WHOLE);
    };
    Share::new(k, n).ok_or_else(|| {
        Error::new(format!(
            "share {k} of {n}: a share is numbered from 0 below {n}"
        ))
    })
}

/// What a job made.
#[derive(Clone, Debug, PartialEq)]
pub struct Done {
    /// The data.
    pub payload: Payload,
    /// For the Bézier models' jobs: how many evaluations ran out of their work budget (where a net
    /// folds over itself very many times the data is approximate there).
    pub approximate: Option<usize>,
    /// For a script's run: its report, JSON.
    pub report: Option<String>,
    /// For a share of a model of many solids' surface: `[kept, blocks]`, the blocks of the share
    /// this worker took from its last mesh of the model, of all it meshed.
    pub kept: Option<[usize; 2]>,
}

/// The data of a result, by element type.
#[derive(Clone, Debug, PartialEq)]
pub enum Payload {
    /// A file.
    Bytes(Vec<u8>),
    /// Vertices.
    F32(Vec<f32>),
    /// Segments.
    F64(Vec<f64>),
}

/// The header of a result on the wire.
#[derive(Serialize)]
struct Header<'a> {
    payload: &'static str,
    #[serde(skip_serializing_if = "Option::is_none")]
    approximate: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    report: Option<&'a str>,
    #[serde(skip_serializing_if = "Option::is_none")]
    kept: Option<[usize; 2]>,
}

/// Runs `job`; `progress(done, total)` is called on the way by the jobs that come in steps.
///
/// # Errors
///
/// What is wrong with the job's input.
pub fn run(job: &Job, progress: impl FnMut(usize, usize)) -> Result<Done, Error> {
    use crate::document::headless as bezier;
    let counted = |payload, approximate| Done {
        payload,
        approximate: Some(approximate),
        report: None,
        kept: None,
    };
    let plain = |payload| Done {
        payload,
        approximate: None,
        report: None,
        kept: None,
    };
    Ok(match job {
        Job::Surface {
            model,
            resolution,
            share,
        } => {
            let (m, kept) = bezier::surface_share_kept(model, *resolution, share_of(*share)?)?;
            Done {
                kept,
                ..counted(Payload::F32(m.data), m.approximate)
            }
        }
        Job::Mesh {
            model,
            format,
            resolution,
        } => {
            let m = bezier::mesh_in_steps(model, *format, *resolution, progress)?;
            counted(Payload::Bytes(m.data), m.approximate)
        }
        Job::Stack { model, axis, share } => {
            let m = bezier::stack_share(model, *axis, share_of(*share)?, progress)?;
            counted(Payload::F64(m.data), m.approximate)
        }
        Job::Measure { model, resolution } => {
            let m = bezier::measure_in_steps(model, *resolution, progress)?;
            counted(Payload::Bytes(m.data.into_bytes()), m.approximate)
        }
        Job::Svg { model } => {
            let m = bezier::svg(model)?;
            counted(Payload::Bytes(m.data.into_bytes()), m.approximate)
        }
        Job::Hf { model } => plain(Payload::Bytes(bezier::hyperfun(model)?.into_bytes())),
        Job::EscSurface { model, resolution } => plain(Payload::F32(
            crate::freeform::headless::surface(model, *resolution)?,
        )),
        Job::EscMesh {
            model,
            format,
            resolution,
        } => plain(Payload::Bytes(crate::freeform::headless::mesh_in_steps(
            model,
            *format,
            *resolution,
            progress,
        )?)),
        Job::Plasm { script } => {
            let drawing = crate::script::run(script);
            Done {
                payload: Payload::F32(drawing.floats),
                approximate: None,
                report: Some(drawing.report),
                kept: None,
            }
        }
        Job::PlasmMesh { model, format } => {
            plain(Payload::Bytes(crate::script::export(model, *format)?))
        }
        Job::PlasmPatch { script, index } => plain(Payload::Bytes(
            crate::script::patch_model(script, *index)?.0.into_bytes(),
        )),
        Job::PlasmVolume { script, index } => plain(Payload::Bytes(
            crate::script::volume_model(script, *index)?.0.into_bytes(),
        )),
        Job::HyperfunDraw { model, resolution } => {
            let drawing = crate::hyperfun::draw(model, *resolution, progress)?;
            Done {
                payload: Payload::F32(drawing.floats),
                approximate: None,
                report: Some(drawing.report),
                kept: None,
            }
        }
        Job::HyperfunSection {
            model,
            axis,
            at,
            samples,
        } => {
            let (data, report) = crate::hyperfun::section(model, *axis, *at, *samples)?;
            Done {
                payload: Payload::F64(data),
                approximate: None,
                report: Some(report),
                kept: None,
            }
        }
        Job::HyperfunMesh {
            model,
            format,
            resolution,
        } => plain(Payload::Bytes(crate::hyperfun::export(
            model,
            *format,
            *resolution,
            progress,
        )?)),
        Job::HyperfunMeasure { model, resolution } => plain(Payload::Bytes(
            crate::hyperfun::measure(model, *resolution, progress)?.into_bytes(),
        )),
    })
}

/// A result as one buffer (see the module documentation).
#[must_use]
pub fn encode(done: &Done) -> Vec<u8> {
    let (kind, len) = match &done.payload {
        Payload::Bytes(b) => ("bytes", b.len()),
        Payload::F32(v) => ("f32", v.len() * 4),
        Payload::F64(v) => ("f64", v.len() * 8),
    };
    let header = serde_json::to_vec(&Header {
        payload: kind,
        approximate: done.approximate,
        report: done.report.as_deref(),
        kept: done.kept,
    })
    .unwrap_or_default();
    let start = (4 + header.len()).next_multiple_of(8);
    let mut out = Vec::with_capacity(start + len);
    out.extend_from_slice(&(header.len() as u32).to_le_bytes());
    out.extend_from_slice(&header);
    out.resize(start, 0);
    match &done.payload {
        Payload::Bytes(b) => out.extend_from_slice(b),
        Payload::F32(v) => v
            .iter()
            .for_each(|x| out.extend_from_slice(&x.to_le_bytes())),
        Payload::F64(v) => v
            .iter()
            .for_each(|x| out.extend_from_slice(&x.to_le_bytes())),
    }
    out
}

/// The worker's one entry: a job as JSON bytes in, its result as one buffer out.
///
/// # Errors
///
/// A job the protocol does not know, or what is wrong with its input.
pub fn run_bytes(job: &[u8], progress: impl FnMut(usize, usize)) -> Result<Vec<u8>, Error> {
    let job: Job =
        serde_json::from_slice(job).map_err(|e| Error::new(format!("not a job: {e}")))?;
    Ok(encode(&run(&job, progress)?))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::document::model_json;
    use crate::editor::Editor;
    use bezsolid_core::Solid2;

    /// The header and the payload's bytes of an encoded result.
    fn decode(bytes: &[u8]) -> (serde_json::Value, &[u8]) {
        let n = u32::from_le_bytes(bytes[..4].try_into().unwrap()) as usize;
        let header = serde_json::from_slice(&bytes[4..4 + n]).unwrap();
        let start = (4 + n).next_multiple_of(8);
        assert!(bytes[4 + n..start].iter().all(|&b| b == 0));
        (header, &bytes[start..])
    }

    fn volume() -> String {
        let mut e = Editor::new(Solid2::fig9());
        e.new_volume(3, 3, 3).unwrap();
        model_json(&e)
    }

    /// The page's Measure: the JSON of the headless measurement, with progress on the way.
    #[test]
    fn a_measure_job_gives_the_measurements_as_json() {
        let model = volume();
        let mut steps = 0;
        let bytes = run_bytes(
            serde_json::json!({"kind": "measure", "model": model, "resolution": 16})
                .to_string()
                .as_bytes(),
            |_, _| steps += 1,
        )
        .unwrap();
        let (header, payload) = decode(&bytes);
        assert_eq!(header["payload"], "bytes");
        assert_eq!(header["approximate"], 0);
        let want = crate::document::headless::measure_in_steps(&model, 16, |_, _| {}).unwrap();
        assert_eq!(payload, want.data.as_bytes());
        assert!(steps > 0);
    }

    #[test]
    fn hyperfun_jobs_draw_cut_mesh_and_measure_with_progress() {
        let model = crate::hyperfun::model_json(
            "my_model(x[3], a[1]) { my_model = 1 - x[1]^2 - x[2]^2 - x[3]^2; }",
            &[-2.0, -2.0, -2.0, 2.0, 2.0, 2.0],
        )
        .unwrap();
        let mut steps = Vec::new();
        let mut job = |json: serde_json::Value| {
            run_bytes(json.to_string().as_bytes(), |done, total| {
                steps.push((done, total));
            })
            .unwrap()
        };
        let drawn =
            job(serde_json::json!({"kind": "hyperfun-draw", "model": model, "resolution": 12}));
        let (header, payload) = decode(&drawn);
        assert_eq!(header["payload"], "f32");
        let report: serde_json::Value =
            serde_json::from_str(header["report"].as_str().unwrap()).unwrap();
        assert!(report["error"].is_null(), "{report}");
        let triangles = report["triangles"].as_u64().unwrap() as usize;
        assert_eq!(
            payload.len(),
            triangles * 3 * crate::script::FLOATS_PER_VERTEX * 4
        );
        let cut = job(
            serde_json::json!({"kind": "hyperfun-section", "model": model, "axis": 1, "at": 0.5, "samples": 20}),
        );
        assert_eq!(decode(&cut).0["payload"], "f64");
        let stl = job(
            serde_json::json!({"kind": "hyperfun-mesh", "model": model, "format": "stl", "resolution": 12}),
        );
        let mesh = bezsolid_core::mesh::Format::Stl
            .read(decode(&stl).1)
            .unwrap();
        mesh.check_closed_manifold().unwrap();
        let measured =
            job(serde_json::json!({"kind": "hyperfun-measure", "model": model, "resolution": 12}));
        let m: serde_json::Value = serde_json::from_slice(decode(&measured).1).unwrap();
        assert!(m["volume"].as_f64().unwrap() > 3.5);
        assert_eq!(
            steps.last(),
            Some(&(13, 13)),
            "a report per layer of samples"
        );
    }

    #[test]
    fn jobs_as_the_page_sends_them_run_and_encode() {
        let model = volume();
        let job = |json: serde_json::Value| run_bytes(json.to_string().as_bytes(), |_, _| {});
        let surface =
            job(serde_json::json!({"kind": "surface", "model": model, "resolution": 8})).unwrap();
        let (header, payload) = decode(&surface);
        assert_eq!(header["payload"], "f32");
        assert_eq!(header["approximate"], 0);
        assert!(!payload.is_empty() && payload.len().is_multiple_of(4 * 18));
        let want = crate::document::headless::surface(&model, 8).unwrap().data;
        let got: Vec<f32> = payload
            .chunks_exact(4)
            .map(|c| f32::from_le_bytes(c.try_into().unwrap()))
            .collect();
        assert_eq!(got, want);

        let mut steps = Vec::new();
        let stack = run_bytes(
            serde_json::json!({"kind": "stack", "model": model, "axis": 2})
                .to_string()
                .as_bytes(),
            |done, total| steps.push((done, total)),
        )
        .unwrap();
        assert_eq!(decode(&stack).0["payload"], "f64");
        assert_eq!(steps.last(), Some(&(3, 3)), "a progress report per slice");

        let mut steps = Vec::new();
        let mesh = run_bytes(
            serde_json::json!({"kind": "mesh", "model": model, "format": "stl", "resolution": 8})
                .to_string()
                .as_bytes(),
            |done, total| steps.push((done, total)),
        )
        .unwrap();
        assert_eq!(steps.last(), Some(&(1, 1)), "a mesh reports its end");
        let (_, stl) = decode(&mesh);
        let mesh = bezsolid_core::mesh::Format::Stl.read(stl).unwrap();
        mesh.check_closed_manifold().unwrap();

        let plasm =
            job(serde_json::json!({"kind": "plasm", "script": "MAP:(CONS:<S1, S1>):(Domain:4);"}))
                .unwrap();
        let (header, payload) = decode(&plasm);
        let report: serde_json::Value =
            serde_json::from_str(header["report"].as_str().unwrap()).unwrap();
        assert!(report["error"].is_null(), "{report}");
        assert!(!payload.is_empty());
        assert!(header.get("approximate").is_none());

        // A script's solid: the volume model file, as the page opens it.
        let script = "MAP:<S1, S2 + S1, S3>:(Domain:2 * Domain:2 * Domain:2);";
        let volume =
            job(serde_json::json!({"kind": "plasm-volume", "script": script, "index": 0})).unwrap();
        let (header, payload) = decode(&volume);
        assert_eq!(header["payload"], "bytes");
        let file: serde_json::Value = serde_json::from_slice(payload).unwrap();
        assert_eq!(file["solid"]["kind"], "volume");
        assert_eq!(file["solid"]["degree"], serde_json::json!([1, 1, 1]));
        let curve = job(
            serde_json::json!({"kind": "plasm-volume", "script": "MAP:<S1, S1, S1>:(Domain:2);", "index": 0}),
        );
        assert!(curve.is_err_and(|e| e.to_string().contains("a curve")));
    }

    #[test]
    fn free_form_mesh_jobs_report_progress_and_export_what_the_headless_export_does() {
        use bezsolid_core::esc::{Example, Op};
        use bezsolid_core::model::{EscOperand, ModelFile};
        let model = serde_json::to_string(&ModelFile::from_esc(
            Some(Op::Difference),
            vec![
                EscOperand::example(Example::Icosphere, [0.0; 3]),
                EscOperand::example(Example::Torus, [0.0, 0.0, 0.4]),
            ],
        ))
        .unwrap();
        let job = |resolution: usize, steps: &mut Vec<(usize, usize)>| {
            run_bytes(
                serde_json::json!({"kind": "esc-mesh", "model": model, "format": "stl",
                    "resolution": resolution})
                .to_string()
                .as_bytes(),
                |done, total| steps.push((done, total)),
            )
        };
        let mut steps = Vec::new();
        let done = job(12, &mut steps).unwrap();
        let (header, stl) = decode(&done);
        assert_eq!(header["payload"], "bytes");
        let want = crate::freeform::headless::mesh(&model, ExportFormat::Stl, 12).unwrap();
        assert_eq!(stl, &want[..]);
        let total = steps.last().unwrap().1;
        assert!(total > 12, "{steps:?}");
        assert_eq!(steps, (1..=total).map(|d| (d, total)).collect::<Vec<_>>());
        for resolution in [1, 161] {
            let got = job(resolution, &mut Vec::new()).unwrap_err().to_string();
            let want = crate::freeform::headless::mesh(&model, ExportFormat::Stl, resolution)
                .unwrap_err()
                .to_string();
            assert_eq!(got, want);
        }
    }

    /// A worker asked again for its share after an edit of one solid of a model of many solids
    /// remakes only the blocks near that solid (its header says how many it kept), and gives
    /// what a worker new to the model gives.
    #[test]
    fn a_share_after_an_edit_is_the_share_made_afresh() {
        // The box's height changes inside the sphere's bounds: the grid stays.
        let model = |height: f64| {
            serde_json::json!({"format": "bezsolid", "version": 1, "solid": {"kind": "union",
                "of": [
                    {"kind": "sphere", "center": [0, 0, 0], "radius": 1},
                    {"kind": "box", "min": [1.5, -0.3, -0.3], "max": [2.4, height, 0.3]}]}})
            .to_string()
        };
        let share = |text: &str| {
            let job = serde_json::json!({"kind": "surface", "model": text, "resolution": 32,
                "share": [1, 2]});
            run_bytes(job.to_string().as_bytes(), |_, _| {}).unwrap()
        };
        let kept = |bytes: &[u8]| -> [usize; 2] {
            serde_json::from_value(decode(bytes).0["kept"].clone()).unwrap()
        };
        for (k, height) in [0.3, 0.25, 0.28, 0.25, 0.25].into_iter().enumerate() {
            let text = model(height);
            let here = share(&text);
            // Another thread has no cache of the model.
            let afresh = std::thread::scope(|s| s.spawn(|| share(&text)).join().unwrap());
            let ([kept, blocks], [none, all]) = (kept(&here), kept(&afresh));
            assert_eq!((none, all), (0, blocks));
            assert_eq!(decode(&here).1, decode(&afresh).1, "height {height}");
            assert!(decode(&here).1.len() > 1000);
            match k {
                0 => assert_eq!(kept, 0),
                4 => assert_eq!(kept, blocks, "the same model again"),
                _ => assert!(kept * 2 > blocks && kept < blocks, "{kept} of {blocks}"),
            }
        }
    }

    /// A page with several workers asks each for a share of the surface and joins their floats:
    /// the surface one worker makes (bit for bit for a volume; for a tree, a vertex two shares
    /// have is the same root to within the mesher's accuracy).
    #[test]
    fn surface_shares_joined_are_the_surface() {
        let tree = r#"{"format": "bezsolid", "version": 1, "solid": {"kind": "union", "of": [
            {"kind": "sphere", "center": [0, 0, 0], "radius": 1},
            {"kind": "box", "min": [0.5, -0.3, -0.3], "max": [1.4, 0.3, 0.3]}]}}"#;
        let floats = |bytes: &[u8]| -> Vec<f32> {
            decode(bytes)
                .1
                .chunks_exact(4)
                .map(|c| f32::from_le_bytes(c.try_into().unwrap()))
                .collect()
        };
        for (model, exact) in [(volume(), true), (tree.to_owned(), false)] {
            let job = |share: Option<[usize; 2]>| {
                let mut json =
                    serde_json::json!({"kind": "surface", "model": model, "resolution": 24});
                if let Some(s) = share {
                    json["share"] = serde_json::json!(s);
                }
                floats(&run_bytes(json.to_string().as_bytes(), |_, _| {}).unwrap())
            };
            let whole = job(None);
            assert!(whole.len() > 18 * 100);
            for n in [2, 3] {
                let joined: Vec<f32> = (0..n).flat_map(|k| job(Some([k, n]))).collect();
                assert_eq!(joined.len(), whole.len(), "{n} shares");
                if exact {
                    assert_eq!(joined, whole, "{n} shares");
                } else {
                    let apart = joined
                        .iter()
                        .zip(&whole)
                        .map(|(a, b)| (a - b).abs())
                        .fold(0.0f32, f32::max);
                    assert!(apart < 1e-5, "{n} shares: {apart}");
                }
            }
        }
        let err = run_bytes(
            serde_json::json!({"kind": "surface", "model": volume(), "resolution": 8, "share": [2, 2]})
                .to_string()
                .as_bytes(),
            |_, _| {},
        )
        .unwrap_err();
        assert!(err.message().contains("share 2 of 2"), "{err}");
    }

    /// A stack made in shares of slices: joined in order, the stack one worker makes, each share
    /// reporting its own slices.
    #[test]
    fn stack_shares_joined_are_the_stack() {
        let model = volume();
        let job = |share: Option<[usize; 2]>, steps: &mut Vec<(usize, usize)>| -> Vec<u8> {
            let mut json = serde_json::json!({"kind": "stack", "model": model, "axis": 2});
            if let Some(s) = share {
                json["share"] = serde_json::json!(s);
            }
            let bytes = run_bytes(json.to_string().as_bytes(), |d, t| steps.push((d, t))).unwrap();
            decode(&bytes).1.to_vec()
        };
        let whole = job(None, &mut Vec::new());
        assert!(whole.len() > 8 * 6 * 10);
        // Three slices (a degree-2 net across w): in two shares of two and one, in three of one.
        for (n, slices) in [(2, [2, 1, 0]), (3, [1, 1, 1])] {
            let mut joined = Vec::new();
            for (k, &s) in slices.iter().enumerate().take(n) {
                let mut steps = Vec::new();
                joined.extend(job(Some([k, n]), &mut steps));
                assert_eq!(
                    steps,
                    (1..=s).map(|d| (d, s)).collect::<Vec<_>>(),
                    "share {k} of {n}"
                );
            }
            assert_eq!(joined, whole, "{n} shares");
        }
    }

    #[test]
    fn unknown_jobs_and_bad_inputs_are_errors() {
        for bad in [
            &b"not json"[..],
            br#"{"kind": "format-disk"}"#,
            br#"{"kind": "surface", "model": "{}"}"#,
            br#"{"kind": "mesh", "model": "{}", "format": "gltf", "resolution": 8}"#,
            br#"{"kind": "stack", "model": "{}", "axis": 3}"#,
            br#"{"kind": "stack", "model": "{}", "axis": -1}"#,
        ] {
            assert!(run_bytes(bad, |_, _| {}).is_err());
        }
        let err = run_bytes(
            br#"{"kind": "surface", "model": "{", "resolution": 8}"#,
            |_, _| {},
        )
        .unwrap_err();
        assert!(err.message().contains("model"), "{err}");
        let err =
            run_bytes(br#"{"kind": "stack", "model": "{}", "axis": 7}"#, |_, _| {}).unwrap_err();
        assert!(err.message().contains("axes are 0 (u)"), "{err}");
        let err = run_bytes(
            br#"{"kind": "plasm-mesh", "model": "", "format": "step"}"#,
            |_, _| {},
        )
        .unwrap_err();
        assert!(
            err.message().contains("obj"),
            "the formats are named: {err}"
        );
    }

    #[test]
    fn jobs_round_trip_through_json() {
        let jobs = [
            Job::Stack {
                model: "m".into(),
                axis: Axis::V,
                share: None,
            },
            Job::Stack {
                model: "m".into(),
                axis: Axis::U,
                share: Some([1, 3]),
            },
            Job::EscMesh {
                model: "m".into(),
                format: ExportFormat::Ply,
                resolution: 12,
            },
        ];
        for job in jobs {
            let json = serde_json::to_string(&job).unwrap();
            assert_eq!(serde_json::from_str::<Job>(&json).unwrap(), job, "{json}");
        }
        assert_eq!(
            serde_json::to_value(Job::Stack {
                model: "m".into(),
                axis: Axis::W,
                share: None,
            })
            .unwrap()["axis"],
            2
        );
    }
}
