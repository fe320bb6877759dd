//! The realtime mode's denoiser, after SVGF (Schied et al., "Spatiotemporal Variance-Guided
//! Filtering", HPG 2017): three passes over the frame's direct and indirect light, demodulated
//! by the surface albedo (`shaders/lib/demodulate.wgsl`), filtered, and left for the composite
//! to multiply back. The punctual lights' part of the direct light is left out when it is exact
//! (`FrameTargets::direct_punctual`: every light evaluated, no sampling noise) and the
//! composite adds it back unfiltered, so that the noise of the sampled light does not blur a
//! sun's sharp shadows (SVGF filters direct and indirect light apart for the same reason).
//!
//! 1. `temporal`: reprojection through the motion vectors with disocclusion tests against the
//!    previous frame's G-buffer (kept here as copies), a moving average of the lighting and of
//!    its luminance moments, history length, a non-finite guard.
//! 2. `variance`: luminance variance from the moments, spatial while the history is short.
//! 3. `atrous`: [`DenoiseSettings::atrous_iterations`] edge-avoiding iterations (steps 1, 2,
//!    4, ...); the last one's output is [`Denoiser::output`]. The next frame's colour history
//!    is the temporal average (see [`Denoiser::record_atrous`]).
//!
//! Pixels that are not a covered surface that shades pass their light (direct + indirect, not
//! demodulated; a non-finite value as 0) through to the output unfiltered.

use bytemuck::{Pod, Zeroable};
use glam::{Vec3, Vec4};

use crate::passes::atrous::AtrousPass;
use crate::passes::temporal::{TemporalPass, TemporalResources};
use crate::passes::variance::VariancePass;
use crate::readback::{ReadbackError, read_texture};
use crate::settings::DenoiseSettings;
use crate::shaders::ShaderError;
use crate::still_view::HistoryWeights;
use crate::targets::{
    EMISSION_FORMAT, FrameTargets, HDR_FORMAT, POSITION_FORMAT, SURFACE_FORMAT, Target,
};

/// Most a-trous iterations (what [`crate::FrameSettings::validate`] accepts).
pub const MAX_ATROUS_ITERATIONS: usize = 10;

/// Bytes between the copies of [`DenoiseParams`] in the parameter buffer (one per iteration; the
/// storage-buffer offset alignment WebGPU guarantees).
const PARAMS_STRIDE: u64 = 256;

/// The denoiser's parameters (mirrored by `DenoiseParams` in `shaders/lib/denoise.wgsl`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
#[repr(C)]
pub struct DenoiseParams {
    /// Least weight of the new frame in the temporal moving average this frame
    /// ([`crate::still_view::history_floor`]).
    pub temporal_floor: f32,
    /// 1: drop all history this frame.
    pub reset: u32,
    /// This a-trous iteration's step in pixels.
    pub step: u32,
    /// A-trous iterations this frame.
    pub iterations: u32,
    /// SVGF's sigma_z.
    pub sigma_depth: f32,
    /// SVGF's sigma_n.
    pub sigma_normal: f32,
    /// SVGF's sigma_l.
    pub sigma_luminance: f32,
    /// The variance of a long history's average relative to one frame's sample
    /// ([`crate::still_view::history_variance`]).
    pub history_variance: f32,
}

/// The denoiser's passes, its history and its output at one size.
pub struct Denoiser {
    temporal: TemporalPass,
    variance: VariancePass,
    atrous: AtrousPass,
    params: wgpu::Buffer,
    /// Copies of the last frame's G-buffer position, surface and emission.
    previous: [Target; 3],
    color_history: Target,
    moments_history: Target,
    moments: Target,
    lighting: Target,
    filtered: Target,
    output: Target,
    /// The temporal average (copied into the colour history after the a-trous iterations).
    integrated: Target,
    /// The a-trous ping-pong pair: iteration 0 writes the first, iteration i >= 1 reads
    /// i - 1's and writes the other (the last iteration writes the output instead).
    first_iteration: Target,
    /// Textures that only bind groups name (the edge data, the second of the ping-pong pair),
    /// owned here for the denoiser's lifetime.
    _internal: [Target; 2],
    temporal_group: wgpu::BindGroup,
    variance_group: wgpu::BindGroup,
    /// Iteration 0: the variance pass's output into the first ping-pong texture.
    first_group: wgpu::BindGroup,
    /// Iterations 1.. (index - 1): into the ping-pong texture, or into the output (the last).
    later_groups: Vec<[wgpu::BindGroup; 2]>,
    iterations: usize,
    /// No history yet: the next frame starts afresh whatever `prepare` says.
    fresh: bool,
}

