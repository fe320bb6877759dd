//! Owen-scrambled Sobol points: the parts the CPU reference's sampler and the GPU's share, and
//! the GPU's draws in full (`shaders/lib/owen_sobol.wgsl` mirrors [`draw1`], [`draw2`] and
//! [`draw3`] bit for bit).
//!
//! A draw reads the first one, two or three dimensions of the Sobol sequence (Sobol 1967; the
//! second from the primitive polynomial x + 1, the third from x^2 + x + 1 with initial numbers
//! 1, 3 as in Joe and Kuo 2008). The first two form a (0, 2)-sequence in base 2, the first three a
//! (1, 3)-sequence, so each draw alone is stratified over a pixel's samples. Each draw has its
//! own order of the points (a nested uniform scramble of the sample index) and its own Owen
//! scramble of the values, both the hash-based permutation of Burley (2020, "Practical
//! Hash-based Owen Scrambling", JCGT 9(4), after Laine and Karras 2011): the draws are not
//! correlated with each other and every point is uniform, so estimates stay unbiased (Owen
//! 1995). This is the layout of pbrt-v4's padded Sobol sampler (Pharr, Jakob and Humphreys,
//! "Physically Based Rendering", 4th ed., section 8.7).
//!
//! The GPU's draws are keyed by 32-bit words (WGSL has no 64-bit integers): a pixel's key
//! ([`pixel_key`]) and the draw's dimension number; [`draw_seeds`] hashes them into the four
//! permutation seeds.

use glam::Vec2;

/// Direction numbers of the Sobol sequence's second dimension: bit k of the index XORs column k
/// into the point. From the polynomial x + 1 (degree 1, initial number m_1 = 1), the recurrence
/// is v_k = v_(k-1) ^ (v_(k-1) >> 1), starting at one half.
pub const SECOND_DIMENSION: [u32; 32] = second_dimension_columns();

const fn second_dimension_columns() -> [u32; 32] {
    let mut columns = [0u32; 32];
    columns[0] = 1 << 31;
    let mut k = 1;
    while k < 32 {
        columns[k] = columns[k - 1] ^ (columns[k - 1] >> 1);
        k += 1;
    }
    columns
}

/// Direction numbers of the Sobol sequence's third dimension, from the polynomial x^2 + x + 1
/// (degree 2, a = 1, initial numbers m = 1, 3; Joe and Kuo 2008): v_k = v_(k-1) ^ v_(k-2) ^
/// (v_(k-2) >> 2).
pub const THIRD_DIMENSION: [u32; 32] = third_dimension_columns();

const fn third_dimension_columns() -> [u32; 32] {
    let mut columns = [0u32; 32];
    columns[0] = 1 << 31;
    columns[1] = 3 << 30;
    let mut k = 2;
    while k < 32 {
        columns[k] = columns[k - 1] ^ columns[k - 2] ^ (columns[k - 2] >> 2);
        k += 1;
    }
    columns
}

/// The third dimension's columns combined a byte of the index at a time, bits reversed: entry
/// [b][v] is the XOR of the columns of byte b's set bits in v, reversed (the form the scramble
/// reads).
type ByteTables = [[u32; 256]; 4];

const THIRD_DIMENSION_BYTES: ByteTables = byte_tables(&THIRD_DIMENSION);

const fn byte_tables(columns: &[u32; 32]) -> ByteTables {
    let mut table = [[0u32; 256]; 4];
    let mut byte = 0;
    while byte < 4 {
        let mut v = 0;
        while v < 256 {
            let mut point = 0;
            let mut k = 0;
            while k < 8 {
                if v & (1 << k) != 0 {
                    point ^= columns[8 * byte + k];
                }
                k += 1;
            }
            table[byte][v] = point.reverse_bits();
            v += 1;
        }
        byte += 1;
    }
    table
}

fn by_bytes(tables: &ByteTables, index: u32) -> u32 {
    let [b0, b1, b2, b3] = index.to_le_bytes();
    tables[0][b0 as usize]
        ^ tables[1][b1 as usize]
        ^ tables[2][b2 as usize]
        ^ tables[3][b3 as usize]
}

