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

/// The surface's next texture and a view of it, or `None` for this frame (a lost or outdated
/// surface is configured again, to draw on the next).
fn frame_texture(
    surface: &wgpu::Surface<'static>,
    device: &wgpu::Device,
    config: &wgpu::SurfaceConfiguration,
) -> Option<(wgpu::SurfaceTexture, wgpu::TextureView)> {
    let texture = match surface.get_current_texture() {
        wgpu::CurrentSurfaceTexture::Success(t) | wgpu::CurrentSurfaceTexture::Suboptimal(t) => t,
        wgpu::CurrentSurfaceTexture::Outdated | wgpu::CurrentSurfaceTexture::Lost => {
            surface.configure(device, config);
            return None;
        }
        _ => return None,
    };
    let view = texture
        .texture
        .create_view(&wgpu::TextureViewDescriptor::default());
    Some((texture, view))
}

/// A device and a configured-to-be surface on one canvas.
struct Gpu {
    surface: wgpu::Surface<'static>,
    adapter: wgpu::Adapter,
    device: wgpu::Device,
    queue: wgpu::Queue,
    config: wgpu::SurfaceConfiguration,
    max_size: u32,
    backend: &'static str,
    info: wgpu::AdapterInfo,
}

impl Gpu {
    /// An adapter and device for `canvas` on `backend` (`"auto"`, `"webgpu"` or `"webgl2"`). Each
    /// canvas gets its own: a WebGL2 device draws only on the canvas it was made for.
    async fn bring_up(canvas: &HtmlCanvasElement, backend: Backend) -> Result<Self, JsError> {
        let backends = wgpu::Backends::try_from(backend)?;
        if !cfg!(feature = "webgl") && backend == Backend::Webgl2 {
            return Err(JsError::new(
                "this build of the page draws with WebGPU only: load the WebGL2 build",
            ));
        }
        let mut desc = wgpu::InstanceDescriptor::new_without_display_handle();
        desc.backends = backends;
        let instance = wgpu::util::new_instance_with_webgpu_detection(desc).await;
        let surface = instance
            .create_surface(wgpu::SurfaceTarget::Canvas(canvas.clone()))
            .map_err(|e| error("cannot draw on the canvas", e))?;
        let adapter = instance
            .request_adapter(&wgpu::RequestAdapterOptions {
                compatible_surface: Some(&surface),
                ..Default::default()
            })
            .await
            .map_err(|e| error("no graphics adapter", e))?;
        let info = adapter.get_info();
        let backend = match info.backend {
            wgpu::Backend::BrowserWebGpu => "WebGPU",
            wgpu::Backend::Gl => "WebGL2",
            _ => "unknown",
        };
        let limits = wgpu::Limits::downlevel_webgl2_defaults().using_resolution(adapter.limits());
        let max_size = limits.max_texture_dimension_2d;
        let (device, queue) = adapter
            .request_device(&wgpu::DeviceDescriptor {
                label: Some("bezsolid"),
                required_limits: limits,
                ..Default::default()
            })
            .await
            .map_err(|e| error("no graphics device", e))?;
        device.on_uncaptured_error(std::sync::Arc::new(|e| {
            web_sys::console::error_1(&format!("bezsolid: GPU error: {e}").into());
        }));
        let caps = surface.get_capabilities(&adapter);
        // A plain (not sRGB) format: the colours are computed for display as they are.
        let format = caps
            .formats
            .iter()
            .copied()
            .find(|f| !f.is_srgb())
            .or(caps.formats.first().copied());
        let (w, h) = (canvas.width().max(1), canvas.height().max(1));
        let mut config = surface
            .get_default_config(&adapter, w, h)
            .ok_or_else(|| JsError::new("the canvas cannot be drawn on by this adapter"))?;
        if let Some(format) = format {
            config.format = format;
        }
        Ok(Self {
            surface,
            adapter,
            device,
            queue,
            config,
            max_size,
            backend,
            info,
        })
    }
}

/// Device pixels for a canvas of `width × height` CSS pixels at `dpr`, shrunk by one factor past
/// the largest texture (the picture keeps its shape).
fn device_pixels(width: f64, height: f64, dpr: f64, max_size: u32) -> (u32, u32) {
    let dpr = if dpr.is_finite() && dpr > 0.0 {
        dpr.clamp(0.25, 8.0)
    } else {
        1.0
    };
    let w = (width.max(1.0) * dpr).round();
    let h = (height.max(1.0) * dpr).round();
    let shrink = (f64::from(max_size) / w.max(h)).min(1.0);
    (((w * shrink) as u32).max(1), ((h * shrink) as u32).max(1))
}

/// The GPU objects the renderers hold now and have made: `[buffers, textures, made in all]` (a
/// texture view that keeps its texture counts as a texture). The soak test watches them level off.
#[wasm_bindgen]
#[must_use]
pub fn gpu_objects() -> Vec<u32> {
    crate::render::live_objects().map(|n| n as u32).to_vec()
}

