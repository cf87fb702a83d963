//! Checkpoints: the film's sums and counts after whole passes, so that a render can go on later
//! to the same image an uninterrupted render gives (`foton render --resume`).
//!
//! The file is little-endian binary: the magic `FOTONCK3`; width, height and completed passes
//! (u32); the seed and a hash of the rendered pixel set (u64); the rejected-sample count (u64);
//! the film's sample clamp (f64, 0 for none: a resumed render must clamp alike); then per pixel the three f64 weighted sums, the f64 weight sum and the u64 count. Written atomically (temporary, rename).

use std::fs;
use std::io::Write;
use std::path::Path;

use glam::DVec3;

use super::Film;
use super::output::temporary_path;

const MAGIC: &[u8; 8] = b"FOTONCK3";
const HEADER: usize = 8 + 3 * 4 + 4 * 8;
const PER_PIXEL: usize = 5 * 8;

/// What a checkpoint holds besides the film: the settings it must be resumed with.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CheckpointInfo {
    pub passes: u32,
    pub seed: u64,
    /// `pixel_set_hash` of the pixels rendered (`--crop`, `--pixel`), or of none for all.
    pub pixel_set: u64,
}

/// A hash naming the set of pixels rendered (`None`: all of them); FNV-1a over the indices.
pub fn pixel_set_hash(pixels: Option<&[u32]>) -> u64 {
    let Some(pixels) = pixels else { return 0 };
    pixels
        .iter()
        .flat_map(|p| p.to_le_bytes())
        .fold(0xcbf2_9ce4_8422_2325, |h, b| {
            (h ^ u64::from(b)).wrapping_mul(0x100_0000_01b3)
        })
}

pub fn write_checkpoint(path: &Path, film: &Film, info: CheckpointInfo) -> Result<(), String> {
    let mut bytes = Vec::with_capacity(HEADER + film.counts().len() * PER_PIXEL);
    bytes.extend_from_slice(MAGIC);
    for v in [film.width(), film.height(), info.passes] {
        bytes.extend_from_slice(&v.to_le_bytes());
    }
    for v in [info.seed, info.pixel_set, film.rejected_samples()] {
        bytes.extend_from_slice(&v.to_le_bytes());
    }
    let clamp = film.max_component().map_or(0.0, f64::from);
    bytes.extend_from_slice(&clamp.to_le_bytes());
    for (pixel, count) in film.counts().iter().enumerate() {
        for v in film
            .sum(pixel)
            .to_array()
            .into_iter()
            .chain([film.weight(pixel)])
        {
            bytes.extend_from_slice(&v.to_le_bytes());
        }
        bytes.extend_from_slice(&count.to_le_bytes());
    }
    let temporary = temporary_path(path);
    let written = fs::File::create(&temporary)
        .and_then(|mut f| f.write_all(&bytes).and_then(|()| f.sync_all()))
        .and_then(|()| fs::rename(&temporary, path))
        .map_err(|e| format!("{}: {e}", path.display()));
    if written.is_err() {
        // Best effort: the temporary may not exist.
        let _ = fs::remove_file(&temporary);
    }
    written
}

pub fn read_checkpoint(path: &Path) -> Result<(Film, CheckpointInfo), String> {
    let bytes = fs::read(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let bad = |what: &str| format!("{}: not a foton checkpoint ({what})", path.display());
    if bytes.len() < HEADER || &bytes[..8] != MAGIC {
        return Err(bad("no FOTONCK3 header"));
    }
    let u32_at = |i: usize| u32::from_le_bytes(bytes[i..i + 4].try_into().unwrap_or_default());
    let u64_at = |i: usize| u64::from_le_bytes(bytes[i..i + 8].try_into().unwrap_or_default());
    let (width, height, passes) = (u32_at(8), u32_at(12), u32_at(16));
    let (seed, pixel_set, rejected) = (u64_at(20), u64_at(28), u64_at(36));
    let clamp = f64::from_bits(u64_at(44));
    let max_component = (clamp > 0.0).then_some(clamp as f32);
    let n = width as usize * height as usize;
    if bytes.len() != HEADER + n * PER_PIXEL {
        return Err(bad(&format!(
            "{} bytes for a {width}x{height} film",
            bytes.len()
        )));
    }
    let mut sums = Vec::with_capacity(n);
    let mut weights = Vec::with_capacity(n);
    let mut counts = Vec::with_capacity(n);
    for p in bytes[HEADER..].chunks_exact(PER_PIXEL) {
        let f = |i: usize| f64::from_le_bytes(p[i..i + 8].try_into().unwrap_or_default());
        sums.push(DVec3::new(f(0), f(8), f(16)));
        weights.push(f(24));
        counts.push(u64::from_le_bytes(p[32..40].try_into().unwrap_or_default()));
    }
    let film = Film::from_parts(
        width,
        height,
        sums,
        weights,
        counts,
        rejected,
        max_component,
    )
    .ok_or_else(|| bad("film size"))?;
    Ok((
        film,
        CheckpointInfo {
            passes,
            seed,
            pixel_set,
        },
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    #[test]
    fn checkpoint_round_trip_is_exact_and_refuses_other_files() {
        let dir = std::env::temp_dir().join(format!("foton-checkpoint-{}", std::process::id()));
        fs::create_dir_all(&dir).unwrap_or_else(|e| panic!("{e}"));
        let path = dir.join("a.checkpoint");
        let mut film = Film::new(3, 2);
        film.clamp_samples(Some(2.5));
        film.splat_with(crate::film::PixelFilter::new(
            crate::film::FilterKind::Gaussian { alpha: 2.0 },
            glam::Vec2::splat(1.5),
        ));
        let position = glam::Vec2::new(1.3, 0.6);
        film.add_sample(1, position, Vec3::new(0.1, 1e-9, 3e7));
        film.add_sample(1, position, Vec3::new(0.7, 2.0, 1.0 / 3.0));
        film.add_sample(5, position, Vec3::new(f32::NAN, 0.0, 0.0));
        let info = CheckpointInfo {
            passes: 2,
            seed: 42,
            pixel_set: pixel_set_hash(Some(&[1, 5])),
        };
        write_checkpoint(&path, &film, info).unwrap_or_else(|e| panic!("{e}"));
        let (read, read_info) = read_checkpoint(&path).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(read_info, info);
        for pixel in 0..film.counts().len() {
            assert_eq!(read.sum(pixel), film.sum(pixel));
            assert_eq!(read.weight(pixel), film.weight(pixel));
        }
        assert_eq!(read.counts(), film.counts());
        assert_eq!(read.rejected_samples(), 1);
        assert_eq!(read.max_component(), Some(2.5));
        fs::write(&path, b"FOTONCK1 but short").unwrap_or_else(|e| panic!("{e}"));
        let e = read_checkpoint(&path).err().unwrap_or_default();
        assert!(
            e.contains("a.checkpoint") && e.contains("not a foton checkpoint"),
            "{e}"
        );
        assert_ne!(pixel_set_hash(Some(&[1, 5])), pixel_set_hash(Some(&[1, 6])));
    }
}
