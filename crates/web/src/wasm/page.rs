//! The page's half: [`start`] brings up wgpu on a canvas and returns a [`Modeler`] whose methods the
//! page calls on input and on animation frames, with the 3D view ([`Viewer3`]), the Free-form and
//! Script modes' views. Logic stays in the plain-Rust modules ([`crate::editor`],
//! [`crate::view2d`], [`crate::view3d`], …).

use super::{
    Backend, DragMode, FreeFormDisplay, FreeFormExample, Operation, ParamAxis, PartKind,
    PartOperation,
};
use glam::{DVec2, DVec3};
use wasm_bindgen::prelude::*;
use web_sys::HtmlCanvasElement;

use crate::document;
use crate::editor::Editor;
use crate::error::Error;
use crate::frame2d::{
    Sectioned, TREE_MAPPED_SAMPLES, TREE_SAMPLES, frame, frame_parameter_section, frame_section,
    frame_tree, parameter_point, plane_axes,
};
use crate::freeform::FreeForm;
use crate::panel::{FrameFigures, Panel};
use crate::parts::Parts;
use crate::render::Renderer;
use crate::render3d::Renderer3;
use crate::view2d::View2;
use crate::view3d::{Handle, View3, Whole};
use bezsolid_core::Solid2;
use bezsolid_core::model::ModelFile;

/// The methods of a view whose only interaction is its camera (`state` has `resize`, `scene`,
/// `orbit` and `fit`): the free-form and script views.
macro_rules! orbit_view {
    ($view:ty) => {
        #[wasm_bindgen]
        impl $view {
            /// Sizes the view on `viewer`'s canvas; returns the canvas size in device pixels.
            pub fn resize(
                &mut self,
                viewer: &mut Viewer3,
                width: f64,
                height: f64,
                dpr: f64,
            ) -> Vec<u32> {
                self.state.resize(width, height);
                viewer.fit_canvas(width, height, dpr)
            }

            /// Draws on `viewer`.
            pub fn render(&mut self, viewer: &mut Viewer3) {
                let scene = self.state.scene();
                viewer.present(&scene);
            }

            /// Pointer pressed at CSS pixel `(x, y)`: orbit, or pan with `pan`.
            pub fn pointer_down(&mut self, x: f64, y: f64, pan: bool) {
                self.state.orbit().pointer_down(DVec2::new(x, y), pan);
            }

            /// Pointer moved; returns whether the camera moved.
            pub fn pointer_move(&mut self, x: f64, y: f64) -> bool {
                self.state.orbit().pointer_move(DVec2::new(x, y))
            }

            /// Pointer released.
            pub fn pointer_up(&mut self) {
                self.state.orbit().pointer_up();
            }

            /// The wheel: zooms.
            pub fn wheel(&mut self, delta_y: f64) {
                self.state.orbit().wheel(delta_y);
            }

            /// Two fingers: zoom by their spread's `scale` (now over before) and pan by their
            /// midpoint's move `(dx, dy)` in CSS pixels. Returns whether the camera moved.
            pub fn pinch(&mut self, scale: f64, dx: f64, dy: f64) -> bool {
                self.state.orbit().pinch(scale, DVec2::new(dx, dy))
            }

            /// Frames the scene again.
            pub fn fit(&mut self) {
                self.state.fit();
            }
        }
    };
}

mod freeform_view;
mod gpu;
mod parts;
mod script_view;
mod section;
mod view3d;

pub use freeform_view::FreeFormView;
use gpu::{Gpu, frame_texture};
pub use gpu::{Viewer3, gpu_objects, start_3d};
pub use script_view::ScriptViewer;

/// The modeler on one canvas: the contour view's state and the GPU that draws it.
#[wasm_bindgen]
pub struct Modeler {
    editor: Editor,
    view2: View2,
    view3: View3,
    renderer: Renderer,
    surface: wgpu::Surface<'static>,
    config: wgpu::SurfaceConfiguration,
    max_size: u32,
    backend: &'static str,
    adapter: String,
    /// The last 2D frame's figures, for the panel.
    figures: FrameFigures,
    /// A model of many solids, when the model is one: the editor then holds its open part.
    parts: Option<Parts>,
    /// The editor's revision the 3D view's frame of the tree was last made for.
    whole_revision: Option<u64>,
    /// A 2D model of many solids compiled for one revision of the editor: the tree, and whether
    /// a Bézier part of it is space-mapped (the 2D view then samples it more coarsely).
    plane: Option<(u64, bezsolid_core::tree::Tree<2>, bool)>,
    /// A 3D model of many solids compiled for one revision of the editor, while a true section
    /// is shown (it cuts the whole model): the tree, its box, and whether a Bézier part of it is
    /// space-mapped.
    space: Option<(u64, bezsolid_core::tree::Tree<3>, (DVec3, DVec3), bool)>,
    /// Whether the 3D surface is cut at the true section's plane (while the section is on).
    cap_on: bool,
    /// Whether the section is across the volume's parameters (u, v, w) instead of space.
    section_parameters: bool,
}

