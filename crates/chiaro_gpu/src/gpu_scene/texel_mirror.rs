//! An array of 16-byte-multiple records held in an `Rgba32Uint` texture instead of a storage
//! buffer, mirrored on the CPU so that an update writes only the element ranges that differ.
//!
//! The BVH lives in such textures because the shaders' per-lane loads are the traversal's
//! bottleneck on lavapipe (Mesa 22.3): a storage-buffer load at a per-lane address is a loop over
//! the lanes, one 32-bit word at a time, where a texel fetch gathers a lane's 16 bytes at once.
//! Measured with the `traversal_bench` example (docs/experiments/gpu-bvh-traversal.md). The light
//! tables and the light trees, which every light sample walks, and the environment's texels and
//! importance table, which every environment sample searches, live in them for the same reason
//! (docs/experiments/lavapipe-storage-loads.md).
//!
//! Layout: record `i` of `T` is texels `i * T::TEXELS .. (i + 1) * T::TEXELS` in row-major order,
//! [`TEXEL_ROW_WIDTH`] texels to a row (`shaders/lib/bvh_bindings.wgsl` reads them so).

use bytemuck::Pod;

use super::cpu_copy::CpuCopy;
use super::mirror::UploadStats;

/// Texels in a row of every texel array: 2^11, the least `max_texture_dimension_2d` a device
/// may have, so that the row is the same on every device and the shaders can hold it as a
/// constant. A device's largest height then bounds the array.
pub const TEXEL_ROW_WIDTH: u32 = 1 << TEXEL_ROW_BITS;

/// log2 of [`TEXEL_ROW_WIDTH`].
pub const TEXEL_ROW_BITS: u32 = 11;

const TEXEL_BYTES: usize = 16;

/// A texel array larger than the device's largest texture.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error(
    "{label}: {records} records need {rows} rows of {TEXEL_ROW_WIDTH} texels; the device's \
     largest texture has {max_rows}"
)]
pub struct TexelOverflow {
    /// The array.
    pub label: &'static str,
    /// Records asked for.
    pub records: usize,
    /// Rows they need.
    pub rows: u64,
    /// The device's `max_texture_dimension_2d`.
    pub max_rows: u32,
}

/// An `Rgba32Uint` texture holding records of `T` (whose size is a multiple of 16 bytes),
/// mirrored on the CPU.
pub struct MirrorTexels<T: Pod> {
    label: &'static str,
    texture: wgpu::Texture,
    view: wgpu::TextureView,
    rows: u32,
    cpu: CpuCopy<T>,
    overflow: Option<TexelOverflow>,
}

impl<T: Pod + PartialEq> MirrorTexels<T> {
    /// Texels per record.
    pub const TEXELS: usize = {
        assert!(
            size_of::<T>().is_multiple_of(TEXEL_BYTES),
            "a record is whole texels"
        );
        size_of::<T>() / TEXEL_BYTES
    };

    /// An empty array of one row (bindings may not be empty), its contents kept on the CPU.
    pub fn new(device: &wgpu::Device, label: &'static str) -> Self {
        Self::with_copy(device, label, CpuCopy::new(false))
    }

    /// [`MirrorTexels::new`] for bulk data never read back: the CPU keeps fingerprints of its
    /// blocks, not its contents ([`CpuCopy::Blocks`]).
    pub fn bulk(device: &wgpu::Device, label: &'static str) -> Self {
        Self::with_copy(device, label, CpuCopy::new(true))
    }

    fn with_copy(device: &wgpu::Device, label: &'static str, cpu: CpuCopy<T>) -> Self {
        let texture = Self::allocate(device, label, 1);
        Self {
            label,
            view: texture.create_view(&wgpu::TextureViewDescriptor::default()),
            texture,
            rows: 1,
            cpu,
            overflow: None,
        }
    }