impl Denoiser {
    /// Textures and pipelines at the targets' size; `camera` is the frame's camera parameters.
    pub fn new(
        device: &wgpu::Device,
        targets: &FrameTargets,
        camera: &wgpu::Buffer,
    ) -> Result<Self, ShaderError> {
        use wgpu::TextureUsages as U;
        let size = (targets.width, targets.height);
        let copy = U::COPY_SRC | U::COPY_DST | U::TEXTURE_BINDING;
        let hdr = |label| Target::new(device, label, HDR_FORMAT, size, copy | U::STORAGE_BINDING);
        let temporal = TemporalPass::new(device)?;
        let variance = VariancePass::new(device)?;
        let atrous = AtrousPass::new(device)?;
        let params = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("denoise params"),
            size: PARAMS_STRIDE * MAX_ATROUS_ITERATIONS as u64,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let previous = [
            Target::new(
                device,
                "denoise previous position",
                POSITION_FORMAT,
                size,
                copy,
            ),
            Target::new(
                device,
                "denoise previous surface",
                SURFACE_FORMAT,
                size,
                copy,
            ),
            Target::new(
                device,
                "denoise previous emission",
                EMISSION_FORMAT,
                size,
                copy,
            ),
        ];
        let color_history = hdr("denoise colour history");
        let moments_history = hdr("denoise moments history");
        let integrated = hdr("denoise integrated");
        let moments = hdr("denoise moments");
        let edges = hdr("denoise edges");
        let lighting = hdr("denoise lighting");
        let filtered = hdr("denoise variance");
        let ping = [hdr("denoise atrous ping"), hdr("denoise atrous pong")];
        let output = hdr("denoise output");
        let binding = |i: u64| wgpu::BufferBinding {
            buffer: &params,
            offset: i * PARAMS_STRIDE,
            size: wgpu::BufferSize::new(size_of::<DenoiseParams>() as u64),
        };
        let temporal_group = temporal.bind_group(
            device,
            targets,
            &TemporalResources {
                camera,
                params: binding(0),
                previous: [&previous[0].view, &previous[1].view, &previous[2].view],
                color_history: &color_history.view,
                moments_history: &moments_history.view,
                integrated: &integrated.view,
                moments: &moments.view,
                edges: &edges.view,
                lighting: &lighting.view,
            },
        );
        let variance_group = variance.bind_group(
            device,
            binding(0),
            [&integrated.view, &moments.view, &edges.view, &filtered.view],
        );
        let first_group = atrous.bind_group(
            device,
            binding(0),
            [&filtered.view, &edges.view, &ping[0].view],
            targets,
        );
        let later_groups = (1..MAX_ATROUS_ITERATIONS)
            .map(|i| {
                let input = &ping[(i - 1) % 2].view;
                let group = |out| {
                    atrous.bind_group(
                        device,
                        binding(i as u64),
                        [input, &edges.view, out],
                        targets,
                    )
                };
                [group(&ping[i % 2].view), group(&output.view)]
            })
            .collect();
        let [first_iteration, ping1] = ping;
        Ok(Self {
            temporal,
            variance,
            atrous,
            params,
            previous,
            color_history,
            moments_history,
            moments,
            lighting,
            filtered,
            output,
            integrated,
            first_iteration,
            _internal: [edges, ping1],
            temporal_group,
            variance_group,
            first_group,
            later_groups,
            iterations: DenoiseSettings::default().atrous_iterations as usize,
            fresh: true,
        })
    }

    /// Writes the parameters for the next frame; `reset` drops all history (first frame,
    /// resize, scene switch, or frames rendered without the denoiser); `weights` are the
    /// temporal averages' for this frame ([`crate::still_view::history_weights`]).
    pub fn prepare(
        &mut self,
        queue: &wgpu::Queue,
        settings: &DenoiseSettings,
        reset: bool,
        weights: HistoryWeights,
    ) {
        self.iterations = (settings.atrous_iterations as usize).min(MAX_ATROUS_ITERATIONS);
        let mut bytes = vec![0u8; (PARAMS_STRIDE as usize) * MAX_ATROUS_ITERATIONS];
        for (i, chunk) in bytes.chunks_exact_mut(PARAMS_STRIDE as usize).enumerate() {
            let p = DenoiseParams {
                temporal_floor: weights.floor,
                reset: u32::from(reset || self.fresh),
                step: 1 << i,
                iterations: self.iterations as u32,
                sigma_depth: settings.sigma_depth,
                sigma_normal: settings.sigma_normal,
                sigma_luminance: settings.sigma_luminance,
                history_variance: weights.variance,
            };
            chunk[..size_of::<DenoiseParams>()].copy_from_slice(bytemuck::bytes_of(&p));
        }
        queue.write_buffer(&self.params, 0, &bytes);
        self.fresh = false;
    }

