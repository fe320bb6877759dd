//! Copies a texture back to the CPU: linear HDR as `Vec3` per pixel, LDR as RGBA8 bytes. A copy
//! is recorded after the frames submitted so far and read when the GPU has made it
//! ([`PendingRead`]): the caller waits for it ([`read_texture`]) or goes on rendering and takes
//! it once it is there, so a readback need not stall the frames in flight.

use std::sync::{Arc, OnceLock};

use glam::Vec3;
use thiserror::Error;

/// A readback failed.
#[derive(Debug, Error)]
#[error("cannot read back '{label}': {reason}")]
pub struct ReadbackError {
    /// The texture.
    pub label: String,
    /// Why.
    pub reason: String,
}

/// A texture's copy on its way to the CPU.
pub struct PendingRead {
    label: String,
    buffer: wgpu::Buffer,
    /// Bytes of a row of pixels, and of a row in the buffer (aligned for the copy).
    row: u32,
    padded: u32,
    height: u32,
    submission: wgpu::SubmissionIndex,
    /// Set when the buffer is mapped, or the mapping failed.
    mapped: Arc<OnceLock<Result<(), String>>>,
}

/// Copies `texture` (of `bytes_per_pixel`) into a buffer after everything submitted so far,
/// and asks for the buffer to be mapped once the copy is done. Returns without waiting.
pub fn start_read(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    texture: &wgpu::Texture,
    bytes_per_pixel: u32,
) -> PendingRead {
    let (width, height) = (texture.width(), texture.height());
    let row = width * bytes_per_pixel;
    let padded =
        row.div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
    let buffer = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("readback buffer"),
        size: u64::from(padded) * u64::from(height),
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
        label: Some("readback encoder"),
    });
    encoder.copy_texture_to_buffer(
        wgpu::TexelCopyTextureInfo {
            texture,
            mip_level: 0,
            origin: wgpu::Origin3d::ZERO,
            aspect: wgpu::TextureAspect::All,
        },
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(padded),
                rows_per_image: Some(height),
            },
        },
        texture.size(),
    );
    let submission = queue.submit([encoder.finish()]);
    let mapped = Arc::new(OnceLock::new());
    let seen = Arc::clone(&mapped);
    buffer.map_async(wgpu::MapMode::Read, .., move |result| {
        let _ = seen.set(result.map_err(|e| e.to_string()));
    });
    PendingRead {
        label: format!("{texture:?}"),
        buffer,
        row,
        padded,
        height,
        submission,
        mapped,
    }
}

impl PendingRead {
    /// Whether the bytes are there (or the readback failed): [`PendingRead::wait`] would not
    /// wait. Does not block.
    pub fn ready(&self, device: &wgpu::Device) -> bool {
        let _ = device.poll(wgpu::PollType::Poll);
        self.mapped.get().is_some()
    }

    /// The texture's bytes, rows packed, after waiting for the copy if it is not done.
    pub fn wait(self, device: &wgpu::Device) -> Result<Vec<u8>, ReadbackError> {
        let fail = |reason: String| ReadbackError {
            label: self.label.clone(),
            reason,
        };
        if self.mapped.get().is_none() {
            device
                .poll(wgpu::PollType::Wait {
                    submission_index: Some(self.submission.clone()),
                    timeout: None,
                })
                .map_err(|e| fail(e.to_string()))?;
        }
        match self.mapped.get() {
            Some(Ok(())) => {}
            Some(Err(reason)) => return Err(fail(reason.clone())),
            None => {
                return Err(fail(
                    "the copy finished but the buffer was not mapped".into(),
                ));
            }
        }
        let (row, padded) = (self.row as usize, self.padded as usize);
        let mut out = Vec::with_capacity(row * self.height as usize);
        {
            let view = self
                .buffer
                .get_mapped_range(..)
                .map_err(|e| fail(e.to_string()))?;
            for y in 0..self.height as usize {
                out.extend_from_slice(&view[y * padded..y * padded + row]);
            }
        }
        self.buffer.unmap();
        Ok(out)
    }
}

/// The bytes of a 2D texture of `bytes_per_pixel`, rows packed, after waiting for the GPU.
pub fn read_texture(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    texture: &wgpu::Texture,
    bytes_per_pixel: u32,
) -> Result<Vec<u8>, ReadbackError> {
    start_read(device, queue, texture, bytes_per_pixel).wait(device)
}

/// The pixels of an `Rgba32Float` texture's bytes as linear RGB (alpha dropped).
pub fn hdr_pixels(bytes: &[u8]) -> Vec<Vec3> {
    let floats: Vec<f32> = bytemuck::pod_collect_to_vec(bytes);
    floats
        .chunks_exact(4)
        .map(|p| Vec3::new(p[0], p[1], p[2]))
        .collect()
}

/// An `Rgba32Float` texture as linear RGB per pixel (alpha dropped).
pub fn read_hdr(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    texture: &wgpu::Texture,
) -> Result<Vec<Vec3>, ReadbackError> {
    Ok(hdr_pixels(&read_texture(device, queue, texture, 16)?))
}

/// A frame's images on their way to the CPU ([`crate::Renderer::read_later`]).
pub struct PendingImage {
    hdr: PendingRead,
    ldr: PendingRead,
    width: u32,
    height: u32,
    frames: u32,
}

impl PendingImage {
    /// The copies of the HDR and LDR images, started, of an image of `width` x `height` that
    /// holds `frames` frames.
    pub(crate) fn new(
        hdr: PendingRead,
        ldr: PendingRead,
        (width, height): (u32, u32),
        frames: u32,
    ) -> Self {
        Self {
            hdr,
            ldr,
            width,
            height,
            frames,
        }
    }

    /// Whether both images are there: [`PendingImage::wait`] would not wait. Does not block.
    pub fn ready(&self, device: &wgpu::Device) -> bool {
        self.hdr.ready(device) && self.ldr.ready(device)
    }

    /// The images (without pass times), after waiting for their copies if they are not done.
    pub fn wait(self, device: &wgpu::Device) -> Result<crate::RenderOutput, ReadbackError> {
        Ok(crate::RenderOutput {
            width: self.width,
            height: self.height,
            hdr: hdr_pixels(&self.hdr.wait(device)?),
            ldr: self.ldr.wait(device)?,
            frames: self.frames,
            times: Vec::new(),
        })
    }
}
