//! The window's GPU side: a surface, the chiaro context made on the surface's adapter, the
//! frame renderer, and egui's painter, which draws the panel and the frame (the frame's 8-bit
//! image, or a debug view, registered as an egui texture and drawn into the area beside the
//! panel: 1:1, or upscaled at a render scale below 1).

use std::sync::Arc;

use chiaro_gpu::context::missing_capabilities;
use chiaro_gpu::gpu_scene::GpuScene;
use chiaro_gpu::{GpuContext, Renderer};
use glam::Vec3;
use winit::event_loop::OwnedDisplayHandle;
use winit::window::Window;

use crate::ViewerError;
use crate::debug_view::{DebugPass, DebugView};

/// The surface, the renderer and the painter of one window.
pub struct Display {
    surface: wgpu::Surface<'static>,
    config: wgpu::SurfaceConfiguration,
    /// The chiaro frame renderer (on the surface's adapter).
    pub renderer: Renderer,
    painter: egui_wgpu::Renderer,
    frame_texture: Option<egui::TextureId>,
    debug: Option<DebugPass>,
    /// Whether the window shows the debug pass's image (not the frame).
    showing_debug: bool,
}

/// Preference of an adapter kind: lower is better.
fn kind_rank(kind: wgpu::DeviceType) -> u8 {
    match kind {
        wgpu::DeviceType::DiscreteGpu => 0,
        wgpu::DeviceType::IntegratedGpu => 1,
        wgpu::DeviceType::VirtualGpu => 2,
        wgpu::DeviceType::Cpu => 3,
        wgpu::DeviceType::Other => 4,
    }
}

impl Display {
    /// A surface on `window` and a chiaro context on the best adapter that can present to it
    /// and has what chiaro needs (`WGPU_BACKEND` narrows the backends, as for headless
    /// renders).
    pub fn new(window: Arc<Window>, display: OwnedDisplayHandle) -> Result<Self, ViewerError> {
        let descriptor = wgpu::InstanceDescriptor {
            backends: wgpu::Backends::VULKAN | wgpu::Backends::GL,
            ..wgpu::InstanceDescriptor::new_with_display_handle(Box::new(display))
        }
        .with_env();
        let backends = descriptor.backends;
        let instance = wgpu::Instance::new(descriptor);
        let size = window.inner_size();
        let surface = instance
            .create_surface(window)
            .map_err(|e| ViewerError::Gpu(format!("cannot create a surface: {e}")))?;
        let mut adapters = pollster::block_on(instance.enumerate_adapters(backends));
        adapters.sort_by_key(|a| {
            let info = a.get_info();
            (
                kind_rank(info.device_type),
                u8::from(info.backend != wgpu::Backend::Vulkan),
            )
        });
        let mut refusals = Vec::new();
        let mut chosen = None;
        for adapter in adapters {
            let name = adapter.get_info().name;
            let missing = missing_capabilities(&adapter);
            if !adapter.is_surface_supported(&surface) {
                refusals.push(format!("{name}: cannot present to the window"));
            } else if !missing.is_empty() {
                refusals.push(format!("{name}: {missing}"));
            } else {
                chosen = Some(adapter);
                break;
            }
        }
        let Some(adapter) = chosen else {
            return Err(ViewerError::Gpu(format!(
                "no adapter on {backends:?} can present to the window and run chiaro ({})",
                if refusals.is_empty() {
                    "none found".to_string()
                } else {
                    refusals.join("; ")
                }
            )));
        };
        let context = GpuContext::from_adapter(instance, adapter)
            .map_err(|e| ViewerError::Gpu(e.to_string()))?;
        let mut config = surface
            .get_default_config(&context.adapter, size.width.max(1), size.height.max(1))
            .ok_or_else(|| ViewerError::Gpu("the surface has no configuration".into()))?;
        // A non-sRGB format takes egui's (and the frame's) sRGB-encoded bytes as they are.
        let formats = surface.get_capabilities(&context.adapter).formats;
        if let Some(&plain) = formats.iter().find(|f| !f.is_srgb()) {
            config.format = plain;
        }
        config.present_mode = wgpu::PresentMode::AutoVsync;
        surface.configure(&context.device, &config);
        let painter = egui_wgpu::Renderer::new(
            &context.device,
            config.format,
            egui_wgpu::RendererOptions::default(),
        );
        let mut renderer = Renderer::new(context);
        // An edit that brings a feature the scene did not use compiles its pipelines on other
        // threads while the old ones render: the window never stalls on it.
        renderer.compile_in_background(true);
        Ok(Self {
            surface,
            config,
            renderer,
            painter,
            frame_texture: None,
            debug: None,
            showing_debug: false,
        })
    }