/// What a true section cuts: the piecewise volume where the model is one (`pieces`), else the
/// editor's volume; `None` for a patch.
fn sectioned<'a>(
    editor: &'a Editor,
    pieces: Option<&'a bezsolid_core::piecewise::Piecewise3>,
) -> Option<&'a dyn Sectioned> {
    match pieces {
        Some(p) => Some(p),
        None => editor.volume().map(|v| v as &dyn Sectioned),
    }
}

fn error(context: &str, e: impl core::fmt::Display) -> JsError {
    JsError::new(&format!("{context}: {e}"))
}

/// Brings up the renderer on `canvas` with the default model (the paper's Fig. 9).
///
/// `backend` is `"auto"` (WebGPU when the browser has an adapter, else WebGL2), `"webgpu"` or
/// `"webgl2"`. A canvas keeps its first context type: to fall back after a failure, call again with a
/// fresh canvas.
///
/// # Errors
///
/// When no adapter or device can be had on the requested backend.
#[wasm_bindgen]
pub async fn start(canvas: HtmlCanvasElement, backend: Backend) -> Result<Modeler, JsError> {
    console_error_panic_hook::set_once();
    let gpu = Gpu::bring_up(&canvas, backend).await?;
    let renderer = Renderer::new(gpu.device, gpu.queue, &gpu.adapter, gpu.config.format);
    gpu.surface.configure(renderer.device(), &gpu.config);
    let editor = Editor::new(Solid2::fig9());
    let view3 = View3::new(&editor);
    let (surface, config, max_size, backend, info) =
        (gpu.surface, gpu.config, gpu.max_size, gpu.backend, gpu.info);
    Ok(Modeler {
        editor,
        view2: View2::new(),
        view3,
        renderer,
        surface,
        config,
        max_size,
        backend,
        adapter: info.name.clone(),
        figures: FrameFigures::default(),
        parts: None,
        cap_on: false,
        section_parameters: false,
        whole_revision: None,
        plane: None,
        space: None,
    })
}

#[wasm_bindgen]
impl Modeler {
    /// `"WebGPU"` or `"WebGL2"`.
    #[must_use]
    pub fn backend(&self) -> String {
        self.backend.to_owned()
    }

    /// The adapter's name, as the browser reports it.
    #[must_use]
    pub fn adapter(&self) -> String {
        self.adapter.clone()
    }

    /// The canvas's size in CSS pixels and the device pixel ratio. Returns the size in device pixels
    /// that the canvas's `width`/`height` must have (the page sets them).
    pub fn resize(&mut self, width: f64, height: f64, dpr: f64) -> Vec<u32> {
        self.view2.resize(width, height, dpr);
        let (w, h) = self.view2.device_size();
        // Past the largest texture, shrink both sides by one factor: the picture keeps its shape.
        let shrink = (f64::from(self.max_size) / f64::from(w.max(h))).min(1.0);
        let (w, h) = (
            (f64::from(w) * shrink) as u32,
            (f64::from(h) * shrink) as u32,
        );
        let (w, h) = (w.max(1), h.max(1));
        if (w, h) != (self.config.width, self.config.height) {
            self.config.width = w;
            self.config.height = h;
            self.surface.configure(self.renderer.device(), &self.config);
        }
        vec![w, h]
    }

    /// What the panel shows, one snapshot as JSON ([`Panel`]): the selection and its point, the last
    /// frame's range, contour pieces and whether the net folds, the degrees, the slice, the
    /// volume's surface and contour stack drawn, undo and redo, the drag mode.
    #[must_use]
    pub fn panel(&self) -> String {
        let mut panel = Panel::of(&self.editor, self.figures, &self.view3);
        if let Some(parts) = &self.parts {
            panel.can_undo = parts.can_undo() && !self.editor.busy();
            panel.can_redo = parts.can_redo() && !self.editor.busy();
        }
        panel.to_json()
    }

