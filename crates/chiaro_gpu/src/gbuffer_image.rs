//! The G-buffer read back to the CPU (for tests and debug views), decoded as
//! `shaders/lib/gbuffer_packing.wgsl` packs it.

use glam::{Vec2, Vec3};

use crate::readback::{ReadbackError, read_texture};
use crate::targets::FrameTargets;

/// Parts of a G-buffer read back (for tests and debug views), row-major, top row first.
#[derive(Clone, Debug)]
pub struct GbufferImage {
    /// World position per pixel (meaningless where `instance` is `None`).
    pub position: Vec<Vec3>,
    /// The instance drawn per pixel, `None` where nothing was.
    pub instance: Vec<Option<u32>>,
    /// The geometric normal per pixel (unit; its triangle's, turned to the camera's side where
    /// the material is double-sided).
    pub geometric_normal: Vec<Vec3>,
    /// Pixels from the current to the previous frame's position of what the pixel shows
    /// (infinite where the motion was out of the packed range).
    pub motion: Vec<Vec2>,
}

/// The bits of the G-buffer emission target's w that hold the instance + 1; bits 31 and 30 are
/// flags (`shaders/lib/gbuffer_packing.wgsl`: the surface shades, the back face is seen).
const GBUFFER_INSTANCE_BITS: u32 = 0x3fff_ffff;

impl GbufferImage {
    /// Reads the G-buffer of `targets` back (waits for the GPU).
    pub fn read(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        targets: &FrameTargets,
    ) -> Result<Self, ReadbackError> {
        let words = |target: &crate::targets::Target, bytes| -> Result<Vec<u32>, ReadbackError> {
            Ok(bytemuck::pod_collect_to_vec(&read_texture(
                device,
                queue,
                &target.texture,
                bytes,
            )?))
        };
        let position = words(&targets.position, 16)?;
        let emission = words(&targets.emission, 16)?;
        let surface = words(&targets.surface, 16)?;
        let motion = words(&targets.motion, 4)?;
        Ok(Self {
            position: position
                .chunks_exact(4)
                .map(|p| {
                    Vec3::new(
                        f32::from_bits(p[0]),
                        f32::from_bits(p[1]),
                        f32::from_bits(p[2]),
                    )
                })
                .collect(),
            instance: emission
                .chunks_exact(4)
                .map(|e| (e[3] & GBUFFER_INSTANCE_BITS).checked_sub(1))
                .collect(),
            geometric_normal: surface
                .chunks_exact(4)
                .map(|s| octahedral_decode(s[0]))
                .collect(),
            motion: motion.iter().map(|&m| motion_unpack(m)).collect(),
        })
    }
}

/// The unit vector of an octahedral normal in two 16-bit snorms (x low), as
/// `lib/gbuffer_packing.wgsl` decodes it.
fn octahedral_decode(packed: u32) -> Vec3 {
    let snorm = |bits: u32| (f32::from(bits as u16 as i16) / 32767.0).max(-1.0);
    let f = Vec2::new(snorm(packed), snorm(packed >> 16));
    let mut n = Vec3::new(f.x, f.y, 1.0 - f.x.abs() - f.y.abs());
    let t = (-n.z).clamp(0.0, 1.0);
    n.x += if n.x >= 0.0 { -t } else { t };
    n.y += if n.y >= 0.0 { -t } else { t };
    n.normalize()
}

/// A motion vector packed as two f16 (x low), as `lib/gbuffer_packing.wgsl`'s `motion_pack`
/// writes it.
fn motion_unpack(packed: u32) -> Vec2 {
    let half = |bits: u32| half::f16::from_bits(bits as u16).to_f32();
    Vec2::new(half(packed), half(packed >> 16))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn motion_unpacks_as_the_shader_packs_it() {
        // (1.5, -0.25) as f16 bits: 0x3e00 and 0xb400; MOTION_NONE is two f16 infinities.
        assert_eq!(motion_unpack(0xb400_3e00), Vec2::new(1.5, -0.25));
        let none = motion_unpack(0x7c00_7c00);
        assert!(none.x.is_infinite() && none.y.is_infinite());
    }
}