/// The second Sobol dimension of point `index` as a 32-bit fraction, bits reversed. Its
/// columns are the rows of Pascal's triangle mod 2, so bit j of the result is the XOR of the
/// index's bits k with binomial(k, j) odd, that is (Lucas) with j's set bits a subset of k's:
/// a superset sum over the five bits of a bit's position, one shift and mask each.
pub fn sobol_second_reversed(index: u32) -> u32 {
    let mut x = index;
    x ^= (x >> 1) & 0x5555_5555;
    x ^= (x >> 2) & 0x3333_3333;
    x ^= (x >> 4) & 0x0f0f_0f0f;
    x ^= (x >> 8) & 0x00ff_00ff;
    x ^= (x >> 16) & 0x0000_ffff;
    x
}

/// The third Sobol dimension of point `index` as a 32-bit fraction, bits reversed.
pub fn sobol_third_reversed(index: u32) -> u32 {
    by_bytes(&THIRD_DIMENSION_BYTES, index)
}

/// Burley's (2020) improved Laine-Karras permutation: a multiplication by an odd number, an
/// addition, and XORs with products by even numbers, each of which changes a bit only as the
/// bits below it say. Applied to a fraction's reversed bits, it is a nested uniform (Owen)
/// scramble drawn by `seed`: each bit flipped or not depending on the bits above it alone.
pub fn laine_karras(mut v: u32, seed: u32) -> u32 {
    v ^= v.wrapping_mul(0x3d20_adea);
    v = v.wrapping_add(seed);
    v = v.wrapping_mul((seed >> 16) | 1);
    v ^= v.wrapping_mul(0x0552_6c56);
    v ^= v.wrapping_mul(0x53a2_2864);
    v
}

/// The nested uniform scramble of the 32-bit fraction whose bits reversed are `reversed`.
pub fn scramble_reversed(reversed: u32, seed: u32) -> u32 {
    laine_karras(reversed, seed).reverse_bits()
}

/// A 32-bit fraction as a float in [0, 1): its top 24 bits, exactly.
pub fn to_unit(x: u32) -> f32 {
    (x >> 8) as f32 * (1.0 / 16_777_216.0)
}

/// A 32-bit mixing function (the constants of Wellons's "lowbias32", from his hash-prospector
/// search, 2018): every input bit changes about half the output bits.
pub fn hash32(mut x: u32) -> u32 {
    x ^= x >> 16;
    x = x.wrapping_mul(0x7feb_352d);
    x ^= x >> 15;
    x = x.wrapping_mul(0x846c_a68b);
    x ^ (x >> 16)
}

/// The key of pixel `pixel`'s sequence under the 64-bit seed (`seed_lo`, `seed_hi`).
pub fn pixel_key(seed_lo: u32, seed_hi: u32, pixel: u32) -> u32 {
    hash32(hash32(hash32(seed_lo) ^ seed_hi) ^ pixel)
}

/// The four permutation seeds of draw `dimension` of the sequence keyed `key`: the sample
/// order's, then the first, second and third coordinates'.
pub fn draw_seeds(key: u32, dimension: u32) -> [u32; 4] {
    let base = hash32(key ^ hash32(dimension));
    [0u32, 1, 2, 3].map(|i| hash32(base.wrapping_add(i.wrapping_mul(0x9e37_79b9))))
}

/// The index of sample `index` in the order of the draw whose order seed is `seed`.
fn shuffled_index(index: u32, seed: u32) -> u32 {
    laine_karras(index.reverse_bits(), seed).reverse_bits()
}

/// The draw `dimension` of sample `index` of the sequence keyed `key`, one number: the first
/// Sobol dimension (van der Corput), shuffled and scrambled.
pub fn draw1(key: u32, dimension: u32, index: u32) -> f32 {
    let s = draw_seeds(key, dimension);
    let n = shuffled_index(index, s[0]);
    to_unit(scramble_reversed(n, s[1]))
}

/// The draw `dimension` of sample `index` of the sequence keyed `key`, two numbers: the first
/// two Sobol dimensions, a (0, 2)-sequence.
pub fn draw2(key: u32, dimension: u32, index: u32) -> Vec2 {
    let s = draw_seeds(key, dimension);
    let n = shuffled_index(index, s[0]);
    Vec2::new(
        to_unit(scramble_reversed(n, s[1])),
        to_unit(scramble_reversed(sobol_second_reversed(n), s[2])),
    )
}