    /// Draws the current state.
    pub fn render(&mut self) {
        self.follow_parts();
        self.follow_space();
        let section = self.section_plane();
        let across = self.parameter_plane();
        if let Some((_, _, scene)) = section.or(across) {
            self.view2.set_scene(Some(scene));
        }
        self.view2.sync(&self.editor);
        // The piecewise volume is made only for a section (its cells' inverse maps).
        let pieces = section.or(across).and_then(|_| self.editor.piecewise3());
        let whole = self.whole_section();
        let cut = whole.as_ref().map(|w| w as &dyn Sectioned);
        let frame = match (
            &self.plane,
            section,
            sectioned(&self.editor, pieces.as_ref()),
        ) {
            (None, Some((axis, at, _)), Some(volume)) => {
                frame_section(&self.editor, &self.view2, cut.unwrap_or(volume), axis, at)
            }
            (None, None, Some(volume)) if across.is_some() => {
                let (axis, t, _) = across.unwrap_or_default();
                frame_parameter_section(&self.editor, &self.view2, volume, axis, t)
            }
            // The model is its one Bézier part, open: drawn as that solid (its unclipped curve,
            // a moved net's image).
            (Some(_), ..) if self.parts.as_ref().and_then(Parts::open) == Some(&[]) => {
                frame(&self.editor, &self.view2)
            }
            (Some((_, tree, mapped)), ..) => {
                let part = self.parts.as_ref().is_some_and(|p| p.open().is_some());
                let samples = if *mapped {
                    TREE_MAPPED_SAMPLES
                } else {
                    TREE_SAMPLES
                };
                frame_tree(&self.editor, &self.view2, tree, part, samples)
            }
            _ => frame(&self.editor, &self.view2),
        };
        self.figures = FrameFigures::from(&frame);
        let Some((texture, view)) =
            frame_texture(&self.surface, self.renderer.device(), &self.config)
        else {
            return;
        };
        self.renderer
            .draw(&view, (self.config.width, self.config.height), &frame);
        self.renderer.queue().present(texture);
    }

    /// The key of the surface the 3D view wants: the model's revision with the cap's changes
    /// (see `surface_request`).
    #[must_use]
    pub fn surface_revision(&self) -> f64 {
        self.view3.surface_key(&self.editor) as f64
    }

    /// Pointer pressed at CSS pixel `(x, y)` of the canvas, with the modifier that gives the other
    /// drag mode held or not; returns whether a point was grabbed.
    pub fn pointer_down(&mut self, x: f64, y: f64, other_mode: bool) -> bool {
        if !self.points_shown() {
            return false;
        }
        self.view2
            .pointer_down(&mut self.editor, DVec2::new(x, y), other_mode)
    }

    /// Pointer moved; returns whether the solid changed.
    pub fn pointer_move(&mut self, x: f64, y: f64) -> bool {
        self.view2.pointer_move(&mut self.editor, DVec2::new(x, y))
    }

    /// Pointer released or cancelled.
    pub fn pointer_up(&mut self) {
        self.view2.pointer_up(&mut self.editor);
    }

    /// Whether a point is being dragged.
    #[must_use]
    pub fn dragging(&self) -> bool {
        self.editor.dragging()
    }

    /// Whether a control point is under CSS pixel `(x, y)` (for the cursor).
    #[must_use]
    pub fn hit(&self, x: f64, y: f64) -> bool {
        if !self.points_shown() {
            return false;
        }
        self.view2.pick(&self.editor, DVec2::new(x, y)).is_some()
    }

    /// Zooms the 2D view about CSS pixel `(x, y)` by a wheel's `deltaY`, wherever the pointer is
    /// (a trackpad's pinch comes as the wheel with Ctrl). Returns whether the view changed.
    pub fn zoom_at(&mut self, x: f64, y: f64, delta_y: f64) -> bool {
        self.view2.zoom_at(&self.editor, DVec2::new(x, y), delta_y)
    }

    /// The wheel with `deltaY` at CSS pixel `(x, y)`: over the selected point, or with `xi` (the
    /// Alt key) held, changes its ξ; elsewhere zooms about the pointer ([`View2::wheel`]).
    /// Returns whether the solid changed (the view may have zoomed: redraw it either way).
    pub fn wheel(&mut self, x: f64, y: f64, delta_y: f64, xi: bool) -> bool {
        let q = DVec2::new(x, y);
        if !self.points_shown() {
            self.view2.zoom_at(&self.editor, q, delta_y);
            return false;
        }
        self.view2.wheel(&mut self.editor, q, delta_y, xi)
    }

