// The inputs of a compute pass that shades the G-buffer (chiaro_gpu's GbufferShadingPass):
// group 1, bindings 0..3, the G-buffer's position, surface and emission targets and the
// camera. The pass declares binding 4 (its parameters) and binding 5 (its output) itself.

#import lib/camera.wgsl
#import lib/gbuffer_packing.wgsl

@group(1) @binding(0) var gbuffer_position: texture_2d<u32>;
@group(1) @binding(1) var gbuffer_surface: texture_2d<u32>;
@group(1) @binding(2) var gbuffer_emission: texture_2d<u32>;
@group(1) @binding(3) var<storage, read> camera: GpuCamera;

// The G-buffer's texels at a pixel.
fn gbuffer_load(pixel: vec2<i32>) -> GbufferTexels {
    var texels: GbufferTexels;
    texels.position = textureLoad(gbuffer_position, pixel, 0);
    texels.surface = textureLoad(gbuffer_surface, pixel, 0);
    texels.emission = textureLoad(gbuffer_emission, pixel, 0);
    return texels;
}
