//! Exposure and tone mapping: what is applied to linear radiance before display encoding.
//!
//! [`exposure_scale`] gives the global scale of the linear maps; [`ToneMapOp::apply`] runs
//! LuxRender 1.x's `fleximage` tone mapping kernels (`tonemaps/*.cpp`), which scale each pixel's
//! colour by a factor that may depend on its luminance.

use glam::Vec3;

/// How linear radiance is scaled for display.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ToneMap {
    /// LuxRender's `autolinear`: exposure from the image's mean luminance.
    AutoLinear,
    /// A fixed scale.
    Linear { scale: f32 },
    /// LuxRender's `reinhard`: Reinhard et al. 2002's global operator.
    Reinhard {
        prescale: f32,
        postscale: f32,
        burn: f32,
    },
    /// LuxRender 0.x's `reinhard`: the curve on absolute luminance (see
    /// [`ToneMapOp::ReinhardAbsolute`]).
    ReinhardAbsolute {
        prescale: f32,
        postscale: f32,
        burn: f32,
    },
    /// LuxRender's `contrast`: Ward 1994, `ywa` the display adaptation luminance.
    Contrast { ywa: f32 },
    /// LuxRender's `maxwhite`: the brightest pixel to white.
    MaxWhite,
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
        // Applied per pixel by [`apply_display_tone_map`].
        ToneMap::Reinhard { .. }
        | ToneMap::ReinhardAbsolute { .. }
        | ToneMap::Contrast { .. }
        | ToneMap::MaxWhite => 1.0,
    }
}

/// Applies the per-pixel kernels (`reinhard`, `contrast`, `maxwhite`) to an image bound for an
/// 8-bit display; the linear ones are [`exposure_scale`]'s.
pub fn apply_display_tone_map(tonemap: ToneMap, pixels: &mut [Vec3], gamma: f32) {
    let op = match tonemap {
        ToneMap::Reinhard {
            prescale,
            postscale,
            burn,
        } => ToneMapOp::Reinhard {
            prescale,
            postscale,
            burn,
        },
        ToneMap::ReinhardAbsolute {
            prescale,
            postscale,
            burn,
        } => ToneMapOp::ReinhardAbsolute {
            prescale,
            postscale,
            burn,
        },
        ToneMap::Contrast { ywa } => ToneMapOp::Contrast { ywa },
        ToneMap::MaxWhite => ToneMapOp::MaxWhite,
        ToneMap::AutoLinear | ToneMap::Linear { .. } => return,
    };
    op.apply(pixels, gamma);
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

/// The largest display luminance LuxRender passes to its tone maps (`film/fleximage.cpp`,
/// `ApplyImagingPipeline`: `toneMap->Map(xyzpixels, xResolution, yResolution, 100.f)`).
const MAX_DISPLAY_Y: f32 = 100.0;

/// LuxRender's tone mapping kernels (`"string tonemapkernel"`), with its parameter names and
/// defaults.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ToneMapOp {
    /// `autolinear`: see [`exposure_scale`].
    AutoLinear,
    /// `linear`: `linear_sensitivity` (100), `linear_exposure` (1/1000 s), `linear_fstop`
    /// (2.8), `linear_gamma` (2.2).
    Linear {
        sensitivity: f32,
        exposure: f32,
        fstop: f32,
        gamma: f32,
    },
    /// `reinhard`: `reinhard_prescale` (1), `reinhard_postscale` (1), `reinhard_burn` (7).
    Reinhard {
        prescale: f32,
        postscale: f32,
        burn: f32,
    },
    /// `reinhard` of LuxRender 0.x, with the same parameters.
    ReinhardAbsolute {
        prescale: f32,
        postscale: f32,
        burn: f32,
    },
    /// `contrast`: `contrast_ywa` (50), the display adaptation luminance.
    Contrast { ywa: f32 },
    /// `maxwhite`: the brightest pixel to white.
    MaxWhite,
}

/// The reciprocal of the squared white luminance of Reinhard's curve; LuxRender's 1e5 when the
/// white is not positive (the curve is then L / (1 + L) for any L that matters).
fn inverse_white_squared(white: f32) -> f32 {
    if white > 0.0 {
        1.0 / (white * white)
    } else {
        1e5
    }
}