/// The 3D view's canvas and GPU; the model and camera live in [`Modeler`].
#[wasm_bindgen]
pub struct Viewer3 {
    renderer: Renderer3,
    surface: wgpu::Surface<'static>,
    config: wgpu::SurfaceConfiguration,
    max_size: u32,
}

impl Viewer3 {
    /// Sizes the canvas's surface for `width × height` CSS pixels at `dpr`; returns the size in
    /// device pixels.
    fn fit_canvas(&mut self, width: f64, height: f64, dpr: f64) -> Vec<u32> {
        let (w, h) = device_pixels(width, height, dpr, self.max_size);
        if (w, h) != (self.config.width, self.config.height) {
            self.config.width = w;
            self.config.height = h;
            self.surface.configure(self.renderer.device(), &self.config);
        }
        vec![w, h]
    }

    /// Draws `scene` on the canvas and presents it.
    fn present(&mut self, scene: &crate::scene::Scene<'_>) {
        let Some((texture, view)) =
            frame_texture(&self.surface, self.renderer.device(), &self.config)
        else {
            return;
        };
        self.renderer
            .draw(&view, (self.config.width, self.config.height), scene);
        self.renderer.queue().present(texture);
    }
}

/// Brings up the 3D view's renderer on `canvas`, on `backend` as [`start`] takes it.
///
/// # Errors
///
/// When no adapter or device can be had on the requested backend.
#[wasm_bindgen]
pub async fn start_3d(canvas: HtmlCanvasElement, backend: Backend) -> Result<Viewer3, JsError> {
    let gpu = Gpu::bring_up(&canvas, backend).await?;
    let renderer = Renderer3::new(gpu.device, gpu.queue, &gpu.adapter, gpu.config.format);
    gpu.surface.configure(renderer.device(), &gpu.config);
    Ok(Viewer3 {
        renderer,
        surface: gpu.surface,
        config: gpu.config,
        max_size: gpu.max_size,
    })
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

    /// Draws the volume's true section by a plane across the control slice's axis (`x` across u,
    /// `y` across v, `z` across w), at `at` from 0 (the box's low face) to 1, instead of the slice
    /// (`on`), or the slice again. The section's control points are not edited: the slice's are,
    /// with the section off.
    pub fn set_section(&mut self, on: bool, at: f64) {
        let was = self.view2.section().is_some();
        self.view2.set_section(on.then_some(at));
        if was && !on && self.parts.is_none() {
            self.view2.set_scene(None);
        }
    }

    /// Cuts the 3D surface at the true section's plane (`on`, while the section is on), the cut
    /// face closed: the solid below the plane is shown (the whole model's, in a model of many
    /// solids).
    pub fn set_section_cap(&mut self, on: bool) {
        self.cap_on = on;
        self.sync_cap();
    }

    /// Gives the 3D view the section's plane as its cap, where the cap is on: where the plane is
    /// now (it follows the box as points move).
    fn sync_cap(&mut self) {
        self.follow_space();
        let plane = self.section_plane();
        let cap = plane
            .filter(|_| self.cap_on)
            .map(|(axis, at, _)| (axis, at));
        self.view3.set_cap(cap);
        let shown = plane.and_then(|(axis, at, _)| {
            let (_, _, (lo, hi)) = self.section_box()?;
            Some(crate::view3d::SectionPlane { axis, at, lo, hi })
        });
        self.view3.set_section_plane(shown);
    }

    /// The whole 3D model of many solids as the true section cuts it, when one is open and
    /// compiled ([`Self::follow_space`]).
    fn whole_section(&self) -> Option<crate::frame2d::TreeSection<'_>> {
        self.space
            .as_ref()
            .map(|(_, tree, bounds, mapped)| crate::frame2d::TreeSection {
                tree,
                bounds: *bounds,
                mapped: *mapped,
            })
    }

    /// Compiles what the views show of a 3D model of many solids for the true section, while one
    /// is shown across space (the section then cuts the whole model, in its box); forgets it
    /// otherwise.
    fn follow_space(&mut self) {
        let wanted = self.view2.section().is_some()
            && !self.section_parameters
            && self.editor.volume().is_some();
        let Some(parts) = self
            .parts
            .as_ref()
            .filter(|p| wanted && p.outline().dimension() == 3)
        else {
            self.space = None;
            return;
        };
        let revision = self.editor.revision();
        if self.space.as_ref().is_some_and(|(r, ..)| *r == revision) {
            return;
        }
        let shown = parts
            .shown(&self.editor)
            .map(|s| ModelFile::from_spec(s).to_tree());
        self.space = match shown {
            Some(Ok(bezsolid_core::tree::ModelTree::Space(t))) => t
                .bounds()
                .filter(|(lo, hi)| (0..3).all(|a| lo[a] < hi[a]))
                .or_else(|| t.parts_box())
                .map(|(lo, hi)| {
                    let bounds = (DVec3::from_array(lo), DVec3::from_array(hi));
                    let mapped = parts.has_space_mapped_part(&self.editor);
                    (revision, t, bounds, mapped)
                }),
            _ => None,
        };
    }

    /// Where the true section's plane lies, from 0 (the box's low face) to 1; `undefined` with
    /// no section.
    #[must_use]
    pub fn section_fraction(&self) -> Option<f64> {
        self.view2.section()
    }

    /// Whether the section's plane is being dragged in the 3D view.
    #[must_use]
    pub fn section_dragged_3d(&self) -> bool {
        self.view3.section_dragged()
    }

    /// The CSS pixel `[x, y]` of the section plane's point at fractions `(s, t)` of its extent
    /// along its two other axes in the 3D view (`0` or `1` on its frame, which a drag moves);
    /// `undefined` with no section.
    #[must_use]
    pub fn section_screen_3d(&self, s: f64, t: f64) -> Option<Vec<f64>> {
        self.view3
            .section_screen(s, t)
            .map(|q| q.to_array().to_vec())
    }

    /// The key of the surface the 3D view wants: the model's revision with the cap's changes
    /// (see `surface_request`).
    #[must_use]
    pub fn surface_revision(&self) -> f64 {
        self.view3.surface_key(&self.editor) as f64
    }

    /// Puts the true section across the volume's parameters (`on`: the plane `u[axis] = t` of
    /// the parameter box, `f` at its points `S(u)`) or across space.
    pub fn set_section_parameters(&mut self, on: bool) {
        self.section_parameters = on;
        self.sync_cap();
    }

    /// The section across the parameters drawn, when one is: its axis (0 = u), the parameter
    /// it lies at, and the volume's box in the plane's axes (where the parameter square is shown).
    fn parameter_plane(&self) -> Option<(usize, f64, (DVec2, DVec2))> {
        let (axis, t, (lo, hi)) = self.section_box().filter(|_| self.section_parameters)?;
        let [a, b] = plane_axes(axis);
        Some((
            axis,
            t,
            (DVec2::new(lo[a], lo[b]), DVec2::new(hi[a], hi[b])),
        ))
    }

    /// The section's axis (the slice's), where it lies from 0 to 1, and the volume's box.
    fn section_box(&self) -> Option<(usize, f64, (glam::DVec3, glam::DVec3))> {
        let fraction = self.view2.section()?;
        let volume = self.editor.volume()?;
        let (axis, _) = self.editor.slice()?;
        // Across space in a model of many solids: the whole model's box.
        let bounds = match &self.space {
            Some((_, _, bounds, _)) if !self.section_parameters => *bounds,
            _ => volume.domain(),
        };
        Some((axis.index(), fraction, bounds))
    }

    /// The true section drawn across space, when one is: its axis, where it lies and the
    /// plane's box.
    fn section_plane(&self) -> Option<(usize, f64, (DVec2, DVec2))> {
        let (axis, fraction, (lo, hi)) = self.section_box().filter(|_| !self.section_parameters)?;
        let at = lo[axis] + fraction * (hi[axis] - lo[axis]);
        let [a, b] = plane_axes(axis);
        Some((
            axis,
            at,
            (DVec2::new(lo[a], lo[b]), DVec2::new(hi[a], hi[b])),
        ))
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

    /// Sizes the 3D view: CSS pixels and the device pixel ratio; returns the canvas size in device
    /// pixels.
    pub fn resize_3d(
        &mut self,
        viewer: &mut Viewer3,
        width: f64,
        height: f64,
        dpr: f64,
    ) -> Vec<u32> {
        self.view3.resize(&self.editor, width, height);
        viewer.fit_canvas(width, height, dpr)
    }

    /// Draws the 3D view.
    pub fn render_3d(&mut self, viewer: &mut Viewer3) {
        self.follow_parts();
        self.sync_cap();
        let scene = self.view3.scene(&self.editor);
        viewer.present(&scene);
    }

    /// Pointer pressed in the 3D view: `pan` for the right button; `shift` pans on empty space and
    /// gives the other drag mode on a control point. Returns whether a point was grabbed.
    pub fn pointer_down_3d(&mut self, x: f64, y: f64, pan: bool, shift: bool) -> bool {
        let grabbed = self
            .view3
            .pointer_down(&mut self.editor, DVec2::new(x, y), pan, shift);
        if self.view3.handle_dragged().is_some()
            && let Some(parts) = &mut self.parts
            && let Err(e) = parts.begin_handle(&mut self.editor)
        {
            // Nothing to move: the gesture ends here.
            self.view3.pointer_up(&mut self.editor);
            web_sys::console::warn_1(&format!("bezsolid: {e}").into());
            return false;
        }
        // The contour view holds still from the start of the drag, as for its own drags.
        self.view2.sync(&self.editor);
        grabbed
    }

    /// Pointer moved in the 3D view; returns whether the camera or the model changed.
    pub fn pointer_move_3d(&mut self, x: f64, y: f64) -> bool {
        let changed = self.view3.pointer_move(&mut self.editor, DVec2::new(x, y));
        if let Some(at) = self.view3.take_section_drag()
            && let Some((a, _, (lo, hi))) = self.section_box()
        {
            // The plane dragged in 3D: the 2D view's section (and the cut) follow.
            let fraction = ((at - lo[a]) / (hi[a] - lo[a])).clamp(0.0, 1.0);
            if fraction.is_finite() {
                self.view2.set_section(Some(fraction));
                self.sync_cap();
            }
        }
        if let (Some((handle, amount)), Some(parts)) = (self.view3.take_handle(), &mut self.parts) {
            parts.drag_handle(handle, amount, &mut self.editor);
            self.follow_parts();
        }
        changed
    }

    /// Pointer released in the 3D view.
    pub fn pointer_up_3d(&mut self) {
        if self.view3.handle_dragged().is_some()
            && let Some(parts) = &mut self.parts
        {
            parts.end_handle();
        }
        self.view3.pointer_up(&mut self.editor);
    }

    /// Whether a control point is being dragged (in either view).
    #[must_use]
    pub fn editing_3d(&self) -> bool {
        self.editor.dragging()
            || self.editor.volume_dragged().is_some()
            || self.view3.handle_dragged().is_some()
    }

    /// Whether a 3D gesture (orbit, pan or point drag) is under way.
    #[must_use]
    pub fn busy_3d(&self) -> bool {
        self.view3.busy()
    }

    /// Whether a control point's sphere is under CSS pixel `(x, y)` of the 3D view.
    #[must_use]
    pub fn hit_3d(&self, x: f64, y: f64) -> bool {
        let q = DVec2::new(x, y);
        self.view3.pick(&self.editor, q).is_some()
            || self.view3.over_handle(q)
            || self.view3.over_section(q)
    }

    /// The wheel over the 3D view: zooms.
    pub fn wheel_3d(&mut self, delta_y: f64) {
        self.view3.wheel(delta_y);
    }

    /// Two fingers on the 3D view: zoom by their spread's `scale` (now over before) and pan by
    /// their midpoint's move `(dx, dy)` in CSS pixels. Returns whether the camera moved.
    pub fn pinch_3d(&mut self, scale: f64, dx: f64, dy: f64) -> bool {
        self.view3.pinch(scale, DVec2::new(dx, dy))
    }

    /// Cancels the 3D gesture under way (a second finger came down): a point's drag puts the
    /// point back as Esc does; a handle's drag ends as one undo step; an orbit or pan stops.
    pub fn cancel_3d(&mut self) {
        if self.view3.handle_dragged().is_some()
            && let Some(parts) = &mut self.parts
        {
            parts.end_handle();
        }
        self.view3.cancel(&mut self.editor);
    }

    /// The CSS pixel `[x, y]` of control point `index`'s sphere in the 3D view (`index` as in the
    /// model file), or `undefined`.
    #[must_use]
    pub fn sphere_screen_3d(&self, index: usize) -> Option<Vec<f64>> {
        self.view3
            .screen_of(&self.editor, index)
            .map(|q| q.to_array().to_vec())
    }

    /// The CSS pixel `[x, y]` of the selection's handle in the 3D view (0 moves, 1 turns about
    /// z, 2 scales), or `undefined` when the selection has none.
    #[must_use]
    pub fn handle_screen_3d(&self, which: u32) -> Option<Vec<f64>> {
        let handle = match which {
            0 => Handle::Move,
            1 => Handle::Turn,
            2 => Handle::Scale,
            _ => return None,
        };
        self.view3
            .handle_screen(handle)
            .map(|q| q.to_array().to_vec())
    }

    /// Frames the model in the 3D view again.
    pub fn fit_3d(&mut self) {
        self.view3.fit(&self.editor);
    }

    /// What the outliner shows of a model of many solids, as JSON ([`Parts::to_json`]: the
    /// rows, the selection, the part open in the editors, the selection's numbers), or
    /// `undefined` for a model of one solid.
    #[must_use]
    pub fn outline(&self) -> Option<String> {
        self.parts.as_ref().map(Parts::to_json)
    }

    /// Selects the node at `path` (child indices from the root); a Bézier part opens in the 2D
    /// and 3D editors.
    ///
    /// # Errors
    ///
    /// No such node.
    pub fn outline_select(&mut self, path: Vec<u32>) -> Result<(), JsError> {
        let path: Vec<usize> = path.into_iter().map(|i| i as usize).collect();
        self.with_parts(|parts, editor| parts.select(&path, editor))
    }

    /// Adds a part beside the selection (a model of one solid becomes a union of two); the new
    /// part is selected. One undo step.
    ///
    /// # Errors
    ///
    /// A kind of the other dimension, or a model past its caps.
    pub fn outline_add(&mut self, kind: PartKind) -> Result<(), JsError> {
        let kind = kind.try_into()?;
        self.with_parts(|parts, editor| parts.add(kind, editor))
    }

    /// Adds a cell along `axis` to the selected Bézier part, after its last (the last cells
    /// mirrored across their face; a single patch or volume becomes a piecewise one). One undo
    /// step.
    ///
    /// # Errors
    ///
    /// No Bézier part selected, an axis the part lacks, or a net past what the editor takes.
    pub fn add_cell(&mut self, axis: ParamAxis) -> Result<(), JsError> {
        let axis = bezsolid_core::Axis::from(axis).index();
        self.with_parts(|parts, editor| parts.add_cell(axis, editor))
    }

    /// Removes the selected part's last cell along `axis` (one cell left everywhere: a single
    /// patch or volume again). One undo step.
    ///
    /// # Errors
    ///
    /// No Bézier part selected, or one cell along `axis`.
    pub fn remove_cell(&mut self, axis: ParamAxis) -> Result<(), JsError> {
        let axis = bezsolid_core::Axis::from(axis).index();
        self.with_parts(|parts, editor| parts.remove_cell(axis, editor))
    }

    /// Puts an operation or a transform around the selection. One undo step.
    ///
    /// # Errors
    ///
    /// A model past its caps.
    pub fn outline_wrap(&mut self, operation: PartOperation) -> Result<(), JsError> {
        let op = operation.try_into()?;
        self.with_parts(|parts, editor| parts.wrap(op, editor))
    }

    /// Removes the selection. One undo step.
    ///
    /// # Errors
    ///
    /// For the root.
    pub fn outline_remove(&mut self) -> Result<(), JsError> {
        self.with_parts(Parts::remove)
    }

    /// Moves the selection `by` places among its siblings. One undo step.
    ///
    /// # Errors
    ///
    /// None in practice.
    pub fn outline_reorder(&mut self, by: i32) -> Result<(), JsError> {
        self.with_parts(|parts, editor| parts.reorder(by as isize, editor))
    }

    /// Names the selection (an empty name takes a shown part's name away). One undo step.
    ///
    /// # Errors
    ///
    /// A name past 256 bytes.
    pub fn outline_rename(&mut self, name: &str) -> Result<(), JsError> {
        self.with_parts(|parts, editor| parts.rename(name, editor))
    }

    /// Hides the selection from the views, or shows it again (the model and its exports keep
    /// it). One undo step.
    ///
    /// # Errors
    ///
    /// None in practice.
    pub fn outline_hide(&mut self) -> Result<(), JsError> {
        self.with_parts(Parts::toggle_hidden)
    }

    /// The model file (JSON) of what the views show: the model, less the hidden parts of a model
    /// of many solids (what the worker meshes for the 3D view); `undefined` when all is hidden.
    #[must_use]
    pub fn view_json(&self) -> Option<String> {
        let shown = match &self.parts {
            Some(parts) => parts.shown(&self.editor)?,
            None => document::model_file(&self.editor).solid,
        };
        // Cut at the section's plane: the model intersected with the half-space below it.
        let spec = match self.view3.cap() {
            Some(cap) => crate::view3d::capped(shown, cap),
            None => shown,
        };
        serde_json::to_string(&ModelFile::from_spec(spec)).ok()
    }

    /// Sets a number of the selection (`radius`, `center[0]`, `a0`, `t`, `translate[2]`, …);
    /// settings of one field in a row are one undo step.
    ///
    /// # Errors
    ///
    /// A field the node lacks or a value its rules refuse: nothing changes.
    pub fn outline_set(&mut self, field: &str, value: f64) -> Result<(), JsError> {
        self.with_parts(|parts, editor| parts.set(field, value, editor))
    }
}

