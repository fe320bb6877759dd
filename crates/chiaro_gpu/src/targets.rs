//! The frame's render targets and images: the G-buffer, the direct and indirect light of the
//! frame, the accumulated HDR image and the tonemapped LDR image, all at the output size.

/// Format of the G-buffer's position target (world xyz, roughness; f32 bits: integer targets
/// render on every backend, 32-bit float ones not on GL).
pub const POSITION_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Uint;
/// Format of the G-buffer's surface target (normals, base colour, metallic).
pub const SURFACE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Uint;
/// Format of the G-buffer's emission target (emission, instance, shading flag).
pub const EMISSION_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Uint;
/// Format of the G-buffer's motion vectors (pixels to the previous frame's position, two f16
/// in a u32: `motion_pack` in `shaders/lib/gbuffer_packing.wgsl`; a format GL can write from a
/// compute pass, unlike `Rg32Uint`).
pub const MOTION_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Uint;
/// Format of the G-buffer's triangle target (the number of the triangle seen in its mesh).
pub const TRIANGLE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Uint;
/// Depth format.
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// Format of the HDR images.
pub const HDR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
/// Format of the direct pass's BRDF-ray hits (`shaders/lib/first_bounce.wgsl`).
pub const FIRST_BOUNCE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Uint;
/// Format of the LDR image.
pub const LDR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;
/// The surface each pixel of the resolve's history saw.
pub const RESOLVE_SURFACE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Uint;
/// Format of the resampled direct light's reservoirs and their surfaces
/// (`shaders/lib/reservoir.wgsl`).
pub const RESERVOIR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Uint;
/// Texels of [`RESERVOIR_FORMAT`] a resampled-indirect reservoir takes, side by side
/// (`GI_RESERVOIR_TEXELS` in `shaders/lib/gi_sample.wgsl`).
pub const GI_RESERVOIR_TEXELS: u32 = 3;

/// A texture and its default view.
pub struct Target {
    /// The texture.
    pub texture: wgpu::Texture,
    /// Its view.
    pub view: wgpu::TextureView,
}

impl Target {
    /// A texture of `format` and `size` with its default view, both labelled `label`.
    pub fn new(
        device: &wgpu::Device,
        label: &str,
        format: wgpu::TextureFormat,
        size: (u32, u32),
        usage: wgpu::TextureUsages,
    ) -> Self {
        let texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some(label),
            size: wgpu::Extent3d {
                width: size.0,
                height: size.1,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage,
            view_formats: &[],
        });
        let view = texture.create_view(&wgpu::TextureViewDescriptor {
            label: Some(label),
            ..Default::default()
        });
        Self { texture, view }
    }
}

/// Every image of a frame.
pub struct FrameTargets {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// G-buffer: world position and roughness.
    pub position: Target,
    /// G-buffer: normals, base colour, metallic.
    pub surface: Target,
    /// G-buffer: emission, instance id + 1 (0: nothing drawn) with the shading flag.
    pub emission: Target,
    /// G-buffer: motion vectors.
    pub motion: Target,
    /// G-buffer: the number of the triangle seen in its mesh (the instance is in `emission`):
    /// with the position it gives the barycentrics, so a pass can read what the other targets
    /// have no room for (the material extensions' textures).
    pub triangle: Target,
    /// Depth.
    pub depth: Target,
    /// This frame's direct light reflected by the surface seen (linear radiance, emission
    /// excluded); where no surface is seen, the environment.
    pub direct: Target,
    /// The part of `direct` from punctual lights where the pass evaluates every one of them
    /// (none picked at random: no sampling noise), 0 elsewhere and where there are more
    /// punctual lights than it evaluates. The denoiser filters the rest of the lighting and
    /// adds this back unfiltered, so a sun's sharp shadow is not blurred by the noise of the
    /// sampled light around it.
    pub direct_punctual: Target,
    /// Where the direct pass's BRDF ray from the surface seen hit (instance, triangle,
    /// barycentrics; `shaders/lib/first_bounce.wgsl`): the indirect pass's first path continues
    /// from it rather than trace the same ray again.
    pub first_bounce: Target,
    /// This frame's indirect light reflected by the surface seen (linear radiance, the mean of
    /// the frame's paths; in naive mode, all the light the surface reflects).
    pub indirect: Target,
    /// The accumulated linear HDR image.
    pub hdr: Target,
    /// The tonemapped sRGB image.
    pub ldr: Target,
    /// Running sum of the frames' radiance (one `vec4<f32>` per pixel).
    pub accumulation: wgpu::Buffer,
    /// The realtime mode's resolved colour and its history length, two of them: each frame
    /// reads one and writes the other. Textures rather than storage buffers: the resolve reads
    /// 16 texels a pixel, and lavapipe loads a texel for all lanes at once but a storage
    /// element lane by lane.
    pub resolve: [Target; 2],
    /// The surface each pixel of `resolve` saw (instance + 1, 0 for none), two of them like
    /// `resolve`.
    pub resolve_surface: [Target; 2],
    /// Resampled direct light (1 x 1 until a frame resamples: [`Self::size_reservoirs`]): the
    /// reservoirs of this frame's candidates merged with last
    /// frame's (`restir_temporal`), read by the spatial pass.
    pub reservoirs_temporal: Target,
    /// Resampled direct light: the final reservoirs (`restir_spatial`), shaded by the direct
    /// pass and merged by the next frame's first pass.
    pub reservoirs: Target,
    /// The surface (view depth, normal) of each of `reservoirs`, for the next frame's
    /// similarity test.
    pub reservoir_surfaces: Target,
    /// Resampled indirect light (1 x 1 until a frame resamples): each pixel's reservoir,
    /// three texels side by side (`shaders/lib/gi_sample.wgsl`): its path's sample, merged
    /// with last frame's reservoir where temporal reuse is on (`restir_gi_initial`), read by
    /// the spatial pass.
    pub gi_reservoirs: Target,
    /// Resampled indirect light: last frame's `gi_reservoirs`, copied after its spatial pass
    /// where temporal reuse is on.
    pub gi_history: Target,
}

