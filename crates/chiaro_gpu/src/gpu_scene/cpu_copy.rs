//! What a mirror remembers of its GPU contents, to find the ranges an update changes: every
//! element (tables the upload reads back, small) or, for bulk geometry nobody reads back, one
//! fingerprint per block of [`BLOCK`] elements: 8 bytes per block instead of a second copy of
//! the scene's vertices, triangles and BVH nodes. A changed element changes its block's
//! fingerprint (a 64-bit hash of the block's bytes) except with a chance of about 2^-64.

use std::ops::Range;

use bytemuck::Pod;

use super::mirror::changed_ranges;

/// Elements per fingerprinted block.
pub const BLOCK: usize = 64;

/// What a mirror remembers.
pub enum CpuCopy<T> {
    /// Every element.
    Whole(Vec<T>),
    /// The element count and a fingerprint per block.
    Blocks {
        /// Elements held.
        len: usize,
        /// [`fingerprint`] of each block, the last one possibly short.
        fingerprints: Vec<u64>,
    },
}

impl<T: Pod + PartialEq> CpuCopy<T> {
    /// An empty copy: whole, or fingerprinted by blocks when `bulk`.
    pub fn new(bulk: bool) -> Self {
        if bulk {
            Self::Blocks {
                len: 0,
                fingerprints: Vec::new(),
            }
        } else {
            Self::Whole(Vec::new())
        }
    }

    /// Elements held.
    pub fn len(&self) -> usize {
        match self {
            Self::Whole(v) => v.len(),
            Self::Blocks { len, .. } => *len,
        }
    }

    /// The elements, for a whole copy; empty for a fingerprinted one.
    pub fn contents(&self) -> &[T] {
        match self {
            Self::Whole(v) => v,
            Self::Blocks { .. } => &[],
        }
    }

    /// Bytes this copy takes.
    pub fn bytes(&self) -> u64 {
        match self {
            Self::Whole(v) => (v.capacity() * size_of::<T>()) as u64,
            Self::Blocks { fingerprints, .. } => (fingerprints.capacity() * 8) as u64,
        }
    }

    /// The element ranges of `new` that differ from what is remembered (whole blocks, for a
    /// fingerprinted copy), then remembers `new`.
    pub fn update(&mut self, new: &[T]) -> Vec<Range<usize>> {
        match self {
            Self::Whole(old) => {
                let ranges = changed_ranges(old, new);
                old.clear();
                old.extend_from_slice(new);
                ranges
            }
            Self::Blocks { len, fingerprints } => {
                let fresh: Vec<u64> = new.chunks(BLOCK).map(fingerprint).collect();
                let mut ranges: Vec<Range<usize>> = Vec::new();
                for (k, f) in fresh.iter().enumerate() {
                    // A block's length is in its fingerprint: a block cut short or filled
                    // up differs.
                    if fingerprints.get(k) == Some(f) {
                        continue;
                    }
                    let block = k * BLOCK..((k + 1) * BLOCK).min(new.len());
                    match ranges.last_mut() {
                        Some(last) if last.end == block.start => last.end = block.end,
                        _ => ranges.push(block),
                    }
                }
                *len = new.len();
                *fingerprints = fresh;
                ranges
            }
        }
    }

    /// Remembers `new` without diffing (after a reallocation wrote it whole).
    pub fn replace(&mut self, new: &[T]) {
        match self {
            Self::Whole(old) => *old = new.to_vec(),
            Self::Blocks { len, fingerprints } => {
                *len = new.len();
                *fingerprints = new.chunks(BLOCK).map(fingerprint).collect();
            }
        }
    }
}

/// A 64-bit hash of `block`'s bytes: its length, then each 8-byte word, mixed by multiply and
/// shift (the words of a `Pod` record whose size is a multiple of 4; a trailing 4 bytes are
/// mixed as a word of their own).
pub fn fingerprint<T: Pod>(block: &[T]) -> u64 {
    const K: u64 = 0x9E37_79B9_7F4A_7C15;
    let bytes: &[u8] = bytemuck::cast_slice(block);
    let mut h = (bytes.len() as u64).wrapping_mul(K);
    let mut words = bytes.chunks_exact(8);
    for word in &mut words {
        let w = u64::from_le_bytes(word.try_into().unwrap_or_default());
        h = (h ^ w).wrapping_mul(K);
        h ^= h >> 29;
    }
    let rest = words.remainder();
    if !rest.is_empty() {
        let mut last = [0u8; 8];
        last[..rest.len()].copy_from_slice(rest);
        h = (h ^ u64::from_le_bytes(last)).wrapping_mul(K);
        h ^= h >> 29;
    }
    h
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_fingerprinted_copy_finds_the_changed_blocks() {
        let mut copy = CpuCopy::<u32>::new(true);
        let mut data: Vec<u32> = (0..1000).collect();
        assert_eq!(copy.update(&data), vec![0..1000]);
        assert!(copy.update(&data).is_empty());
        data[70] = 7;
        data[130] = 7;
        data[999] = 1;
        assert_eq!(copy.update(&data), vec![64..192, 960..1000]);
        // Growing writes the new elements and the short block they complete.
        data.extend(0..100);
        assert_eq!(copy.update(&data), vec![960..1100]);
        // Shrinking rewrites only the last block, now shorter.
        data.truncate(1090);
        assert_eq!(copy.update(&data), vec![1088..1090]);
        assert_eq!(copy.len(), 1090);
        assert!(copy.contents().is_empty());
        assert!(copy.bytes() < 200);
    }

    #[test]
    fn a_whole_copy_keeps_the_elements() {
        let mut copy = CpuCopy::<u32>::new(false);
        let data: Vec<u32> = (0..10).collect();
        copy.update(&data);
        assert_eq!(copy.contents(), &data[..]);
        let mut changed = data.clone();
        changed[3] = 0;
        assert_eq!(copy.update(&changed), vec![3..4]);
    }

    #[test]
    fn fingerprints_see_every_word() {
        let base = [0u32; 65];
        let f = fingerprint(&base);
        for k in 0..base.len() {
            let mut other = base;
            other[k] = 1;
            assert_ne!(fingerprint(&other), f, "word {k}");
        }
        assert_ne!(fingerprint(&base[..64]), f);
    }
}
