//! Writing and reading images: 8-bit sRGB PNG and JPEG for display; EXR (ZIP-compressed 32-bit
//! float, with the render's metadata), Radiance HDR and PFM for linear data.

use std::ffi::OsString;
use std::fs;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use exr::block::chunk::{Chunk, CompressedBlock, CompressedScanLineBlock};
use exr::block::writer::ChunksWriter;
use exr::meta::attribute::{AttributeValue, SampleType, Text};
use exr::prelude::{
    Encoding, Image as ExrImage, Layer, LayerAttributes, SpecificChannels, WritableImage,
};
use glam::Vec3;
use image::{DynamicImage, ImageFormat, Rgb32FImage, RgbImage};
use rayon::prelude::*;

use super::exr_zip;

/// The extensions `write_image` understands, and whether each stores linear values.
pub const OUTPUT_FORMATS: &[(&str, bool)] = &[
    ("png", false),
    ("jpg", false),
    ("jpeg", false),
    ("exr", true),
    ("hdr", true),
    ("pfm", true),
];

/// What the render was, stored in formats that carry metadata (EXR).
#[derive(Clone, Debug, Default)]
pub struct ImageMetadata {
    pub samples_per_pixel: u32,
    pub seconds: f64,
    pub seed: u64,
    pub command_line: String,
}

fn extension(path: &Path) -> Option<String> {
    path.extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
}

/// Whether `path` names a linear (floating-point) format; an error for an unknown extension.
pub fn is_linear_output(path: &Path) -> Result<bool, String> {
    let extension = extension(path).unwrap_or_default();
    OUTPUT_FORMATS
        .iter()
        .find(|(e, _)| *e == extension)
        .map(|&(_, linear)| linear)
        .ok_or_else(|| {
            let names: Vec<String> = OUTPUT_FORMATS
                .iter()
                .map(|(e, _)| format!(".{e}"))
                .collect();
            format!(
                "{}: unsupported image format (supported: {})",
                path.display(),
                names.join(", ")
            )
        })
}

/// Checks before rendering that an image can be written at `path`: a known extension, an existing
/// folder, not a folder itself, and a folder that takes a new file (tried with the temporary
/// file `write_image` would use, then removed).
pub fn check_output(path: &Path) -> Result<(), String> {
    is_linear_output(path)?;
    let folder = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    if !folder.is_dir() {
        return Err(format!(
            "{}: the folder {} does not exist",
            path.display(),
            folder.display()
        ));
    }
    if path.is_dir() {
        return Err(format!("{}: is a folder", path.display()));
    }
    let probe = temporary_path(path);
    fs::File::create(&probe).map_err(|e| {
        format!(
            "{}: cannot write in {}: {e}",
            path.display(),
            folder.display()
        )
    })?;
    // Best effort: the probe was just made.
    let _ = fs::remove_file(&probe);
    Ok(())
}

/// Writes `pixels` (linear RGB, rows from the top) to `path`, by its extension:
/// `.png`, `.jpg`: pixels * exposure, clamped to [0, 1], sRGB-encoded to 8 bits;
/// `.exr` (ZIP, 32-bit float, with `metadata`), `.hdr`, `.pfm`: pixels * exposure, linear.
/// The image goes to a temporary file beside `path` that is then renamed over it, so a failed
/// write never leaves a truncated image.
pub fn write_image(
    path: &Path,
    width: u32,
    height: u32,
    pixels: &[Vec3],
    exposure: f32,
    metadata: &ImageMetadata,
) -> Result<(), String> {
    let expected = width as usize * height as usize;
    if pixels.len() != expected {
        return Err(format!(
            "{}: {} pixels given for a {width}x{height} image",
            path.display(),
            pixels.len()
        ));
    }
    is_linear_output(path)?;
    let scaled: Vec<Vec3> = pixels.iter().map(|&p| p * exposure).collect();
    let temporary = temporary_path(path);
    let written = match extension(path).as_deref() {
        Some("exr") => write_exr(&temporary, width, height, &scaled, metadata),
        Some("pfm") => write_pfm(&temporary, width, height, &scaled),
        Some("hdr") => save(
            &temporary,
            float_image(width, height, &scaled),
            ImageFormat::Hdr,
        ),
        Some("png") => save(
            &temporary,
            srgb8_image(width, height, &scaled),
            ImageFormat::Png,
        ),
        _ => save(
            &temporary,
            srgb8_image(width, height, &scaled),
            ImageFormat::Jpeg,
        ),
    }
    .and_then(|()| fs::rename(&temporary, path).map_err(|e| e.to_string()))
    .map_err(|e| format!("{}: {e}", path.display()));
    if written.is_err() {
        // Best effort: the temporary may not exist.
        let _ = fs::remove_file(&temporary);
    }
    written
}