    fn allocate(device: &wgpu::Device, label: &'static str, rows: u32) -> wgpu::Texture {
        device.create_texture(&wgpu::TextureDescriptor {
            label: Some(label),
            size: wgpu::Extent3d {
                width: TEXEL_ROW_WIDTH,
                height: rows,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Rgba32Uint,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        })
    }

    /// The texture's view (replaced when it grows: see [`MirrorTexels::update`]).
    pub fn view(&self) -> &wgpu::TextureView {
        &self.view
    }

    /// What the texture holds (empty for a [`MirrorTexels::bulk`] one).
    pub fn contents(&self) -> &[T] {
        self.cpu.contents()
    }

    /// Bytes (GPU texture, CPU copy) this mirror holds.
    pub fn bytes(&self) -> (u64, u64) {
        let gpu = u64::from(TEXEL_ROW_WIDTH) * u64::from(self.rows) * TEXEL_BYTES as u64;
        (gpu, self.cpu.bytes())
    }

    /// Why the last update wrote nothing, if it overflowed.
    pub fn overflow(&self) -> Option<&TexelOverflow> {
        self.overflow.as_ref()
    }

    /// Makes the texture hold `data`, writing only the ranges that differ from what it holds.
    /// Returns true when the texture was reallocated (bind groups must be remade); an error,
    /// with nothing written, when `data` needs more rows than the device's largest texture
    /// (kept until an update succeeds: [`MirrorTexels::overflow`]).
    pub fn update(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        data: &[T],
        stats: &mut UploadStats,
    ) -> Result<bool, TexelOverflow> {
        let result = self.try_update(device, queue, data, stats);
        self.overflow = result.as_ref().err().cloned();
        result
    }

    fn try_update(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        data: &[T],
        stats: &mut UploadStats,
    ) -> Result<bool, TexelOverflow> {
        let max_rows = device.limits().max_texture_dimension_2d;
        let rows = rows_for(self.label, data.len(), Self::TEXELS, max_rows)?;
        if rows > self.rows {
            // A first fill (the scene as loaded) gets the rows it needs; growth after that,
            // powers of two.
            self.rows = if self.cpu.len() == 0 {
                rows
            } else {
                rows.next_power_of_two().min(max_rows)
            };
            self.texture = Self::allocate(device, self.label, self.rows);
            self.view = self
                .texture
                .create_view(&wgpu::TextureViewDescriptor::default());
            stats.allocations += 1;
            self.write(queue, data, 0..data.len(), stats);
            self.cpu.replace(data);
            return Ok(true);
        }
        for range in self.cpu.update(data) {
            self.write(queue, data, range, stats);
        }
        Ok(false)
    }

    /// Writes the records `range` of `data`: a partial first row, the whole rows, a partial
    /// last row.
    fn write(
        &self,
        queue: &wgpu::Queue,
        data: &[T],
        range: std::ops::Range<usize>,
        stats: &mut UploadStats,
    ) {
        let bytes: &[u8] = bytemuck::cast_slice(&data[range.clone()]);
        let texels = range.start * Self::TEXELS..range.end * Self::TEXELS;
        let mut written = 0;
        for block in row_blocks(texels) {
            let part = &bytes[written..written + block.width * block.rows * TEXEL_BYTES];
            queue.write_texture(
                wgpu::TexelCopyTextureInfo {
                    texture: &self.texture,
                    mip_level: 0,
                    origin: wgpu::Origin3d {
                        x: block.column as u32,
                        y: block.row as u32,
                        z: 0,
                    },
                    aspect: wgpu::TextureAspect::All,
                },
                part,
                wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some((block.width * TEXEL_BYTES) as u32),
                    rows_per_image: Some(block.rows as u32),
                },
                wgpu::Extent3d {
                    width: block.width as u32,
                    height: block.rows as u32,
                    depth_or_array_layers: 1,
                },
            );
            stats.record(self.label, part.len() as u64);
            written += part.len();
        }
    }
}

/// Rows (at least 1) that `records` records of `texels_per_record` texels need, or the overflow
/// when that is more than `max_rows`.
fn rows_for(
    label: &'static str,
    records: usize,
    texels_per_record: usize,
    max_rows: u32,
) -> Result<u32, TexelOverflow> {
    let texels = records as u64 * texels_per_record as u64;
    let rows = texels.div_ceil(u64::from(TEXEL_ROW_WIDTH)).max(1);
    u32::try_from(rows)
        .ok()
        .filter(|r| *r <= max_rows)
        .ok_or(TexelOverflow {
            label,
            records,
            rows,
            max_rows,
        })
}

/// A rectangle of whole texels that one texture write covers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct RowBlock {
    row: usize,
    column: usize,
    width: usize,
    rows: usize,
}

/// The texel range `texels` (row-major, [`TEXEL_ROW_WIDTH`] to a row) as rectangles: a partial
/// first row, the whole rows, a partial last row.
fn row_blocks(texels: std::ops::Range<usize>) -> Vec<RowBlock> {
    let width = TEXEL_ROW_WIDTH as usize;
    let mut blocks = Vec::new();
    let mut texel = texels.start;
    while texel < texels.end {
        let (row, column) = (texel / width, texel % width);
        let left = texels.end - texel;
        let block = if column == 0 && left >= width {
            RowBlock {
                row,
                column,
                width,
                rows: left / width,
            }
        } else {
            RowBlock {
                row,
                column,
                width: (width - column).min(left),
                rows: 1,
            }
        };
        texel += block.width * block.rows;
        blocks.push(block);
    }
    blocks
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_range_is_a_partial_row_whole_rows_and_a_partial_row() {
        let w = TEXEL_ROW_WIDTH as usize;
        let block = |row, column, width, rows| RowBlock {
            row,
            column,
            width,
            rows,
        };
        assert_eq!(
            row_blocks(w - 3..3 * w + 5),
            [block(0, w - 3, 3, 1), block(1, 0, w, 2), block(3, 0, 5, 1)]
        );
        assert_eq!(row_blocks(w + 2..w + 7), [block(1, 2, 5, 1)]);
        assert_eq!(row_blocks(0..2 * w), [block(0, 0, w, 2)]);
        assert!(row_blocks(4..4).is_empty());
        let covered: usize = row_blocks(7..5 * w + 1)
            .iter()
            .map(|b| b.width * b.rows)
            .sum();
        assert_eq!(covered, 5 * w + 1 - 7);
    }

    #[test]
    fn an_array_beyond_the_largest_texture_is_an_error_naming_it() {
        let w = TEXEL_ROW_WIDTH as usize;
        assert_eq!(rows_for("nodes", 0, 5, 16), Ok(1));
        assert_eq!(rows_for("nodes", w, 5, 16), Ok(5));
        let error = rows_for("scene blas nodes", 4 * w, 5, 16).unwrap_err();
        assert_eq!(error.rows, 20);
        let message = error.to_string();
        assert!(
            message.contains("scene blas nodes") && message.contains("16"),
            "{message}"
        );
    }
}