    /// Two fingers (or a pan) on the 2D view: the world point under CSS pixel `(x, y)` (their
    /// midpoint before) goes to `(x + dx, y + dy)` (their midpoint now), magnified by `scale`
    /// (their spread now over before). Returns whether the view changed.
    pub fn pinch(&mut self, x: f64, y: f64, scale: f64, dx: f64, dy: f64) -> bool {
        self.view2
            .pinch(&self.editor, DVec2::new(x, y), scale, DVec2::new(dx, dy))
    }

    /// Cancels the 2D view's drag, putting the point back as Esc does (a second finger came
    /// down). Returns whether there was a drag.
    pub fn cancel_drag(&mut self) -> bool {
        self.view2.cancel_drag(&mut self.editor)
    }

    /// How many times the 2D view is magnified from the fitted picture (1 when fitted).
    #[must_use]
    pub fn zoom(&self) -> f64 {
        self.view2.zoom(&self.editor)
    }

    /// A key (`KeyboardEvent.key`); returns whether the view used it.
    pub fn key(&mut self, key: &str, shift: bool) -> bool {
        // Without a part open only the view's own keys (F fits it).
        if !self.points_shown() && !matches!(key, "f" | "F") {
            return false;
        }
        self.view2.key(&mut self.editor, key, shift)
    }

    /// ξ of the selected point, or `undefined`.
    #[must_use]
    pub fn selected_xi(&self) -> Option<f64> {
        self.editor.selected_xi()
    }

    /// Sets ξ of the selected point.
    ///
    /// # Errors
    ///
    /// When nothing is selected or the value is not a finite number.
    pub fn set_selected_xi(&mut self, xi: f64) -> Result<(), JsError> {
        self.need_part()?;
        self.editor.set_selected_xi(xi).map_err(JsError::from)
    }

    /// The world point `[x, y]` and `f` there, under CSS pixel `(x, y)`.
    #[must_use]
    pub fn probe(&self, x: f64, y: f64) -> Vec<f64> {
        let q = DVec2::new(x, y);
        let p = self.view2.to_world(&self.editor, q);
        let pieces = (self.section_plane().is_some() || self.parameter_plane().is_some())
            .then(|| self.editor.piecewise3())
            .flatten();
        let whole = self.whole_section();
        let f = match (
            &self.plane,
            self.section_plane(),
            sectioned(&self.editor, pieces.as_ref()),
        ) {
            (None, Some((axis, at, _)), Some(volume)) => {
                let [a, b] = plane_axes(axis);
                let mut s = [at; 3];
                s[a] = p.x;
                s[b] = p.y;
                let cut = whole.as_ref().map_or(volume, |w| w as &dyn Sectioned);
                cut.f(glam::DVec3::from_array(s))
            }
            (None, None, Some(volume)) if self.parameter_plane().is_some() => {
                let (axis, t, _) = self.parameter_plane().unwrap_or_default();
                volume.f(parameter_point(volume, axis, t, p))
            }
            (Some((_, tree, _)), ..) => tree.f(p),
            _ => self.view2.probe(&self.editor, q),
        };
        vec![p.x, p.y, f]
    }

    /// Shows the zero contour of `S_ξ` alone, unclipped and dashed, in the 2D view (or not).
    pub fn set_unclipped(&mut self, on: bool) {
        self.view2.set_unclipped(on);
    }

    /// Sets the drag mode: `"function"` or `"space"`.
    ///
    /// # Errors
    ///
    /// For another name.
    pub fn set_mode(&mut self, mode: DragMode) -> Result<(), JsError> {
        self.editor.set_mode(mode.try_into()?);
        Ok(())
    }

    /// Undoes the last step; returns whether there was one.
    pub fn undo(&mut self) -> bool {
        match &mut self.parts {
            Some(parts) => parts.undo(&mut self.editor),
            None => self.editor.undo(),
        }
    }

    /// Redoes the last undone step; returns whether there was one.
    pub fn redo(&mut self) -> bool {
        match &mut self.parts {
            Some(parts) => parts.redo(&mut self.editor),
            None => self.editor.redo(),
        }
    }

    /// Forgets the undo history (after restoring the autosaved model at start-up).
    pub fn forget_history(&mut self) {
        self.editor.forget_history();
        if let Some(parts) = &mut self.parts {
            parts.forget_history();
        }
    }

