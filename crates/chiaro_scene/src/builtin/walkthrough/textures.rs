//! The walkthrough's generated textures, tileable and deterministic from the seed: dressed
//! stone (base colour, normal, metallic-roughness), polished marble tiles, a leaf with an alpha
//! cut-out for the foliage, and an equirectangular sky.

use glam::{Vec2, Vec3};

use crate::environment::{Environment, EnvironmentSource, EquirectImage};
use crate::texture::{ColorSpace, Texture};

use super::surface::smoothstep;

/// Side of the surface textures, texels.
pub const SIDE: u32 = 256;
/// Side of the leaf texture, texels.
pub const LEAF_SIDE: u32 = 128;

/// A hash of a lattice point to [0, 1).
fn hash(x: i32, y: i32, seed: u32) -> f32 {
    let mut h = (x as u32).wrapping_mul(0x8DA6_B343)
        ^ (y as u32).wrapping_mul(0xD816_3841)
        ^ seed.wrapping_mul(0xCB1A_B31F);
    h ^= h >> 13;
    h = h.wrapping_mul(0x5BD1_E995);
    h ^= h >> 15;
    (h >> 8) as f32 / (1u32 << 24) as f32
}

/// Value noise at `p` on a lattice that repeats every `period` cells: smooth, in [0, 1).
fn noise(p: Vec2, period: i32, seed: u32) -> f32 {
    let cell = p.floor();
    let f = p - cell;
    let s = f * f * (Vec2::splat(3.0) - 2.0 * f);
    let (x, y) = (cell.x as i32, cell.y as i32);
    let at = |dx: i32, dy: i32| {
        hash(
            (x + dx).rem_euclid(period),
            (y + dy).rem_euclid(period),
            seed,
        )
    };
    let top = at(0, 0) + (at(1, 0) - at(0, 0)) * s.x;
    let bottom = at(0, 1) + (at(1, 1) - at(0, 1)) * s.x;
    top + (bottom - top) * s.y
}

/// Four octaves of [`noise`] over the unit square (tileable), in [0, 1).
fn fbm(uv: Vec2, base_period: i32, seed: u32) -> f32 {
    let mut sum = 0.0;
    let mut amplitude = 0.5;
    let mut period = base_period;
    for octave in 0..4 {
        sum += amplitude * noise(uv * period as f32, period, seed + octave);
        amplitude *= 0.5;
        period *= 2;
    }
    sum / 0.9375
}

/// A square texture of side `side` from `texel(uv)` (RGBA in [0, 1]), uv at texel centres.
fn texture(
    name: &str,
    side: u32,
    color_space: ColorSpace,
    texel: impl Fn(Vec2) -> [f32; 4],
) -> Texture {
    let mut rgba8 = Vec::with_capacity((side * side * 4) as usize);
    for y in 0..side {
        for x in 0..side {
            let uv = (Vec2::new(x as f32, y as f32) + 0.5) / side as f32;
            rgba8.extend(texel(uv).map(|c| (c.clamp(0.0, 1.0) * 255.0 + 0.5) as u8));
        }
    }
    Texture {
        name: name.to_owned(),
        width: side,
        height: side,
        rgba8,
        color_space,
    }
}

/// Linear to sRGB encoding of one channel.
fn srgb(linear: f32) -> f32 {
    if linear <= 0.003_130_8 {
        12.92 * linear
    } else {
        1.055 * linear.powf(1.0 / 2.4) - 0.055
    }
}

/// A texel of sRGB-encoded linear `color` and `alpha`.
fn srgb_rgba(color: Vec3, alpha: f32) -> [f32; 4] {
    [srgb(color.x), srgb(color.y), srgb(color.z), alpha]
}

/// A tangent-space normal map of the height field `height` (tileable), `strength` its slope scale.
fn normal_map(name: &str, height: &impl Fn(Vec2) -> f32, strength: f32) -> Texture {
    let e = 1.0 / SIDE as f32;
    texture(name, SIDE, ColorSpace::Linear, |uv| {
        let dx =
            height((uv + Vec2::new(e, 0.0)).fract()) - height((uv - Vec2::new(e, 0.0)).fract());
        let dy =
            height((uv + Vec2::new(0.0, e)).fract()) - height((uv - Vec2::new(0.0, e)).fract());
        // The texture's v runs down the image, the bitangent up the surface's v: y flips.
        let n = Vec3::new(-dx * strength, dy * strength, 1.0).normalize();
        [n.x * 0.5 + 0.5, n.y * 0.5 + 0.5, n.z * 0.5 + 0.5, 1.0]
    })
}

