//! Decoded textures, stored once, in the shared [`Textures`] store.

use crate::asset_store::{AssetId, AssetStore};

/// Index of a texture in [`Textures`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct TextureId(pub u32);

/// How a texture's 8-bit values map to linear values: fixed by the material slot that uses it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ColorSpace {
    /// sRGB-encoded colour (base colour, emissive).
    Srgb,
    /// Linear data (metallic-roughness, normal).
    Linear,
}

/// A decoded RGBA8 texture.
#[derive(Clone, Debug, PartialEq)]
pub struct Texture {
    /// Where it came from (file name, URI or buffer view), for messages.
    pub name: String,
    /// Width in texels.
    pub width: u32,
    /// Height in texels.
    pub height: u32,
    /// Row-major RGBA8 texels, top row first, `width * height * 4` bytes.
    pub rgba8: Vec<u8>,
    /// How the values are to be decoded.
    pub color_space: ColorSpace,
}

/// Every texture of the scene.
pub type Textures = AssetStore<TextureId, Texture>;

impl AssetId for TextureId {
    fn from_index(index: u32) -> Self {
        Self(index)
    }

    fn index(self) -> usize {
        self.0 as usize
    }
}

/// Decoding limits for an image whose sides may not exceed `max_side` texels.
pub(crate) fn image_limits(max_side: u32) -> image::Limits {
    let mut limits = image::Limits::default();
    limits.max_image_width = Some(max_side);
    limits.max_image_height = Some(max_side);
    limits
}
