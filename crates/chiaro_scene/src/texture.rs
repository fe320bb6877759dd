//! Decoded textures, stored once, in the shared [`Textures`] store.

use bevy_ecs::prelude::*;

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
#[derive(Resource, Default, Debug)]
pub struct Textures {
    textures: Vec<Texture>,
}

impl Textures {
    /// Adds a texture and returns its id.
    pub fn add(&mut self, texture: Texture) -> TextureId {
        self.textures.push(texture);
        TextureId(self.textures.len() as u32 - 1)
    }

    /// The texture with this id, if any.
    pub fn get(&self, id: TextureId) -> Option<&Texture> {
        self.textures.get(id.0 as usize)
    }

    /// All textures with their ids.
    pub fn iter(&self) -> impl Iterator<Item = (TextureId, &Texture)> {
        self.textures
            .iter()
            .enumerate()
            .map(|(i, t)| (TextureId(i as u32), t))
    }

    /// Number of textures.
    pub fn len(&self) -> usize {
        self.textures.len()
    }

    /// True when there are none.
    pub fn is_empty(&self) -> bool {
        self.textures.is_empty()
    }
}
