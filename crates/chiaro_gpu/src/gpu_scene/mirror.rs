//! A storage buffer with a CPU copy of what it holds, so that an update writes only the
//! element ranges that differ, and counts the bytes it wrote.

use std::collections::BTreeMap;
use std::ops::Range;

use bytemuck::Pod;

use super::cpu_copy::CpuCopy;

/// Bytes and writes uploaded, in total and per buffer (by label).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct UploadStats {
    /// Bytes written to GPU buffers.
    pub bytes: u64,
    /// `write_buffer` calls.
    pub writes: u64,
    /// Bytes per buffer label.
    pub per_buffer: BTreeMap<&'static str, u64>,
    /// Buffers created (first use or growth).
    pub allocations: u64,
}

impl UploadStats {
    /// Bytes written to the buffer labelled `label`.
    pub fn bytes_of(&self, label: &str) -> u64 {
        self.per_buffer.get(label).copied().unwrap_or(0)
    }

    /// The labels of the buffers that received any bytes.
    pub fn written(&self) -> Vec<&'static str> {
        self.per_buffer
            .iter()
            .filter(|(_, b)| **b > 0)
            .map(|(l, _)| *l)
            .collect()
    }

    pub(super) fn record(&mut self, label: &'static str, bytes: u64) {
        self.bytes += bytes;
        self.writes += 1;
        *self.per_buffer.entry(label).or_default() += bytes;
    }
}

/// Two dirty ranges closer than this many elements are written as one.
const MERGE_GAP: usize = 4;

/// Data too large for one buffer (a storage buffer's binding) of the device.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{label}: {bytes} bytes exceed the device's largest buffer of this kind ({max} bytes)")]
pub struct BufferOverflow {
    /// The buffer.
    pub label: &'static str,
    /// Bytes asked for.
    pub bytes: u64,
    /// The device's `max_storage_buffer_binding_size` (a storage buffer) or `max_buffer_size`.
    pub max: u64,
}

/// A storage buffer of `T` mirrored on the CPU.
pub struct MirrorBuffer<T: Pod> {
    label: &'static str,
    usage: wgpu::BufferUsages,
    buffer: wgpu::Buffer,
    capacity: usize,
    cpu: CpuCopy<T>,
    overflow: Option<BufferOverflow>,
}