    /// Moves the selected point to `(x, y)`.
    ///
    /// # Errors
    ///
    /// When nothing is selected or a coordinate is not a finite number in range.
    pub fn set_selected_xy(&mut self, x: f64, y: f64) -> Result<(), JsError> {
        self.need_part()?;
        self.editor.set_selected_xy(x, y).map_err(JsError::from)
    }

    /// Raises the degree along `u` (`axis` 0) or `v` (1), keeping the shape.
    ///
    /// # Errors
    ///
    /// Past the largest grid, or for another axis.
    pub fn elevate(&mut self, axis: ParamAxis) -> Result<(), JsError> {
        self.need_part()?;
        Ok(self.editor.elevate(axis.into())?)
    }

    /// A new flat grid of `nu × nv` control points.
    ///
    /// # Errors
    ///
    /// For a size outside 2 to 16.
    pub fn reset_grid(&mut self, nu: u32, nv: u32) -> Result<(), JsError> {
        if self.parts.is_some() {
            let mut scratch = self.editor.clone();
            scratch.reset_grid(nu as usize, nv as usize)?;
            return self.replace_part(&scratch);
        }
        self.editor.reset_grid(nu as usize, nv as usize)?;
        self.view3.fit(&self.editor);
        Ok(())
    }

    /// A new flat volume of `nu × nv × nw` control points (one undo step).
    ///
    /// # Errors
    ///
    /// For a size outside 2 to 16.
    pub fn new_volume(&mut self, nu: u32, nv: u32, nw: u32) -> Result<(), JsError> {
        if self.parts.is_some() {
            let mut scratch = self.editor.clone();
            scratch.new_volume(nu as usize, nv as usize, nw as usize)?;
            return self.replace_part(&scratch);
        }
        self.editor
            .new_volume(nu as usize, nv as usize, nw as usize)?;
        self.view3.fit(&self.editor);
        Ok(())
    }

    /// Opens a preset by name: `"fig9"`, `"flat"` (a flat 4×4 grid), the volumes `"blob"`,
    /// `"ring"`, `"fish"`, or the zoo's space-mapped volumes `"chair"`, `"vase"`, `"knot"`,
    /// `"shell"`, `"koi"`, `"tooth"`.
    ///
    /// # Errors
    ///
    /// For an unknown preset.
    pub fn load_preset(&mut self, name: &str) -> Result<(), JsError> {
        let solid = match name {
            "flat" => bezsolid_core::model::ModelSolid::Patch(
                Solid2::regular([3, 3], glam::DVec2::ZERO, glam::DVec2::ONE, |[_, _]| 0.25)
                    .map_err(|e| error("preset", e))?,
            ),
            _ => document::preset(name)?,
        };
        let file = match solid {
            bezsolid_core::model::ModelSolid::Patch(s) => ModelFile::from_solid2(&s),
            bezsolid_core::model::ModelSolid::Volume(v) => ModelFile::from_solid3(&v),
        };
        self.open_file(file)
    }

    /// The model file (JSON).
    #[must_use]
    pub fn model_json(&self) -> String {
        match &self.parts {
            Some(parts) => serde_json::to_string_pretty(&parts.file(&self.editor))
                .map(|s| s + "\n")
                .unwrap_or_default(),
            None => document::model_json(&self.editor),
        }
    }

    /// Opens a model file's text (an undo step); on error the model is unchanged.
    ///
    /// # Errors
    ///
    /// What is wrong with the file.
    pub fn load_model(&mut self, text: &str) -> Result<(), JsError> {
        // A HyperFun file bezsolid exported carries its model.
        if let Some(file) = bezsolid_core::hyperfun::model_of(text) {
            return self.open_file(file.map_err(Error::from)?);
        }
        let start = text.trim_start();
        if !start.starts_with('{') && (start.starts_with("--") || text.contains("my_model(")) {
            return Err(Error::new(
                "a HyperFun program that carries no bezsolid model: the page opens the HyperFun \
                 files bezsolid exported (the command line's `bezsolid eval` evaluates any)",
            )
            .into());
        }
        if !text.trim_start().starts_with('{') {
            // Not JSON: the reader's own message says so.
            document::read_model(text)?;
        }
        self.open_file(document::read_file(text)?)
    }

    /// The share link's fragment, `#v1.…`.
    ///
    /// # Errors
    ///
    /// When the model is too large for a link.
    pub fn link(&self) -> Result<String, JsError> {
        match &self.parts {
            Some(parts) => {
                Ok(bezsolid_core::link::encode(&parts.file(&self.editor)).map_err(Error::from)?)
            }
            None => document::share_fragment(&self.editor).map_err(JsError::from),
        }
    }

