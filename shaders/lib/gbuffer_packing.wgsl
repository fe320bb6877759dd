// The G-buffer's texel formats: how a surface is packed into the position (rgba32uint: world
// position and roughness as f32 bits; integer targets render on every backend, 32-bit float
// ones not on GL), surface (rgba32uint: normals, base colour, metallic) and emission
// (rgba32uint: emission as f32 bits, instance + 1 with the shading flag in bit 31 and the
// back-face flag in bit 30) targets
// and read back. Base colour and metallic are 16-bit unorm; normals are octahedral in
// 2 x 16-bit snorm (Cigolle et al., "A Survey of Efficient Representations for Independent
// Unit Vectors", JCGT 3(2), 2014).

struct GbufferSurface {
    position: vec3<f32>,
    geometric_normal: vec3<f32>,
    shading_normal: vec3<f32>,
    base_color: vec3<f32>,
    metallic: f32,
    roughness: f32,
    shades: bool,
    // The camera sees the triangle's back face (inside a volume's mesh, the medium).
    back_face: bool,
    emission: vec3<f32>,
    instance: u32,
}

struct GbufferTexels {
    position: vec4<u32>,
    surface: vec4<u32>,
    emission: vec4<u32>,
}

// Motion vectors (pixels to the previous frame's position) as two f16 in one u32 (x low): one
// format that every backend can render to and write from a compute pass (GL has no rg32uint
// storage images). f16 keeps 11 significant bits: 1/2048 pixel at half a pixel of motion,
// 1/32 at 64. The halves are converted by hand (round to nearest, below f16's least normal
// flushed to zero): WGSL's pack2x16float needs a capability GL ES may lack. A motion out of
// f16's range (or not finite) becomes MOTION_NONE, which unpacks to infinities: the readers
// take no history there.
const MOTION_NONE: u32 = 0x7c007c00u;

// The f16 bits of x, |x| < 65000.
fn motion_half(x: f32) -> u32 {
    let bits = bitcast<u32>(x);
    let sign = (bits >> 16u) & 0x8000u;
    let magnitude = bits & 0x7fffffffu;
    if magnitude < 0x38800000u {
        return sign;
    }
    // Exponent rebiased from 127 to 15, mantissa cut from 23 to 10 bits and rounded (a carry
    // into the exponent is still the right number).
    let half = ((magnitude >> 13u) - (112u << 10u)) + ((magnitude >> 12u) & 1u);
    return sign | half;
}

fn motion_from_half(h: u32) -> f32 {
    let sign = (h & 0x8000u) << 16u;
    let magnitude = h & 0x7fffu;
    if magnitude == 0u {
        return bitcast<f32>(sign);
    }
    if magnitude >= 0x7c00u {
        return bitcast<f32>(sign | 0x7f800000u);
    }
    return bitcast<f32>(sign | ((magnitude << 13u) + (112u << 23u)));
}

fn motion_pack(m: vec2<f32>) -> u32 {
    // |m| < 65000 on the bits (0x477de800 is 65000.0), so that a NaN fails too: llvmpipe's GL
    // compares a NaN as less.
    let magnitude = bitcast<vec2<u32>>(m) & vec2<u32>(0x7fffffffu);
    if max(magnitude.x, magnitude.y) >= 0x477de800u {
        return MOTION_NONE;
    }
    return motion_half(m.x) | (motion_half(m.y) << 16u);
}

fn motion_unpack(packed: u32) -> vec2<f32> {
    return vec2<f32>(motion_from_half(packed & 0xffffu), motion_from_half(packed >> 16u));
}

fn octahedral_wrap(v: vec2<f32>) -> vec2<f32> {
    return (1.0 - abs(v.yx)) * select(vec2<f32>(-1.0), vec2<f32>(1.0), v >= vec2<f32>(0.0));
}

fn octahedral_encode(n: vec3<f32>) -> u32 {
    let p = n.xy / (abs(n.x) + abs(n.y) + abs(n.z));
    let q = select(octahedral_wrap(p), p, n.z >= 0.0);
    return pack2x16snorm(q);
}

fn octahedral_decode(packed: u32) -> vec3<f32> {
    return octahedral_unfold(unpack2x16snorm(packed));
}

// The unit vector of octahedral coordinates f in [-1, 1]^2.
fn octahedral_unfold(f: vec2<f32>) -> vec3<f32> {
    var n = vec3<f32>(f, 1.0 - abs(f.x) - abs(f.y));
    let t = clamp(-n.z, 0.0, 1.0);
    n.x += select(t, -t, n.x >= 0.0);
    n.y += select(t, -t, n.y >= 0.0);
    return normalize(n);
}

fn gbuffer_pack(s: GbufferSurface) -> GbufferTexels {
    var t: GbufferTexels;
    t.position = bitcast<vec4<u32>>(vec4<f32>(s.position, s.roughness));
    t.surface = vec4<u32>(
        octahedral_encode(s.geometric_normal),
        octahedral_encode(s.shading_normal),
        pack2x16unorm(s.base_color.xy),
        pack2x16unorm(vec2<f32>(s.base_color.z, s.metallic)),
    );
    t.emission = vec4<u32>(bitcast<vec3<u32>>(s.emission),
        (s.instance + 1u) | select(0u, GBUFFER_SHADES, s.shades)
        | select(0u, GBUFFER_BACK_FACE, s.back_face));
    return t;
}

// Bit of the emission target's w set when the surface shades (not a single-sided back face).
const GBUFFER_SHADES: u32 = 0x80000000u;
// Bit of the emission target's w set when the camera sees the triangle's back face.
const GBUFFER_BACK_FACE: u32 = 0x40000000u;
// Both flag bits: the rest of w is the instance + 1.
const GBUFFER_FLAGS: u32 = 0xc0000000u;

// Whether anything was drawn at a texel.
fn gbuffer_covered(t: GbufferTexels) -> bool {
    return t.emission.w != 0u;
}

// The surface of a G-buffer texel (meaningless where gbuffer_covered is false).
fn gbuffer_unpack(t: GbufferTexels) -> GbufferSurface {
    var s: GbufferSurface;
    let position = bitcast<vec4<f32>>(t.position);
    s.position = position.xyz;
    s.roughness = position.w;
    s.geometric_normal = octahedral_decode(t.surface.x);
    s.shading_normal = octahedral_decode(t.surface.y);
    let bz = unpack2x16unorm(t.surface.w);
    s.base_color = vec3<f32>(unpack2x16unorm(t.surface.z), bz.x);
    s.metallic = bz.y;
    s.emission = bitcast<vec3<f32>>(t.emission.xyz);
    s.shades = (t.emission.w & GBUFFER_SHADES) != 0u;
    s.back_face = (t.emission.w & GBUFFER_BACK_FACE) != 0u;
    s.instance = (t.emission.w & ~GBUFFER_FLAGS) - 1u;
    return s;
}
