//! Copies a texture back to the CPU: linear HDR as `Vec3` per pixel, LDR as RGBA8 bytes.

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

/// The bytes of a 2D texture of `bytes_per_pixel`, rows packed.
pub fn read_texture(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    texture: &wgpu::Texture,
    bytes_per_pixel: u32,
) -> Result<Vec<u8>, ReadbackError> {
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
    queue.submit([encoder.finish()]);
    let fail = |reason: String| ReadbackError {
        label: format!("{texture:?}"),
        reason,
    };
    let (sender, receiver) = std::sync::mpsc::channel();
    buffer.map_async(wgpu::MapMode::Read, .., move |r| {
        let _ = sender.send(r);
    });
    device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(|e| fail(e.to_string()))?;
    receiver
        .recv()
        .map_err(|e| fail(e.to_string()))?
        .map_err(|e| fail(e.to_string()))?;
    let mut out = Vec::with_capacity((row * height) as usize);
    {
        let view = buffer
            .get_mapped_range(..)
            .map_err(|e| fail(e.to_string()))?;
        for y in 0..height as usize {
            let start = y * padded as usize;
            out.extend_from_slice(&view[start..start + row as usize]);
        }
    }
    buffer.unmap();
    Ok(out)
}

/// An `Rgba32Float` texture as linear RGB per pixel (alpha dropped).
pub fn read_hdr(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    texture: &wgpu::Texture,
) -> Result<Vec<Vec3>, ReadbackError> {
    let bytes = read_texture(device, queue, texture, 16)?;
    let floats: Vec<f32> = bytemuck::pod_collect_to_vec(&bytes);
    Ok(floats
        .chunks_exact(4)
        .map(|p| Vec3::new(p[0], p[1], p[2]))
        .collect())
}
