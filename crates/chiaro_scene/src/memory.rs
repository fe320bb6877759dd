//! How much memory rendering a scene will take, estimated from what the scene holds before
//! anything is built, so that a scene too large for the machine is refused with the figure and
//! the limit instead of ending in a failed allocation halfway through.
//!
//! The estimate is linear in the scene's instances, stored triangles and texels and in the
//! image's pixels, in two parts: what the GPU holds (the scene's buffers, the frame's targets)
//! and what the CPU holds (the device and its pipelines, the World, the BVHs and their build).
//! Its coefficients are measured, rounded up: the GPU part from the scene's buffers as
//! uploaded (`chiaro render` prints them: 194 bytes a triangle for `builtin:walkthrough`, 0.5
//! vertices a triangle), the whole from peak resident memory on lavapipe, where GPU buffers are
//! host memory too: `builtin:walkthrough` grew by 630 bytes a triangle from 0.34 to 1.34
//! million triangles, a render of N instances of one triangle by 2.3 KB an instance (N = 1e5,
//! 3e5), an image by 450 bytes a pixel (64x64 against 1024x1024), over 213 MB for the Cornell
//! box at 64x64. On a GPU of its own the two parts live apart.

use std::fmt;

use bevy_ecs::prelude::*;

use crate::components::MeshInstance;
use crate::mesh::Meshes;
use crate::texture::Textures;

/// Bytes every render takes whatever the scene: the device, its pipelines, the program.
pub const BASE_BYTES: u64 = 256 << 20;
/// CPU bytes an instance takes: its entity, TLAS leaf and records.
pub const CPU_BYTES_PER_INSTANCE: u64 = 2304;
/// GPU bytes an instance takes: its records for traversal, shading and raster.
pub const GPU_BYTES_PER_INSTANCE: u64 = 256;
/// CPU bytes a stored triangle takes with its share of vertices: mesh data, BLAS and its
/// build.
pub const CPU_BYTES_PER_TRIANGLE: u64 = 512;
/// GPU bytes a stored triangle takes with its share of vertices: vertices, indices, BLAS nodes
/// and triangles, raster lists.
pub const GPU_BYTES_PER_TRIANGLE: u64 = 224;
/// CPU bytes a texel takes: RGBA8 in the scene, and its upload.
pub const CPU_BYTES_PER_TEXEL: u64 = 8;
/// GPU bytes a texel takes in the texel buffer.
pub const GPU_BYTES_PER_TEXEL: u64 = 8;
/// CPU bytes a pixel of the image takes: its readback.
pub const CPU_BYTES_PER_PIXEL: u64 = 128;
/// GPU bytes a pixel of the image takes: the frame's targets and histories.
pub const GPU_BYTES_PER_PIXEL: u64 = 384;

/// What a render of a scene is expected to take, by part.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MemoryEstimate {
    /// Mesh instances in the scene.
    pub instances: u64,
    /// Triangles stored (each mesh once).
    pub triangles: u64,
    /// Texels over every texture.
    pub texels: u64,
    /// Pixels of the image.
    pub pixels: u64,
}

impl MemoryEstimate {
    /// The estimate for rendering `world`'s scene at `width` x `height`.
    pub fn of_world(world: &mut World, width: u32, height: u32) -> Self {
        let triangles = world.get_resource::<Meshes>().map_or(0, |m| {
            m.iter().map(|(_, mesh)| mesh.triangle_count() as u64).sum()
        });
        let texels = world.get_resource::<Textures>().map_or(0, |t| {
            t.iter()
                .map(|(_, tex)| u64::from(tex.width) * u64::from(tex.height))
                .sum()
        });
        let instances = world.query::<&MeshInstance>().iter(world).count() as u64;
        Self {
            instances,
            triangles,
            texels,
            pixels: u64::from(width) * u64::from(height),
        }
    }

    /// The expected peak, bytes: the CPU and GPU parts together (both host memory on a CPU
    /// adapter).
    pub fn bytes(&self) -> u64 {
        self.cpu_bytes().saturating_add(self.gpu_bytes())
    }

    /// The part the CPU holds, bytes.
    pub fn cpu_bytes(&self) -> u64 {
        BASE_BYTES.saturating_add(self.weighted([
            CPU_BYTES_PER_INSTANCE,
            CPU_BYTES_PER_TRIANGLE,
            CPU_BYTES_PER_TEXEL,
            CPU_BYTES_PER_PIXEL,
        ]))
    }

    /// The part the GPU holds, bytes.
    pub fn gpu_bytes(&self) -> u64 {
        self.weighted([
            GPU_BYTES_PER_INSTANCE,
            GPU_BYTES_PER_TRIANGLE,
            GPU_BYTES_PER_TEXEL,
            GPU_BYTES_PER_PIXEL,
        ])
    }

    /// Instances, triangles, texels and pixels times `bytes` each, summed.
    fn weighted(&self, bytes: [u64; 4]) -> u64 {
        [self.instances, self.triangles, self.texels, self.pixels]
            .iter()
            .zip(bytes)
            .fold(0u64, |sum, (count, each)| {
                sum.saturating_add(count.saturating_mul(each))
            })
    }

    /// Ok when the estimate is within `limit` bytes; else the error saying both.
    pub fn check(&self, limit: u64) -> Result<(), OverBudget> {
        match self.bytes() <= limit {
            true => Ok(()),
            false => Err(OverBudget {
                estimate: *self,
                limit,
            }),
        }
    }
}

impl fmt::Display for MemoryEstimate {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "about {} (CPU {}, GPU {}; {} instances, {} triangles stored, {} texels, {} pixels)",
            human_bytes(self.bytes()),
            human_bytes(self.cpu_bytes()),
            human_bytes(self.gpu_bytes()),
            self.instances,
            self.triangles,
            self.texels,
            self.pixels
        )
    }
}

