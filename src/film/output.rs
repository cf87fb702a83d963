//! Writing and reading images: 8-bit sRGB PNG for display, 32-bit float EXR for data.

use std::ffi::OsString;
use std::fs;
use std::path::{Path, PathBuf};

use glam::Vec3;
use image::{DynamicImage, ImageFormat, Rgb32FImage, RgbImage};

/// Writes `pixels` (linear RGB, rows from the top) to `path`, by its extension:
/// `.png`: pixels * exposure, clamped to [0, 1], sRGB-encoded to 8 bits;
/// `.exr`: the linear values as 32-bit floats (no exposure).
/// The image goes to a temporary file beside `path` that is then renamed over it, so a failed
/// write never leaves a truncated image.
pub fn write_image(
    path: &Path,
    width: u32,
    height: u32,
    pixels: &[Vec3],
    exposure: f32,
) -> Result<(), String> {
    let expected = width as usize * height as usize;
    if pixels.len() != expected {
        return Err(format!(
            "{}: {} pixels given for a {width}x{height} image",
            path.display(),
            pixels.len()
        ));
    }
    let extension = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    let (image, format) = match extension.as_deref() {
        Some("png") => {
            let bytes = pixels
                .iter()
                .flat_map(|&p| (p * exposure).to_array())
                .map(encode_srgb8)
                .collect();
            (
                RgbImage::from_raw(width, height, bytes).map(DynamicImage::ImageRgb8),
                ImageFormat::Png,
            )
        }
        Some("exr") => {
            let floats = pixels.iter().flat_map(|p| p.to_array()).collect();
            (
                Rgb32FImage::from_raw(width, height, floats).map(DynamicImage::ImageRgb32F),
                ImageFormat::OpenExr,
            )
        }
        _ => {
            return Err(format!(
                "{}: unsupported image format (supported: .png, .exr)",
                path.display()
            ));
        }
    };
    let image = image.ok_or_else(|| format!("{}: image buffer size mismatch", path.display()))?;
    let temporary = temporary_path(path);
    let written = image
        .save_with_format(&temporary, format)
        .map_err(|e| format!("{}: {e}", path.display()))
        .and_then(|()| {
            fs::rename(&temporary, path).map_err(|e| format!("{}: {e}", path.display()))
        });
    if written.is_err() {
        // Best effort: the temporary may not exist.
        let _ = fs::remove_file(&temporary);
    }
    written
}

/// Reads an EXR file as linear RGB (alpha dropped).
pub fn read_exr(path: &Path) -> Result<(u32, u32, Vec<Vec3>), String> {
    let image = open(path, ImageFormat::OpenExr)?.into_rgb32f();
    let pixels = image.pixels().map(|p| Vec3::from_array(p.0)).collect();
    Ok((image.width(), image.height(), pixels))
}

/// Reads an 8-bit PNG and decodes the sRGB transfer function to linear RGB.
pub fn read_png_linear(path: &Path) -> Result<(u32, u32, Vec<Vec3>), String> {
    let image = open(path, ImageFormat::Png)?.into_rgb8();
    let pixels = image
        .pixels()
        .map(|p| Vec3::from_array(p.0.map(decode_srgb8)))
        .collect();
    Ok((image.width(), image.height(), pixels))
}

fn open(path: &Path, format: ImageFormat) -> Result<DynamicImage, String> {
    let mut reader =
        image::ImageReader::open(path).map_err(|e| format!("{}: {e}", path.display()))?;
    reader.set_format(format);
    reader
        .decode()
        .map_err(|e| format!("{}: {e}", path.display()))
}

/// `dir/.name.tmp-<pid>`: same directory (so the rename is atomic), hidden, per process.
fn temporary_path(path: &Path) -> PathBuf {
    let mut name = OsString::from(".");
    name.push(path.file_name().unwrap_or_default());
    name.push(format!(".tmp-{}", std::process::id()));
    path.with_file_name(name)
}