impl Modeler {
    /// Whether the editor holds the model, or the open Bézier part of a model of many solids
    /// (with none open, what it holds is not in the model: it is not edited).
    fn part_open(&self) -> bool {
        self.parts.as_ref().is_none_or(|p| p.open().is_some())
    }

    /// Whether the 2D view shows points to pick: a part is open and no true section is drawn
    /// instead of its slice.
    fn points_shown(&self) -> bool {
        self.part_open() && self.section_plane().is_none() && self.parameter_plane().is_none()
    }

    /// [`Self::part_open`], or the error that says what to do.
    fn need_part(&self) -> Result<(), JsError> {
        if self.part_open() {
            Ok(())
        } else {
            Err(JsError::new(
                "select a Bézier part under Parts to edit its control points",
            ))
        }
    }

    /// Runs an edit of the model of many solids (a model of one solid becomes one first); on
    /// error nothing changes.
    fn with_parts(
        &mut self,
        edit: impl FnOnce(&mut Parts, &mut Editor) -> Result<(), Error>,
    ) -> Result<(), JsError> {
        if self.editor.busy() {
            return Err(JsError::new("finish the drag first"));
        }
        let Some(mut parts) = self.parts.take() else {
            // The first edit of a model of one solid: on a copy, kept only if the edit is made.
            let mut editor = self.editor.clone();
            let mut parts = Parts::of_editor(&mut editor)?;
            edit(&mut parts, &mut editor)?;
            self.editor = editor;
            self.parts = Some(parts);
            self.follow_parts();
            return Ok(());
        };
        let result = edit(&mut parts, &mut self.editor);
        self.parts = Some(parts);
        self.follow_parts();
        Ok(result?)
    }

