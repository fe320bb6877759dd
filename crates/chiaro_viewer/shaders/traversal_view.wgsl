// The viewer's traversal heatmap: per pixel, the BVH traversal steps (TLAS nodes whose children
// are tested, BLAS nodes visited, triangles tested: lib/bvh.wgsl's bvh_steps) of the closest-hit
// query along the camera ray through the frame's jittered sample of that pixel, shown through
// the viridis colour map (van der Walt and Smith, matplotlib 1.5, 2015: lightness rises
// monotonically from dark blue to yellow) from 0 steps to params.max_steps (and above). The
// map's stops arrive in the parameters as 8-bit sRGB over 255 and are written as they are.

#import lib/generated.wgsl
#import lib/bvh.wgsl
#import lib/alpha.wgsl
#import lib/camera.wgsl

// Stops of the colour map (chiaro_viewer::traversal_view::HEAT_STOPS).
const HEAT_STOP_COUNT: u32 = 10u;

struct TraversalParams {
    // Colour-map stops, evenly spaced from 0 to max_steps (rgb, w unused).
    stops: array<vec4<f32>, HEAT_STOP_COUNT>,
    // Steps shown as the last stop.
    max_steps: f32,
    pad0: f32,
    pad1: f32,
    pad2: f32,
}

@group(1) @binding(0) var<storage, read> camera: GpuCamera;
@group(1) @binding(1) var<storage, read> params: TraversalParams;
@group(1) @binding(2) var output: texture_storage_2d<rgba8unorm, write>;

// The colour map at t in [0, 1] (clamped): linear between the two nearest stops.
fn heat(t: f32) -> vec3<f32> {
    let x = clamp(t, 0.0, 1.0) * f32(HEAT_STOP_COUNT - 1u);
    let i = min(u32(x), HEAT_STOP_COUNT - 2u);
    return mix(params.stops[i].rgb, params.stops[i + 1u].rgb, x - f32(i));
}

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(output);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let primary = camera_ray(camera, vec2<f32>(id.xy) + camera.jitter);
    bvh_steps = 0u;
    _ = trace_closest(Ray(primary.origin, 0.0, primary.direction), f32_infinity());
    let colour = heat(f32(bvh_steps) / params.max_steps);
    textureStore(output, vec2<i32>(id.xy), vec4<f32>(colour, 1.0));
}
