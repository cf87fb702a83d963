//! The first dimensions of the Sobol' sequence and hash-based Owen scrambling.
//!
//! Point `i` of Sobol' dimension `d` is the XOR of the columns `C_d[k]` of the dimension's
//! generator matrix for the set bits `k` of `i` (Sobol' 1967; Bratley & Fox 1988). The columns
//! follow from a primitive polynomial of degree `s` over GF(2), `x^s + a_1 x^(s-1) + ... +
//! a_(s-1) x + 1`, and `s` initial odd integers `m_1..m_s` by the recurrence (Joe & Kuo 2008,
//! eq. 2): `m_k = 2 a_1 m_(k-1) ^ 4 a_2 m_(k-2) ^ ... ^ 2^s m_(k-s) ^ m_(k-s)`, and
//! `C_d[k] = m_(k+1) 2^(31-k)` as a 32-bit fraction. The first four dimensions are
//! the van der Corput sequence and Joe & Kuo's dimensions 2 to 4 (the table `new-joe-kuo-6.21201`,
//! as pbrt-v4's `SobolMatrices32` tabulates them): dimensions 0 and 1 together are a
//! (0, 2)-sequence, so the first `2^k` points of a pixel are a (0, k, 2)-net, stratified in every
//! elementary interval of area `2^-k`; dimensions 2 and 3 a (1, 2)-sequence.
//!
//! Owen scrambling (Owen 1995) flips each digit of a point depending on the digits before it, a
//! random permutation at every node of the binary tree of intervals, which keeps the net's
//! stratification and makes each point uniform in [0, 1). It is applied with a hash
//! (Burley 2020, "Practical Hash-based Owen Scrambling", JCGT 9(4)): on the bit-reversed
//! value, where a multiply carries only towards higher bits, so that output bit `j` depends on
//! input bits `0..=j` only, which is what Owen scrambling of the reversed digits means. The hash
//! is Vegard's improved Laine-Karras permutation (psychopath.io, 2021), as Blender Cycles'
//! `reversed_bit_owen` uses.

/// Sobol' dimensions tabulated: two pairs, the film position and the lens.
pub const SOBOL_DIMENSIONS: usize = 4;

/// Degree `s`, polynomial coefficients `a` (bits a_1..a_(s-1), a_1 highest) and initial `m` of
/// dimensions 1 to 3 (dimension 0 is the identity matrix).
const POLYNOMIALS: [(usize, u32, [u32; 3]); SOBOL_DIMENSIONS - 1] =
    [(1, 0, [1, 0, 0]), (2, 1, [1, 3, 0]), (3, 1, [1, 3, 1])];

/// The generator matrices' columns, one row per dimension.
const MATRICES: [[u32; 32]; SOBOL_DIMENSIONS] = generator_matrices();

const fn generator_matrices() -> [[u32; 32]; SOBOL_DIMENSIONS] {
    let mut matrices = [[0u32; 32]; SOBOL_DIMENSIONS];
    let mut k = 0;
    while k < 32 {
        matrices[0][k] = 1 << (31 - k);
        k += 1;
    }
    let mut d = 1;
    while d < SOBOL_DIMENSIONS {
        let (s, a, initial) = POLYNOMIALS[d - 1];
        // m_1..m_32 (index k holds m_(k+1)); they fit in 32 bits: m_k < 2^k.
        let mut m = [0u64; 32];
        let mut k = 0;
        while k < 32 {
            m[k] = if k < s {
                initial[k] as u64
            } else {
                let mut v = m[k - s] ^ (m[k - s] << s);
                let mut j = 1;
                while j < s {
                    if (a >> (s - 1 - j)) & 1 == 1 {
                        v ^= m[k - j] << j;
                    }
                    j += 1;
                }
                v
            };
            matrices[d][k] = (m[k] << (31 - k)) as u32;
            k += 1;
        }
        d += 1;
    }
    matrices
}

/// Point `index` of Sobol' dimension `dimension` (below [`SOBOL_DIMENSIONS`]), as a 32-bit
/// fraction.
pub fn sobol(mut index: u32, dimension: usize) -> u32 {
    let mut value = 0;
    for column in &MATRICES[dimension] {
        if index == 0 {
            break;
        }
        if index & 1 == 1 {
            value ^= column;
        }
        index >>= 1;
    }
    value
}

/// The index and the second dimension's point, both from a bit-reversed index, a byte of it at
/// a time: `TABLES[p][b]` holds in its high word the bits `31 - (8 p + t)` and in its low word
/// the XOR of the reversed columns `C_1[31 - (8 p + t)]`, for the set bits `t` of `b` (bit
/// `8 p + t` of the reversed index is bit `31 - 8 p - t` of the index). Both are linear over
/// GF(2) in the reversed index, so one lookup per byte gives the index's reversal and the
/// matrix product together. 8 KiB.
const INDEX_AND_SECOND_DIMENSION_REVERSED: [[u64; 256]; 4] = index_and_second_dimension_tables();

const fn index_and_second_dimension_tables() -> [[u64; 256]; 4] {
    let mut tables = [[0u64; 256]; 4];
    let mut p = 0;
    while p < 4 {
        let mut b = 0;
        while b < 256 {
            let mut value = 0u64;
            let mut t = 0;
            while t < 8 {
                if (b >> t) & 1 == 1 {
                    let bit = 31 - (8 * p + t);
                    value ^= (1u64 << (32 + bit)) | MATRICES[1][bit].reverse_bits() as u64;
                }
                t += 1;
            }
            tables[p][b] = value;
            b += 1;
        }
        p += 1;
    }
    tables
}

