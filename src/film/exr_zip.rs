//! OpenEXR's ZIP compression of one block of scan lines, at a fast zlib level.
//!
//! The exr crate compresses ZIP blocks with miniz_oxide at level 4, which made writing an EXR a
//! large part of a short render. Here level 1 (flate2's `Compression::fast()`, miniz_oxide's
//! greedy fast path). Level 4 -> 1, in one thread's CPU time for the blocks of foton's renders:
//! dof-sky at 1920x1080, 1 spp, 496-502 -> 98-111 ms, 14.7 -> 15.9 MB (+8 %); at 256x192, 4 spp,
//! 12.6 -> 2.2 ms, 373 -> 389 KB (+4 %); a Cornell box at 1920x1080, 393 -> 100 ms,
//! 13.77 -> 13.97 MB (+1.4 %). In `foton render` (wall time less the render's, EXR less PFM,
//! medians of 9, blocks compressed in parallel on 2 cores): 257 -> 41 ms at 1920x1080, 14 -> 4 ms
//! at 256x192 (771 -> 194 and 18 -> 5 ms with the cores shared by other work).
//! Not taken: miniz_oxide's levels 2 and 3 share level 4's slow path (as slow, as small);
//! zlib-rs level 1 (a static Huffman code) is larger (67.2 % of the raw bytes against 65.4 %) and
//! slower (148 ms), its level 2 nearly as small as level 4 (+0.8 %) but 266-277 ms; Huffman-only
//! and run-length strategies are larger (73-76 %) and no faster; fdeflate, fast, does not shrink
//! these bytes at all (its fixed code suits PNG's filtered bytes, near 0, not ZIP's, near 128).

use flate2::Compression;
use flate2::write::ZlibEncoder;
use std::io::Write;

/// Compresses one block's pixel bytes as OpenEXR's ZIP and ZIPS compressions do
/// (OpenEXR ImfZip.cpp, `Zip::compress`): the bytes at even indices then those at odd indices,
/// each byte then replaced by its difference to the one before plus 128 (mod 256), and the result
/// zlib-compressed. `raw_le` is the block as stored uncompressed: for each scan line, each
/// channel's samples in the header's channel order, little-endian. Where compression would not
/// shrink the block, the raw bytes are returned instead, as OpenEXR stores such a block (readers
/// tell the two apart by the length).
pub(crate) fn compress_block(raw_le: Vec<u8>) -> Vec<u8> {
    let predicted = predict(&raw_le);
    let mut encoder = ZlibEncoder::new(Vec::with_capacity(raw_le.len() / 2), Compression::fast());
    // Writing to a Vec cannot fail.
    let compressed = encoder
        .write_all(&predicted)
        .and_then(|()| encoder.finish())
        .unwrap_or_default();
    if !compressed.is_empty() && compressed.len() < raw_le.len() {
        compressed
    } else {
        raw_le
    }
}

/// The ZIP predictor: even-index bytes, then odd-index bytes, then the wrapping differences
/// (plus 128) of consecutive bytes, the first byte kept.
fn predict(raw: &[u8]) -> Vec<u8> {
    let half = raw.len().div_ceil(2);
    let mut split = vec![0; raw.len()];
    let (evens, odds) = split.split_at_mut(half);
    for (pair, (even, odd)) in raw
        .chunks_exact(2)
        .zip(evens.iter_mut().zip(odds.iter_mut()))
    {
        *even = pair[0];
        *odd = pair[1];
    }
    if raw.len() % 2 == 1 {
        evens[half - 1] = raw[raw.len() - 1];
    }
    let mut previous = split.first().copied().unwrap_or_default();
    for byte in split.iter_mut().skip(1) {
        let current = *byte;
        *byte = current.wrapping_sub(previous).wrapping_add(128);
        previous = current;
    }
    split
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Read;

    /// Undoes `predict` as a reader does (OpenEXR ImfZip.cpp, `Zip::uncompress`).
    fn unpredict(predicted: &[u8]) -> Vec<u8> {
        let mut summed = predicted.to_vec();
        for i in 1..summed.len() {
            summed[i] = summed[i].wrapping_add(summed[i - 1]).wrapping_sub(128);
        }
        let half = summed.len().div_ceil(2);
        (0..summed.len())
            .map(|i| summed[if i % 2 == 0 { i / 2 } else { half + i / 2 }])
            .collect()
    }

    #[test]
    fn predictor_splits_then_differences() {
        assert_eq!(predict(&[1, 2, 3, 4, 5]), [1, 130, 130, 125, 130]);
        assert_eq!(predict(&[]), Vec::<u8>::new());
        let raw: Vec<u8> = (0..1001u32).map(|i| (i * i * 7 + i) as u8).collect();
        assert_eq!(unpredict(&predict(&raw)), raw);
    }

    #[test]
    fn compressed_blocks_inflate_to_the_prediction_and_noise_stays_raw() {
        let smooth: Vec<u8> = (0..3000u32)
            .flat_map(|i| (i as f32).to_le_bytes())
            .collect();
        let block = compress_block(smooth.clone());
        assert!(block.len() < smooth.len());
        let mut inflated = Vec::new();
        flate2::read::ZlibDecoder::new(block.as_slice())
            .read_to_end(&mut inflated)
            .unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(unpredict(&inflated), smooth);
        // Bytes with no pattern (a xorshift sequence) do not shrink: stored as they are.
        let mut state = 0x9e37_79b9_7f4a_7c15_u64;
        let noise: Vec<u8> = (0..4096)
            .map(|_| {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                state as u8
            })
            .collect();
        assert_eq!(compress_block(noise.clone()), noise);
    }
}