/// The draw `dimension` of sample `index` of the sequence keyed `key`, a choice and two numbers:
/// the choice is the third Sobol dimension, the pair the first two, so the pairs whose choice
/// falls in an interval of 2^-k are still stratified (the three are a (1, 3)-sequence).
pub fn draw3(key: u32, dimension: u32, index: u32) -> (f32, Vec2) {
    let s = draw_seeds(key, dimension);
    let n = shuffled_index(index, s[0]);
    (
        to_unit(scramble_reversed(sobol_third_reversed(n), s[3])),
        Vec2::new(
            to_unit(scramble_reversed(n, s[1])),
            to_unit(scramble_reversed(sobol_second_reversed(n), s[2])),
        ),
    )
}

/// Where a render's numbers come from.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Sampler {
    /// Independent uniform numbers, one PCG32 stream per pixel: plain Monte Carlo, whose error
    /// falls as 1/n.
    Independent,
    /// Owen-scrambled Sobol points, one to three dimensions per draw: randomised quasi-Monte
    /// Carlo, unbiased, each draw stratified over a pixel's samples.
    #[default]
    Sobol,
}

impl std::fmt::Display for Sampler {
    /// Its name on the command line.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Self::Independent => "independent",
            Self::Sobol => "sobol",
        })
    }
}

impl std::str::FromStr for Sampler {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "independent" => Ok(Self::Independent),
            "sobol" => Ok(Self::Sobol),
            other => Err(format!(
                "unknown sampler '{other}' (expected independent or sobol)"
            )),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_pixel_s_draws_are_nets_and_differ_between_dimensions() {
        // The first 2^m samples of one two-number draw put one point in each elementary box of
        // area 2^-m (the shuffle keeps blocks, the scramble keeps nets).
        let key = pixel_key(7, 0, 1234);
        for m in 1..=8u32 {
            let n = 1u32 << m;
            for a in 0..=m {
                let (na, nb) = (1u32 << a, 1u32 << (m - a));
                let mut count = vec![0u32; n as usize];
                for i in 0..n {
                    let p = draw2(key, 5, i);
                    count[((p.x * na as f32) as u32 * nb + (p.y * nb as f32) as u32) as usize] += 1;
                }
                assert!(count.iter().all(|&k| k == 1), "{n} points, {na}x{nb}");
            }
        }
        let (a, b): (Vec<f32>, Vec<f32>) = (0..64)
            .map(|i| (draw1(key, 0, i), draw1(key, 1, i)))
            .unzip();
        assert_ne!(a, b);
        assert_ne!(draw1(key, 0, 3), draw1(pixel_key(7, 0, 1235), 0, 3));
    }

    #[test]
    fn a_choice_draw_is_a_three_dimensional_net() {
        let key = pixel_key(1, 2, 3);
        for m in 1..=8u32 {
            let n = 1u32 << m;
            let points: Vec<(f32, Vec2)> = (0..n).map(|i| draw3(key, 9, i)).collect();
            for a in 0..m {
                for b in 0..m - a {
                    let c = m - 1 - a - b;
                    let (na, nb, nc) = (1u32 << a, 1u32 << b, 1u32 << c);
                    let mut count = vec![0u32; (na * nb * nc) as usize];
                    for (choice, p) in &points {
                        let cell = ((choice * na as f32) as u32 * nb + (p.x * nb as f32) as u32)
                            * nc
                            + (p.y * nc as f32) as u32;
                        count[cell as usize] += 1;
                    }
                    assert!(count.iter().all(|&k| k == 2), "{na}x{nb}x{nc}");
                }
            }
        }
    }

    #[test]
    fn the_fast_forms_combine_the_columns() {
        let mut rng = crate::rng::Pcg32::new(3, 4);
        type Fast = fn(u32) -> u32;
        let dimensions: [(&[u32; 32], Fast); 2] = [
            (&SECOND_DIMENSION, sobol_second_reversed),
            (&THIRD_DIMENSION, sobol_third_reversed),
        ];
        for (columns, fast) in dimensions {
            for _ in 0..1000 {
                let index = rng.next_u32();
                let by_bits = (0..32)
                    .filter(|k| index & (1 << k) != 0)
                    .fold(0u32, |point, k| point ^ columns[k]);
                assert_eq!(fast(index), by_bits.reverse_bits(), "index {index:#x}");
            }
        }
    }

    #[test]
    fn draws_of_one_sample_share_their_pair() {
        // draw2 and draw3 of one dimension read the same shuffled point.
        let key = pixel_key(3, 4, 5);
        for i in 0..100 {
            assert_eq!(draw2(key, 2, i), draw3(key, 2, i).1);
            assert_eq!(draw1(key, 2, i), draw2(key, 2, i).x);
        }
    }
}
