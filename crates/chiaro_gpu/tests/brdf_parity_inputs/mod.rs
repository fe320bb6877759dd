//! brdf_parity's inputs: the record the GPU kernel reads, random materials with their edge
//! values drawn often (as chiaro_shading's own tests do), and directions from the whole
//! sphere, grazing ones, the normal and the view's mirror reflection.

use bytemuck::{Pod, Zeroable};
use chiaro_shading::brdf::{MIRROR_ALPHA, SurfaceParams};
use chiaro_shading::rng::Pcg32;
use chiaro_shading::sampling::uniform_sphere;
use glam::Vec3;

/// One input: a material, two directions and the sampling numbers (mirrored by the kernel's
/// WGSL struct).
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable, Debug)]
pub struct BrdfInput {
    pub base_color: [f32; 3],
    pub metallic: f32,
    pub wo: [f32; 3],
    pub roughness: f32,
    pub wi: [f32; 3],
    pub f0_dielectric: f32,
    pub u: [f32; 2],
    pub u_lobe: f32,
    pub absorption: f32,
    pub specular_color: [f32; 3],
    pub specular: f32,
    pub clearcoat: f32,
    pub clearcoat_roughness: f32,
    pub transmission: f32,
    pub sheen_roughness: f32,
    pub sheen_color: [f32; 3],
    pub eta: f32,
    pub coat_normal: [f32; 3],
    pub pad: u32,
}

/// A unit direction with cosine `mu` to the normal and azimuth `phi`.
fn at_cosine(mu: f32, phi: f32) -> Vec3 {
    let s = (1.0 - mu * mu).max(0.0).sqrt();
    Vec3::new(s * phi.cos(), s * phi.sin(), mu)
}

/// A view or light direction: the whole sphere, the hemisphere, grazing, or the normal.
fn random_direction(rng: &mut Pcg32) -> Vec3 {
    let phi = rng.next_f32() * std::f32::consts::TAU;
    match rng.next_u32() % 8 {
        0..=2 => uniform_sphere(rng.next_vec2()),
        3 | 4 => {
            let d = uniform_sphere(rng.next_vec2());
            Vec3::new(d.x, d.y, d.z.abs())
        }
        5 | 6 => {
            let grazing = [0.0, 1e-7, -1e-7, 1e-6, 1e-5, 1e-4, 1e-3, 1e-2, -1e-2];
            at_cosine(grazing[(rng.next_u32() % 9) as usize], phi)
        }
        _ => Vec3::Z,
    }
}

/// Random material parameters, edge values drawn often (as chiaro_shading's own tests do).
fn random_params(rng: &mut Pcg32) -> SurfaceParams {
    let mut pick = |edges: &[f32]| {
        if rng.next_f32() < 0.3 {
            edges[(rng.next_u32() as usize) % edges.len()]
        } else {
            rng.next_f32()
        }
    };
    let roughness = pick(&[
        0.0,
        1.0,
        MIRROR_ALPHA.sqrt(),
        MIRROR_ALPHA.sqrt() * 1.001,
        MIRROR_ALPHA.sqrt() * 0.999,
        0.05,
        0.01,
    ]);
    let metallic = pick(&[0.0, 1.0]);
    let f0_dielectric = pick(&[0.0, 0.04, 1.0]);
    let absorption = pick(&[0.0, 1.0]);
    let specular = pick(&[0.0, 1.0]);
    let base_color = Vec3::new(pick(&[0.0, 1.0]), pick(&[0.0, 1.0]), pick(&[0.0, 1.0]));
    let specular_color = Vec3::new(pick(&[0.0, 1.0]), pick(&[1.0]), pick(&[0.0, 30.0]));
    // Half the materials have no coat.
    let clearcoat = pick(&[0.0, 1.0]) * f32::from(u8::from(pick(&[0.0, 1.0]) >= 0.5));
    let clearcoat_roughness = pick(&[0.0, 1.0, MIRROR_ALPHA.sqrt() * 1.001, 0.05]);
    // Half the materials transmit nothing; half have no sheen.
    let transmission = pick(&[0.0, 1.0]) * f32::from(u8::from(pick(&[0.0, 1.0]) >= 0.5));
    let sheen = f32::from(u8::from(pick(&[0.0, 1.0]) >= 0.5));
    let sheen_color = Vec3::new(pick(&[0.0, 1.0]), pick(&[1.0]), pick(&[0.0, 1.0])) * sheen;
    let sheen_roughness = pick(&[0.0, 1.0, 0.3]);
    // Half the materials are thin-walled; the others refract, entering a volume or leaving it.
    let eta = match rng.next_u32() % 6 {
        0..=2 => 0.0,
        3 => [1.5, 1.0 / 1.5, 1.0][(rng.next_u32() % 3) as usize],
        _ => 0.25 + 3.0 * rng.next_f32(),
    };
    SurfaceParams {
        base_color,
        metallic,
        roughness,
        f0_dielectric,
        specular,
        specular_color,
        clearcoat,
        clearcoat_roughness,
        transmission,
        sheen_color,
        sheen_roughness,
        absorption,
        eta,
        coat_normal: Vec3::Z,
    }
}

