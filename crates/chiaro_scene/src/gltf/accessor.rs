//! Checked accessor reading. Every byte range (buffer view in buffer, accessor in view, sparse
//! indices and values) is bounds-checked with overflow-checked arithmetic before anything is
//! read, formats are checked against what the attribute allows, and nothing is allocated beyond
//! what the file's own data backs (or [`MAX_ZERO_FILLED_ELEMENTS`] for view-less accessors).
//! The gltf crate's own reader is not used: it panics on several malformed inputs.

use gltf::accessor::{Accessor, DataType, Dimensions};

/// Most elements a view-less (zero-filled, possibly sparse) accessor may declare.
pub const MAX_ZERO_FILLED_ELEMENTS: usize = 1 << 24;

/// Component encodings an attribute accepts.
#[derive(Clone, Copy)]
pub(crate) enum Formats {
    /// 32-bit floats only.
    Float,
    /// Floats, or normalized unsigned bytes / shorts.
    FloatOrUnorm,
    /// Floats, or normalized signed or unsigned bytes / shorts (animated rotations).
    FloatOrNorm,
    /// Unsigned bytes, shorts or ints, not normalized (indices).
    UnsignedInt,
    /// Unsigned bytes or shorts, not normalized (joint indices).
    Joints,
}

/// Reads accessors against the file's loaded buffers.
pub(crate) struct AccessorReader<'a> {
    pub buffers: &'a [Vec<u8>],
}

fn component_size(t: DataType) -> usize {
    match t {
        DataType::I8 | DataType::U8 => 1,
        DataType::I16 | DataType::U16 => 2,
        DataType::U32 | DataType::F32 => 4,
    }
}

fn dimension_count(d: Dimensions) -> usize {
    match d {
        Dimensions::Scalar => 1,
        Dimensions::Vec2 => 2,
        Dimensions::Vec3 => 3,
        Dimensions::Vec4 => 4,
        Dimensions::Mat2 => 4,
        Dimensions::Mat3 => 9,
        Dimensions::Mat4 => 16,
    }
}

/// Decodes one component at the start of `bytes` (long enough by construction).
fn component(bytes: &[u8], t: DataType, normalized: bool) -> f64 {
    let v = match t {
        DataType::I8 => bytes[0] as i8 as f64,
        DataType::U8 => bytes[0] as f64,
        DataType::I16 => i16::from_le_bytes([bytes[0], bytes[1]]) as f64,
        DataType::U16 => u16::from_le_bytes([bytes[0], bytes[1]]) as f64,
        DataType::U32 => u32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]) as f64,
        DataType::F32 => f32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]) as f64,
    };
    if !normalized {
        return v;
    }
    match t {
        DataType::I8 => (v / 127.0).max(-1.0),
        DataType::U8 => v / 255.0,
        DataType::I16 => (v / 32767.0).max(-1.0),
        DataType::U16 => v / 65535.0,
        DataType::U32 | DataType::F32 => v,
    }
}