/// Which block of an ashlar course pattern `uv` falls in (4 courses of 2 blocks, every other
/// course offset by half a block), and how far it is from the nearest joint, in uv units.
fn ashlar(uv: Vec2) -> (i32, f32) {
    let course = (uv.y * 4.0).floor();
    let shift = if course as i32 % 2 == 0 { 0.0 } else { 0.25 };
    let x = (uv.x + shift).fract() * 2.0;
    let block = course as i32 * 2 + x.floor() as i32;
    let to_joint_x = (x.fract().min(1.0 - x.fract())) / 2.0;
    let to_joint_y = (uv.y * 4.0).fract().min(1.0 - (uv.y * 4.0).fract()) / 4.0;
    (block, to_joint_x.min(to_joint_y))
}

/// The generated textures of a walkthrough.
pub struct Textures {
    /// Dressed stone: base colour (sRGB).
    pub stone_color: Texture,
    /// Dressed stone: normal map.
    pub stone_normal: Texture,
    /// Dressed stone: metallic (blue) and roughness (green).
    pub stone_metal_rough: Texture,
    /// Marble tiles: base colour (sRGB).
    pub marble_color: Texture,
    /// Marble tiles: normal map (the joints).
    pub marble_normal: Texture,
    /// Marble tiles: metallic and roughness.
    pub marble_metal_rough: Texture,
    /// A sprig of leaves, alpha 0 around them.
    pub leaf: Texture,
}

/// Generates the textures for `seed`.
pub fn generate(seed: u32) -> Textures {
    let stone_height = move |uv: Vec2| {
        let (_, joint) = ashlar(uv);
        smoothstep(0.0, 0.012, joint) * (0.85 + 0.15 * fbm(uv, 8, seed))
    };
    let marble_height = |uv: Vec2| {
        let t = (uv * 2.0).fract();
        let joint = t.x.min(1.0 - t.x).min(t.y).min(1.0 - t.y) / 2.0;
        smoothstep(0.0, 0.006, joint)
    };
    Textures {
        stone_color: texture("walkthrough stone", SIDE, ColorSpace::Srgb, |uv| {
            let (block, joint) = ashlar(uv);
            let tint = 0.85 + 0.3 * hash(block, 7, seed);
            let grain = 0.75 + 0.5 * fbm(uv, 16, seed + 11);
            let stone = Vec3::new(0.58, 0.52, 0.44) * tint * grain;
            let color = Vec3::splat(0.3).lerp(stone, smoothstep(0.0, 0.012, joint));
            srgb_rgba(color, 1.0)
        }),
        stone_normal: normal_map("walkthrough stone normal", &stone_height, 6.0),
        stone_metal_rough: texture(
            "walkthrough stone roughness",
            SIDE,
            ColorSpace::Linear,
            |uv| {
                let (_, joint) = ashlar(uv);
                let roughness = 0.95 - 0.3 * smoothstep(0.0, 0.012, joint) * fbm(uv, 8, seed + 3);
                [0.0, roughness, 0.0, 1.0]
            },
        ),
        marble_color: texture("walkthrough marble", SIDE, ColorSpace::Srgb, |uv| {
            let tile = (uv * 2.0).floor();
            let dark = (tile.x + tile.y) as i32 % 2 == 1;
            let vein = (((uv.x + uv.y) * 9.0 + 6.0 * fbm(uv, 4, seed + 5)) * std::f32::consts::PI)
                .sin()
                .abs()
                .powf(12.0);
            let base = if dark {
                Vec3::new(0.12, 0.16, 0.14)
            } else {
                Vec3::new(0.78, 0.76, 0.72)
            };
            let color = base.lerp(Vec3::splat(if dark { 0.45 } else { 0.35 }), vein * 0.6);
            srgb_rgba(color, 1.0)
        }),
        marble_normal: normal_map("walkthrough marble normal", &marble_height, 2.0),
        marble_metal_rough: texture(
            "walkthrough marble roughness",
            SIDE,
            ColorSpace::Linear,
            |uv| {
                let roughness =
                    0.08 + 0.12 * fbm(uv, 4, seed + 9) + 0.6 * (1.0 - marble_height(uv));
                [0.0, roughness, 0.0, 1.0]
            },
        ),
        leaf: leaf(seed),
    }
}

