// Indirect light per pixel of the G-buffer (placeholder until the path tracer lands: zero,
// and the non-finite test hook).

#import lib/generated.wgsl
#import lib/camera.wgsl

// chiaro_gpu::passes::indirect::IndirectParams.
struct IndirectParams {
    frame: u32,
    seed_lo: u32,
    seed_hi: u32,
    spp: u32,
    bounces: u32,
    naive: u32,
    poison: u32,
    pad: u32,
}

@group(1) @binding(0) var gbuffer_position: texture_2d<u32>;
@group(1) @binding(1) var gbuffer_surface: texture_2d<u32>;
@group(1) @binding(2) var gbuffer_emission: texture_2d<u32>;
@group(1) @binding(3) var<uniform> camera: GpuCamera;
@group(1) @binding(4) var<uniform> params: IndirectParams;
@group(1) @binding(5) var indirect_out: texture_storage_2d<rgba32float, write>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(indirect_out);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    textureStore(indirect_out, vec2<i32>(id.xy), vec4<f32>(0.0, 0.0, 0.0, 1.0));
}
