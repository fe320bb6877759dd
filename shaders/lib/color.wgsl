// Colour: Rec. 709 luminance and the sRGB transfer functions (IEC 61966-2-1:1999). Mirrors
// chiaro_shading::color.

#import lib/generated.wgsl

// Luminance of a linear Rec. 709 RGB colour.
fn luminance(rgb: vec3<f32>) -> f32 {
    return dot(rgb, vec3<f32>(LUMINANCE_R, LUMINANCE_G, LUMINANCE_B));
}

// The colour scaled down to a luminance of `most` when above it (its hue kept); `most` = 0:
// as it is. The realtime mode's firefly clamp.
fn clamp_luminance(rgb: vec3<f32>, most: f32) -> vec3<f32> {
    let y = luminance(rgb);
    if most > 0.0 && y > most {
        return rgb * (most / y);
    }
    return rgb;
}

// Decodes one sRGB-encoded channel in [0, 1] to linear.
fn srgb_to_linear(encoded: f32) -> f32 {
    if encoded <= 0.04045 {
        return encoded / 12.92;
    }
    return pow((encoded + 0.055) / 1.055, 2.4);
}

// Encodes one linear channel to sRGB; the input is clamped to [0, 1].
fn linear_to_srgb(linear: f32) -> f32 {
    let x = clamp(linear, 0.0, 1.0);
    if x <= 0.0031308 {
        return x * 12.92;
    }
    return 1.055 * pow(x, 1.0 / 2.4) - 0.055;
}