/// A coat normal: a quarter of the coats have one of their own, tilted up to 80 degrees, or a
/// zero vector (which counts as the shading normal). Drawn from a generator of its own, so
/// that the other fields' stream is the same with and without it.
fn random_coat_normal(rng: &mut Pcg32) -> Vec3 {
    match rng.next_u32() % 8 {
        0 => Vec3::ZERO,
        1 => {
            let d = uniform_sphere(rng.next_vec2());
            Vec3::new(d.x, d.y, d.z.abs().max(0.18))
        }
        _ => Vec3::Z,
    }
}

/// One input: the material, directions and sampling numbers from `rng`, the coat normal from
/// `coat_rng`.
pub fn random_input(rng: &mut Pcg32, coat_rng: &mut Pcg32) -> BrdfInput {
    let p = SurfaceParams {
        coat_normal: random_coat_normal(coat_rng),
        ..random_params(rng)
    };
    let wo = random_direction(rng);
    let wi = match rng.next_u32() % 6 {
        // The exact mirror reflection of the view, and a slight tilt of it.
        0 => Vec3::new(-wo.x, -wo.y, wo.z),
        1 => (Vec3::new(-wo.x, -wo.y, wo.z) + (uniform_sphere(rng.next_vec2()) * 1e-3)).normalize(),
        _ => random_direction(rng),
    };
    let mut uniform = |edges: &[f32]| {
        if rng.next_f32() < 0.1 {
            edges[(rng.next_u32() as usize) % edges.len()]
        } else {
            rng.next_f32()
        }
    };
    let edges = [0.0, 0.5, 0.999_999_94];
    let u = [uniform(&edges), uniform(&edges)];
    let u_lobe = uniform(&edges);
    BrdfInput {
        base_color: p.base_color.to_array(),
        metallic: p.metallic,
        wo: wo.to_array(),
        roughness: p.roughness,
        wi: wi.to_array(),
        f0_dielectric: p.f0_dielectric,
        u,
        u_lobe,
        absorption: p.absorption,
        specular_color: p.specular_color.to_array(),
        specular: p.specular,
        clearcoat: p.clearcoat,
        clearcoat_roughness: p.clearcoat_roughness,
        transmission: p.transmission,
        sheen_roughness: p.sheen_roughness,
        sheen_color: p.sheen_color.to_array(),
        eta: p.eta,
        coat_normal: p.coat_normal.to_array(),
        pad: 0,
    }
}

pub fn params(x: &BrdfInput) -> SurfaceParams {
    SurfaceParams {
        base_color: Vec3::from_array(x.base_color),
        metallic: x.metallic,
        roughness: x.roughness,
        f0_dielectric: x.f0_dielectric,
        specular: x.specular,
        specular_color: Vec3::from_array(x.specular_color),
        clearcoat: x.clearcoat,
        clearcoat_roughness: x.clearcoat_roughness,
        transmission: x.transmission,
        sheen_color: Vec3::from_array(x.sheen_color),
        sheen_roughness: x.sheen_roughness,
        absorption: x.absorption,
        eta: x.eta,
        coat_normal: Vec3::from_array(x.coat_normal),
    }
}
