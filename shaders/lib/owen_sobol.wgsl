// Owen-scrambled Sobol draws: chiaro_shading::owen_sobol's draw1, draw2 and draw3 bit for bit
// (its module documentation has the construction and the references). A draw is keyed by the
// pixel's sequence key and its dimension number, and reads sample `index` of that dimension's
// own order.

// Burley's (2020) improved Laine-Karras permutation (owen_sobol::laine_karras).
fn owen_sobol_laine_karras(v_in: u32, seed: u32) -> u32 {
    var v = v_in;
    v ^= v * 0x3d20adeau;
    v += seed;
    v *= (seed >> 16u) | 1u;
    v ^= v * 0x05526c56u;
    v ^= v * 0x53a22864u;
    return v;
}

// The nested uniform scramble of the fraction whose bits reversed are `reversed`.
fn owen_sobol_scramble(reversed: u32, seed: u32) -> u32 {
    return reverseBits(owen_sobol_laine_karras(reversed, seed));
}

// The top 24 bits of a 32-bit fraction as a float in [0, 1), exactly.
fn owen_sobol_unit(x: u32) -> f32 {
    return f32(x >> 8u) * 0x1p-24f;
}

// owen_sobol::hash32 (Wellons's lowbias32).
fn owen_sobol_hash(x_in: u32) -> u32 {
    var x = x_in;
    x ^= x >> 16u;
    x *= 0x7feb352du;
    x ^= x >> 15u;
    x *= 0x846ca68bu;
    return x ^ (x >> 16u);
}

// The key of pixel `pixel`'s sequence under the seed (low, high).
fn owen_sobol_pixel_key(seed: vec2<u32>, pixel: u32) -> u32 {
    return owen_sobol_hash(owen_sobol_hash(owen_sobol_hash(seed.x) ^ seed.y) ^ pixel);
}

// The seeds of a draw: the sample order's, then the first, second and third coordinates'.
fn owen_sobol_seeds(key: u32, dimension: u32) -> vec4<u32> {
    let base = owen_sobol_hash(key ^ owen_sobol_hash(dimension));
    return vec4<u32>(owen_sobol_hash(base), owen_sobol_hash(base + 0x9e3779b9u),
        owen_sobol_hash(base + 0x3c6ef372u), owen_sobol_hash(base + 0xdaa66d2bu));
}

// The second Sobol dimension of point `index`, bits reversed: owen_sobol::sobol_second_reversed,
// a superset sum over the bits' positions (its columns are Pascal's triangle mod 2).
fn owen_sobol_second_reversed(index: u32) -> u32 {
    var x = index;
    x ^= (x >> 1u) & 0x55555555u;
    x ^= (x >> 2u) & 0x33333333u;
    x ^= (x >> 4u) & 0x0f0f0f0fu;
    x ^= (x >> 8u) & 0x00ff00ffu;
    x ^= (x >> 16u) & 0x0000ffffu;
    return x;
}

// The third Sobol dimension of point `index`, bits reversed: v_k = v_(k-1) ^ v_(k-2) ^
// (v_(k-2) >> 2) from 1/2 and 3/4.
fn owen_sobol_third_reversed(index: u32) -> u32 {
    var point = 0u;
    var older = 0x80000000u;
    var newer = 0xc0000000u;
    var bits = index;
    if (bits & 1u) != 0u {
        point = older;
    }
    bits >>= 1u;
    while bits != 0u {
        if (bits & 1u) != 0u {
            point ^= newer;
        }
        let next = newer ^ older ^ (older >> 2u);
        older = newer;
        newer = next;
        bits >>= 1u;
    }
    return reverseBits(point);
}

// Sample `index`'s place in a draw's order (a nested uniform scramble of the index).
fn owen_sobol_shuffled(index: u32, seed: u32) -> u32 {
    return reverseBits(owen_sobol_laine_karras(reverseBits(index), seed));
}

// One number: owen_sobol::draw1.
fn owen_sobol_draw1(key: u32, dimension: u32, index: u32) -> f32 {
    let s = owen_sobol_seeds(key, dimension);
    let n = owen_sobol_shuffled(index, s.x);
    return owen_sobol_unit(owen_sobol_scramble(n, s.y));
}

// Two numbers: owen_sobol::draw2.
fn owen_sobol_draw2(key: u32, dimension: u32, index: u32) -> vec2<f32> {
    let s = owen_sobol_seeds(key, dimension);
    let n = owen_sobol_shuffled(index, s.x);
    return vec2<f32>(owen_sobol_unit(owen_sobol_scramble(n, s.y)),
        owen_sobol_unit(owen_sobol_scramble(owen_sobol_second_reversed(n), s.z)));
}

// A choice in x and two numbers in yz: owen_sobol::draw3.
fn owen_sobol_draw3(key: u32, dimension: u32, index: u32) -> vec3<f32> {
    let s = owen_sobol_seeds(key, dimension);
    let n = owen_sobol_shuffled(index, s.x);
    return vec3<f32>(owen_sobol_unit(owen_sobol_scramble(owen_sobol_third_reversed(n), s.w)),
        owen_sobol_unit(owen_sobol_scramble(n, s.y)),
        owen_sobol_unit(owen_sobol_scramble(owen_sobol_second_reversed(n), s.z)));
}
