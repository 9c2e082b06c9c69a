//! The wgpu renderer of the 3D view: a [`Scene`]'s opaque triangles with depth, then its translucent
//! ones blended over them, 4× multisampled where the adapter can.

use crate::render::{Counted, attachment, sample_count};
use crate::scene::{MeshVertex, Scene};

const DEPTH: wgpu::TextureFormat = wgpu::TextureFormat::Depth24Plus;
const BACKGROUND: wgpu::Color = wgpu::Color {
    r: 0.955,
    g: 0.96,
    b: 0.97,
    a: 1.0,
};

/// The multisampled colour target (when multisampling), the depth target, and their size.
type Targets = (
    Option<Counted<wgpu::TextureView>>,
    Counted<wgpu::TextureView>,
    (u32, u32),
);

/// GPU state for drawing scenes into targets of one format.
pub(crate) struct Renderer3 {
    device: wgpu::Device,
    queue: wgpu::Queue,
    format: wgpu::TextureFormat,
    samples: u32,
    pipeline: wgpu::RenderPipeline,
    translucent: wgpu::RenderPipeline,
    globals: Counted<wgpu::Buffer>,
    bind_group: wgpu::BindGroup,
    /// The vertex buffer and its capacity in bytes.
    vertices: Option<(Counted<wgpu::Buffer>, u64)>,
    /// The generation of the scene triangles in the buffer: a frame that only moves the camera
    /// uploads nothing but the matrix.
    uploaded: Option<u64>,
    /// The multisampled colour target (when multisampling), the depth target, and their size.
    targets: Option<Targets>,
    bytes: Vec<u8>,
}

impl Renderer3 {
    pub(crate) fn new(
        device: wgpu::Device,
        queue: wgpu::Queue,
        adapter: &wgpu::Adapter,
        format: wgpu::TextureFormat,
    ) -> Self {
        let samples = sample_count(adapter, &[format, DEPTH]);
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("3d view"),
            source: wgpu::ShaderSource::Wgsl(include_str!("shader3d.wgsl").into()),
        });
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("globals"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            }],
        });
        let globals = Counted::buffer(device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("globals"),
            size: 80,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        }));
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("globals"),
            layout: &layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: globals.as_entire_binding(),
            }],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("3d view"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let attributes = wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x4];
        // Opaque triangles write depth; translucent ones are tested against it but do not write
        // it, so overlapping translucent surfaces do not cut holes in each other.
        let make = |depth_write: bool| {
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(if depth_write {
                    "3d view"
                } else {
                    "3d view, translucent"
                }),
                layout: Some(&pipeline_layout),
                vertex: wgpu::VertexState {
                    module: &module,
                    entry_point: Some("vs_mesh"),
                    compilation_options: Default::default(),
                    buffers: &[Some(wgpu::VertexBufferLayout {
                        array_stride: MeshVertex::SIZE as u64,
                        step_mode: wgpu::VertexStepMode::Vertex,
                        attributes: &attributes,
                    })],
                },
                primitive: wgpu::PrimitiveState::default(),
                depth_stencil: Some(wgpu::DepthStencilState {
                    format: DEPTH,
                    depth_write_enabled: Some(depth_write),
                    depth_compare: Some(wgpu::CompareFunction::Less),
                    stencil: Default::default(),
                    bias: Default::default(),
                }),
                multisample: wgpu::MultisampleState {
                    count: samples,
                    ..Default::default()
                },
                fragment: Some(wgpu::FragmentState {
                    module: &module,
                    entry_point: Some("fs_mesh"),
                    compilation_options: Default::default(),
                    targets: &[Some(wgpu::ColorTargetState {
                        format,
                        blend: Some(wgpu::BlendState::ALPHA_BLENDING),
                        write_mask: wgpu::ColorWrites::ALL,
                    })],
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        let pipeline = make(true);
        let translucent = make(false);
        Self {
            device,
            queue,
            format,
            samples,
            pipeline,
            translucent,
            globals,
            bind_group,
            vertices: None,
            uploaded: None,
            targets: None,
            bytes: Vec::new(),
        }
    }

    pub(crate) fn device(&self) -> &wgpu::Device {
        &self.device
    }

    pub(crate) fn queue(&self) -> &wgpu::Queue {
        &self.queue
    }

    /// Draws `scene` into `target`, a view of a `size` texture in the renderer's format.
    pub(crate) fn draw(&mut self, target: &wgpu::TextureView, size: (u32, u32), scene: &Scene) {
        let mut globals = Vec::with_capacity(80);
        for x in scene
            .view_proj
            .iter()
            .flatten()
            .chain(&scene.eye)
            .chain(&[1.0])
        {
            globals.extend_from_slice(&x.to_le_bytes());
        }
        self.queue.write_buffer(&self.globals, 0, &globals);
        if self.uploaded != Some(scene.generation) {
            self.upload(scene);
        }
        self.ensure_targets(size);
        let Some((msaa, depth, _)) = &self.targets else {
            return;
        };
        let mut encoder = self
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("3d frame"),
            });
        {
            let (view, resolve_target) = match msaa {
                Some(m) => (&**m, Some(target)),
                None => (target, None),
            };
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("3d view"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view,
                    depth_slice: None,
                    resolve_target,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(BACKGROUND),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: depth,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(1.0),
                        store: wgpu::StoreOp::Discard,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            let opaque = scene.opaque.len() as u32;
            let count = opaque + scene.translucent.len() as u32;
            if let (Some((buffer, _)), true) = (&self.vertices, count > 0) {
                pass.set_bind_group(0, &self.bind_group, &[]);
                pass.set_vertex_buffer(0, buffer.slice(..));
                pass.set_pipeline(&self.pipeline);
                pass.draw(0..opaque, 0..1);
                pass.set_pipeline(&self.translucent);
                pass.draw(opaque..count, 0..1);
            }
        }
        self.queue.submit([encoder.finish()]);
    }

    /// Encodes and uploads the scene's triangles.
    fn upload(&mut self, scene: &Scene) {
        self.bytes.clear();
        for v in scene.opaque.iter().chain(scene.translucent) {
            v.write(&mut self.bytes);
        }
        let needed = self.bytes.len() as u64;
        if needed > 0 && self.vertices.as_ref().is_none_or(|(_, cap)| *cap < needed) {
            let capacity = needed.next_power_of_two().max(1 << 16);
            let buffer = self.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("3d vertices"),
                size: capacity,
                usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            self.vertices = Some((Counted::buffer(buffer), capacity));
        }
        if let (Some((buffer, _)), true) = (&self.vertices, needed > 0) {
            self.queue.write_buffer(buffer, 0, &self.bytes);
        }
        self.uploaded = Some(scene.generation);
    }

    fn ensure_targets(&mut self, size: (u32, u32)) {
        if self.targets.as_ref().is_some_and(|(_, _, s)| *s == size) {
            return;
        }
        let msaa = (self.samples > 1).then(|| {
            Counted::texture(attachment(
                &self.device,
                "3d msaa",
                size,
                self.format,
                self.samples,
            ))
        });
        let depth = Counted::texture(attachment(
            &self.device,
            "3d depth",
            size,
            DEPTH,
            self.samples,
        ));
        self.targets = Some((msaa, depth, size));
    }
}
