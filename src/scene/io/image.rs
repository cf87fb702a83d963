//! Decoding image files (PNG, JPEG, GIF, BMP, EXR) to linear RGB texels, or, for textures,
//! to the texels as the renderer keeps them (8-bit images in 8 bits).

use std::path::Path;
use std::sync::Arc;

use glam::Vec3;
use image::{
    DynamicImage, GrayAlphaImage, GrayImage, ImageReader, Luma, LumaA, Rgb, RgbImage, Rgba,
    RgbaImage,
};

use crate::material::texels::{CodedTexels, Texels};

/// A decoded image: `width * height` linear RGB texels, rows from the top.
pub struct LinearImage {
    pub width: u32,
    pub height: u32,
    pub texels: Vec<Vec3>,
}

/// A decoded image as a texture keeps it: `width * height` texels, rows from the top.
pub struct TextureImage {
    pub width: u32,
    pub height: u32,
    pub texels: Texels,
}

/// Decodes `path` to linear RGB, the values `decode_texture` gives, each texel stored as f32.
pub fn decode(path: &Path, gamma: f32, gain: f32) -> Result<LinearImage, String> {
    let image = decode_texture(path, gamma, gain)?;
    Ok(LinearImage {
        width: image.width,
        height: image.height,
        texels: Arc::unwrap_or_clone(image.texels.to_linear()),
    })
}

/// Decodes `path`. Integer-valued images are display-encoded: texel = (value / max)^gamma * gain;
/// floating-point images (EXR) are already linear: texel = value * gain. Images of 8 bits a
/// channel keep their codes, decoded at lookup through a table of those very values.
pub fn decode_texture(path: &Path, gamma: f32, gain: f32) -> Result<TextureImage, String> {
    let image = ImageReader::open(path)
        .and_then(|reader| reader.with_guessed_format())
        .map_err(|e| e.to_string())?
        .decode()
        .map_err(|e| e.to_string())?;
    Ok(TextureImage {
        width: image.width(),
        height: image.height(),
        texels: texels(&image, gamma, gain),
    })
}

/// `image`'s texels: coded if it has 8 bits a channel, linear otherwise.
fn texels(image: &DynamicImage, gamma: f32, gain: f32) -> Texels {
    if let Some(values) = code_values(image, gamma, gain) {
        let codes = CodedTexels::new(image.to_rgb8().into_raw(), values);
        return Texels::Coded(Arc::new(codes));
    }
    let is_linear = matches!(
        image,
        DynamicImage::ImageRgb32F(_) | DynamicImage::ImageRgba32F(_)
    );
    let texels = image
        .to_rgb32f()
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
    Texels::Linear(Arc::new(texels))
}

/// The linear value of each of an 8-bit image's 256 codes, the same bits as `powf` per
/// channel and the gain (the table's entries are that very conversion); `None` for other
/// depths. Decoding through the table also spares `powf`: a 512 x 512 texture took 786,432
/// `powf` calls, 50 M instructions, more than the BSDFs of a 4-spp render of the scene.
fn code_values(image: &DynamicImage, gamma: f32, gain: f32) -> Option<[f32; 256]> {
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
    let mut values = [0.0; 256];
    for (value, pixel) in values.iter_mut().zip(codes.to_rgb32f().pixels()) {
        *value = pixel.0[0].powf(gamma) * gain;
    }
    Some(values)
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
                let texels = texels(&image, gamma, gain);
                assert!(
                    matches!(texels, Texels::Coded(_)),
                    "an 8-bit image is coded"
                );
                let table = texels.to_linear();
                let bits = |texels: &[Vec3]| -> Vec<[u32; 3]> {
                    texels
                        .iter()
                        .map(|t| t.to_array().map(f32::to_bits))
                        .collect()
                };
                assert_eq!(bits(&table), bits(&by_powf(&image, gamma, gain)));
            }
        }
        let wide = DynamicImage::ImageRgb16(image::ImageBuffer::from_fn(2, 2, |x, y| {
            Rgb([x as u16 * 40_000, y as u16 * 999, 12_345])
        }));
        let texels = texels(&wide, 2.2, 1.5);
        assert!(
            matches!(texels, Texels::Linear(_)),
            "a 16-bit image is not coded"
        );
        assert_eq!(*texels.to_linear(), by_powf(&wide, 2.2, 1.5));
    }
}
