// The inputs of a compute pass that shades the G-buffer (chiaro_gpu's GbufferShadingPass):
// group 1, bindings 0..3, the G-buffer's position, surface and emission targets and the
// camera, and binding 15, its triangle target (a read-only storage texture: the indirect pass
// uses all 16 sampled textures of WebGPU's downlevel limits). The pass declares binding 4 (its
// parameters) and its images from binding 5 on itself.

#import lib/camera.wgsl
#import lib/gbuffer_packing.wgsl

@group(1) @binding(0) var gbuffer_position: texture_2d<u32>;
@group(1) @binding(1) var gbuffer_surface: texture_2d<u32>;
@group(1) @binding(2) var gbuffer_emission: texture_2d<u32>;
@group(1) @binding(3) var<storage, read> camera: GpuCamera;
@group(1) @binding(15) var gbuffer_triangle: texture_storage_2d<r32uint, read>;

// The G-buffer's texels at a pixel.
fn gbuffer_load(pixel: vec2<i32>) -> GbufferTexels {
    var texels: GbufferTexels;
    texels.position = textureLoad(gbuffer_position, pixel, 0);
    texels.surface = textureLoad(gbuffer_surface, pixel, 0);
    texels.emission = textureLoad(gbuffer_emission, pixel, 0);
    return texels;
}

// The number, in its mesh, of the triangle seen at a pixel.
fn gbuffer_triangle_at(pixel: vec2<i32>) -> u32 {
    return textureLoad(gbuffer_triangle, pixel).x;
}