    /// Opens a model file: a model of many solids, or in one a model of one solid, replaces the
    /// whole model as one undo step of the tree; otherwise the editor opens it as before.
    fn open_file(&mut self, file: ModelFile) -> Result<(), JsError> {
        if self.parts.is_none() && !file.solid.is_tree() {
            let solid = file.to_solid().map_err(Error::from)?;
            document::open(&mut self.editor, solid);
            self.view3.fit(&self.editor);
            return Ok(());
        }
        file.to_tree().map_err(Error::from)?;
        self.with_parts(|parts, editor| parts.replace_root(file.solid, editor))?;
        // The surface drawn is the previous model's: frame the new one by its bounds.
        self.view3.forget_surface();
        self.view3.fit(&self.editor);
        Ok(())
    }

    /// Replaces the open part by `scratch`'s model (a new grid; one undo step).
    fn replace_part(&mut self, scratch: &Editor) -> Result<(), JsError> {
        let node = document::model_file(scratch).solid;
        self.with_parts(|parts, editor| parts.replace_open(node, editor))
    }

    /// Writes what the editor changed back into the tree, and brings the 3D view's frame of the
    /// tree (the part's placement, the selection's box, the model's box) up to date.
    fn follow_parts(&mut self) {
        let Some(parts) = &mut self.parts else {
            self.plane = None;
            return;
        };
        parts.sync(&self.editor);
        let revision = self.editor.revision();
        if parts.outline().dimension() == 2
            && self.plane.as_ref().is_none_or(|(r, ..)| *r != revision)
        {
            let shown = parts
                .shown(&self.editor)
                .map(|s| ModelFile::from_spec(s).to_tree());
            self.plane = match shown {
                Some(Ok(bezsolid_core::tree::ModelTree::Plane(t))) => {
                    let mapped = parts.has_space_mapped_part(&self.editor);
                    Some((revision, t, mapped))
                }
                _ => None,
            };
        } else if parts.outline().dimension() != 2 {
            self.plane = None;
        }
        if self.editor.busy() || self.whole_revision == Some(self.editor.revision()) {
            return;
        }
        self.whole_revision = Some(self.editor.revision());
        if parts.outline().dimension() != 3 {
            self.view3.set_whole(None);
            let placement = parts
                .open()
                .map_or(glam::DAffine2::IDENTITY, |p| parts.placement2(p));
            let scene = self
                .plane
                .as_ref()
                .and_then(|(_, t, _)| t.bounds())
                .map(|(lo, hi)| {
                    let (lo, hi) = (DVec2::from_array(lo), DVec2::from_array(hi));
                    if parts.open().is_none() {
                        return (lo, hi);
                    }
                    // The open part's domain, placed, is in sight too.
                    let (a, b) = self.editor.solid().domain();
                    [a, b, DVec2::new(a.x, b.y), DVec2::new(b.x, a.y)]
                        .map(|c| placement.transform_point2(c))
                        .iter()
                        .fold((lo, hi), |(lo, hi), &c| (lo.min(c), hi.max(c)))
                });
            self.view2.set_scene(scene);
            self.view2.set_placement(placement);
            return;
        }
        self.view2.set_scene(None);
        self.view2.set_placement(glam::DAffine2::IDENTITY);
        let first = self.view3.whole().is_none();
        let open = parts.open();
        let bounds = match parts.tree(&self.editor) {
            Ok(bezsolid_core::tree::ModelTree::Space(t)) => t
                .bounds()
                .map(|(lo, hi)| (glam::DVec3::from_array(lo), glam::DVec3::from_array(hi))),
            _ => None,
        };
        let whole = Whole {
            placement: open.map_or(glam::DAffine3::IDENTITY, |p| parts.placement(p)),
            part: open.is_some() && self.editor.volume().is_some(),
            frame: parts.bounds_of(parts.outline().selected(), &self.editor),
            bounds,
            handles: open.is_none(),
            shown: parts.shown(&self.editor).is_some(),
        };
        self.view3.set_whole(Some(whole));
        if first {
            self.view3.fit(&self.editor);
        }
    }
}

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