impl<T: Pod + PartialEq> MirrorBuffer<T> {
    /// An empty buffer with room for one element (bindings may not be empty), its contents
    /// kept on the CPU.
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        label: &'static str,
        usage: wgpu::BufferUsages,
    ) -> Self {
        Self::with_copy(device, queue, label, usage, CpuCopy::new(false))
    }

    /// [`MirrorBuffer::new`] for bulk data never read back: the CPU keeps fingerprints of its
    /// blocks, not its contents ([`CpuCopy::Blocks`]).
    pub fn bulk(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        label: &'static str,
        usage: wgpu::BufferUsages,
    ) -> Self {
        Self::with_copy(device, queue, label, usage, CpuCopy::new(true))
    }

    fn with_copy(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        label: &'static str,
        usage: wgpu::BufferUsages,
        cpu: CpuCopy<T>,
    ) -> Self {
        let usage = usage | wgpu::BufferUsages::COPY_DST;
        Self {
            label,
            usage,
            buffer: Self::allocate(device, queue, label, usage, 1, &[]),
            capacity: 1,
            cpu,
            overflow: None,
        }
    }

    /// A buffer of `capacity` elements holding `data` (at most that many) at its start.
    fn allocate(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        label: &'static str,
        usage: wgpu::BufferUsages,
        capacity: usize,
        data: &[T],
    ) -> wgpu::Buffer {
        // Whole 16-byte blocks: mapping at creation wants a multiple of 4.
        let size = (capacity.max(1) * size_of::<T>())
            .max(16)
            .next_multiple_of(16);
        let buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size: size as u64,
            usage,
            mapped_at_creation: true,
        });
        let bytes: &[u8] = bytemuck::cast_slice(data);
        if !bytes.is_empty() {
            match buffer.slice(..bytes.len() as u64).get_mapped_range_mut() {
                Ok(mut mapped) => mapped.copy_from_slice(bytes),
                // Not expected of a buffer mapped at creation: written through the queue.
                Err(_) => queue.write_buffer(&buffer, 0, bytes),
            }
        }
        buffer.unmap();
        buffer
    }

    /// The GPU buffer (replaced when it grows: see [`MirrorBuffer::update`]).
    pub fn buffer(&self) -> &wgpu::Buffer {
        &self.buffer
    }

    /// What the GPU buffer holds (empty for a [`MirrorBuffer::bulk`] one).
    pub fn contents(&self) -> &[T] {
        self.cpu.contents()
    }

    /// Bytes (GPU buffer, CPU copy) this mirror holds.
    pub fn bytes(&self) -> (u64, u64) {
        (self.buffer.size(), self.cpu.bytes())
    }

    /// Why the last update wrote nothing, if `data` was larger than one binding may be (kept
    /// until an update succeeds).
    pub fn overflow(&self) -> Option<&BufferOverflow> {
        self.overflow.as_ref()
    }

    /// Makes the GPU buffer hold `data`, writing only the ranges that differ from what it
    /// holds. Returns true when the buffer was reallocated (bind groups must be remade). Data
    /// larger than the device's largest storage binding is not written: the buffer keeps its
    /// contents and [`MirrorBuffer::overflow`] says why.
    pub fn update(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        data: &[T],
        stats: &mut UploadStats,
    ) -> bool {
        let element = size_of::<T>();
        let limits = device.limits();
        let max = if self.usage.contains(wgpu::BufferUsages::STORAGE) {
            limits
                .max_storage_buffer_binding_size
                .min(limits.max_buffer_size)
        } else {
            limits.max_buffer_size
        };
        let most = (max / element as u64) as usize;
        let bytes = std::mem::size_of_val(data) as u64;
        if bytes > max {
            self.overflow = Some(BufferOverflow {
                label: self.label,
                bytes,
                max,
            });
            return false;
        }
        self.overflow = None;
        if data.len() > self.capacity {
            // A first fill (the scene as loaded) gets the room it needs; growth after that,
            // powers of two, but never past what one binding may hold.
            self.capacity = if self.cpu.len() == 0 {
                data.len()
            } else {
                data.len().next_power_of_two().min(most).max(data.len())
            };
            // Written while mapped at creation: no staging copy (on a CPU adapter, none at all).
            self.buffer =
                Self::allocate(device, queue, self.label, self.usage, self.capacity, data);
            stats.allocations += 1;
            if !data.is_empty() {
                stats.record(self.label, std::mem::size_of_val(data) as u64);
            }
            self.cpu.replace(data);
            return true;
        }
        for range in self.cpu.update(data) {
            let bytes: &[u8] = bytemuck::cast_slice(&data[range.clone()]);
            queue.write_buffer(&self.buffer, (range.start * element) as u64, bytes);
            stats.record(self.label, bytes.len() as u64);
        }
        false
    }
}

/// The element ranges where `new` differs from `old` (elements past `old`'s end differ), two
/// ranges closer than [`MERGE_GAP`] elements merged into one.
pub(super) fn changed_ranges<T: PartialEq>(old: &[T], new: &[T]) -> Vec<Range<usize>> {
    let mut ranges = Vec::new();
    let mut i = 0;
    while i < new.len() {
        if old.get(i) == Some(&new[i]) {
            i += 1;
            continue;
        }
        let start = i;
        let mut end = i + 1;
        let mut j = end;
        while j < new.len() && j < end + MERGE_GAP {
            if old.get(j) != Some(&new[j]) {
                end = j + 1;
            }
            j += 1;
        }
        ranges.push(start..end);
        i = end;
    }
    ranges
}

#[cfg(test)]
mod tests {
    use super::changed_ranges;

    #[test]
    fn changed_ranges_merge_near_differences_and_cover_growth() {
        let old = [0u32; 20];
        let mut new = [0u32; 24];
        new[1] = 1;
        new[3] = 1;
        new[12] = 1;
        assert_eq!(changed_ranges(&old, &new), vec![1..4, 12..13, 20..24]);
        assert!(changed_ranges(&old, &old).is_empty());
    }
}