    /// Opens a share link (a whole URL or its fragment; an undo step); on error the model is
    /// unchanged.
    ///
    /// # Errors
    ///
    /// What is wrong with the link.
    pub fn open_link(&mut self, link: &str) -> Result<(), JsError> {
        let file = bezsolid_core::link::decode_file(link).map_err(Error::from)?;
        self.open_file(file)
    }

    /// The |ξ| that colours full blue or red in the 3D view: the largest |ξ| of the control points.
    #[must_use]
    pub fn xi_extent(&self) -> f64 {
        match self.editor.volume() {
            Some(v) => v
                .net()
                .points()
                .iter()
                .fold(1e-12f64, |m, p| m.max(p.w.abs())),
            None => self.editor.xi_scale(),
        }
    }

    /// The resolution the volume surface is meshed at when at rest.
    #[must_use]
    pub fn resolution(&self) -> u32 {
        self.view3.resolution() as u32
    }

    /// Whether the model is a volume.
    #[must_use]
    pub fn is_volume(&self) -> bool {
        self.editor.volume().is_some() && self.parts.as_ref().is_none_or(|p| p.open().is_some())
    }

    /// Opens slice `index` across `axis` (0 = u, 1 = v, 2 = w) of the volume in the patch editor.
    ///
    /// # Errors
    ///
    /// For a patch model, or an axis or index out of range.
    pub fn set_slice(&mut self, axis: ParamAxis, index: u32) -> Result<(), JsError> {
        self.need_part()?;
        Ok(self.editor.set_slice(axis.into(), index as usize)?)
    }

    /// Sets the volume surface's resolution at rest (cells along the longest side); returns the
    /// value taken (8 to 160).
    pub fn set_resolution(&mut self, cells: u32) -> u32 {
        self.view3.set_resolution(cells as usize) as u32
    }

    /// Meshes the volume coarsely (while a point moves) or at the resolution set.
    pub fn set_coarse(&mut self, coarse: bool) {
        self.view3.set_coarse(coarse);
    }

    /// Has the fine volume surface and the contour stack made elsewhere (a Web Worker): the view
    /// then draws a coarse surface and the previous stack, and asks for them through
    /// `surface_request` and `stack_request`.
    pub fn set_external_surface(&mut self, external: bool) {
        self.view3.set_external_surface(external);
    }

    /// A number that changes whenever the model does (what the worker's requests are keyed by).
    #[must_use]
    pub fn revision(&self) -> f64 {
        self.editor.revision() as f64
    }

    /// The contour stack wanted since the last call, `[revision, axis]` (axis 0 = u, 1 = v,
    /// 2 = w), or `undefined`; asked for at rest only.
    pub fn stack_request(&mut self) -> Option<Vec<f64>> {
        self.view3
            .take_stack_request()
            .map(|(r, axis)| vec![r as f64, axis.index() as f64])
    }

    /// A contour stack made elsewhere ([`headless_stack`]) for model `revision` across `axis`;
    /// returns whether it was taken (not when the model or the axis has changed since).
    pub fn set_stack(&mut self, revision: f64, axis: ParamAxis, data: &[f64]) -> bool {
        self.view3
            .set_stack(&self.editor, revision as u64, axis.into(), data)
    }

    /// The model file (JSON) of the patch the 2D view edits (the patch, or the volume's selected
    /// slice): what the worker makes the SVG export of.
    #[must_use]
    pub fn patch_json(&self) -> String {
        match self.parts.as_ref().filter(|p| p.outline().dimension() == 2) {
            Some(parts) => serde_json::to_string(&parts.file(&self.editor)).unwrap_or_default(),
            None => document::patch_json(&self.editor),
        }
    }

    /// The fine surface wanted since the last call, `[revision, resolution]`, or `undefined`.
    pub fn surface_request(&mut self) -> Option<Vec<f64>> {
        self.view3
            .take_request()
            .map(|(r, res)| vec![r as f64, res as f64])
    }

    /// A surface made elsewhere for model `revision` at `resolution` (six `f32` per vertex:
    /// position, normal); returns whether it was taken (not when the model has changed since).
    pub fn set_surface(&mut self, revision: f64, resolution: u32, data: &[f32]) -> bool {
        self.view3
            .set_surface(&self.editor, revision as u64, resolution as usize, data)
    }
}
