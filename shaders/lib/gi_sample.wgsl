// Samples of indirect light for resampling (ReSTIR GI: Ouyang et al., "ReSTIR GI: Path
// Resampling for Real-Time Path Tracing", HPG 2021): a pixel's path as the point y its first
// bounce reached, the normal there, the light L that y reflects back along the path (its own
// emission excluded: the direct pass counts it) and the contribution weight W of the sample.
//
// Measure: samples are weighed over surface area at y, the one domain every pixel shares, so a
// sample reused by another pixel needs no Jacobian of its own: a pixel's BRDF sample of
// solid-angle pdf p has area pdf p cos_y / d^2 (cos_y between y's normal and the segment, d its
// length), and its W is the inverse, d^2 / (p cos_y). The target at a shading point x is the
// luminance of gi_value: f(x) cos_x L cos_y / d^2, the integrand over area without visibility.
//
// Reuse assumes y reflects the same L toward every pixel that reuses it (a diffuse y), as
// Ouyang et al. do: exact for the pixel's own sample, biased at glossy points for others.
//
// A pixel's reservoir (GiReservoir) is the sample it kept, the count M of candidates the sample
// stands for (1 for the pixel's own path, more after temporal reuse) and the surface of the
// pixel that kept it (lib/reservoir.wgsl's view depth and normal, for the next frame's
// similarity test). It takes three rgba32uint texels, side by side in a texture three times
// the image's width: (y, W as f32 bits), (L as f32 bits, y's octahedral normal) and (the
// surface's depth, its normal, M, 0). W < 0 marks a sample that cannot be reused (a delta
// lobe at x: its pdf is not a density); its second texel's L is then the path's whole
// contribution. W = 0 with L = 0 is a path that found nothing to reuse (it ended or missed at
// the first bounce): it counts.

#import lib/float.wgsl
#import lib/frame.wgsl
#import lib/brdf.wgsl
#import lib/gbuffer_packing.wgsl
#import lib/color.wgsl
#import lib/surface.wgsl

// A sample's contribution weight that marks it not reusable.
const GI_NOT_REUSABLE: f32 = -1.0;

struct GiSample {
    point: vec3<f32>,
    normal: vec3<f32>,
    radiance: vec3<f32>,
    weight: f32,
}

// Texels a reservoir takes, side by side.
const GI_RESERVOIR_TEXELS: i32 = 3;

struct GiReservoir {
    sample: GiSample,
    // M: how many candidates the sample was drawn from.
    count: u32,
    // The kept-by pixel's surface (reservoir_surface_pack).
    surface: vec4<u32>,
}

// Texel k of the reservoir of `pixel`.
fn gi_reservoir_texel(pixel: vec2<i32>, k: i32) -> vec2<i32> {
    return vec2<i32>(GI_RESERVOIR_TEXELS * pixel.x + k, pixel.y);
}

// A packed reservoir's third texel: its surface with its count.
fn gi_reservoir_pack_count(r: GiReservoir) -> vec4<u32> {
    return vec4<u32>(r.surface.xy, r.count, 0u);
}

// A packed reservoir; one whose sample is not finite (gi_sample_unpack) stands for no
// candidate: count 0.
fn gi_reservoir_unpack(point: vec4<u32>, radiance: vec4<u32>, count: vec4<u32>) -> GiReservoir {
    let sample = gi_sample_unpack(point, radiance);
    let broken = any(gi_sample_pack_point(sample) != point)
        || any(gi_sample_pack_radiance(sample).xyz != radiance.xyz);
    return GiReservoir(sample, select(count.z, 0u, broken), vec4<u32>(count.xy, 0u, 0u));
}

// Resampling of reservoirs at one shading point (Ouyang et al., algorithms 3 and 4): each
// enters by its sample's target here times its W times its M, and the survivor's W is the sum
// of those weights over the summed counts and its target (1/M).
struct GiResampling {
    kept: GiSample,
    kept_target: f32,
    weight_sum: f32,
    count: u32,
}

// The resampling that starts from the pixel's own reservoir: its sample of target `here`
// at the shading point, standing for `count` candidates.
fn gi_resampling_start(own: GiSample, here: f32, count: u32) -> GiResampling {
    return GiResampling(own, here, here * own.weight * f32(count), count);
}

// Adds a reservoir's sample of target `here` at the shading point, standing for `count`
// candidates, kept with the number `rand`; true if it is kept. A weight that is not positive
// and finite adds its count only.
fn gi_resampling_add(r: ptr<function, GiResampling>, sample: GiSample, here: f32, count: u32, rand: f32) -> bool {
    (*r).count += count;
    return gi_resampling_add_weighted(r, sample, here, f32(count), rand);
}

