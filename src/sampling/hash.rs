//! Integer hashing used to derive seeds and patterns from (seed, pixel, sample, dimension).

/// The golden-ratio increment of SplitMix64 (Steele, Lea & Flood 2014).
const GOLDEN_GAMMA: u64 = 0x9e37_79b9_7f4a_7c15;

/// SplitMix64's output function: a bijective 64-bit mix with full avalanche.
pub fn mix64(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// Hashes a sequence of words by chaining SplitMix64 steps: h <- mix64(h + w + gamma).
/// Every step is a bijection of h for a fixed word, so inputs differing in one word collide only
/// by chance (probability ~2^-64).
pub fn hash_words(words: &[u64]) -> u64 {
    words.iter().fold(GOLDEN_GAMMA, |h, &w| hash_extend(h, w))
}

/// One step of [`hash_words`]' chain: `hash_extend(hash_words(a), w) == hash_words(a ++ [w])`,
/// so a hash over words that share a prefix can start from the prefix's hash.
pub fn hash_extend(h: u64, word: u64) -> u64 {
    mix64(extend_unmixed(h, word))
}

/// [`hash_extend`]'s step before its mix: `hash_extend(h, word) == mix64(extend_unmixed(h,
/// word))`. The step only adds before it mixes, so a word that is a sum of parts can have some
/// of them added ahead, once for many words: `mix64(extend_unmixed(h, a).wrapping_add(b)) ==
/// hash_extend(h, a.wrapping_add(b))`; and it adds to `h` a term of the word alone,
/// `extend_unmixed(0, word)`, which subtracting undoes.
#[inline(always)]
pub fn extend_unmixed(h: u64, word: u64) -> u64 {
    h.wrapping_add(word).wrapping_add(GOLDEN_GAMMA)
}

/// Folds a 64-bit hash to 32 bits (for Kensler's 32-bit pattern seeds).
pub fn fold32(h: u64) -> u32 {
    (h ^ (h >> 32)) as u32
}

/// The top 24 bits of a 32-bit word as a float in [0, 1).
pub fn unit_f32(bits: u32) -> f32 {
    (bits >> 8) as f32 * (1.0 / (1u32 << 24) as f32)
}
