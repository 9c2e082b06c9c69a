//! The tools' half: what runs without a page or a GPU, in the page's Web Worker ([`run_job`]), in
//! node (the `headless_*` functions) and on the page when it has no worker: meshes, contour stacks,
//! exports, free-form results and PLaSM runs.

use wasm_bindgen::prelude::*;

use super::{MeshFormat, ParamAxis};
use crate::document;
use crate::error::Error;

/// The model file (JSON) of a model file or a share link (a whole URL or its fragment); no page or
/// GPU needed (node).
///
/// # Errors
///
/// What is wrong with the input.
#[wasm_bindgen]
pub fn headless_model(text: &str) -> Result<String, JsError> {
    document::headless::model(text).map_err(JsError::from)
}

/// The share link fragment (`#v1.…`) of a model file or link; no page or GPU needed.
///
/// # Errors
///
/// What is wrong with the input, or a model too large for a link.
#[wasm_bindgen]
pub fn headless_link(text: &str) -> Result<String, JsError> {
    document::headless::link(text).map_err(JsError::from)
}

/// The surface of a volume model (a model file or a link) as `"stl"`, `"obj"`, `"ply"`, `"3mf"` or
/// `"glb"` bytes at `resolution` cells along the longest side; no page or GPU needed.
///
/// # Errors
///
/// What is wrong with the input, a patch model, or a resolution outside 2 to 512.
#[wasm_bindgen]
pub fn headless_mesh(text: &str, format: MeshFormat, resolution: u32) -> Result<Vec<u8>, JsError> {
    made(document::headless::mesh(
        text,
        format.try_into()?,
        resolution as usize,
    ))
}

/// The surface a volume model (a model file or link) is drawn with at `resolution`, as six `f32`
/// per vertex (position, normal), three vertices per triangle: the page's Web Worker runs this off
/// the main thread and hands the result to `Modeler::set_surface`.
///
/// # Errors
///
/// What is wrong with the input, a patch model, or a resolution outside 2 to 512.
#[wasm_bindgen]
pub fn headless_surface(text: &str, resolution: u32) -> Result<Vec<f32>, JsError> {
    made(document::headless::surface(text, resolution as usize))
}

/// The contour stack of a volume model (a model file or link) across `axis` (0 = u, 1 = v, 2 = w):
/// the zero contour of each slice, six `f64` per segment, for `Modeler::set_stack`. `progress` is
/// called with `(done, total)` slices after each slice (the page's worker reports it).
///
/// # Errors
///
/// What is wrong with the input, a patch model, or another axis.
#[wasm_bindgen]
pub fn headless_stack(
    text: &str,
    axis: ParamAxis,
    progress: &js_sys::Function,
) -> Result<Vec<f64>, JsError> {
    made(document::headless::stack(
        text,
        axis.into(),
        |done, total| {
            // A progress report that throws changes nothing in the work.
            let _ = progress.call2(&JsValue::NULL, &done.into(), &total.into());
        },
    ))
}

/// What the solid of a model (a model file or link) measures, as JSON: a 3D model's volume, area
/// and bounding box on its mesh at `resolution` cells along the longest side (`{"dimension": 3,
/// "resolution", "triangles", "volume", "area", "bbox": [x0, y0, z0, x1, y1, z1]}`), a 2D model's
/// area and perimeter on its zero contour (`{"dimension": 2, "resolution", "area", "perimeter",
/// "open"}`); exact for the mesh or contour, so as near the solid as the resolution. No page or
/// GPU needed.
///
/// # Errors
///
/// What is wrong with the input, a resolution outside 2 to 512, a model that may be unbounded or
/// an empty solid.
#[wasm_bindgen]
pub fn headless_measure(text: &str, resolution: u32) -> Result<String, JsError> {
    made(document::headless::measure_in_steps(
        text,
        resolution as usize,
        |_, _| {},
    ))
}

/// The zero contours of a patch model (a model file or link) as SVG; no page or GPU needed.
///
/// # Errors
///
/// What is wrong with the input, or a volume model.
#[wasm_bindgen]
pub fn headless_svg(text: &str) -> Result<String, JsError> {
    made(document::headless::svg(text))
}

/// The HyperFun model of a model file or link (a model of many solids as its tree).
///
/// # Errors
///
/// What is wrong with the input, or a space-mapped model past the export's cap.
#[wasm_bindgen]
pub fn headless_hyperfun(text: &str) -> Result<String, JsError> {
    Ok(document::headless::hyperfun(text)?)
}

