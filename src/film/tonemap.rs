//! Exposure: the scale applied to linear radiance before display encoding.

use glam::Vec3;

/// How linear radiance is scaled for display.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ToneMap {
    /// LuxRender's `autolinear`: exposure from the image's mean luminance.
    AutoLinear,
    /// A fixed scale.
    Linear { scale: f32 },
}

/// Luminance Y of linear Rec.709/sRGB: the Y row of the sRGB-to-XYZ matrix (D65), with the
/// digits LuxRender's `RGBColor::Y()` uses.
pub fn luminance(rgb: Vec3) -> f32 {
    0.212671 * rgb.x + 0.715160 * rgb.y + 0.072169 * rgb.z
}

/// The factor to multiply the image by before display with the given `gamma`.
pub fn exposure_scale(tonemap: ToneMap, pixels: &[Vec3], gamma: f32) -> f32 {
    match tonemap {
        ToneMap::Linear { scale } => scale,
        ToneMap::AutoLinear => autolinear_scale(pixels, gamma),
    }
}

/// LuxRender 1.x's `autolinear` (lux tonemaps/lineartonemap.cpp, `EVOp`, registered as
/// "autolinear"), the tone map of the scenes foton reads:
///
///   Y_avg = (sum of the positive, finite pixel luminances) / (number of those pixels)
///   scale = 1.25 / Y_avg * (118/255)^gamma,  or 1 when no pixel is lit.
///
/// It is LuxRender's `linear` camera-response tone map with exposure, f-stop and sensitivity
/// chosen so they cancel: the mean lit luminance lands at 118/255 of white after gamma, scaled
/// by 1.25. Averaging only lit pixels keeps a subject on a black background (the course's
/// pikachu and charizard) from being overexposed. LuxCoreRender (slg/film/imagepipeline/
/// plugins/tonemaps/autolinear.cpp) divides by every pixel instead; LuxRender keeps infinite
/// luminances in the sum, foton skips them (a non-finite pixel never reaches the film anyway).
fn autolinear_scale(pixels: &[Vec3], gamma: f32) -> f32 {
    let (sum, lit) = pixels
        .iter()
        .map(|&p| luminance(p))
        .filter(|y| *y > 0.0 && y.is_finite())
        .fold((0.0f64, 0usize), |(sum, n), y| (sum + f64::from(y), n + 1));
    let y_avg = (sum / lit.max(1) as f64) as f32;
    if y_avg > 0.0 && y_avg.is_finite() {
        1.25 / y_avg * (118.0f32 / 255.0).powf(gamma)
    } else {
        1.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn luminance_weights_sum_to_one() {
        assert!((luminance(Vec3::ONE) - 1.0).abs() < 1e-6);
        assert!((luminance(Vec3::Y) - 0.71516).abs() < 1e-7);
    }

    #[test]
    fn autolinear_on_constant_image() {
        // Constant grey of luminance Y: scale = 1.25 / Y * (118/255)^gamma.
        for (y, gamma) in [(0.18f32, 2.2f32), (4.0, 1.0), (1e-3, 2.2)] {
            let pixels = vec![Vec3::splat(y); 64];
            let expected = 1.25 / y * (118.0f32 / 255.0).powf(gamma);
            let scale = exposure_scale(ToneMap::AutoLinear, &pixels, gamma);
            assert!((scale / expected - 1.0).abs() < 1e-5, "{scale} {expected}");
        }
        // Documented value for Y = 1, gamma 2.2: 1.25 * (118/255)^2.2 = 0.22944...
        let one = exposure_scale(ToneMap::AutoLinear, &[Vec3::ONE], 2.2);
        assert!((one - 0.229_436).abs() < 1e-5, "{one}");
    }

    #[test]
    fn autolinear_averages_only_lit_pixels() {
        // Black pixels and NaN/inf/negative ones add nothing and do not count: the two lit
        // pixels of Y = 2 give Y_avg = 2.
        let mut pixels = vec![Vec3::ZERO, Vec3::ZERO, Vec3::splat(2.0), Vec3::splat(2.0)];
        pixels.extend([
            Vec3::NAN,
            Vec3::splat(f32::INFINITY),
            Vec3::splat(-1.0),
            Vec3::ZERO,
        ]);
        let scale = exposure_scale(ToneMap::AutoLinear, &pixels, 1.0);
        assert!((scale - 1.25 / 2.0 * 118.0 / 255.0).abs() < 1e-6);
        assert_eq!(
            exposure_scale(ToneMap::AutoLinear, &[Vec3::ZERO; 4], 2.2),
            1.0
        );
        assert_eq!(exposure_scale(ToneMap::AutoLinear, &[], 2.2), 1.0);
        assert_eq!(
            exposure_scale(ToneMap::Linear { scale: 3.5 }, &pixels, 2.2),
            3.5
        );
    }
}
