//! Decoding image files (PNG, JPEG, GIF, BMP, EXR) to linear RGB texels.

use std::path::Path;

use glam::Vec3;
use image::{DynamicImage, ImageReader};

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