fn srgb8_image(width: u32, height: u32, pixels: &[Vec3]) -> Option<DynamicImage> {
    let bytes = pixels
        .iter()
        .flat_map(|p| p.to_array())
        .map(encode_srgb8)
        .collect();
    RgbImage::from_raw(width, height, bytes).map(DynamicImage::ImageRgb8)
}

fn float_image(width: u32, height: u32, pixels: &[Vec3]) -> Option<DynamicImage> {
    let floats = pixels.iter().flat_map(|p| p.to_array()).collect();
    Rgb32FImage::from_raw(width, height, floats).map(DynamicImage::ImageRgb32F)
}

fn save(path: &Path, image: Option<DynamicImage>, format: ImageFormat) -> Result<(), String> {
    image
        .ok_or("image buffer size mismatch")?
        .save_with_format(path, format)
        .map_err(|e| e.to_string())
}

/// The EXR layer's attributes: the software's name and the render's settings.
fn exr_attributes(metadata: &ImageMetadata) -> LayerAttributes {
    let mut attributes = LayerAttributes::named("");
    attributes.software_name = Some(text("foton"));
    for (name, value) in [
        ("foton:spp", metadata.samples_per_pixel.to_string()),
        ("foton:seconds", format!("{:.3}", metadata.seconds)),
        ("foton:seed", metadata.seed.to_string()),
        ("foton:command", metadata.command_line.clone()),
    ] {
        attributes
            .other
            .insert(text(name), AttributeValue::Text(text(&value)));
    }
    attributes
}

/// OpenEXR, ZIP-compressed scan lines of 32-bit floats; the render's settings as attributes
/// (`foton:spp`, `foton:seconds`, `foton:seed`, `foton:command`) and the software's name.
/// The exr crate writes the header and the offset table; the blocks of 16 scan lines are
/// compressed here (`exr_zip`, a faster zlib level than the crate's), in parallel, each
/// independently of the thread count, so the file's bytes do not depend on it.
fn write_exr(
    path: &Path,
    width: u32,
    height: u32,
    pixels: &[Vec3],
    metadata: &ImageMetadata,
) -> Result<(), String> {
    let attributes = exr_attributes(metadata);
    let w = width as usize;
    // The channels only name R, G, B as 32-bit floats for the header; the samples are packed
    // below, in the header's channel order.
    let channels = SpecificChannels::rgb(|_: exr::math::Vec2<usize>| (0.0_f32, 0.0_f32, 0.0_f32));
    let layer = Layer::new(
        (w, height as usize),
        attributes,
        Encoding::SMALL_LOSSLESS,
        channels,
    );
    let headers = ExrImage::from_layer(layer).write().infer_meta_data();
    let header = &headers[0];
    let components = header
        .channels
        .list
        .iter()
        .map(
            |channel| match (channel.name.to_string().as_str(), channel.sample_type) {
                ("R", SampleType::F32) => Ok(0),
                ("G", SampleType::F32) => Ok(1),
                ("B", SampleType::F32) => Ok(2),
                (name, kind) => Err(format!("unexpected EXR channel {name} ({kind:?})")),
            },
        )
        .collect::<Result<Vec<usize>, String>>()?;
    let lines_per_block = header.compression.scan_lines_per_block();
    let top = header.own_attributes.layer_position.y();
    let blocks: Vec<Vec<u8>> = pixels
        .par_chunks(w.max(1) * lines_per_block)
        .map(|rows| {
            let mut raw_le = Vec::with_capacity(rows.len() * components.len() * 4);
            for row in rows.chunks_exact(w.max(1)) {
                for &component in &components {
                    for pixel in row {
                        raw_le.extend_from_slice(&pixel[component].to_le_bytes());
                    }
                }
            }
            exr_zip::compress_block(raw_le)
        })
        .collect();
    let file = fs::File::create(path).map_err(|e| e.to_string())?;
    exr::block::write(BufWriter::new(file), headers, true, |_, chunks| {
        for (index, compressed_pixels_le) in blocks.into_iter().enumerate() {
            let y_coordinate = i32::try_from(index * lines_per_block)
                .map_err(|_| exr::error::Error::Invalid("image too tall".into()))?
                + top;
            chunks.write_chunk(
                index,
                Chunk {
                    layer_index: 0,
                    compressed_block: CompressedBlock::ScanLine(CompressedScanLineBlock {
                        y_coordinate,
                        compressed_pixels_le,
                    }),
                },
            )?;
        }
        Ok(())
    })
    .map_err(|e| e.to_string())
}

