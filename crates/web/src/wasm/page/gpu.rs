//! The GPU on a canvas: the device and surface the views draw on, the textures of each frame,
//! and the 3D view's canvas ([`Viewer3`]) with its start.

use super::*;

/// The surface's next texture and a view of it, or `None` for this frame (a lost or outdated
/// surface is configured again, to draw on the next).
pub(super) fn frame_texture(
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
pub(super) struct Gpu {
    pub(super) surface: wgpu::Surface<'static>,
    pub(super) adapter: wgpu::Adapter,
    pub(super) device: wgpu::Device,
    pub(super) queue: wgpu::Queue,
    pub(super) config: wgpu::SurfaceConfiguration,
    pub(super) max_size: u32,
    pub(super) backend: &'static str,
    pub(super) info: wgpu::AdapterInfo,
}

impl Gpu {
    /// An adapter and device for `canvas` on `backend` (`"auto"`, `"webgpu"` or `"webgl2"`). Each
    /// canvas gets its own: a WebGL2 device draws only on the canvas it was made for.
    pub(super) async fn bring_up(
        canvas: &HtmlCanvasElement,
        backend: Backend,
    ) -> Result<Self, JsError> {
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
    pub(super) fn fit_canvas(&mut self, width: f64, height: f64, dpr: f64) -> Vec<u32> {
        let (w, h) = device_pixels(width, height, dpr, self.max_size);
        if (w, h) != (self.config.width, self.config.height) {
            self.config.width = w;
            self.config.height = h;
            self.surface.configure(self.renderer.device(), &self.config);
        }
        vec![w, h]
    }

    /// Draws `scene` on the canvas and presents it.
    pub(super) fn present(&mut self, scene: &crate::scene::Scene<'_>) {
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
