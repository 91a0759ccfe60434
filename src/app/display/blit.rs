//! The desktop's display: the snapshot in an `Rgba32Float` texture, drawn
//! by `blit.wgsl` in an egui_wgpu paint callback (see `display.rs`).

use std::num::NonZeroU64;

use eframe::egui;
use eframe::egui_wgpu::{self, CallbackResources, CallbackTrait, ScreenDescriptor, wgpu};

use super::ImageSource;
use crate::render::display::{DisplaySettings, Tonemap};

/// Creates the blit's pipeline for the renderer and registers it.
pub fn install(render_state: &egui_wgpu::RenderState) {
    BlitResources::install(render_state);
}

/// Uniforms of `blit.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct Params {
    scale: f32,
    tonemap: u32,
    encode_srgb: u32,
    /// 1 for a false-colour image: no exposure, no tonemap.
    false_colour: u32,
}

/// GPU objects that live as long as the renderer (in egui_wgpu's callback resources).
pub struct BlitResources {
    pipeline: wgpu::RenderPipeline,
    layout: wgpu::BindGroupLayout,
    params: wgpu::Buffer,
    encode_srgb: bool,
    texture: Option<ImageTexture>,
}

struct ImageTexture {
    texture: wgpu::Texture,
    bind_group: wgpu::BindGroup,
    width: u32,
    height: u32,
    /// Which image it holds (see `ImageSource::key`).
    key: (bool, u64),
}

impl BlitResources {
    /// Creates the pipeline for `target_format` and registers it with the renderer.
    pub fn install(render_state: &egui_wgpu::RenderState) {
        let resources = Self::new(&render_state.device, render_state.target_format);
        render_state
            .renderer
            .write()
            .callback_resources
            .insert(resources);
    }

    pub fn new(device: &wgpu::Device, target_format: wgpu::TextureFormat) -> Self {
        let shader = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("lumiere blit"),
            source: wgpu::ShaderSource::Wgsl(include_str!("../blit.wgsl").into()),
        });
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("lumiere blit"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable: false },
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 1,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: false,
                        min_binding_size: NonZeroU64::new(std::mem::size_of::<Params>() as u64),
                    },
                    count: None,
                },
            ],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("lumiere blit"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("lumiere blit"),
            layout: Some(&pipeline_layout),
            vertex: wgpu::VertexState {
                module: &shader,
                entry_point: Some("vs_main"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            fragment: Some(wgpu::FragmentState {
                module: &shader,
                entry_point: Some("fs_main"),
                compilation_options: Default::default(),
                targets: &[Some(target_format.into())],
            }),
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: None,
            multisample: wgpu::MultisampleState::default(),
            multiview_mask: None,
            cache: None,
        });
        let params = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("lumiere blit params"),
            size: std::mem::size_of::<Params>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        Self {
            pipeline,
            layout,
            params,
            encode_srgb: !target_format.is_srgb(),
            texture: None,
        }
    }

    /// Uploads `source` if it is not the one on the GPU already, and the display uniforms.
    pub fn prepare(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        source: &ImageSource,
        display: DisplaySettings,
    ) {
        let key = source.key();
        let (width, height, pixels) = source.pixels();
        let params = Params {
            scale: display.exposure.exp2(),
            tonemap: match display.tonemap {
                Tonemap::None => 0,
                Tonemap::Reinhard => 1,
                Tonemap::Aces => 2,
            },
            encode_srgb: self.encode_srgb as u32,
            false_colour: key.0 as u32,
        };
        queue.write_buffer(&self.params, 0, bytemuck::bytes_of(&params));
        if pixels.is_empty() || self.texture.as_ref().is_some_and(|t| t.key == key) {
            return;
        }
        let fits = self
            .texture
            .as_ref()
            .is_some_and(|t| (t.width, t.height) == (width, height));
        if !fits {
            self.texture = Some(self.create_texture(device, width, height));
        }
        let Some(image) = &mut self.texture else {
            return;
        };
        queue.write_texture(
            wgpu::TexelCopyTextureInfo {
                texture: &image.texture,
                mip_level: 0,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            bytemuck::cast_slice(pixels),
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(width * 16),
                rows_per_image: Some(height),
            },
            wgpu::Extent3d {
                width,
                height,
                depth_or_array_layers: 1,
            },
        );
        image.key = key;
    }

    fn create_texture(&self, device: &wgpu::Device, width: u32, height: u32) -> ImageTexture {
        let texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("lumiere film"),
            size: wgpu::Extent3d {
                width,
                height,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Rgba32Float,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        });
        let view = texture.create_view(&wgpu::TextureViewDescriptor::default());
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("lumiere blit"),
            layout: &self.layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::TextureView(&view),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: self.params.as_entire_binding(),
                },
            ],
        });
        ImageTexture {
            texture,
            bind_group,
            width,
            height,
            key: (false, u64::MAX),
        }
    }

    /// Draws the image over the whole viewport (the callback's rectangle).
    pub fn paint(&self, render_pass: &mut wgpu::RenderPass<'static>) {
        if let Some(image) = &self.texture {
            render_pass.set_pipeline(&self.pipeline);
            render_pass.set_bind_group(0, &image.bind_group, &[]);
            render_pass.draw(0..3, 0..1);
        }
    }
}

/// The per-frame paint callback: which image, with which display settings.
pub struct BlitCallback {
    pub source: ImageSource,
    pub display: DisplaySettings,
}

impl CallbackTrait for BlitCallback {
    fn prepare(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        _screen: &ScreenDescriptor,
        _encoder: &mut wgpu::CommandEncoder,
        resources: &mut CallbackResources,
    ) -> Vec<wgpu::CommandBuffer> {
        if let Some(blit) = resources.get_mut::<BlitResources>() {
            blit.prepare(device, queue, &self.source, self.display);
        }
        Vec::new()
    }

    fn paint(
        &self,
        _info: egui::PaintCallbackInfo,
        render_pass: &mut wgpu::RenderPass<'static>,
        resources: &CallbackResources,
    ) {
        if let Some(blit) = resources.get::<BlitResources>() {
            blit.paint(render_pass);
        }
    }
}

/// Adds the image to `ui`'s painter, drawn in `rect` (points).
pub fn paint_image(ui: &egui::Ui, rect: egui::Rect, source: ImageSource, display: DisplaySettings) {
    ui.painter().add(egui_wgpu::Callback::new_paint_callback(
        rect,
        BlitCallback { source, display },
    ));
}