/// LuxRender 0.x's world adaptation luminance: the sum of the positive pixel luminances over
/// the number of *all* pixels (an arithmetic mean with unlit pixels counted as 0); 1 when none
/// is lit.
fn mean_luminance(pixels: &[Vec3]) -> f32 {
    let sum: f64 = pixels
        .iter()
        .map(|&p| luminance(p))
        .filter(|y| *y > 0.0 && y.is_finite())
        .map(f64::from)
        .sum();
    let mean = (sum / pixels.len().max(1) as f64) as f32;
    if mean > 0.0 { mean } else { 1.0 }
}

/// Reinhard et al.'s key value a, the mid grey a scene's adaptation luminance maps to.
const REINHARD_KEY: f32 = 0.1;

/// The log-average luminance (the geometric mean) of the pixels with positive luminance, as
/// LuxRender's `reinhard` and `contrast` compute it; 1 when none is lit.
fn log_average_luminance(pixels: &[Vec3]) -> f32 {
    let (sum, n) = pixels
        .iter()
        .map(|&p| luminance(p))
        .filter(|y| *y > 0.0 && y.is_finite())
        .fold((0.0f64, 0usize), |(s, n), y| {
            (s + f64::from(y.max(1e-6)).ln(), n + 1)
        });
    if n == 0 {
        1.0
    } else {
        (sum / n as f64).exp() as f32
    }
}

