// Composite: adds this frame's radiance to the running sum (a progressive Monte Carlo
// estimate: the mean of independent frames) and writes the mean as the linear HDR image.
// Non-finite radiance never enters the sum (DESIGN.md: tested by exponent bits).

#import lib/float.wgsl

// chiaro_gpu::passes::composite::CompositeParams.
struct CompositeParams {
    // Frames in the sum after this one (1 on the first: the sum restarts).
    frames: u32,
    pad0: u32,
    pad1: u32,
    pad2: u32,
}

@group(0) @binding(0) var frame_radiance: texture_2d<f32>;
@group(0) @binding(1) var<storage, read_write> accumulation: array<vec4<f32>>;
@group(0) @binding(2) var<uniform> params: CompositeParams;
@group(0) @binding(3) var hdr_out: texture_storage_2d<rgba32float, write>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(hdr_out);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let index = id.y * size.x + id.x;
    var x = textureLoad(frame_radiance, vec2<i32>(id.xy), 0).xyz;
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
