//! Texture lookups for the reference: the material slot's UV set and KHR_texture_transform, the
//! sampler's wrap modes, bilinear filtering (or nearest, as the sampler asks) of texels decoded to
//! linear before filtering. No mip-mapping: the reference supersamples the pixel instead.

use chiaro_scene::material::{Filter, WrapMode};
use chiaro_scene::{ColorSpace, Texture, TextureRef, Textures};
use chiaro_shading::color::srgb_to_linear;
use glam::{Vec2, Vec4};

fn wrap(i: i64, size: u32, mode: WrapMode) -> usize {
    let n = size as i64;
    let w = match mode {
        WrapMode::Repeat => i.rem_euclid(n),
        WrapMode::ClampToEdge => i.clamp(0, n - 1),
        WrapMode::MirroredRepeat => {
            let period = i.rem_euclid(2 * n);
            if period < n {
                period
            } else {
                2 * n - 1 - period
            }
        }
    };
    w as usize
}

fn texel(texture: &Texture, x: usize, y: usize) -> Vec4 {
    let i = (y * texture.width as usize + x) * 4;
    let raw = Vec4::from_array(std::array::from_fn(|k| texture.rgba8[i + k] as f32 / 255.0));
    match texture.color_space {
        ColorSpace::Linear => raw,
        ColorSpace::Srgb => Vec4::new(
            srgb_to_linear(raw.x),
            srgb_to_linear(raw.y),
            srgb_to_linear(raw.z),
            raw.w,
        ),
    }
}

/// The linear RGBA value of `slot` at the mesh UVs `uvs` (sets 0 and 1, if present), or `None`
/// when the texture or its UV set is missing.
pub fn sample_slot(textures: &Textures, slot: &TextureRef, uvs: [Option<Vec2>; 2]) -> Option<Vec4> {
    let texture = textures.get(slot.texture)?;
    let uv = uvs.get(slot.uv_set as usize).copied().flatten()?;
    let uv = slot.transform.transform_point2(uv);
    let (w, h) = (texture.width, texture.height);
    if w == 0 || h == 0 || !uv.is_finite() {
        return None;
    }
    let (sx, sy) = (slot.sampler.wrap_u, slot.sampler.wrap_v);
    let x = uv.x * w as f32 - 0.5;
    let y = uv.y * h as f32 - 0.5;
    if slot.sampler.mag_filter == Filter::Nearest {
        let (xi, yi) = ((x + 0.5).floor() as i64, (y + 0.5).floor() as i64);
        return Some(texel(texture, wrap(xi, w, sx), wrap(yi, h, sy)));
    }
    let (x0, y0) = (x.floor(), y.floor());
    let (fx, fy) = (x - x0, y - y0);
    let (x0, y0) = (x0 as i64, y0 as i64);
    let at = |dx: i64, dy: i64| texel(texture, wrap(x0 + dx, w, sx), wrap(y0 + dy, h, sy));
    let top = at(0, 0).lerp(at(1, 0), fx);
    let bottom = at(0, 1).lerp(at(1, 1), fx);
    Some(top.lerp(bottom, fy))
}

#[cfg(test)]
mod tests {
    use super::*;
    use chiaro_scene::material::Sampler;
    use chiaro_scene::{AssetStore, TextureId};
    use glam::Affine2;

    fn store() -> Textures {
        let mut textures = AssetStore::default();
        // 2x1: black then white, linear.
        textures.add(Texture {
            name: "t".into(),
            width: 2,
            height: 1,
            rgba8: vec![0, 0, 0, 255, 255, 255, 255, 255],
            color_space: ColorSpace::Linear,
        });
        textures
    }

    fn slot(wrap_u: WrapMode, mag_filter: Filter) -> TextureRef {
        TextureRef {
            texture: TextureId(0),
            uv_set: 0,
            transform: Affine2::IDENTITY,
            sampler: Sampler {
                wrap_u,
                mag_filter,
                ..Sampler::default()
            },
        }
    }

    #[test]
    fn bilinear_blends_between_texel_centres() {
        let t = store();
        let s = slot(WrapMode::ClampToEdge, Filter::Linear);
        let mid = sample_slot(&t, &s, [Some(Vec2::new(0.5, 0.5)), None]).unwrap();
        assert!((mid.x - 0.5).abs() < 1e-6);
        let left = sample_slot(&t, &s, [Some(Vec2::new(0.25, 0.5)), None]).unwrap();
        assert!(left.x.abs() < 1e-6);
    }

    #[test]
    fn wrap_modes_tile_clamp_and_mirror() {
        assert_eq!(wrap(-1, 4, WrapMode::Repeat), 3);
        assert_eq!(wrap(5, 4, WrapMode::ClampToEdge), 3);
        assert_eq!(wrap(4, 4, WrapMode::MirroredRepeat), 3);
        assert_eq!(wrap(-1, 4, WrapMode::MirroredRepeat), 0);
        let t = store();
        let nearest = slot(WrapMode::Repeat, Filter::Nearest);
        let v = sample_slot(&t, &nearest, [Some(Vec2::new(1.75, 0.5)), None]).unwrap();
        assert_eq!(v.x, 1.0);
    }

    #[test]
    fn missing_uv_set_gives_none() {
        let t = store();
        let mut s = slot(WrapMode::Repeat, Filter::Linear);
        s.uv_set = 1;
        assert!(sample_slot(&t, &s, [Some(Vec2::ZERO), None]).is_none());
    }
}