/// From a bit-reversed index, the index and its point of Sobol' dimension 1 bit-reversed: the
/// forms the padded sampler scrambles (four table lookups rather than a bit reversal and a loop
/// over 32 columns).
#[inline(always)]
pub fn index_and_second_dimension_reversed(index_reversed: u32) -> (u32, u32) {
    let [b0, b1, b2, b3] = index_reversed.to_le_bytes();
    let t = &INDEX_AND_SECOND_DIMENSION_REVERSED;
    let both = t[0][b0 as usize] ^ t[1][b1 as usize] ^ t[2][b2 as usize] ^ t[3][b3 as usize];
    ((both >> 32) as u32, both as u32)
}

/// The second dimension's point of `index`, bit-reversed, by shifts and XORs (for lanes, where
/// the byte tables would take gathers). Its generator matrix is Pascal's triangle mod 2
/// (`m_k = m_(k-1) ^ 2 m_(k-1)`): index bit `q` sets bit `q - j` of the reversed point for
/// each `j` with C(q, j) odd, which by Lucas' theorem are the `j` whose bits are a subset of
/// `q`'s, so that `q - j = q ^ j` runs over those subsets too. Bit `p` of the reversed point is
/// the XOR of the index's bits at the supersets of `p` (as five-bit positions): the
/// superset-sum transform over GF(2), one shift-and-XOR step per bit of the position.
#[inline(always)]
pub fn second_dimension_reversed(mut index: u32) -> u32 {
    index ^= (index >> 1) & 0x5555_5555;
    index ^= (index >> 2) & 0x3333_3333;
    index ^= (index >> 4) & 0x0f0f_0f0f;
    index ^= (index >> 8) & 0x00ff_00ff;
    index ^ (index >> 16) & 0x0000_ffff
}

/// Owen scrambling of a bit-reversed 32-bit fraction: a permutation of [0, 2^32) in which bit `j`
/// of the result depends only on bits `0..=j` of `reversed` and on `seed`.
pub fn owen_scramble_reversed(mut reversed: u32, seed: u32) -> u32 {
    reversed ^= reversed.wrapping_mul(0x3d20_adea);
    reversed = reversed.wrapping_add(seed);
    reversed = reversed.wrapping_mul((seed >> 16) | 1);
    reversed ^= reversed.wrapping_mul(0x0552_6c56);
    reversed ^ reversed.wrapping_mul(0x53a2_2864)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The first columns as pbrt-v4's `SobolMatrices32` lists them (dimensions 1 to 3).
    #[test]
    fn generator_matrices_match_the_published_columns() {
        assert_eq!(
            MATRICES[1][..4],
            [0x8000_0000, 0xc000_0000, 0xa000_0000, 0xf000_0000]
        );
        assert_eq!(
            MATRICES[2][..6],
            [
                0x8000_0000,
                0xc000_0000,
                0x6000_0000,
                0x9000_0000,
                0xe800_0000,
                0x5c00_0000
            ]
        );
        assert_eq!(
            MATRICES[3][..6],
            [
                0x8000_0000,
                0xc000_0000,
                0x2000_0000,
                0x5000_0000,
                0xf800_0000,
                0x7400_0000
            ]
        );
    }

    /// The byte tables, and the shift-and-XOR form, give the index and the matrix product of the
    /// second dimension, for indices with every byte in use.
    #[test]
    fn index_and_second_dimension_tables_match_the_matrix() {
        for index in (0..5000u32).map(|i| i.wrapping_mul(0x9e37_79b9) ^ (i << 3)) {
            assert_eq!(
                index_and_second_dimension_reversed(index.reverse_bits()),
                (index, sobol(index, 1).reverse_bits()),
                "{index:#x}"
            );
            assert_eq!(
                second_dimension_reversed(index),
                sobol(index, 1).reverse_bits(),
                "{index:#x}"
            );
        }
    }

    /// Dimensions 0 and 1 are a (0, 2)-sequence: every block of 2^k points starting at a
    /// multiple of 2^k has one point in each elementary interval of area 2^-k.
    #[test]
    fn first_pair_is_a_zero_two_sequence() {
        for k in [2, 4, 6, 8] {
            let n = 1u32 << k;
            for block in 0..3 {
                for a in 0..=k {
                    let mut seen = vec![false; n as usize];
                    for i in block * n..(block + 1) * n {
                        let x = u64::from(sobol(i, 0)) >> (32 - a);
                        let y = u64::from(sobol(i, 1)) >> (32 - (k - a));
                        let cell = ((x << (k - a)) | y) as usize;
                        assert!(!seen[cell], "k {k} block {block} a {a}");
                        seen[cell] = true;
                    }
                }
            }
        }
    }

    /// Each bit of the scrambled value depends on the bits below it only, so the scramble maps
    /// every aligned interval of 2^-j to one such interval: scrambled points keep their strata.
    #[test]
    fn owen_scramble_keeps_prefixes_together() {
        for seed in [0, 1, 0xdead_beef, 0x1234_5678] {
            for j in [1, 3, 8, 20] {
                let mask = (1u32 << j) - 1;
                for x in (0..2000u32).map(|i| i.wrapping_mul(0x9e37_79b9)) {
                    let other = x ^ (u32::MAX << j);
                    assert_eq!(
                        owen_scramble_reversed(x, seed) & mask,
                        owen_scramble_reversed(other, seed) & mask
                    );
                }
            }
        }
    }
}