/// A sprig: a stem up the middle with leaves on both sides, alpha 1 on them and 0 elsewhere.
fn leaf(seed: u32) -> Texture {
    texture("walkthrough leaf", LEAF_SIDE, ColorSpace::Srgb, |uv| {
        // Texture v runs down: the stem grows from the bottom (v = 1) up.
        let p = Vec2::new(uv.x - 0.5, 1.0 - uv.y);
        let mut inside = (p.x.abs() < 0.012 && p.y < 0.95) as u8 as f32;
        let mut shade = 0.6;
        for k in 0..6 {
            let y = 0.15 + 0.13 * k as f32;
            let side = if k % 2 == 0 { 1.0 } else { -1.0 };
            let center = Vec2::new(side * 0.17, y + 0.06);
            let axis = Vec2::new(side * 0.9, 0.45).normalize();
            let d = p - center;
            let along = d.dot(axis) / 0.2;
            let across = d.perp_dot(axis) / 0.075;
            if along * along + across * across < 1.0 {
                inside = 1.0;
                shade = 0.7 + 0.3 * hash(k, 3, seed);
            }
        }
        let tip = Vec2::new(p.x / 0.08, (p.y - 0.93) / 0.12);
        if tip.length_squared() < 1.0 {
            inside = 1.0;
        }
        let color = Vec3::new(0.10, 0.32, 0.06) * shade;
        srgb_rgba(color, inside)
    })
}

/// A clear late-afternoon sky without its sun (a directional light is the sun): blue at the
/// zenith, pale at the horizon, a dim ground below.
pub fn sky() -> Environment {
    let (width, height) = (128u32, 64u32);
    let zenith = Vec3::new(0.10, 0.22, 0.55);
    let horizon = Vec3::new(0.55, 0.55, 0.52);
    let ground = Vec3::new(0.12, 0.11, 0.10);
    let texels = (0..height)
        .flat_map(|y| {
            let elevation = std::f32::consts::FRAC_PI_2
                - (y as f32 + 0.5) / height as f32 * std::f32::consts::PI;
            let color = if elevation > 0.0 {
                horizon.lerp(zenith, elevation.sin().sqrt())
            } else {
                ground.lerp(horizon, (1.0 + elevation.sin() * 8.0).max(0.0))
            };
            std::iter::repeat_n(color, width as usize)
        })
        .collect();
    Environment {
        source: EnvironmentSource::Equirect(EquirectImage {
            path: "walkthrough sky".into(),
            width,
            height,
            texels,
        }),
        strength: 1.0,
        rotation: 0.0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn noise_tiles_and_stays_in_range() {
        for k in 0..50 {
            let p = Vec2::new(k as f32 * 0.37, k as f32 * 0.11);
            let a = noise(p, 8, 3);
            assert!((0.0..1.0).contains(&a));
            assert!((a - noise(p + Vec2::new(8.0, 0.0), 8, 3)).abs() < 1e-5);
            assert!((fbm(p.fract(), 4, 1) - fbm(p.fract() + Vec2::Y, 4, 1)).abs() < 1e-4);
        }
    }

    #[test]
    fn textures_are_deterministic_and_the_leaf_is_cut_out() {
        let a = generate(5);
        assert_eq!(a.stone_color, generate(5).stone_color);
        assert_ne!(a.stone_color, generate(6).stone_color);
        let alpha: Vec<u8> = a.leaf.rgba8.chunks(4).map(|t| t[3]).collect();
        let opaque = alpha.iter().filter(|&&a| a == 255).count();
        assert!(alpha.iter().all(|&a| a == 0 || a == 255));
        // Leaves cover some of the square, not all of it.
        let covered = opaque as f32 / alpha.len() as f32;
        assert!((0.1..0.6).contains(&covered), "{covered}");
        // A flat normal map texel is (0.5, 0.5, 1): the stone's faces are mostly flat.
        let flat = a
            .stone_normal
            .rgba8
            .chunks(4)
            .filter(|t| t[2] > 240)
            .count();
        assert!(flat * 2 > a.stone_normal.rgba8.len() / 4);
    }
}