/// The sRGB transfer function (IEC 61966-2-1) to 8 bits, rounding to nearest; NaN is black.
fn encode_srgb8(linear: f32) -> u8 {
    let c = if linear.is_nan() {
        0.0
    } else {
        linear.clamp(0.0, 1.0)
    };
    let v = if c <= 0.003_130_8 {
        12.92 * c
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    };
    (v * 255.0 + 0.5) as u8
}

/// The inverse of the sRGB transfer function for an 8-bit value.
fn decode_srgb8(byte: u8) -> f32 {
    let v = f32::from(byte) / 255.0;
    if v <= 0.040_45 {
        v / 12.92
    } else {
        ((v + 0.055) / 1.055).powf(2.4)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("foton-output-{}", std::process::id()));
        let _ = fs::create_dir_all(&dir);
        dir.join(name)
    }

    #[test]
    fn exr_round_trip_is_exact() {
        let pixels: Vec<Vec3> = (0..6)
            .map(|i| Vec3::new(i as f32 * 0.1, 1e-7 * i as f32, 1234.5678 + i as f32))
            .collect();
        let path = scratch("round.exr");
        write_image(&path, 3, 2, &pixels, 100.0)
            .map_err(|e| panic!("{e}"))
            .ok();
        let (w, h, read) = read_exr(&path).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!((w, h), (3, 2));
        assert_eq!(read, pixels);
        let _ = fs::remove_file(&path);
    }

    #[test]
    fn png_encodes_srgb_bytes() {
        // Known sRGB codes: 0 -> 0, 1 -> 255, 0.5 -> 188 (0.7354 * 255 = 187.5..), 0.0031308
        // -> 10 (the linear segment: 0.04045 * 255 = 10.3), 0.216 -> 128 (0.5021 * 255 = 128.04).
        // Exposure 2 doubles first; values above 1 clip.
        let pixels = vec![
            Vec3::new(0.0, 0.5, 1.0),
            Vec3::new(0.25, 0.003_130_8 / 2.0, 3.0),
            Vec3::new(0.108, f32::NAN, -1.0),
        ];
        let path = scratch("codes.png");
        write_image(&path, 3, 1, &pixels, 2.0).unwrap_or_else(|e| panic!("{e}"));
        let bytes = image::open(&path)
            .unwrap_or_else(|e| panic!("{e}"))
            .into_rgb8()
            .into_raw();
        assert_eq!(bytes, [0, 255, 255, 188, 10, 255, 128, 0, 0]);
        let (_, _, linear) = read_png_linear(&path).unwrap_or_else(|e| panic!("{e}"));
        assert!((linear[1].x - 0.5).abs() < 3e-3 && linear[0].z == 1.0);
        let _ = fs::remove_file(&path);
    }

    #[test]
    fn write_rejects_bad_extension_and_size_without_leaving_files() {
        let path = scratch("image.tiff");
        let e = write_image(&path, 1, 1, &[Vec3::ONE], 1.0)
            .err()
            .unwrap_or_default();
        assert!(
            e.contains("image.tiff") && e.contains(".png") && e.contains(".exr"),
            "{e}"
        );
        let e = write_image(&scratch("short.png"), 2, 2, &[Vec3::ONE], 1.0);
        assert!(e.is_err());
        // A directory that does not exist: the error names the path, nothing is left behind.
        let missing = scratch("no-such-dir").join("x.png");
        let e = write_image(&missing, 1, 1, &[Vec3::ONE], 1.0)
            .err()
            .unwrap_or_default();
        assert!(e.contains("x.png"), "{e}");
        assert!(!missing.exists() && !scratch("short.png").exists());
    }

    #[test]
    fn srgb_decode_inverts_encode() {
        for b in 0..=255u8 {
            assert_eq!(encode_srgb8(decode_srgb8(b)), b);
        }
    }
}