/// The worker's one entry ([`crate::jobs`]): a job as JSON bytes in, its result as one buffer out.
/// `progress` is called with `(done, total)` by the jobs that come in steps.
///
/// # Errors
///
/// A job the protocol does not know, or what is wrong with its input.
#[wasm_bindgen]
pub fn run_job(job: &[u8], progress: &js_sys::Function) -> Result<Vec<u8>, JsError> {
    Ok(crate::jobs::run_bytes(job, |done, total| {
        // A progress report that throws changes nothing in the work.
        let _ = progress.call2(&JsValue::NULL, &done.into(), &total.into());
    })?)
}

thread_local! {
    /// [`headless_approximate`]'s answer.
    static APPROXIMATE: std::cell::Cell<usize> = const { std::cell::Cell::new(0) };
}

/// The data of a headless job; its count of approximate evaluations is kept for
/// [`headless_approximate`] (0 on an error).
fn made<T>(job: Result<document::headless::Made<T>, Error>) -> Result<T, JsError> {
    let (data, approximate) = match job {
        Ok(m) => (Ok(m.data), m.approximate),
        Err(e) => (Err(e.into()), 0),
    };
    APPROXIMATE.with(|a| a.set(approximate));
    data
}

/// How many evaluations of `f` in the last `headless_mesh`, `headless_surface`, `headless_stack`
/// or `headless_svg` ran out of their work budget, where the net folds over itself very many
/// times: 0 when its result is exact; otherwise it is approximate there (the page says so).
#[wasm_bindgen]
#[must_use]
pub fn headless_approximate() -> u32 {
    APPROXIMATE
        .with(std::cell::Cell::get)
        .try_into()
        .unwrap_or(u32::MAX)
}

/// The result's surface of a free-form model file or link at `resolution` (the worker's job).
///
/// # Errors
///
/// What is wrong with the input.
#[wasm_bindgen]
pub fn headless_esc_surface(text: &str, resolution: u32) -> Result<Vec<f32>, JsError> {
    crate::freeform::headless::surface(text, resolution as usize).map_err(JsError::from)
}

/// A mesh file (`stl`, `obj`, `ply`, `3mf`, `glb`) of a free-form model's result.
///
/// # Errors
///
/// What is wrong with the input, an empty result, or another format.
#[wasm_bindgen]
pub fn headless_esc_mesh(
    text: &str,
    format: MeshFormat,
    resolution: u32,
) -> Result<Vec<u8>, JsError> {
    Ok(crate::freeform::headless::mesh(
        text,
        format.try_into()?,
        resolution as usize,
    )?)
}

/// A script's run: the drawing's floats and the report (see `script::Drawing`).
#[wasm_bindgen]
pub struct PlasmRun {
    floats: Vec<f32>,
    report: String,
}

#[wasm_bindgen]
impl PlasmRun {
    /// The report, JSON.
    #[must_use]
    pub fn report(&self) -> String {
        self.report.clone()
    }

    /// The drawing (taken: a second call gives nothing).
    pub fn take_floats(&mut self) -> Vec<f32> {
        core::mem::take(&mut self.floats)
    }
}

/// Runs a PLaSM script and draws its results (the worker's job).
#[wasm_bindgen]
#[must_use]
pub fn headless_plasm(script: &str) -> PlasmRun {
    let d = crate::script::run(script);
    PlasmRun {
        floats: d.floats,
        report: d.report,
    }
}

/// A mesh file (`obj`, `stl`, `ply`, `3mf`, `glb`) of a script's results.
///
/// # Errors
///
/// The script's error, nothing to export, or another format.
#[wasm_bindgen]
pub fn headless_plasm_mesh(script: &str, format: MeshFormat) -> Result<Vec<u8>, JsError> {
    Ok(crate::script::export(script, format.try_into()?)?)
}

/// The model file of a patch solid equal to the surface of a script's top-level value `index`
/// (`script::patch_model`), to edit in the Bézier mode.
///
/// # Errors
///
/// Why that value has no Bézier net.
#[wasm_bindgen]
pub fn script_patch_model(script: &str, index: usize) -> Result<String, JsError> {
    crate::script::patch_model(script, index)
        .map(|(json, _)| json)
        .map_err(JsError::from)
}

/// The model file of a volume solid equal to the solid of a script's top-level value `index`
/// (`script::volume_model`), to edit in the Bézier mode.
///
/// # Errors
///
/// Why that value has no Bézier volume (not a solid, or a map that is no polynomial).
#[wasm_bindgen]
pub fn script_volume_model(script: &str, index: usize) -> Result<String, JsError> {
    crate::script::volume_model(script, index)
        .map(|(json, _)| json)
        .map_err(JsError::from)
}