/// An EXR text attribute: `s`, its non-ASCII characters as `?`.
pub(crate) fn text(s: &str) -> Text {
    Text::new_or_none(s).unwrap_or_else(|| {
        let ascii: String = s
            .chars()
            .map(|c| if c.is_ascii() { c } else { '?' })
            .collect();
        Text::new_or_none(ascii).unwrap_or_default()
    })
}

/// Portable float map: `PF`, the size, -1 for little-endian, then rows from the bottom.
fn write_pfm(path: &Path, width: u32, height: u32, pixels: &[Vec3]) -> Result<(), String> {
    let mut bytes = format!("PF\n{width} {height}\n-1.0\n").into_bytes();
    for row in pixels.chunks_exact(width.max(1) as usize).rev() {
        for v in row.iter().flat_map(|p| p.to_array()) {
            bytes.extend_from_slice(&v.to_le_bytes());
        }
    }
    fs::File::create(path)
        .and_then(|mut f| f.write_all(&bytes))
        .map_err(|e| e.to_string())
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
pub(crate) fn temporary_path(path: &Path) -> PathBuf {
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

    fn metadata(samples_per_pixel: u32, seconds: f64, seed: u64, command: &str) -> ImageMetadata {
        ImageMetadata {
            samples_per_pixel,
            seconds,
            seed,
            command_line: command.into(),
        }
    }

    /// Writes `pixels` (times `exposure`) as the scratch EXR `name`, reads it back and checks
    /// its size: the file's path and the pixels read.
    fn write_and_read_exr(
        name: &str,
        width: u32,
        height: u32,
        pixels: &[Vec3],
        exposure: f32,
        metadata: &ImageMetadata,
    ) -> (PathBuf, Vec<Vec3>) {
        let path = scratch(name);
        write_image(&path, width, height, pixels, exposure, metadata)
            .unwrap_or_else(|e| panic!("{e}"));
        let (w, h, read) = read_exr(&path).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!((w, h), (width, height));
        (path, read)
    }

    #[test]
    fn linear_formats_round_trip_with_exposure_and_exr_metadata() {
        let pixels: Vec<Vec3> = (0..6)
            .map(|i| Vec3::new(i as f32 * 0.1, 1e-7 * i as f32, 1234.5678 + i as f32))
            .collect();
        let metadata = metadata(7, 1.5, 99, "foton render x.lxs");
        let (path, read) = write_and_read_exr("round.exr", 3, 2, &pixels, 2.0, &metadata);
        let doubled: Vec<Vec3> = pixels.iter().map(|&p| p * 2.0).collect();
        assert_eq!(read, doubled);
        let meta =
            exr::meta::MetaData::read_from_file(&path, false).unwrap_or_else(|e| panic!("{e}"));
        let header = &meta.headers[0];
        assert_eq!(header.compression, exr::compression::Compression::ZIP16);
        let attribute = |name: &str| {
            header
                .own_attributes
                .other
                .get(&Text::new_or_none(name).unwrap_or_default())
                .cloned()
        };
        assert_eq!(
            attribute("foton:spp"),
            Some(AttributeValue::Text(
                Text::new_or_none("7").unwrap_or_default()
            ))
        );
        assert_eq!(
            attribute("foton:command"),
            Some(AttributeValue::Text(
                Text::new_or_none("foton render x.lxs").unwrap_or_default()
            ))
        );
        // Radiance HDR reads back through the image crate, to its 8-bit mantissas.
        let path = scratch("round.hdr");
        write_image(&path, 3, 2, &pixels, 1.0, &metadata).unwrap_or_else(|e| panic!("{e}"));
        let image = image::open(&path)
            .unwrap_or_else(|e| panic!("{e}"))
            .into_rgb32f();
        assert_eq!((image.width(), image.height()), (3, 2));
        for (p, q) in image.pixels().zip(&pixels) {
            let p = Vec3::from_array(p.0);
            // Shared exponent: each channel within 1/128 of the largest one.
            assert!(
                (p - *q).abs().max_element() <= q.max_element() / 128.0,
                "{p} vs {q}"
            );
        }
        // PFM: a text header, then little-endian floats with the bottom row first.
        let path = scratch("round.pfm");
        write_image(&path, 3, 2, &pixels, 1.0, &metadata).unwrap_or_else(|e| panic!("{e}"));
        let bytes = fs::read(&path).unwrap_or_default();
        let header = b"PF\n3 2\n-1.0\n";
        assert_eq!(&bytes[..header.len()], header);
        let floats: Vec<f32> = bytes[header.len()..]
            .chunks_exact(4)
            .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            .collect();
        let bottom_up: Vec<f32> = pixels[3..]
            .iter()
            .chain(&pixels[..3])
            .flat_map(|p| p.to_array())
            .collect();
        assert_eq!(floats, bottom_up);
        let _ = fs::remove_file(&path);
    }

    #[test]
    fn exr_blocks_decode_bit_exactly_with_the_crates_header() {
        // 37 rows: two full blocks of 16 scan lines and a partial one of 5. Smooth values (they
        // compress), a noisy band (stored raw where it does not shrink), and special floats.
        let (width, height) = (29u32, 37u32);
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        let mut noise = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            // Finite floats of any sign and exponent.
            f32::from_bits(state as u32 & 0xff7f_ffff)
        };
        let pixels: Vec<Vec3> = (0..width * height)
            .map(|i| match (i / width, i % 7) {
                (16..=31, _) => Vec3::new(noise(), noise(), noise()),
                (_, 0) => Vec3::new(f32::INFINITY, -0.0, f32::MIN_POSITIVE / 4.0),
                _ => Vec3::new(i as f32 * 0.01, 1.0 / (1 + i) as f32, 2.5),
            })
            .collect();
        let metadata = metadata(3, 0.25, 5, "foton render blocks.xml");
        let (path, read) = write_and_read_exr("blocks.exr", width, height, &pixels, 1.0, &metadata);
        let bits = |p: &[Vec3]| -> Vec<u32> {
            p.iter()
                .flat_map(|v| v.to_array())
                .map(f32::to_bits)
                .collect()
        };
        assert_eq!(bits(&read), bits(&pixels));
        let meta =
            exr::meta::MetaData::read_from_file(&path, true).unwrap_or_else(|e| panic!("{e}"));
        let header = &meta.headers[0];
        assert_eq!(header.compression, exr::compression::Compression::ZIP16);
        assert_eq!(header.chunk_count, 3);
        // The noisy middle block does not shrink: stored raw, the others compressed.
        let block_sizes: Vec<usize> = exr::block::read(
            std::io::BufReader::new(fs::File::open(&path).unwrap_or_else(|e| panic!("{e}"))),
            true,
        )
        .and_then(|reader| reader.all_chunks(true))
        .unwrap_or_else(|e| panic!("{e}"))
        .map(
            |chunk| match chunk.unwrap_or_else(|e| panic!("{e}")).compressed_block {
                CompressedBlock::ScanLine(block) => block.compressed_pixels_le.len(),
                _ => panic!("not a scan line block"),
            },
        )
        .collect();
        let raw_block = width as usize * 16 * 12;
        assert!(block_sizes[0] < raw_block && block_sizes[2] < width as usize * 5 * 12);
        assert_eq!(block_sizes[1], raw_block);
        // The header is the one the crate's own writer makes for the same image.
        let reference = scratch("blocks-crate.exr");
        let channels = SpecificChannels::rgb(|p: exr::math::Vec2<usize>| {
            let v = pixels[p.y() * width as usize + p.x()];
            (v.x, v.y, v.z)
        });
        let layer = Layer::new(
            (width as usize, height as usize),
            exr_attributes(&metadata),
            Encoding::SMALL_LOSSLESS,
            channels,
        );
        ExrImage::from_layer(layer)
            .write()
            .to_file(&reference)
            .unwrap_or_else(|e| panic!("{e}"));
        let crate_meta =
            exr::meta::MetaData::read_from_file(&reference, true).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(meta.headers, crate_meta.headers);
        let _ = fs::remove_file(&path);
        let _ = fs::remove_file(&reference);
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
        write_image(&path, 3, 1, &pixels, 2.0, &ImageMetadata::default())
            .unwrap_or_else(|e| panic!("{e}"));
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
        let e = write_image(&path, 1, 1, &[Vec3::ONE], 1.0, &ImageMetadata::default())
            .err()
            .unwrap_or_default();
        assert!(
            e.contains("image.tiff") && e.contains(".png") && e.contains(".exr"),
            "{e}"
        );
        let e = write_image(
            &scratch("short.png"),
            2,
            2,
            &[Vec3::ONE],
            1.0,
            &ImageMetadata::default(),
        );
        assert!(e.is_err());
        // A directory that does not exist: the error names the path, nothing is left behind.
        let missing = scratch("no-such-dir").join("x.png");
        let e = write_image(&missing, 1, 1, &[Vec3::ONE], 1.0, &ImageMetadata::default())
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
