// Composite: the frame's radiance from its parts, then the running mean over frames.
//
// Per pixel: where the camera sees no surface, the environment (which the direct pass wrote);
// where it sees one, its emission plus the light it reflects: the direct and indirect estimates
// as they are (modes direct, reference and naive, and realtime without the denoiser), or the
// denoiser's filtered lighting multiplied back by the demodulation albedo (realtime). The
// running mean of independent frames is a progressive Monte Carlo estimate; the realtime mode
// passes frames = 1, its history being the temporal pass's. Non-finite radiance never enters
// the sum (DESIGN.md: tested by exponent bits).

#import lib/generated.wgsl
#import lib/float.wgsl
#import lib/gbuffer_packing.wgsl
#import lib/demodulate.wgsl

// chiaro_gpu::passes::composite::CompositeParams.
struct CompositeParams {
    // Frames in the sum after this one (1 on the first: the sum restarts).
    frames: u32,
    // COMPOSITE_DIRECT, COMPOSITE_PATHS or COMPOSITE_FILTERED.
    source: u32,
    pad0: u32,
    pad1: u32,
}

@group(0) @binding(0) var direct_light: texture_2d<f32>;
@group(0) @binding(1) var indirect_light: texture_2d<f32>;
@group(0) @binding(2) var filtered_lighting: texture_2d<f32>;
@group(0) @binding(3) var gbuffer_position: texture_2d<u32>;
@group(0) @binding(4) var gbuffer_surface: texture_2d<u32>;
@group(0) @binding(5) var gbuffer_emission: texture_2d<u32>;
@group(0) @binding(6) var<storage, read_write> accumulation: array<vec4<f32>>;
@group(0) @binding(7) var<uniform> params: CompositeParams;
@group(0) @binding(8) var hdr_out: texture_storage_2d<rgba32float, write>;

// This frame's radiance at a pixel.
fn frame_radiance(pixel: vec2<i32>) -> vec3<f32> {
    let direct = textureLoad(direct_light, pixel, 0).xyz;
    var texels: GbufferTexels;
    texels.position = textureLoad(gbuffer_position, pixel, 0);
    texels.surface = textureLoad(gbuffer_surface, pixel, 0);
    texels.emission = textureLoad(gbuffer_emission, pixel, 0);
    if !gbuffer_covered(texels) {
        return direct;
    }
    let g = gbuffer_unpack(texels);
    if params.source == COMPOSITE_DIRECT {
        return g.emission + direct;
    }
    if params.source == COMPOSITE_PATHS || !g.shades {
        return g.emission + direct + textureLoad(indirect_light, pixel, 0).xyz;
    }
    let lighting = textureLoad(filtered_lighting, pixel, 0).xyz;
    return g.emission + lighting * demodulation_albedo(g.base_color);
}

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(hdr_out);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let index = id.y * size.x + id.x;
    var x = frame_radiance(vec2<i32>(id.xy));
    if !vec3_is_finite(x) {
        x = vec3<f32>(0.0);
    }
    var sum = vec4<f32>(x, 1.0);
    if params.frames > 1u {
        sum += accumulation[index];
    }
    accumulation[index] = sum;
    textureStore(hdr_out, vec2<i32>(id.xy), vec4<f32>(sum.xyz / f32(params.frames), 1.0));
}
