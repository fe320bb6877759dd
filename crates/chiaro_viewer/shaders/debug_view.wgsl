// The viewer's debug views of the frame: the G-buffer's base colour, shading normal, distance
// and instance id, the motion vectors, this frame's direct and raw (unfiltered) indirect light,
// the denoiser's filtered (demodulated) lighting, the luminance variance of its moments history
// and its history length, written as 8-bit sRGB for display (the history length as a linear
// grey, length / 32, so a test can read it back). Normals are decoded by the G-buffer's own packing
// (octahedral: Cigolle et al., "A Survey of Efficient Representations for Independent Unit
// Vectors", JCGT 3(2), 2014); light is shown through Reinhard's x / (1 + x) (Reinhard et al.,
// "Photographic Tone Reproduction for Digital Images", SIGGRAPH 2002).

#import lib/gbuffer_packing.wgsl

// Which view (DebugView's index), and its scales.
struct DebugParams {
    view: u32,
    // Distance shown as mid grey.
    depth_scale: f32,
    // Pixels of motion shown at full saturation.
    motion_scale: f32,
    pad: f32,
    // Camera position (xyz).
    eye: vec4<f32>,
}

@group(0) @binding(0) var position_target: texture_2d<u32>;
@group(0) @binding(1) var surface_target: texture_2d<u32>;
@group(0) @binding(2) var emission_target: texture_2d<u32>;
@group(0) @binding(3) var motion_target: texture_2d<u32>;
@group(0) @binding(4) var direct_target: texture_2d<f32>;
@group(0) @binding(5) var indirect_target: texture_2d<f32>;
@group(0) @binding(6) var output: texture_storage_2d<rgba8unorm, write>;
@group(0) @binding(7) var<storage, read> params: DebugParams;
@group(0) @binding(8) var filtered_target: texture_2d<f32>;
// Mean luminance, mean squared luminance, history length in frames, 0.
@group(0) @binding(9) var moments_target: texture_2d<f32>;

// Longest history the history view tells apart (shown as white).
const HISTORY_WHITE: f32 = 32.0;

fn srgb_encode(linear: vec3<f32>) -> vec3<f32> {
    let c = clamp(linear, vec3<f32>(0.0), vec3<f32>(1.0));
    let curve = 1.055 * pow(c, vec3<f32>(1.0 / 2.4)) - 0.055;
    return select(curve, 12.92 * c, c <= vec3<f32>(0.0031308));
}

fn reinhard(radiance: vec3<f32>) -> vec3<f32> {
    let r = max(radiance, vec3<f32>(0.0));
    return r / (vec3<f32>(1.0) + r);
}

// A distinct colour per instance (a PCG-style hash of the id to three bytes).
fn instance_colour(id: u32) -> vec3<f32> {
    var h = id * 747796405u + 2891336453u;
    h = ((h >> ((h >> 28u) + 4u)) ^ h) * 277803737u;
    h = (h >> 22u) ^ h;
    return vec3<f32>(f32(h & 255u), f32((h >> 8u) & 255u), f32((h >> 16u) & 255u)) / 255.0;
}

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(output);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let p = vec2<i32>(id.xy);
    var texels: GbufferTexels;
    texels.position = textureLoad(position_target, p, 0);
    texels.surface = textureLoad(surface_target, p, 0);
    texels.emission = textureLoad(emission_target, p, 0);
    let covered = gbuffer_covered(texels);
    let s = gbuffer_unpack(texels);
    var colour = vec3<f32>(0.0);
    switch params.view {
        case 1u: {
            if covered {
                colour = srgb_encode(s.base_color);
            }
        }
        case 2u: {
            if covered {
                colour = 0.5 + 0.5 * s.shading_normal;
            }
        }
        case 3u: {
            if covered {
                let d = distance(s.position, params.eye.xyz);
                colour = vec3<f32>(params.depth_scale / (params.depth_scale + d));
            }
        }
        case 4u: {
            let m = motion_unpack(textureLoad(motion_target, p, 0).x);
            let shown = clamp(0.5 + 0.5 * m / params.motion_scale, vec2<f32>(0.0), vec2<f32>(1.0));
            colour = vec3<f32>(shown, 0.5);
        }
        case 5u: {
            colour = srgb_encode(reinhard(textureLoad(direct_target, p, 0).rgb));
        }
        case 6u: {
            colour = srgb_encode(reinhard(textureLoad(indirect_target, p, 0).rgb));
        }
        case 7u: {
            if covered {
                colour = instance_colour(s.instance);
            }
        }
        case 8u: {
            colour = srgb_encode(reinhard(textureLoad(filtered_target, p, 0).rgb));
        }
        case 9u: {
            // Standard deviation relative to the mean luminance.
            let m = textureLoad(moments_target, p, 0);
            let deviation = sqrt(max(m.y - m.x * m.x, 0.0));
            colour = vec3<f32>(srgb_encode(vec3<f32>(deviation / (m.x + 0.01))).x);
        }
        case 10u: {
            let length = textureLoad(moments_target, p, 0).z;
            colour = vec3<f32>(min(length, HISTORY_WHITE) / HISTORY_WHITE);
        }
        default: {}
    }
    textureStore(output, p, vec4<f32>(colour, 1.0));
}