    /// Reconfigures the surface for a new window size.
    pub fn resize(&mut self, width: u32, height: u32) {
        if width == 0 || height == 0 {
            return;
        }
        self.config.width = width;
        self.config.height = height;
        self.surface
            .configure(&self.renderer.context.device, &self.config);
    }

    /// The egui texture showing the frame (after the first frame).
    pub fn frame_texture(&self) -> Option<egui::TextureId> {
        self.frame_texture
    }

    /// Points the frame's egui texture at what the window shows: the renderer's current 8-bit
    /// image (remade when the frame is resized or the scene replaced), or `view` of it seen
    /// from `eye` (`depth_scale`: the distance the depth view shows as mid grey; `scene`: the
    /// frame's scene, traced by the traversal view); `upscaled`: the image is smaller than its
    /// place in the window (filtered bilinearly, else nearest).
    pub fn update_frame_texture(
        &mut self,
        scene: &GpuScene,
        view: DebugView,
        eye: Vec3,
        depth_scale: f32,
        upscaled: bool,
    ) -> Result<(), ViewerError> {
        let Some(frame) = self.renderer.frame() else {
            return Ok(());
        };
        let (device, queue) = (&self.renderer.context.device, &self.renderer.context.queue);
        let shown = if view == DebugView::Frame {
            &frame.targets.ldr.view
        } else {
            if self.debug.is_none() {
                let pass = DebugPass::new(device).map_err(|e| ViewerError::Gpu(e.to_string()))?;
                self.debug = Some(pass);
            }
            let pass = self.debug.as_mut().expect("made above");
            pass.run(device, queue, frame, scene, view, eye, depth_scale)
                .map_err(|e| ViewerError::Gpu(e.to_string()))?
                .1
        };
        self.showing_debug = view != DebugView::Frame;
        let filter = if upscaled {
            wgpu::FilterMode::Linear
        } else {
            wgpu::FilterMode::Nearest
        };
        match self.frame_texture {
            Some(id) => self
                .painter
                .update_egui_texture_from_wgpu_texture(device, shown, filter, id),
            None => {
                let id = self.painter.register_native_texture(device, shown, filter);
                self.frame_texture = Some(id);
            }
        }
        Ok(())
    }

    /// The debug view's image when the window shows one.
    pub fn debug_image(&self) -> Option<&wgpu::Texture> {
        self.debug
            .as_ref()
            .filter(|_| self.showing_debug)
            .and_then(DebugPass::image)
    }

    /// Applies egui's texture changes, paints its output (the panel and the frame) to the
    /// window and presents it.
    pub fn present(
        &mut self,
        jobs: &[egui::ClippedPrimitive],
        mut textures: egui::TexturesDelta,
        pixels_per_point: f32,
    ) -> Result<(), ViewerError> {
        let (device, queue) = (&self.renderer.context.device, &self.renderer.context.queue);
        for (id, deltas) in std::mem::take(&mut textures.set) {
            for delta in &deltas {
                self.painter.update_texture(device, queue, id, delta);
            }
        }
        let free = std::mem::take(&mut textures.free);
        let drawn = self.draw(jobs, pixels_per_point);
        for id in &free {
            self.painter.free_texture(id);
        }
        drawn
    }

    /// Paints `jobs` to the next surface texture and presents it.
    fn draw(
        &mut self,
        jobs: &[egui::ClippedPrimitive],
        pixels_per_point: f32,
    ) -> Result<(), ViewerError> {
        let (device, queue) = (&self.renderer.context.device, &self.renderer.context.queue);
        let texture = match self.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(t)
            | wgpu::CurrentSurfaceTexture::Suboptimal(t) => t,
            wgpu::CurrentSurfaceTexture::Outdated | wgpu::CurrentSurfaceTexture::Lost => {
                self.surface.configure(device, &self.config);
                return Ok(());
            }
            wgpu::CurrentSurfaceTexture::Timeout | wgpu::CurrentSurfaceTexture::Occluded => {
                return Ok(());
            }
            wgpu::CurrentSurfaceTexture::Validation => {
                return Err(ViewerError::Gpu("the surface texture is invalid".into()));
            }
        };
        let screen = egui_wgpu::ScreenDescriptor {
            size_in_pixels: [self.config.width, self.config.height],
            pixels_per_point,
        };
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("viewer present"),
        });
        let uploads = self
            .painter
            .update_buffers(device, queue, &mut encoder, jobs, &screen);
        let view = texture.texture.create_view(&wgpu::TextureViewDescriptor {
            label: Some("viewer surface view"),
            ..Default::default()
        });
        {
            let pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("viewer panel and frame"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                ..Default::default()
            });
            self.painter
                .render(&mut pass.forget_lifetime(), jobs, &screen);
        }
        queue.submit(uploads.into_iter().chain([encoder.finish()]));
        queue.present(texture);
        Ok(())
    }
}
