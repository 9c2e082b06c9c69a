//! The wgpu renderer of the contour view. It draws a [`Frame`] into any texture view, so the page's
//! surface and an offscreen texture share one path.

use core::ops::Deref;
use core::sync::atomic::{AtomicUsize, Ordering};

use crate::frame2d::{Frame, ShapeVertex};

static BUFFERS: AtomicUsize = AtomicUsize::new(0);
static TEXTURES: AtomicUsize = AtomicUsize::new(0);
static MADE: AtomicUsize = AtomicUsize::new(0);

/// A GPU buffer or texture (or a view that keeps its texture) that the renderers made, counted
/// while it lives: [`live_objects`] tells whether they level off however long the page runs.
pub(crate) struct Counted<T> {
    inner: T,
    count: &'static AtomicUsize,
}

impl<T> Counted<T> {
    fn new(inner: T, count: &'static AtomicUsize) -> Self {
        count.fetch_add(1, Ordering::Relaxed);
        MADE.fetch_add(1, Ordering::Relaxed);
        Self { inner, count }
    }

    /// A buffer, counted.
    pub(crate) fn buffer(inner: T) -> Self {
        Self::new(inner, &BUFFERS)
    }

    /// A texture or a view of one, counted.
    pub(crate) fn texture(inner: T) -> Self {
        Self::new(inner, &TEXTURES)
    }
}

impl<T> Deref for Counted<T> {
    type Target = T;
    fn deref(&self) -> &T {
        &self.inner
    }
}

impl<T> Drop for Counted<T> {
    fn drop(&mut self) {
        self.count.fetch_sub(1, Ordering::Relaxed);
    }
}

/// `[buffers, textures]` the renderers hold now, and how many of either they have made in all.
pub(crate) fn live_objects() -> [usize; 3] {
    [
        BUFFERS.load(Ordering::Relaxed),
        TEXTURES.load(Ordering::Relaxed),
        MADE.load(Ordering::Relaxed),
    ]
}

/// GPU state for drawing frames into targets of one format.
pub(crate) struct Renderer {
    device: wgpu::Device,
    queue: wgpu::Queue,
    format: wgpu::TextureFormat,
    samples: u32,
    field_pipeline: wgpu::RenderPipeline,
    shape_pipeline: wgpu::RenderPipeline,
    field_layout: wgpu::BindGroupLayout,
    sampler: wgpu::Sampler,
    /// The field texture, its size and its bind group; remade when the size changes.
    field: Option<(Counted<wgpu::Texture>, (u32, u32), wgpu::BindGroup)>,
    /// The vertex buffer and its capacity in bytes.
    shapes: Option<(Counted<wgpu::Buffer>, u64)>,
    /// The multisampled colour target and its size.
    msaa: Option<(Counted<wgpu::TextureView>, (u32, u32))>,
    bytes: Vec<u8>,
}

