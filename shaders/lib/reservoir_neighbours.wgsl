// The neighbours spatial reuse draws (restir_spatial.wgsl, restir_gi_spatial.wgsl): a pixel in
// a disc around the shading pixel whose surface is similar to its own (lib/reservoir.wgsl's
// test: view depth within 10%, normals within 25 degrees).

#import lib/camera.wgsl
#import lib/gbuffer_packing.wgsl
#import lib/gbuffer_inputs.wgsl
#import lib/sampling.wgsl
#import lib/reservoir.wgsl

// A neighbour drawn: its pixel and world position; found false where the draw fell outside
// the image, on the pixel itself or on a surface not similar.
struct ReservoirNeighbour {
    pixel: vec2<i32>,
    position: vec3<f32>,
    found: bool,
}

// The neighbour of `pixel` (its surface: view depth `depth`, shading normal `normal`) at the
// disc point of `u` in a disc of `radius` pixels, in an image of `size`.
fn reservoir_neighbour(pixel: vec2<i32>, size: vec2<u32>, u: vec2<f32>, radius: f32, depth: f32, normal: vec3<f32>) -> ReservoirNeighbour {
    var out: ReservoirNeighbour;
    out.pixel = pixel + vec2<i32>(round(concentric_disk(u) * radius));
    out.found = false;
    let q = out.pixel;
    if all(q == pixel) || any(q < vec2<i32>(0)) || any(q >= vec2<i32>(size)) {
        return out;
    }
    let texels = gbuffer_load(q);
    let n = gbuffer_unpack(texels);
    out.position = n.position;
    out.found = gbuffer_covered(texels) && n.shades
        && reservoir_surfaces_similar(reservoir_depth(camera, n.position), n.shading_normal, depth,
            normal);
    return out;
}