orbit_view!(FreeFormView);
orbit_view!(ScriptViewer);

/// The Free-form mode ([`crate::freeform`]) for the page: its scene draws on the 3D view's
/// [`Viewer3`].
#[wasm_bindgen]
pub struct FreeFormView {
    state: FreeForm,
}

impl Default for FreeFormView {
    fn default() -> Self {
        Self::new()
    }
}

#[wasm_bindgen]
impl FreeFormView {
    /// The default scene (the blob minus a torus).
    #[wasm_bindgen(constructor)]
    #[must_use]
    pub fn new() -> Self {
        Self {
            state: FreeForm::new(),
        }
    }

    /// Operand `slot` (0: A, 1: B) becomes a built-in example.
    ///
    /// # Errors
    ///
    /// An unknown example or slot.
    pub fn set_example(&mut self, slot: usize, example: FreeFormExample) -> Result<(), JsError> {
        Ok(self.state.set_example(slot, example.try_into()?)?)
    }

    /// Operand `slot` becomes the mesh in the OBJ or STL file `bytes`, named `name`.
    ///
    /// # Errors
    ///
    /// What is wrong with the file (malformed, too large, not closed) or the slot.
    pub fn import_mesh(&mut self, slot: usize, name: &str, bytes: &[u8]) -> Result<(), JsError> {
        let mesh =
            bezsolid_core::mesh::read(bytes).map_err(|e| JsError::new(&format!("{name}: {e}")))?;
        self.state
            .set_mesh(slot, name, &mesh)
            .map_err(|e| JsError::new(&format!("{name}: {e}")))
    }