impl Renderer {
    /// Pipelines for targets of `format`, with 4× multisampling where the adapter has it.
    pub(crate) fn new(
        device: wgpu::Device,
        queue: wgpu::Queue,
        adapter: &wgpu::Adapter,
        format: wgpu::TextureFormat,
    ) -> Self {
        let samples = sample_count(adapter, &[format]);
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("contour view"),
            source: wgpu::ShaderSource::Wgsl(include_str!("shader.wgsl").into()),
        });
        let field_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("field"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable: true },
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 1,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                    count: None,
                },
            ],
        });
        let field_pipeline_layout =
            device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("field"),
                bind_group_layouts: &[Some(&field_layout)],
                immediate_size: 0,
            });
        let shape_pipeline_layout =
            device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("shapes"),
                bind_group_layouts: &[],
                immediate_size: 0,
            });
        let target = [Some(wgpu::ColorTargetState {
            format,
            blend: Some(wgpu::BlendState::ALPHA_BLENDING),
            write_mask: wgpu::ColorWrites::ALL,
        })];
        let multisample = wgpu::MultisampleState {
            count: samples,
            ..Default::default()
        };
        let field_pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("field"),
            layout: Some(&field_pipeline_layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs_field"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: None,
            multisample,
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fs_field"),
                compilation_options: Default::default(),
                targets: &target,
            }),
            multiview_mask: None,
            cache: None,
        });
        let attributes = wgpu::vertex_attr_array![0 => Float32x2, 1 => Float32x4];
        let shape_pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("shapes"),
            layout: Some(&shape_pipeline_layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs_shape"),
                compilation_options: Default::default(),
                buffers: &[Some(wgpu::VertexBufferLayout {
                    array_stride: ShapeVertex::SIZE as u64,
                    step_mode: wgpu::VertexStepMode::Vertex,
                    attributes: &attributes,
                })],
            },
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: None,
            multisample,
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fs_shape"),
                compilation_options: Default::default(),
                targets: &target,
            }),
            multiview_mask: None,
            cache: None,
        });
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("field"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            ..Default::default()
        });
        Self {
            device,
            queue,
            format,
            samples,
            field_pipeline,
            shape_pipeline,
            field_layout,
            sampler,
            field: None,
            shapes: None,
            msaa: None,
            bytes: Vec::new(),
        }
    }

    /// The device, for configuring surfaces.
    pub(crate) fn device(&self) -> &wgpu::Device {
        &self.device
    }

    /// The queue, for presenting.
    pub(crate) fn queue(&self) -> &wgpu::Queue {
        &self.queue
    }

    /// Draws `frame` into `target`, a view of a `size` texture in the renderer's format.
    pub(crate) fn draw(&mut self, target: &wgpu::TextureView, size: (u32, u32), frame: &Frame) {
        self.upload_field(frame);
        let vertex_count = self.upload_shapes(frame);
        let msaa = self.msaa_view(size);
        let mut encoder = self
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("frame"),
            });
        {
            let (view, resolve_target) = match msaa {
                Some(ref m) => (m, Some(target)),
                None => (target, None),
            };
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("contour view"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view,
                    depth_slice: None,
                    resolve_target,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color::WHITE),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: None,
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            if let Some((_, _, bind_group)) = &self.field {
                pass.set_pipeline(&self.field_pipeline);
                pass.set_bind_group(0, bind_group, &[]);
                pass.draw(0..3, 0..1);
            }
            if let (Some((buffer, _)), true) = (&self.shapes, vertex_count > 0) {
                pass.set_pipeline(&self.shape_pipeline);
                pass.set_vertex_buffer(0, buffer.slice(..));
                pass.draw(0..vertex_count, 0..1);
            }
        }
        self.queue.submit([encoder.finish()]);
    }

    fn upload_field(&mut self, frame: &Frame) {
        let image = &frame.field;
        let size = (image.width, image.height);
        if self.field.as_ref().is_none_or(|(_, s, _)| *s != size) {
            let texture = self.device.create_texture(&wgpu::TextureDescriptor {
                label: Some("field"),
                size: wgpu::Extent3d {
                    width: size.0,
                    height: size.1,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: wgpu::TextureFormat::Rgba8Unorm,
                usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
                view_formats: &[],
            });
            let view = texture.create_view(&wgpu::TextureViewDescriptor::default());
            let bind_group = self.device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("field"),
                layout: &self.field_layout,
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: wgpu::BindingResource::TextureView(&view),
                    },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: wgpu::BindingResource::Sampler(&self.sampler),
                    },
                ],
            });
            self.field = Some((Counted::texture(texture), size, bind_group));
        }
        if let Some((texture, _, _)) = &self.field {
            self.queue.write_texture(
                wgpu::TexelCopyTextureInfo {
                    texture,
                    mip_level: 0,
                    origin: wgpu::Origin3d::ZERO,
                    aspect: wgpu::TextureAspect::All,
                },
                &image.rgba,
                wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(4 * size.0),
                    rows_per_image: Some(size.1),
                },
                wgpu::Extent3d {
                    width: size.0,
                    height: size.1,
                    depth_or_array_layers: 1,
                },
            );
        }
    }

    /// Uploads the shapes; returns the vertex count.
    fn upload_shapes(&mut self, frame: &Frame) -> u32 {
        self.bytes.clear();
        for v in &frame.shapes {
            v.write(&mut self.bytes);
        }
        let needed = self.bytes.len() as u64;
        if needed == 0 {
            return 0;
        }
        if self.shapes.as_ref().is_none_or(|(_, cap)| *cap < needed) {
            let capacity = needed.next_power_of_two().max(4096);
            let buffer = self.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("shapes"),
                size: capacity,
                usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            self.shapes = Some((Counted::buffer(buffer), capacity));
        }
        if let Some((buffer, _)) = &self.shapes {
            self.queue.write_buffer(buffer, 0, &self.bytes);
        }
        frame.shapes.len() as u32
    }

    fn msaa_view(&mut self, size: (u32, u32)) -> Option<wgpu::TextureView> {
        if self.samples == 1 {
            return None;
        }
        if self.msaa.as_ref().is_none_or(|(_, s)| *s != size) {
            let view = attachment(&self.device, "msaa", size, self.format, self.samples);
            self.msaa = Some((Counted::texture(view), size));
        }
        self.msaa.as_ref().map(|(v, _)| (**v).clone())
    }
}

/// 4× multisampling where the adapter has it for every one of `formats` (the targets of one pass),
/// else none.
pub(crate) fn sample_count(adapter: &wgpu::Adapter, formats: &[wgpu::TextureFormat]) -> u32 {
    if formats.iter().all(|&f| {
        adapter
            .get_texture_format_features(f)
            .flags
            .sample_count_supported(4)
    }) {
        4
    } else {
        1
    }
}

/// A render attachment of `size` (sides at least 1) and its view.
pub(crate) fn attachment(
    device: &wgpu::Device,
    label: &str,
    size: (u32, u32),
    format: wgpu::TextureFormat,
    samples: u32,
) -> wgpu::TextureView {
    device
        .create_texture(&wgpu::TextureDescriptor {
            label: Some(label),
            size: wgpu::Extent3d {
                width: size.0.max(1),
                height: size.1.max(1),
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: samples,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
            view_formats: &[],
        })
        .create_view(&wgpu::TextureViewDescriptor::default())
}
