//! LuxRender's `blackbody` colour texture (`textures/blackbody.h`, `core/spds/blackbodyspd.cpp`):
//! Planck's law at `temperature` kelvin, sampled over 380-720 nm and normalised so that its
//! largest sample is 1, then (foton renders in RGB) projected to CIE XYZ and to linear sRGB.

use glam::{Mat3, Vec3};

/// LuxRender's wavelength range for the blackbody SPD, in nm.
const LAMBDA_MIN: f32 = 380.0;
const LAMBDA_MAX: f32 = 720.0;
/// Integration steps over the range (1 nm).
const STEPS: usize = 340;

/// Planck's spectral radiance at wavelength `nm` and temperature `kelvin`, up to a constant:
/// lambda^-5 / (exp(c2 / (lambda T)) - 1), c2 = hc / k = 1.4388e-2 m K.
fn planck(nm: f32, kelvin: f32) -> f64 {
    let lambda = f64::from(nm) * 1e-9;
    lambda.powi(-5) / ((1.4388e-2 / (lambda * f64::from(kelvin))).exp() - 1.0)
}

/// The normalised SPD: Planck's law divided by its maximum over [380, 720] nm. Planck's law
/// rises up to Wien's peak, 2.8978e6 / T nm, and falls after it, so the maximum is at the peak
/// or at the nearer end of the range.
pub fn blackbody_spd(nm: f32, kelvin: f32) -> f32 {
    let peak = (2.897_772e6 / kelvin).clamp(LAMBDA_MIN, LAMBDA_MAX);
    (planck(nm, kelvin) / planck(peak, kelvin)) as f32
}

/// A piecewise Gaussian lobe, the building block of Wyman, Sloan and Shirley 2013, "Simple
/// Analytic Approximations to the CIE XYZ Color Matching Functions" (JCGT 2(2)), eq. 2.
fn lobe(nm: f32, mu: f32, sigma_below: f32, sigma_above: f32) -> f32 {
    let sigma = if nm < mu { sigma_below } else { sigma_above };
    (-0.5 * ((nm - mu) / sigma).powi(2)).exp()
}

/// The CIE 1931 2-degree colour matching functions (x, y, z) at `nm`, by Wyman et al.'s
/// multi-lobe fit (their eq. 2 and table 1; within about 1% of the tabulated functions).
pub fn cie_xyz(nm: f32) -> Vec3 {
    Vec3::new(
        1.056 * lobe(nm, 599.8, 37.9, 31.0) + 0.362 * lobe(nm, 442.0, 16.0, 26.7)
            - 0.065 * lobe(nm, 501.1, 20.4, 26.2),
        0.821 * lobe(nm, 568.8, 46.9, 40.5) + 0.286 * lobe(nm, 530.9, 16.3, 31.1),
        1.217 * lobe(nm, 437.0, 11.8, 36.0) + 0.681 * lobe(nm, 459.0, 26.0, 13.8),
    )
}

/// XYZ (D65) to linear sRGB (IEC 61966-2-1).
pub const XYZ_TO_SRGB: Mat3 = Mat3::from_cols(
    Vec3::new(3.240_454_2, -0.969_266, 0.055_643_4),
    Vec3::new(-1.537_138_5, 1.876_010_8, -0.204_025_9),
    Vec3::new(-0.498_531_4, 0.041_556, 1.057_225_2),
);

/// The XYZ colour of the normalised SPD (see [`spectrum_xyz`]).
pub fn blackbody_xyz(kelvin: f32) -> Vec3 {
    if !(kelvin > 0.0 && kelvin.is_finite()) {
        return Vec3::ZERO;
    }
    spectrum_xyz(|nm| blackbody_spd(nm, kelvin))
}

/// The XYZ colour of a spectrum `spd` (a function of the wavelength in nm): the integral of
/// SPD x CMF over [380, 720] nm divided by that of the y CMF, so that a flat SPD of 1 has Y = 1
/// (how a spectral renderer's Y of a reflectance spectrum is defined).
pub fn spectrum_xyz(spd: impl Fn(f32) -> f32) -> Vec3 {
    let step = (LAMBDA_MAX - LAMBDA_MIN) / STEPS as f32;
    let (mut xyz, mut y_norm) = (Vec3::ZERO, 0.0);
    for i in 0..STEPS {
        let nm = LAMBDA_MIN + (i as f32 + 0.5) * step;
        let cmf = cie_xyz(nm);
        xyz += spd(nm) * cmf;
        y_norm += cmf.y;
    }
    xyz / y_norm
}

/// The linear sRGB colour of a blackbody at `kelvin` (0 for a non-positive temperature);
/// negative components (colours outside the sRGB gamut) are clamped to 0.
pub fn blackbody_rgb(kelvin: f32) -> Vec3 {
    (XYZ_TO_SRGB * blackbody_xyz(kelvin)).max(Vec3::ZERO)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The SPD's maximum is 1, at Wien's peak when it lies in the range.
    #[test]
    fn spd_peaks_at_one() {
        for kelvin in [5000.0f32, 6500.0, 7500.0] {
            let peak = 2.897_772e6 / kelvin;
            assert!((blackbody_spd(peak, kelvin) - 1.0).abs() < 1e-6);
            assert!(blackbody_spd(peak - 20.0, kelvin) < 1.0);
            assert!(blackbody_spd(peak + 20.0, kelvin) < 1.0);
        }
        // 2000 K peaks in the infrared: the largest sample is the last one, 720 nm.
        assert!((blackbody_spd(720.0, 2000.0) - 1.0).abs() < 1e-6);
        assert!(blackbody_spd(600.0, 2000.0) < 0.5);
    }

    /// The chromaticities of the Planckian locus from the CIE tables: 2856 K (illuminant A)
    /// (0.4476, 0.4074) and 6504 K (0.3135, 0.3236). Tolerance 0.0025 (measured error 0.0012): the analytic CMF fit
    /// and the 380-720 nm range (the CMFs' tails beyond it hold under 0.1% of Y) move them
    /// by about that much.
    #[test]
    fn chromaticity_on_the_planckian_locus() {
        for (kelvin, x, y) in [(2856.0, 0.4476, 0.4074), (6504.0, 0.3135, 0.3236)] {
            let xyz = blackbody_xyz(kelvin);
            let sum = xyz.x + xyz.y + xyz.z;
            let (cx, cy) = (xyz.x / sum, xyz.y / sum);
            println!("{kelvin} K: ({cx}, {cy})");
            assert!(
                (cx - x).abs() < 4e-3 && (cy - y).abs() < 4e-3,
                "{kelvin}: {cx} {cy}"
            );
        }
    }

    #[test]
    fn colour_warms_as_temperature_falls() {
        let warm = blackbody_rgb(2000.0);
        assert!(warm.x > warm.y && warm.y > warm.z, "{warm}");
        let cool = blackbody_rgb(12000.0);
        assert!(cool.z > cool.x, "{cool}");
        // Near D65, the sRGB white point, the channels nearly agree.
        let white = blackbody_rgb(6504.0);
        assert!(white.max_element() / white.min_element() < 1.1, "{white}");
        assert_eq!(blackbody_rgb(0.0), Vec3::ZERO);
        assert_eq!(blackbody_rgb(f32::NAN), Vec3::ZERO);
    }
}