    /// Moves operand `slot` by `(x, y, z)`.
    ///
    /// # Errors
    ///
    /// An unknown slot or numbers that are not finite.
    pub fn set_offset(&mut self, slot: usize, x: f64, y: f64, z: f64) -> Result<(), JsError> {
        self.state
            .set_offset(slot, [x, y, z])
            .map_err(JsError::from)
    }

    /// `union`, `intersection` or `difference` over every solid, `complement` (of A alone), or
    /// `none` (A alone).
    ///
    /// # Errors
    ///
    /// An unknown operation.
    pub fn set_operation(&mut self, operation: Operation) -> Result<(), JsError> {
        Ok(self.state.set_combine(operation.try_into()?)?)
    }

    /// The operation as [`FreeFormView::set_operation`] names it, or `expression` for any other
    /// expression.
    #[must_use]
    pub fn operation(&self) -> String {
        self.state
            .combine()
            .map_or_else(|| "expression".into(), |c| Operation::from(c).text().into())
    }

    /// Combines the solids by an expression over their names: `|` union, `&` intersection,
    /// `-` difference, `!` complement, brackets.
    ///
    /// # Errors
    ///
    /// What is wrong with the text and where (the scene is kept).
    pub fn set_expression(&mut self, text: &str) -> Result<(), JsError> {
        Ok(self.state.set_expression(text)?)
    }

