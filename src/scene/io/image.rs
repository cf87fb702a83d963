//! Decoding image files (PNG, JPEG, GIF, BMP, EXR) to linear RGB texels.

use std::path::Path;

use glam::Vec3;
use image::{
    DynamicImage, GrayAlphaImage, GrayImage, ImageReader, Luma, LumaA, Rgb, RgbImage, Rgba,
    RgbaImage,
};

/// A decoded image: `width * height` linear RGB texels, rows from the top.
pub struct LinearImage {
    pub width: u32,
    pub height: u32,
    pub texels: Vec<Vec3>,
}

/// Decodes `path`. Integer-valued images are display-encoded: texel = (value / max)^gamma * gain;
/// floating-point images (EXR) are already linear: texel = value * gain.
pub fn decode(path: &Path, gamma: f32, gain: f32) -> Result<LinearImage, String> {
    let image = ImageReader::open(path)
        .and_then(|reader| reader.with_guessed_format())
        .map_err(|e| e.to_string())?
        .decode()
        .map_err(|e| e.to_string())?;
    if let Some(texels) = decode_8bit(&image, gamma, gain) {
        return Ok(LinearImage {
            width: image.width(),
            height: image.height(),
            texels,
        });
    }
    let is_linear = matches!(
        image,
        DynamicImage::ImageRgb32F(_) | DynamicImage::ImageRgba32F(_)
    );
    let rgb = image.to_rgb32f();
    let texels = rgb
        .pixels()
        .map(|pixel| {
            let encoded = Vec3::from_array(pixel.0);
            let linear = if is_linear {
                encoded
            } else {
                encoded.powf(gamma)
            };
            linear * gain
        })
        .collect();
    Ok(LinearImage {
        width: rgb.width(),
        height: rgb.height(),
        texels,
    })
}

/// An 8-bit image's texels through a table of its 256 codes' linear values, the same bits as
/// `powf` per channel (the table's entries are that very conversion); `None` for other depths.
/// A 512 x 512 texture took 786,432 `powf` calls, 50 M instructions: more than the BSDFs of a
/// 4-spp render of the scene that uses it.
fn decode_8bit(image: &DynamicImage, gamma: f32, gain: f32) -> Option<Vec<Vec3>> {
    // Each code as `to_rgb32f` scales it from this very layout (grey converts with other
    // roundings than RGB), raised to `gamma`.
    let codes = match image {
        DynamicImage::ImageLuma8(_) => {
            DynamicImage::ImageLuma8(GrayImage::from_fn(256, 1, |code, _| Luma([code as u8])))
        }
        DynamicImage::ImageLumaA8(_) => {
            DynamicImage::ImageLumaA8(GrayAlphaImage::from_fn(256, 1, |code, _| {
                LumaA([code as u8, u8::MAX])
            }))
        }
        DynamicImage::ImageRgb8(_) => {
            DynamicImage::ImageRgb8(RgbImage::from_fn(256, 1, |code, _| Rgb([code as u8; 3])))
        }
        DynamicImage::ImageRgba8(_) => {
            DynamicImage::ImageRgba8(RgbaImage::from_fn(256, 1, |code, _| {
                Rgba([code as u8, code as u8, code as u8, u8::MAX])
            }))
        }
        _ => return None,
    };
    let linear: Vec<f32> = codes
        .to_rgb32f()
        .pixels()
        .map(|pixel| pixel.0[0].powf(gamma))
        .collect();
    let texels = image
        .to_rgb8()
        .pixels()
        .map(|pixel| Vec3::from_array(pixel.0.map(|code| linear[usize::from(code)])) * gain)
        .collect();
    Some(texels)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each channel as `decode` computed it before the table: `to_rgb32f`, then `powf`.
    fn by_powf(image: &DynamicImage, gamma: f32, gain: f32) -> Vec<Vec3> {
        image
            .to_rgb32f()
            .pixels()
            .map(|pixel| Vec3::from_array(pixel.0).powf(gamma) * gain)
            .collect()
    }

    #[test]
    fn the_8bit_table_gives_powf_to_the_bit() {
        // Every code in every channel of each 8-bit layout, alpha varying (it is dropped).
        let rgba = RgbaImage::from_fn(256, 3, |x, y| {
            let code = x as u8;
            Rgba([code, code.wrapping_mul(7), 255 - code, (y * 100) as u8])
        });
        let grey = GrayAlphaImage::from_fn(256, 1, |x, _| LumaA([x as u8, 9]));
        let plain_grey = GrayImage::from_fn(256, 1, |x, _| Luma([x as u8]));
        let rgb = RgbImage::from_fn(256, 1, |x, _| Rgb([x as u8, 3, 250]));
        for image in [
            DynamicImage::ImageRgba8(rgba),
            DynamicImage::ImageLumaA8(grey),
            DynamicImage::ImageLuma8(plain_grey),
            DynamicImage::ImageRgb8(rgb),
        ] {
            for (gamma, gain) in [(2.2, 1.0), (1.0, 0.5), (2.4, 3.0)] {
                let table = decode_8bit(&image, gamma, gain).expect("an 8-bit image");
                let bits = |texels: &[Vec3]| -> Vec<[u32; 3]> {
                    texels
                        .iter()
                        .map(|t| t.to_array().map(f32::to_bits))
                        .collect()
                };
                assert_eq!(bits(&table), bits(&by_powf(&image, gamma, gain)));
            }
        }
        let wide = DynamicImage::ImageRgb16(image::ImageBuffer::new(2, 2));
        assert!(decode_8bit(&wide, 2.2, 1.0).is_none());
    }
}
