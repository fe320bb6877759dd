// Demodulation: the lighting the denoiser filters is the reflected radiance divided by the
// surface's albedo, so that texture and colour detail are not blurred with the noise (Schied
// et al., "Spatiotemporal Variance-Guided Filtering", HPG 2017, section 4); the composite
// multiplies the filtered lighting back by the same albedo, so without filtering the round
// trip is exact. The albedo is the base colour with a floor, so a black surface's (specular)
// light stays finite.

const DEMODULATION_FLOOR: f32 = 0.02;

// The albedo that lighting at a surface of this base colour is divided by.
fn demodulation_albedo(base_color: vec3<f32>) -> vec3<f32> {
    return max(base_color, vec3<f32>(DEMODULATION_FLOOR));
}