    /// The expression over the solids' names.
    #[must_use]
    pub fn expression(&self) -> String {
        self.state.expression()
    }

    /// The solids' names in the expression (`A`, `B`, …).
    #[must_use]
    pub fn letters(&self) -> Vec<String> {
        self.state.letters()
    }

    /// The number of solids.
    #[must_use]
    pub fn operand_count(&self) -> usize {
        self.state.operand_count()
    }

    /// Adds a built-in example beside the scene, joining the union; returns its slot.
    ///
    /// # Errors
    ///
    /// Past the most solids a model has.
    pub fn add_operand(&mut self, example: FreeFormExample) -> Result<usize, JsError> {
        Ok(self.state.add_operand(example.try_into()?)?)
    }

    /// Removes solid `slot` (and it from the expression).
    ///
    /// # Errors
    ///
    /// An unknown slot, or the last solid.
    pub fn remove_operand(&mut self, slot: usize) -> Result<(), JsError> {
        Ok(self.state.remove_operand(slot)?)
    }

    /// Places solid `slot`: offset, rotation about x, y, z in degrees, scale per axis.
    ///
    /// # Errors
    ///
    /// An unknown slot, or numbers that are refused (not finite, a zero scale).
    #[allow(clippy::too_many_arguments)] // nine numbers, as the panel's fields give them
    pub fn set_placement(
        &mut self,
        slot: usize,
        x: f64,
        y: f64,
        z: f64,
        rx: f64,
        ry: f64,
        rz: f64,
        sx: f64,
        sy: f64,
        sz: f64,
    ) -> Result<(), JsError> {
        Ok(self
            .state
            .set_placement(slot, [x, y, z], [rx, ry, rz], [sx, sy, sz])?)
    }

    /// Solid `slot`'s crease angle: edges whose faces turn by more than `degrees` stay sharp.
    ///
    /// # Errors
    ///
    /// An unknown slot or an angle outside 0 to 180.
    pub fn set_crease(&mut self, slot: usize, degrees: f64) -> Result<(), JsError> {
        Ok(self.state.set_crease(slot, degrees)?)
    }

    /// Solid `slot`'s crease angle in degrees, or `undefined`.
    #[must_use]
    pub fn crease(&self, slot: usize) -> Option<f64> {
        self.state.crease(slot)
    }

    /// Solid `slot`'s placement: offset, rotation (degrees) and scale, nine numbers, or
    /// `undefined`.
    #[must_use]
    pub fn placement(&self, slot: usize) -> Option<Vec<f64>> {
        self.state
            .placement(slot)
            .map(|(o, r, s)| [o, r, s].concat())
    }

    /// Begins dragging solid `slot` from CSS pixel `(x, y)` of the view: it moves in the plane
    /// facing the view. Returns whether it began.
    pub fn move_start(&mut self, slot: usize, x: f64, y: f64) -> bool {
        self.state.move_start(slot, glam::DVec2::new(x, y))
    }

    /// Moves the dragged solid under the pointer; returns whether it moved.
    pub fn move_to(&mut self, x: f64, y: f64) -> bool {
        self.state.move_to(glam::DVec2::new(x, y))
    }

    /// Ends the drag (one undo step).
    pub fn move_end(&mut self) {
        self.state.move_end();
    }

    /// Operand `slot`'s name (an example's or the imported file's), or `undefined`.
    #[must_use]
    pub fn operand_name(&self, slot: usize) -> Option<String> {
        self.state.operand(slot).map(|o| o.0)
    }