    /// Records the temporal pass, then copies this frame's G-buffer and moments into the
    /// history the next frame's temporal pass reads.
    pub fn record_temporal(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        targets: &FrameTargets,
        timestamps: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) {
        self.temporal
            .record(encoder, &self.temporal_group, targets, timestamps);
        let sources = [&targets.position, &targets.surface, &targets.emission];
        for (source, destination) in sources.into_iter().zip(&self.previous) {
            copy(encoder, source, destination);
        }
        copy(encoder, &self.moments, &self.moments_history);
    }

    /// Records the variance pass.
    pub fn record_variance(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        targets: &FrameTargets,
        timestamps: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) {
        self.variance
            .record(encoder, &self.variance_group, targets, timestamps);
    }

    /// All a-trous iterations in one compute pass (one timing entry). With no iteration the
    /// output is the variance pass's colour (the temporal average).
    ///
    /// The next frame's colour history is this frame's temporal average, not SVGF's first
    /// a-trous iteration: that one is filtered again every frame it is kept, so a history that
    /// lasts (a still view's running mean, or the moving average's twenty frames while the
    /// camera moves) is blurred again and again. docs/experiments/temporal-average-as-history.md.
    pub fn record_atrous(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        targets: &FrameTargets,
        timestamps: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) {
        let n = self.iterations;
        let mut groups = Vec::with_capacity(n);
        if n > 0 {
            groups.push(&self.first_group);
        }
        for i in 1..n {
            groups.push(&self.later_groups[i - 1][usize::from(i == n - 1)]);
        }
        self.atrous.record(encoder, &groups, targets, timestamps);
        match n {
            0 => copy(encoder, &self.filtered, &self.output),
            1 => copy(encoder, &self.first_iteration, &self.output),
            _ => {}
        }
        copy(encoder, &self.integrated, &self.color_history);
    }

    /// The filtered, demodulated lighting (rgba32float, the targets' size; the same view every
    /// frame).
    pub fn output(&self) -> &wgpu::TextureView {
        &self.output.view
    }

    /// The moments history (rgba32float, the targets' size; the same view every frame): what
    /// [`Denoiser::read_moments`] reads.
    pub fn moments(&self) -> &wgpu::TextureView {
        &self.moments_history.view
    }

    /// The last frame's filtered lighting (what [`Denoiser::output`] views), per pixel.
    pub fn read_output(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Result<Vec<Vec3>, ReadbackError> {
        Ok(read_rgba(device, queue, &self.output)?
            .into_iter()
            .map(|v| v.truncate())
            .collect())
    }

    /// The last frame's lighting before filtering: direct + indirect, less the exact punctual
    /// part, over the demodulation albedo where a surface shades, the light itself elsewhere
    /// (as computed: a NaN or an infinity from the input shows here).
    pub fn read_lighting(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Result<Vec<Vec3>, ReadbackError> {
        Ok(read_rgba(device, queue, &self.lighting)?
            .into_iter()
            .map(|v| v.truncate())
            .collect())
    }

    /// The colour history the next frame reprojects (the last frame's temporal average), per
    /// pixel.
    pub fn read_color_history(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Result<Vec<Vec3>, ReadbackError> {
        Ok(read_rgba(device, queue, &self.color_history)?
            .into_iter()
            .map(|v| v.truncate())
            .collect())
    }

    /// The moments history per pixel: mean luminance, mean squared luminance, history length
    /// in frames (0 where nothing is filtered), 0.
    pub fn read_moments(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Result<Vec<Vec4>, ReadbackError> {
        read_rgba(device, queue, &self.moments_history)
    }

    /// The history length per pixel in frames: 1 where the history restarted this frame, 0
    /// where nothing is filtered.
    pub fn read_history_length(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Result<Vec<f32>, ReadbackError> {
        Ok(self
            .read_moments(device, queue)?
            .into_iter()
            .map(|m| m.z)
            .collect())
    }
}

/// Copies the whole of `source` into `destination` (same size and format).
fn copy(encoder: &mut wgpu::CommandEncoder, source: &Target, destination: &Target) {
    encoder.copy_texture_to_texture(
        source.texture.as_image_copy(),
        destination.texture.as_image_copy(),
        source.texture.size(),
    );
}

fn read_rgba(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    target: &Target,
) -> Result<Vec<Vec4>, ReadbackError> {
    let bytes = read_texture(device, queue, &target.texture, 16)?;
    let floats: Vec<f32> = bytemuck::pod_collect_to_vec(&bytes);
    Ok(floats.chunks_exact(4).map(Vec4::from_slice).collect())
}