// Adds a sample of target `here` at the shading point with the MIS weight (or count) `m`,
// kept with the number `rand`; true if it is kept. The count is left to the caller.
fn gi_resampling_add_weighted(r: ptr<function, GiResampling>, sample: GiSample, here: f32, m: f32, rand: f32) -> bool {
    let weight = here * sample.weight * m;
    if !(weight > 0.0) || !f32_is_finite(weight) {
        return false;
    }
    (*r).weight_sum += weight;
    if rand * (*r).weight_sum < weight {
        (*r).kept = sample;
        (*r).kept_target = here;
        return true;
    }
    return false;
}

// The survivor's contribution weight W; 0 where it has no target or nothing was weighed.
fn gi_resampling_weight(r: GiResampling) -> f32 {
    let w = r.weight_sum / (f32(r.count) * r.kept_target);
    return select(0.0, w, r.kept_target > 0.0 && r.weight_sum > 0.0 && f32_is_finite(w));
}

// A path that reached no point to reuse: counts as a candidate of weight 0.
fn gi_sample_none() -> GiSample {
    return GiSample(vec3<f32>(0.0), vec3<f32>(0.0, 0.0, 1.0), vec3<f32>(0.0), 0.0);
}

// A path whose contribution `c` is shaded as is and never reused.
fn gi_sample_own(c: vec3<f32>) -> GiSample {
    return GiSample(vec3<f32>(0.0), vec3<f32>(0.0, 0.0, 1.0), c, GI_NOT_REUSABLE);
}

fn gi_sample_reusable(s: GiSample) -> bool {
    return s.weight >= 0.0;
}

fn gi_sample_pack_point(s: GiSample) -> vec4<u32> {
    return vec4<u32>(bitcast<vec3<u32>>(s.point), bitcast<u32>(s.weight));
}

fn gi_sample_pack_radiance(s: GiSample) -> vec4<u32> {
    return vec4<u32>(bitcast<vec3<u32>>(s.radiance), octahedral_encode(s.normal));
}

// A packed sample; anything not finite (a NaN written by a broken path or a test) becomes a
// sample of weight 0.
fn gi_sample_unpack(point: vec4<u32>, radiance: vec4<u32>) -> GiSample {
    var s = GiSample(bitcast<vec3<f32>>(point.xyz), octahedral_decode(radiance.w),
        bitcast<vec3<f32>>(radiance.xyz), bitcast<f32>(point.w));
    if !vec3_is_finite(s.point) || !vec3_is_finite(s.radiance) || !f32_is_finite(s.weight)
        || any(s.radiance < vec3<f32>(0.0)) {
        return gi_sample_none();
    }
    return s;
}

// The sample's area-measure weight for a path from x whose first bounce, drawn with
// solid-angle pdf `pdf`, reached y with geometric normal n_y: d^2 / (pdf cos_y); 0 where the
// segment grazes y or the pdf is not positive.
fn gi_area_weight(x: vec3<f32>, y: vec3<f32>, n_y: vec3<f32>, pdf: f32) -> f32 {
    let to_x = x - y;
    let d2 = dot(to_x, to_x);
    let cos_y = abs(dot(n_y, to_x)) * inverseSqrt(max(d2, 1e-30));
    let w = d2 / (pdf * cos_y);
    return select(0.0, w, pdf > 0.0 && cos_y > 0.0 && f32_is_finite(w));
}

// cos_y / d^2 of the segment from x to the sample's point: the area-to-solid-angle factor.
fn gi_geometry(x: vec3<f32>, sample: GiSample) -> f32 {
    let to_x = x - sample.point;
    let d2 = dot(to_x, to_x);
    let g = abs(dot(sample.normal, to_x)) * inverseSqrt(max(d2, 1e-30)) / d2;
    return select(0.0, g, f32_is_finite(g) && d2 > 0.0);
}

// f cos_x L cos_y / d^2 at the shading point s of the sample's light, before visibility: 0
// where the direction leaves on the wrong side of s.
fn gi_value(s: Shading, sample: GiSample) -> vec3<f32> {
    let wi = safe_normalize(sample.point - s.position, vec3<f32>(0.0, 0.0, 1.0));
    let local = frame_to_local(s.frame, wi);
    if !on_its_side(s, wi, local.z) {
        return vec3<f32>(0.0);
    }
    let v = brdf_eval(s.params, s.wo, local) * abs(local.z) * sample.radiance
        * gi_geometry(s.position, sample);
    return select(vec3<f32>(0.0), v, vec3_is_finite(v));
}