    /// Whether operand `slot` is a built-in example (else an imported mesh).
    #[must_use]
    pub fn operand_is_example(&self, slot: usize) -> bool {
        self.state.operand(slot).is_some_and(|o| o.2)
    }

    /// Operand `slot`'s offset `[x, y, z]`, or `undefined`.
    #[must_use]
    pub fn operand_offset(&self, slot: usize) -> Option<Vec<f64>> {
        self.state.operand(slot).map(|o| o.1.to_vec())
    }

    /// The triangles of each operand's mesh.
    #[must_use]
    pub fn triangle_counts(&self) -> Vec<u32> {
        self.state
            .boolean()
            .solids
            .iter()
            .map(|s| s.triangles().len() as u32)
            .collect()
    }

    /// What the view shows: `result`, `points` or `operands`.
    ///
    /// # Errors
    ///
    /// Another name.
    pub fn set_display(&mut self, display: FreeFormDisplay) -> Result<(), JsError> {
        self.state.set_display(display.try_into()?);
        Ok(())
    }

    /// The result surface's resolution at rest; returns the value taken.
    pub fn set_resolution(&mut self, cells: u32) -> u32 {
        self.state.set_resolution(cells as usize) as u32
    }

    /// The result surface's resolution at rest (cells along the longest side of an export).
    #[must_use]
    pub fn resolution(&self) -> u32 {
        self.state.resolution() as u32
    }

    /// Undoes the last change of an operand, its place or the operation.
    pub fn undo(&mut self) -> bool {
        self.state.undo()
    }

    /// Redoes the last undone change.
    pub fn redo(&mut self) -> bool {
        self.state.redo()
    }

    /// Whether there is a change to undo.
    pub fn can_undo(&self) -> bool {
        self.state.can_undo()
    }

    /// Whether there is an undone change to redo.
    pub fn can_redo(&self) -> bool {
        self.state.can_redo()
    }

    /// Forgets the undo and redo steps (after restoring the autosaved scene).
    pub fn forget_history(&mut self) {
        self.state.forget_history();
    }

    /// Changes whenever the scene does (for saving only what changed).
    #[must_use]
    pub fn revision(&self) -> f64 {
        self.state.revision() as f64
    }

    /// The fine surface wanted from the worker: `[revision, resolution]`, once.
    pub fn surface_request(&mut self) -> Option<Vec<f64>> {
        self.state
            .surface_request()
            .map(|(r, n)| vec![r as f64, n as f64])
    }

    /// The worker's fine surface; returns whether it was taken (not stale).
    pub fn set_surface(&mut self, revision: f64, resolution: u32, data: &[f32]) -> bool {
        self.state
            .set_surface(revision as u64, resolution as usize, data)
    }

    /// `[triangles, resolution]` of the result's surface drawn now, or `undefined`.
    #[must_use]
    pub fn surface_info(&self) -> Option<Vec<u32>> {
        self.state
            .surface_info()
            .map(|(t, r)| vec![t as u32, r as u32])
    }

    /// `[points in the partial chain or result, marked]` of the point mesh last drawn, or
    /// `undefined` before it is drawn.
    #[must_use]
    pub fn point_counts(&self) -> Option<Vec<u32>> {
        self.state
            .point_counts()
            .map(|(a, b)| vec![a as u32, b as u32])
    }

    /// The model file (JSON): indented, or compact when it holds an imported mesh (a 200 k-triangle
    /// mesh indented would pass the 16 MiB a model file may have).
    #[must_use]
    pub fn model_json(&self) -> String {
        crate::freeform::model_json(&self.state.model_file())
    }

    /// Opens a free-form model file or link.
    ///
    /// # Errors
    ///
    /// What is wrong with it (the scene is kept).
    pub fn open(&mut self, text: &str) -> Result<(), JsError> {
        let file = crate::freeform::read_file(text)?;
        self.state.open(&file).map_err(JsError::from)
    }

    /// The share link fragment `#v1.…`.
    ///
    /// # Errors
    ///
    /// When an imported mesh makes the model too large for a link (save the model file instead).
    pub fn link(&self) -> Result<String, JsError> {
        bezsolid_core::link::encode(&self.state.model_file()).map_err(|e| {
            JsError::new(&format!(
                "{e}. An imported mesh travels in the model file: use Export → Model file"
            ))
        })
    }
}

/// The Script mode's view: the drawing of a script's run and an orbit camera.
#[wasm_bindgen]
#[derive(Default)]
pub struct ScriptViewer {
    state: crate::script::ScriptView,
}

#[wasm_bindgen]
impl ScriptViewer {
    /// An empty view.
    #[wasm_bindgen(constructor)]
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Shows a drawing made by [`headless_plasm`]; frames it if `refit` or the camera was not
    /// moved.
    ///
    /// # Errors
    ///
    /// Data that is not whole triangles.
    pub fn set_drawing(&mut self, floats: &[f32], refit: bool) -> Result<(), JsError> {
        self.state.set_drawing(floats, refit).map_err(JsError::from)
    }

    /// Triangles drawn.
    #[must_use]
    pub fn triangle_count(&self) -> usize {
        self.state.triangle_count()
    }
}