/// A render refused because it would need more memory than allowed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error(
    "rendering it would take {estimate}, more than the memory limit of {}",
    human_bytes(*limit)
)]
pub struct OverBudget {
    /// What the render would take.
    pub estimate: MemoryEstimate,
    /// The limit, bytes.
    pub limit: u64,
}

/// `bytes` in the largest binary unit that keeps a number of at least 1 (one decimal).
pub fn human_bytes(bytes: u64) -> String {
    const UNITS: [&str; 5] = ["bytes", "KiB", "MiB", "GiB", "TiB"];
    let mut value = bytes as f64;
    let mut unit = 0;
    while value >= 1024.0 && unit + 1 < UNITS.len() {
        value /= 1024.0;
        unit += 1;
    }
    match unit {
        0 => format!("{bytes} bytes"),
        _ => format!("{value:.1} {}", UNITS[unit]),
    }
}

/// A size such as `512M`, `8G`, `1.5GiB` or `1000000` (bytes), in binary units.
pub fn parse_bytes(text: &str) -> Result<u64, String> {
    let t = text.trim();
    let digits = t
        .find(|c: char| !(c.is_ascii_digit() || c == '.'))
        .unwrap_or(t.len());
    let (number, unit) = t.split_at(digits);
    let value: f64 = number
        .parse()
        .map_err(|_| format!("'{text}' is not a size such as 512M or 8G"))?;
    let shift = match unit.trim().to_ascii_uppercase().as_str() {
        "" | "B" => 0,
        "K" | "KB" | "KIB" => 10,
        "M" | "MB" | "MIB" => 20,
        "G" | "GB" | "GIB" => 30,
        "T" | "TB" | "TIB" => 40,
        _ => return Err(format!("'{text}': unknown unit (use K, M, G or T)")),
    };
    let bytes = value * (1u64 << shift) as f64;
    if !bytes.is_finite() || bytes < 1.0 || bytes > u64::MAX as f64 {
        return Err(format!("'{text}' is not a size of at least 1 byte"));
    }
    Ok(bytes as u64)
}

/// Memory the system can give a new allocation now (Linux: `MemAvailable` of /proc/meminfo);
/// `None` where that cannot be read.
pub fn available_memory() -> Option<u64> {
    let info = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = info.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    kib.checked_mul(1024)
}

/// The process's peak resident memory so far (Linux: `VmHWM` of /proc/self/status); `None`
/// where that cannot be read.
pub fn peak_resident() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    kib.checked_mul(1024)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::load::load_scene;

    #[test]
    fn the_estimate_grows_with_each_part() {
        let small = MemoryEstimate {
            instances: 1,
            triangles: 10,
            texels: 0,
            pixels: 64 * 64,
        };
        assert!(small.bytes() < 300 << 20, "{}", small);
        let many = MemoryEstimate {
            instances: 300_000,
            ..small
        };
        assert!(many.bytes() > small.bytes() + 700_000_000, "{}", many);
        let huge = MemoryEstimate {
            triangles: u64::MAX,
            ..small
        };
        assert_eq!(huge.bytes(), u64::MAX);
    }

    #[test]
    fn the_cpu_and_gpu_parts_make_the_whole() {
        let estimate = MemoryEstimate {
            instances: 151,
            triangles: 1_336_838,
            texels: 409_600,
            pixels: 256 * 256,
        };
        assert_eq!(
            estimate.bytes(),
            estimate.cpu_bytes() + estimate.gpu_bytes()
        );
        // builtin:walkthrough's scene buffers measured 248 MiB on the GPU, its render's peak
        // 1.16 GiB resident on lavapipe: the estimate covers both.
        assert!(
            (248 << 20..320 << 20).contains(&estimate.gpu_bytes()),
            "{estimate}"
        );
        assert!(
            (1188 << 20..1400 << 20).contains(&estimate.bytes()),
            "{estimate}"
        );
        let text = estimate.to_string();
        assert!(text.contains("(CPU ") && text.contains(", GPU "), "{text}");
    }

    #[test]
    fn a_scene_is_counted_from_the_world() {
        let mut world = World::new();
        load_scene(&mut world, "builtin:instances?n=100").unwrap();
        let estimate = MemoryEstimate::of_world(&mut world, 32, 16);
        assert_eq!(estimate.pixels, 512);
        assert!(estimate.instances >= 100, "{estimate:?}");
        assert!(estimate.triangles > 0);
        let err = estimate.check(BASE_BYTES).unwrap_err().to_string();
        assert!(
            err.contains("more than the memory limit of 256.0 MiB"),
            "{err}"
        );
        assert!(err.contains("instances"), "{err}");
        estimate.check(estimate.bytes()).unwrap();
    }

    #[test]
    fn sizes_parse_in_binary_units() {
        assert_eq!(parse_bytes("512M"), Ok(512 << 20));
        assert_eq!(parse_bytes("1.5GiB"), Ok(3 << 29));
        assert_eq!(parse_bytes("4096"), Ok(4096));
        assert_eq!(parse_bytes("8 g"), Ok(8 << 30));
        for bad in ["", "x", "-1G", "0", "1Q", "nanG"] {
            assert!(parse_bytes(bad).is_err(), "{bad}");
        }
        assert_eq!(human_bytes(3 << 29), "1.5 GiB");
        assert_eq!(human_bytes(10), "10 bytes");
    }

    #[test]
    fn available_memory_is_read_where_the_system_says_it() {
        if std::path::Path::new("/proc/meminfo").exists() {
            assert!(available_memory().is_some_and(|b| b > 0));
        }
    }
}