impl AccessorReader<'_> {
    /// The bytes of buffer view `view`, checked to lie inside its buffer.
    fn view_bytes(&self, view: &gltf::buffer::View) -> Result<&[u8], String> {
        let buffer = self
            .buffers
            .get(view.buffer().index())
            .ok_or_else(|| format!("buffer view {} refers to a missing buffer", view.index()))?;
        let end = view.offset().checked_add(view.length());
        end.and_then(|end| buffer.get(view.offset()..end))
            .ok_or_else(|| {
                format!(
                    "buffer view {} (offset {}, length {}) does not fit its buffer of {} bytes",
                    view.index(),
                    view.offset(),
                    view.length(),
                    buffer.len()
                )
            })
    }

    /// `count` elements of `size` bytes each, `stride` apart, from `offset` in the view's bytes.
    fn strided<'b>(
        bytes: &'b [u8],
        offset: usize,
        count: usize,
        size: usize,
        stride: usize,
        what: &str,
    ) -> Result<Vec<&'b [u8]>, String> {
        if count == 0 {
            return Ok(Vec::new());
        }
        let end = stride
            .checked_mul(count - 1)
            .and_then(|s| s.checked_add(size))
            .and_then(|s| s.checked_add(offset));
        match end {
            Some(end) if end <= bytes.len() => Ok((0..count)
                .map(|i| &bytes[offset + i * stride..][..size])
                .collect()),
            _ => Err(format!(
                "{what} ({count} elements of {size} bytes, stride {stride}, from offset {offset}) \
                 does not fit its buffer view of {} bytes",
                bytes.len()
            )),
        }
    }

    /// Reads an accessor of `N` components per element as f64, checking the format.
    pub(crate) fn read<const N: usize>(
        &self,
        accessor: &Accessor,
        formats: Formats,
    ) -> Result<Vec<[f64; N]>, String> {
        let what = format!("accessor {}", accessor.index());
        let t = accessor.data_type();
        let normalized = accessor.normalized();
        let dims = dimension_count(accessor.dimensions());
        let format_ok = dims == N
            && match formats {
                Formats::Float => t == DataType::F32,
                Formats::FloatOrUnorm => {
                    t == DataType::F32 || (normalized && matches!(t, DataType::U8 | DataType::U16))
                }
                Formats::FloatOrNorm => t == DataType::F32 || (normalized && t != DataType::U32),
                Formats::UnsignedInt => {
                    !normalized && matches!(t, DataType::U8 | DataType::U16 | DataType::U32)
                }
                Formats::Joints => !normalized && matches!(t, DataType::U8 | DataType::U16),
            };
        if !format_ok {
            return Err(format!(
                "{what} has {dims} components of {t:?}{} where {N} of {} are needed",
                if normalized { " (normalized)" } else { "" },
                match formats {
                    Formats::Float => "F32",
                    Formats::FloatOrUnorm => "F32 or normalized U8/U16",
                    Formats::FloatOrNorm => "F32 or normalized I8/U8/I16/U16",
                    Formats::UnsignedInt => "U8, U16 or U32",
                    Formats::Joints => "U8 or U16",
                }
            ));
        }
        let csize = component_size(t);
        let size = csize * N;
        let count = accessor.count();
        let decode = |bytes: &[u8]| -> [f64; N] {
            std::array::from_fn(|k| component(&bytes[k * csize..], t, normalized))
        };

        let mut values: Vec<[f64; N]> = match accessor.view() {
            Some(view) => {
                let bytes = self.view_bytes(&view)?;
                let stride = view.stride().unwrap_or(size);
                if stride < size {
                    return Err(format!(
                        "{what}: byte stride {stride} is smaller than its element size {size}"
                    ));
                }
                Self::strided(bytes, accessor.offset(), count, size, stride, &what)?
                    .into_iter()
                    .map(decode)
                    .collect()
            }
            None if count <= MAX_ZERO_FILLED_ELEMENTS => vec![[0.0; N]; count],
            None => {
                return Err(format!(
                    "{what} has no buffer view and declares {count} elements \
                     (more than {MAX_ZERO_FILLED_ELEMENTS})"
                ));
            }
        };

        if let Some(sparse) = accessor.sparse() {
            let sparse_count = sparse.count();
            if sparse_count == 0 || sparse_count > count {
                return Err(format!(
                    "{what}: sparse count {sparse_count} is outside 1..={count}"
                ));
            }
            let indices = sparse.indices();
            let isize = indices.index_type().size();
            let ibytes = self.view_bytes(&indices.view())?;
            let index_slices = Self::strided(
                ibytes,
                indices.offset(),
                sparse_count,
                isize,
                isize,
                &format!("{what} sparse indices"),
            )?;
            let vals = sparse.values();
            let vbytes = self.view_bytes(&vals.view())?;
            let value_slices = Self::strided(
                vbytes,
                vals.offset(),
                sparse_count,
                size,
                size,
                &format!("{what} sparse values"),
            )?;
            for (ib, vb) in index_slices.into_iter().zip(value_slices) {
                let index = match isize {
                    1 => ib[0] as usize,
                    2 => u16::from_le_bytes([ib[0], ib[1]]) as usize,
                    _ => u32::from_le_bytes([ib[0], ib[1], ib[2], ib[3]]) as usize,
                };
                let slot = values.get_mut(index).ok_or_else(|| {
                    format!("{what}: sparse index {index} is past its {count} elements")
                })?;
                *slot = decode(vb);
            }
        }
        Ok(values)
    }

    /// Reads a float attribute as `f32` arrays.
    pub(crate) fn read_f32<const N: usize>(
        &self,
        accessor: &Accessor,
        formats: Formats,
    ) -> Result<Vec<[f32; N]>, String> {
        Ok(self
            .read::<N>(accessor, formats)?
            .into_iter()
            .map(|v| v.map(|c| c as f32))
            .collect())
    }

    /// Reads a colour attribute (glTF's COLOR_n): RGB or RGBA, of floats or normalized
    /// unsigned bytes or shorts, as RGBA (alpha 1 for RGB).
    pub(crate) fn read_color(&self, accessor: &Accessor) -> Result<Vec<[f32; 4]>, String> {
        match accessor.dimensions() {
            Dimensions::Vec3 => Ok(self
                .read_f32::<3>(accessor, Formats::FloatOrUnorm)?
                .into_iter()
                .map(|[r, g, b]| [r, g, b, 1.0])
                .collect()),
            Dimensions::Vec4 => self.read_f32::<4>(accessor, Formats::FloatOrUnorm),
            other => Err(format!(
                "accessor {} is a colour of {} components where 3 (RGB) or 4 (RGBA) are needed",
                accessor.index(),
                dimension_count(other)
            )),
        }
    }

    /// Reads an index accessor.
    pub(crate) fn read_indices(&self, accessor: &Accessor) -> Result<Vec<u32>, String> {
        Ok(self
            .read::<1>(accessor, Formats::UnsignedInt)?
            .into_iter()
            .map(|[i]| i as u32)
            .collect())
    }
}