impl FrameTargets {
    /// Targets of `width` x `height` pixels; with `traced_gbuffer`, the G-buffer's colour
    /// targets are storage textures too (the traced G-buffer writes them from a compute pass).
    pub fn new(device: &wgpu::Device, width: u32, height: u32, traced_gbuffer: bool) -> Self {
        use wgpu::TextureUsages as U;
        let size = (width, height);
        let raster = U::RENDER_ATTACHMENT | U::TEXTURE_BINDING | U::COPY_SRC;
        let gbuffer = raster
            | if traced_gbuffer {
                U::STORAGE_BINDING
            } else {
                U::empty()
            };
        let storage = U::STORAGE_BINDING | U::TEXTURE_BINDING | U::COPY_SRC;
        let [
            reservoirs_temporal,
            reservoirs,
            reservoir_surfaces,
            gi_reservoirs,
            gi_history,
        ] = reservoir_targets(device, (1, 1));
        Self {
            width,
            height,
            position: Target::new(device, "gbuffer position", POSITION_FORMAT, size, gbuffer),
            surface: Target::new(device, "gbuffer surface", SURFACE_FORMAT, size, gbuffer),
            emission: Target::new(device, "gbuffer emission", EMISSION_FORMAT, size, gbuffer),
            motion: Target::new(device, "gbuffer motion", MOTION_FORMAT, size, gbuffer),
            // Storage always: the direct and indirect passes read it as a storage texture.
            triangle: Target::new(
                device,
                "gbuffer triangle",
                TRIANGLE_FORMAT,
                size,
                raster | U::STORAGE_BINDING,
            ),
            depth: Target::new(device, "gbuffer depth", DEPTH_FORMAT, size, raster),
            direct: Target::new(device, "direct light", HDR_FORMAT, size, storage),
            direct_punctual: Target::new(
                device,
                "direct punctual light",
                HDR_FORMAT,
                size,
                storage,
            ),
            first_bounce: Target::new(
                device,
                "first bounce hits",
                FIRST_BOUNCE_FORMAT,
                size,
                storage,
            ),
            indirect: Target::new(device, "indirect light", HDR_FORMAT, size, storage),
            hdr: Target::new(device, "hdr image", HDR_FORMAT, size, storage),
            ldr: Target::new(device, "ldr image", LDR_FORMAT, size, storage),
            accumulation: pixel_buffer(device, "accumulation", size, 16),
            resolve: ["resolve history a", "resolve history b"]
                .map(|label| Target::new(device, label, HDR_FORMAT, size, storage)),
            resolve_surface: ["resolve surfaces a", "resolve surfaces b"]
                .map(|label| Target::new(device, label, RESOLVE_SURFACE_FORMAT, size, storage)),
            reservoirs_temporal,
            reservoirs,
            reservoir_surfaces,
            gi_reservoirs,
            gi_history,
        }
    }

    /// Gives the reservoirs and samples of resampled direct and indirect light the frame's
    /// size, the first time a frame resamples either: they start at 1 x 1, so a frame that
    /// never does holds 144 bytes a pixel less.
    /// Returns whether they were made again (and so must be bound again).
    pub fn size_reservoirs(&mut self, device: &wgpu::Device) -> bool {
        let size = (self.width, self.height);
        let texture = &self.reservoirs.texture;
        if (texture.width(), texture.height()) == size {
            return false;
        }
        [
            self.reservoirs_temporal,
            self.reservoirs,
            self.reservoir_surfaces,
            self.gi_reservoirs,
            self.gi_history,
        ] = reservoir_targets(device, size);
        true
    }
}

/// The resampled light's targets at `size`: direct light's first-pass reservoirs, final ones
/// and their surfaces, indirect light's reservoirs and last frame's (three texels a pixel).
fn reservoir_targets(device: &wgpu::Device, (width, height): (u32, u32)) -> [Target; 5] {
    use wgpu::TextureUsages as U;
    let usage = U::STORAGE_BINDING | U::TEXTURE_BINDING | U::COPY_SRC | U::COPY_DST;
    let target =
        |label, width| Target::new(device, label, RESERVOIR_FORMAT, (width, height), usage);
    [
        target("reservoirs temporal", width),
        target("reservoirs", width),
        target("reservoir surfaces", width),
        target("gi reservoirs", GI_RESERVOIR_TEXELS * width),
        target("gi history", GI_RESERVOIR_TEXELS * width),
    ]
}

/// A storage buffer of `bytes` per pixel.
fn pixel_buffer(
    device: &wgpu::Device,
    label: &str,
    (width, height): (u32, u32),
    bytes: u64,
) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: u64::from(width) * u64::from(height) * bytes,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}
