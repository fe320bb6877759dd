// Resampled indirect light, first pass (ReSTIR GI: Ouyang et al., "ReSTIR GI: Path Resampling
// for Real-Time Path Tracing", HPG 2021, section 4): each pixel traces one path as the
// indirect pass does (lib/path.wgsl; the first bounce along the direct pass's BRDF ray) and
// keeps it as a sample (lib/gi_sample.wgsl): the point y its first bounce reached, the light
// y reflects back along it (next-event estimation at y and what lies beyond, with its own
// throughput from y, so Russian roulette there weighs the path after y alone), and the
// sample's area-measure weight. restir_gi_spatial.wgsl resamples these and writes the
// indirect light.
//
// A path whose first direction is a delta lobe's (a mirror, smooth glass) has no density to
// reuse: it is kept as its own contribution. Test hook: with `poison` nonzero, the pixel at the
// image's centre and the one to its right write NaN and infinite samples (where the Cornell
// box's neighbours reuse them), which the spatial pass must not spread.

#import lib/generated.wgsl
#import lib/float.wgsl
#import lib/rng_source.wgsl
#import lib/camera.wgsl
#import lib/gbuffer_inputs.wgsl
#import lib/surface.wgsl
#import lib/color.wgsl
#import lib/first_bounce.wgsl
#import lib/path.wgsl
#import lib/gi_sample.wgsl
#import lib/lane_tiles.wgsl

// lib/next_event.wgsl's hook.
fn light_tree_sampling() -> bool {
    return params.light_sampling == LIGHT_SAMPLING_TREE;
}

@group(1) @binding(4) var<storage, read> params: IndirectParams;
@group(1) @binding(5) var points_out: texture_storage_2d<rgba32uint, write>;
@group(1) @binding(6) var radiance_out: texture_storage_2d<rgba32uint, write>;
@group(1) @binding(7) var first_bounce: texture_2d<u32>;

// The sample of one path from x0 whose first direction is `first`'s.
fn gi_path(x0: Shading, rng: ptr<function, Rng>, first: FirstBounce) -> GiSample {
    let step = brdf_scatter(x0, first.numbers);
    if !step.valid || !vec3_is_finite(step.weight) || all(step.weight == vec3<f32>(0.0)) {
        return gi_sample_none();
    }
    var hit: Hit;
    if first_bounce_traced(first.texel) {
        hit = first_bounce_decode(first.texel);
    } else {
        hit = trace_closest(leaving_ray(x0, step.wi), f32_infinity());
    }
    if hit.instance == BVH_NO_HIT || params.bounces == 0u {
        return gi_sample_none();
    }
    var transmittance = vec3<f32>(1.0);
    if FEATURE_VOLUMES {
        transmittance = medium_transmittance(x0.position, step.wi, hit);
    }
    let y = surface_at_hit(step.wi, hit);
    if !y.shades {
        return gi_sample_none();
    }
    var path = Path(y.shading, vec3<f32>(1.0), vec3<f32>(0.0), 1u);
    loop {
        if !path_step(&path, rng, false, first) {
            break;
        }
    }
    let radiance = path.total * transmittance;
    if !vec3_is_finite(radiance) {
        return gi_sample_none();
    }
    if step.delta {
        return gi_sample_own(clamp_luminance(step.weight * radiance, params.firefly_clamp));
    }
    let weight = gi_area_weight(x0.position, y.shading.position, y.shading.geometric_normal,
        step.pdf);
    return GiSample(y.shading.position, y.shading.geometric_normal, radiance, weight);
}

@compute @workgroup_size(8, 8)
fn main(@builtin(workgroup_id) workgroup: vec3<u32>, @builtin(local_invocation_index) local_index: u32) {
    let id = lane_tile_pixel(workgroup, local_index);
    let size = textureDimensions(points_out);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let pixel = vec2<i32>(id.xy);
    let texels = gbuffer_load(pixel);
    var sample = gi_sample_none();
    if gbuffer_covered(texels) {
        let g = gbuffer_unpack(texels);
        if g.shades {
            let x0 = gbuffer_shading(g, gbuffer_triangle_at(pixel), camera);
            let start = path_start(id.y * size.x + id.x, textureLoad(first_bounce, pixel, 0));
            var rng = start.rng;
            sample = gi_path(x0, &rng, start.first);
        }
    }
    let centre = size / 2u;
    if params.poison != 0u && id.y == centre.y && (id.x == centre.x || id.x == centre.x + 1u) {
        let poison = select(bitcast<f32>(0x7fc00000u), f32_infinity(), id.x != centre.x);
        sample = GiSample(vec3<f32>(poison), vec3<f32>(0.0, 0.0, 1.0), vec3<f32>(poison), poison);
    }
    textureStore(points_out, pixel, gi_sample_pack_point(sample));
    textureStore(radiance_out, pixel, gi_sample_pack_radiance(sample));
}