impl ToneMapOp {
    /// Tone maps linear RGB `pixels` in place. Each kernel multiplies a pixel's colour by a
    /// factor (LuxRender scales XYZ; the same factor on linear RGB is the same map, RGB being
    /// linear in XYZ). `gamma` is the display gamma (for `autolinear`).
    pub fn apply(&self, pixels: &mut [Vec3], gamma: f32) {
        match *self {
            ToneMapOp::AutoLinear => {
                let s = exposure_scale(ToneMap::AutoLinear, pixels, gamma);
                pixels.iter_mut().for_each(|p| *p *= s);
            }
            // `tonemaps/lineartonemap.h` (LuxRender 1.x, "taken from the ISO speed article"):
            // factor = exposure / fstop^2 x sensitivity x 0.65 / 10 x (118/255)^gamma.
            ToneMapOp::Linear {
                sensitivity,
                exposure,
                fstop,
                gamma,
            } => {
                let s = exposure / (fstop * fstop) * sensitivity * 0.65 / 10.0
                    * (118.0f32 / 255.0).powf(gamma);
                let s = if s.is_finite() { s } else { 1.0 };
                pixels.iter_mut().for_each(|p| *p *= s);
            }
            // `tonemaps/reinhard.cpp` (LuxRender 1.x, its comment: eq. 4 of Reinhard et al.
            // 2002, "Photographic Tone Reproduction for Digital Images"): with the key a = 0.1
            // and the log-average luminance Y_wa, the scaled luminance L = a Y / Y_wa maps to
            // L (1 + L / burn^2) / (1 + L), so L = burn maps to 1; prescale divides L before
            // the curve, postscale multiplies the result.
            ToneMapOp::Reinhard {
                prescale,
                postscale,
                burn,
            } => {
                let scale = REINHARD_KEY / log_average_luminance(pixels);
                let inv_burn2 = inverse_white_squared(burn);
                let pre = scale / prescale;
                let post = scale * postscale;
                for p in pixels.iter_mut() {
                    let ys = luminance(*p) * pre;
                    *p *= post * (1.0 + ys * inv_burn2) / (1.0 + ys);
                }
            }
            // `tonemaps/reinhard.cpp` of LuxRender 0.x (the `vector<XYZColor>` versions before
            // the `luxrays` colour classes): the same eq. 4, but with the world adaptation Y_wa
            // the arithmetic mean ([`mean_luminance`]) and the curve applied to the absolute
            // luminance Y, its white at Y_w = prescale x 0.1 x burn:
            //   Y' = Y x postscale x prescale x 0.1 / Y_wa x (1 + Y / Y_w^2) / (1 + Y).
            // Below Y ~ 1 it is linear in Y / Y_wa; above, the curve compresses, so the image
            // depends on its absolute scale (LuxRender's film units: `lxs::version`).
            ToneMapOp::ReinhardAbsolute {
                prescale,
                postscale,
                burn,
            } => {
                let inv_white2 = inverse_white_squared(prescale * REINHARD_KEY * burn);
                let scale = postscale * prescale * REINHARD_KEY / mean_luminance(pixels);
                for p in pixels.iter_mut() {
                    let y = luminance(*p);
                    *p *= scale * (1.0 + y * inv_white2) / (1.0 + y);
                }
            }
            // `tonemaps/contrast.cpp` (Ward 1994, "A Contrast-Based Scalefactor for Luminance
            // Display"): s = ((1.219 + ywa^0.4) / (1.219 + Y_wa^0.4))^2.5 / 100, Y_wa the
            // log-average luminance, 100 the display's maximum luminance.
            ToneMapOp::Contrast { ywa } => {
                let world = log_average_luminance(pixels);
                let s =
                    ((1.219 + ywa.powf(0.4)) / (1.219 + world.powf(0.4))).powf(2.5) / MAX_DISPLAY_Y;
                pixels.iter_mut().for_each(|p| *p *= s);
            }
            // `tonemaps/maxwhite.cpp`: divide by the largest luminance.
            ToneMapOp::MaxWhite => {
                let max = pixels
                    .iter()
                    .map(|&p| luminance(p))
                    .filter(|y| y.is_finite())
                    .fold(0.0f32, f32::max);
                if max > 0.0 {
                    pixels.iter_mut().for_each(|p| *p /= max);
                }
            }
        }
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

    fn grey(y: f32) -> Vec3 {
        Vec3::splat(y)
    }

    /// Reinhard et al.'s curve maps L = burn (with prescale 1) to exactly 1, L = 0 to 0, and is
    /// L / (1 + L) as burn grows; postscale multiplies the output.
    #[test]
    fn reinhard_maps_burn_to_white() {
        // Half the pixels at Y = 1, half at Y = 4: Y_wa = 2, so a pixel of luminance
        // Y = burn Y_wa / 0.1 has L = burn.
        let burn = 6.0f32;
        let y_white = burn * 2.0 / 0.1;
        let mut pixels = vec![grey(1.0), grey(4.0), grey(1.0), grey(4.0)];
        let ywa = log_average_luminance(&pixels);
        assert!((ywa - 2.0).abs() < 1e-5, "{ywa}");
        pixels.extend([grey(y_white), Vec3::ZERO]);
        // Recompute with the extra pixels: the black one is skipped, the white one counts.
        let ywa = log_average_luminance(&pixels);
        let l_white = 0.1 * y_white / ywa;
        let mut out = pixels.clone();
        ToneMapOp::Reinhard {
            prescale: 1.0,
            postscale: 1.0,
            burn: l_white,
        }
        .apply(&mut out, 2.2);
        assert!((luminance(out[4]) - 1.0).abs() < 1e-4, "{}", out[4]);
        assert_eq!(out[5], Vec3::ZERO);
        // Large burn: L / (1 + L); postscale 1.2 scales the result.
        let mut out = pixels.clone();
        ToneMapOp::Reinhard {
            prescale: 1.0,
            postscale: 1.2,
            burn: 1e6,
        }
        .apply(&mut out, 2.2);
        let l = 0.1 * 4.0 / ywa;
        assert!((luminance(out[1]) - 1.2 * l / (1.0 + l)).abs() < 1e-5);
        // Colour ratios are kept.
        let mut c = [Vec3::new(0.2, 0.4, 0.8)];
        ToneMapOp::Reinhard {
            prescale: 1.0,
            postscale: 1.0,
            burn: 7.0,
        }
        .apply(&mut c, 2.2);
        assert!((c[0].y / c[0].x - 2.0).abs() < 1e-5 && (c[0].z / c[0].x - 4.0).abs() < 1e-5);
    }

    /// LuxRender 0.x's Reinhard by hand. Two lit pixels (Y = 1 and 3) and two black ones: the
    /// adaptation luminance counts the black ones, Y_wa = (1 + 3) / 4 = 1. With prescale 1,
    /// postscale 1.2 and burn 6 the white is Y_w = 0.1 x 6 = 0.6, and Y maps to
    /// Y x 0.12 x (1 + Y / 0.36) / (1 + Y): 1 -> 0.12 x (1 + 1 / 0.36) / 2 = 0.226667 and
    /// 3 -> 3 x 0.12 x (1 + 3 / 0.36) / 4 = 0.84.
    #[test]
    fn absolute_reinhard_by_hand() {
        let op = ToneMapOp::ReinhardAbsolute {
            prescale: 1.0,
            postscale: 1.2,
            burn: 6.0,
        };
        let mut p = vec![grey(1.0), grey(3.0), Vec3::ZERO, Vec3::ZERO];
        op.apply(&mut p, 2.2);
        assert!((p[0].x - 0.226_667).abs() < 1e-5, "{p:?}");
        assert!((p[1].x - 0.84).abs() < 1e-5, "{p:?}");
        assert_eq!(p[2], Vec3::ZERO);
        // Not scale invariant, unlike 1.x's: the same image at twice the luminance gives
        // Y = 2 -> 2 x 0.06 x (1 + 2 / 0.36) / 3 = 0.262222, not 0.226667.
        let mut doubled = vec![grey(2.0), grey(6.0), Vec3::ZERO, Vec3::ZERO];
        op.apply(&mut doubled, 2.2);
        assert!((doubled[0].x - 0.262_222).abs() < 1e-5, "{doubled:?}");
        // burn 0 (no white): LuxRender's 1e5 for 1 / Y_w^2.
        let mut p = vec![grey(1.0), grey(3.0), Vec3::ZERO, Vec3::ZERO];
        ToneMapOp::ReinhardAbsolute {
            prescale: 1.0,
            postscale: 1.0,
            burn: 0.0,
        }
        .apply(&mut p, 2.2);
        assert!((p[0].x - 0.1 * (1.0 + 1e5) / 2.0).abs() < 1.0, "{p:?}");
    }

    #[test]
    fn linear_contrast_and_maxwhite() {
        // LuxRender's linear defaults: 1/1000 s at f/2.8, ISO 100.
        let mut p = [grey(1.0)];
        ToneMapOp::Linear {
            sensitivity: 100.0,
            exposure: 1e-3,
            fstop: 2.8,
            gamma: 2.2,
        }
        .apply(&mut p, 2.2);
        let expected = 1e-3 / 7.84 * 100.0 * 0.65 / 10.0 * (118.0f32 / 255.0).powf(2.2);
        assert!((p[0].x / expected - 1.0).abs() < 1e-5, "{}", p[0].x);
        // Contrast: a scene whose log-average equals the display adaptation luminance is
        // scaled by 1 / 100 (the display maximum).
        let mut p = vec![grey(10.0), grey(250.0)];
        ToneMapOp::Contrast { ywa: 50.0 }.apply(&mut p, 2.2);
        assert!(
            (p[0].x - 0.1).abs() < 1e-4 && (p[1].x - 2.5).abs() < 1e-3,
            "{p:?}"
        );
        // Max white: the brightest pixel's luminance becomes 1.
        let mut p = vec![grey(0.5), Vec3::new(2.0, 4.0, 1.0), Vec3::ZERO];
        ToneMapOp::MaxWhite.apply(&mut p, 2.2);
        assert!((luminance(p[1]) - 1.0).abs() < 1e-6);
        assert!((p[0].x * luminance(Vec3::new(2.0, 4.0, 1.0)) - 0.5).abs() < 1e-6);
        // A black image stays black and finite under every kernel.
        for op in [
            ToneMapOp::AutoLinear,
            ToneMapOp::Reinhard {
                prescale: 1.0,
                postscale: 1.2,
                burn: 6.0,
            },
            ToneMapOp::ReinhardAbsolute {
                prescale: 1.0,
                postscale: 1.2,
                burn: 6.0,
            },
            ToneMapOp::Contrast { ywa: 50.0 },
            ToneMapOp::MaxWhite,
        ] {
            let mut p = vec![Vec3::ZERO; 4];
            op.apply(&mut p, 2.2);
            assert!(p.iter().all(|v| *v == Vec3::ZERO), "{op:?}");
        }
    }
}
