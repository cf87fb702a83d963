//! LuxRender's `sun` (and the sun of `sunsky`): the solar spectrum outside the atmosphere
//! attenuated along the sun's path through it, after Preetham, Shirley and Smits 1999, "A
//! Practical Analytic Model for Daylight" (SIGGRAPH), appendix A.3, as LuxRender 1.x computes
//! it in `lights/sun.cpp` (its tables, `lights/data/sun_spect.h`, are from Iqbal 1983, "An
//! Introduction to Solar Radiation").
//!
//! With the relative optical mass of the air along the sun's path at zenith angle theta_s
//! (Kasten's formula, the paper's eq. A.3)
//!   m = 1 / (cos theta_s + 0.00094 (1.6386 - theta_s)^-1.253),
//! the spectral radiance at wavelength lambda (in micrometres in the formulas) is the
//! extraterrestrial radiance times five transmittances:
//!   Rayleigh scattering   tau_R  = exp(-m 0.008735 lambda^-4.08)
//!   aerosols (Angstrom)   tau_a  = exp(-m beta lambda^-alpha), alpha = 1.3,
//!                                   beta = 0.04608365822050 T - 0.04586025928522
//!   ozone                 tau_o  = exp(-m k_o(lambda) l), l = 0.35 cm
//!   mixed gases           tau_g  = exp(-1.41 k_g m / (1 + 118.93 k_g m)^0.45)
//!   water vapour          tau_wa = exp(-0.2385 k_wa w m / (1 + 20.07 k_wa w m)^0.45), w = 2 cm
//! (T: the turbidity). The extraterrestrial radiance is in W m^-2 sr^-1 nm^-1 (about 2.7e4 at
//! 500 nm: the solar constant's 1.9 W m^-2 nm^-1 over the disc's 6.8e-5 sr), so the luminance
//! is 683 lm/W times the integral of L(lambda) y(lambda) d lambda, in cd/m^2: the unit of the
//! sky's luminance ([`super::sky`]), so sun and sky keep their physical ratio. LuxRender renders
//! the spectrum; foton projects it to CIE XYZ and linear sRGB.
//!
//! The light is the sun's disc ([`crate::light::sun_disc`]): this radiance inside the cone
//! the disc subtends, sampled uniformly, seen by escaped rays (soft shadows, the sun in
//! mirrors). `relsize` 0 is LuxRender's older point-like sun, a delta distant light.

use std::f32::consts::FRAC_PI_2;

use glam::Vec3;

use crate::texture::blackbody::{XYZ_TO_SRGB, spectrum_xyz};

/// Ozone absorption coefficient k_o (1/cm) at wavelengths in nm (Iqbal p. 127; LuxRender's
/// `sun_k_o*`, whose 65th amplitude has no wavelength and is unused).
const OZONE: [(f32, f32); 64] = [
    (300.0, 10.0),
    (305.0, 4.8),
    (310.0, 2.7),
    (315.0, 1.35),
    (320.0, 0.8),
    (325.0, 0.38),
    (330.0, 0.16),
    (335.0, 0.075),
    (340.0, 0.04),
    (345.0, 0.019),
    (350.0, 0.007),
    (355.0, 0.0),
    (445.0, 0.003),
    (450.0, 0.003),
    (455.0, 0.004),
    (460.0, 0.006),
    (465.0, 0.008),
    (470.0, 0.009),
    (475.0, 0.012),
    (480.0, 0.014),
    (485.0, 0.017),
    (490.0, 0.021),
    (495.0, 0.025),
    (500.0, 0.03),
    (505.0, 0.035),
    (510.0, 0.04),
    (515.0, 0.045),
    (520.0, 0.048),
    (525.0, 0.057),
    (530.0, 0.063),
    (535.0, 0.07),
    (540.0, 0.075),
    (545.0, 0.08),
    (550.0, 0.085),
    (555.0, 0.095),
    (560.0, 0.103),
    (565.0, 0.11),
    (570.0, 0.12),
    (575.0, 0.122),
    (580.0, 0.12),
    (585.0, 0.118),
    (590.0, 0.115),
    (595.0, 0.12),
    (600.0, 0.125),
    (605.0, 0.13),
    (610.0, 0.12),
    (620.0, 0.105),
    (630.0, 0.09),
    (640.0, 0.079),
    (650.0, 0.067),
    (660.0, 0.057),
    (670.0, 0.048),
    (680.0, 0.036),
    (690.0, 0.028),
    (700.0, 0.023),
    (710.0, 0.018),
    (720.0, 0.014),
    (730.0, 0.011),
    (740.0, 0.01),
    (750.0, 0.009),
    (760.0, 0.007),
    (770.0, 0.004),
    (780.0, 0.0),
    (790.0, 0.0),
];

/// Mixed gases (oxygen's A band) absorption coefficient k_g (1/cm) (Iqbal p. 130).
const MIXED_GASES: [(f32, f32); 4] = [(759.0, 0.0), (760.0, 3.0), (770.0, 0.21), (771.0, 0.0)];

/// Water vapour absorption coefficient k_wa (1/cm) (Iqbal p. 130).
const WATER_VAPOUR: [(f32, f32); 13] = [
    (689.0, 0.0),
    (690.0, 0.016),
    (700.0, 0.024),
    (710.0, 0.0125),
    (720.0, 1.0),
    (730.0, 0.87),
    (740.0, 0.061),
    (750.0, 0.001),
    (760.0, 1e-5),
    (770.0, 1e-5),
    (780.0, 6e-4),
    (790.0, 0.0175),
    (800.0, 0.036),
];

/// The sun's spectral radiance outside the atmosphere, W m^-2 sr^-1 nm^-1, from 380 nm every
/// 10 nm to 750 nm (Preetham et al. table 2; LuxRender's `sun_solAmplitudes`).
const EXTRATERRESTRIAL: [f32; 38] = [
    16550.0, 16230.0, 21120.0, 25880.0, 25820.0, 24230.0, 26760.0, 29660.0, 30540.0, 30060.0,
    30660.0, 28830.0, 28710.0, 27820.0, 27100.0, 27230.0, 26360.0, 25500.0, 25060.0, 25310.0,
    25350.0, 25130.0, 24630.0, 24170.0, 23680.0, 23210.0, 22820.0, 22340.0, 21970.0, 21530.0,
    21100.0, 20730.0, 20240.0, 19870.0, 19430.0, 19070.0, 18630.0, 18260.0,
];

/// The maximum luminous efficacy of radiation, lm/W (CIE), and the integral of the CIE 1931
/// y function in nm: [`spectrum_xyz`] gives the mean of L weighted by y, so its Y times both
/// is 683 times the integral of L y.
const LUMENS_PER_WATT: f32 = 683.0;
const Y_INTEGRAL_NM: f32 = 106.857;

/// The sun's radius and mean distance, km (LuxRender's values, from NASA's fact sheet).
const SUN_RADIUS_KM: f32 = 695_500.0;
const SUN_DISTANCE_KM: f32 = 149_600_000.0;

/// A table linearly interpolated between its wavelengths, 0 outside them (as LuxRender's
/// `IrregularSPD`).
fn interpolate(table: &[(f32, f32)], nm: f32) -> f32 {
    let i = table.partition_point(|&(w, _)| w <= nm);
    if i == 0 || i == table.len() && nm > table[i - 1].0 {
        return 0.0;
    }
    if i == table.len() {
        return table[i - 1].1;
    }
    let ((w0, v0), (w1, v1)) = (table[i - 1], table[i]);
    v0 + (v1 - v0) * (nm - w0) / (w1 - w0)
}

/// The extraterrestrial radiance at `nm`, linear between its 10 nm samples, 0 outside
/// 380-750 nm (LuxRender's `RegularSPD`).
fn extraterrestrial(nm: f32) -> f32 {
    let x = (nm - 380.0) / 10.0;
    if !(0.0..=(EXTRATERRESTRIAL.len() - 1) as f32).contains(&x) {
        return 0.0;
    }
    let i = (x as usize).min(EXTRATERRESTRIAL.len() - 2);
    let t = x - i as f32;
    EXTRATERRESTRIAL[i] * (1.0 - t) + EXTRATERRESTRIAL[i + 1] * t
}

/// The sun's spectral radiance (W m^-2 sr^-1 nm^-1) at `nm` on the ground, the sun at zenith
/// angle `theta_s` (radians, at most pi/2), for `turbidity` (the module's formulas).
pub fn sun_spectral_radiance(nm: f32, theta_s: f32, turbidity: f32) -> f32 {
    let m = 1.0 / (theta_s.cos() + 0.00094 * (1.6386 - theta_s).powf(-1.253));
    let beta = 0.046_083_66 * turbidity - 0.045_860_26;
    let um = nm / 1000.0;
    let rayleigh = (-m * 0.008735 * um.powf(-4.08)).exp();
    let aerosol = (-m * beta * um.powf(-1.3)).exp();
    let ozone = (-m * interpolate(&OZONE, nm) * 0.35).exp();
    let k_g = interpolate(&MIXED_GASES, nm) * m;
    let mixed_gases = (-1.41 * k_g / (1.0 + 118.93 * k_g).powf(0.45)).exp();
    let k_wa = interpolate(&WATER_VAPOUR, nm) * 2.0 * m;
    let water_vapour = (-0.2385 * k_wa / (1.0 + 20.07 * k_wa).powf(0.45)).exp();
    extraterrestrial(nm) * rayleigh * aerosol * ozone * mixed_gases * water_vapour
}

/// The sun's radiance in linear sRGB, luminance in cd/m^2, at zenith angle `theta_s`; black
/// below the horizon (Kasten's air mass has its pole at 93.9 degrees; LuxRender's light is
/// NaN there, and the ground hides it anyway).
pub fn sun_radiance(theta_s: f32, turbidity: f32) -> Vec3 {
    if theta_s.is_nan() || theta_s > FRAC_PI_2 {
        return Vec3::ZERO;
    }
    let xyz = spectrum_xyz(|nm| sun_spectral_radiance(nm, theta_s, turbidity))
        * (LUMENS_PER_WATT * Y_INTEGRAL_NM);
    (XYZ_TO_SRGB * xyz).max(Vec3::ZERO)
}

/// The sine of the half-angle of the cone that the sun's disc `relsize` times its real size
/// (0.53 degrees across) subtends: sin theta_max = relsize r / d (`SunLight`'s constructor).
/// `None` when the disc would exceed a hemisphere (relsize above d / r = 215), which LuxRender
/// clamps to one (with a warning).
pub fn sun_sin_theta_max(relsize: f32) -> Option<f32> {
    let sin_theta_max = relsize.abs() * SUN_RADIUS_KM / SUN_DISTANCE_KM;
    (sin_theta_max <= 1.0).then_some(sin_theta_max)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::film::luminance;

    fn close(a: f32, b: f32, tolerance: f32) -> bool {
        (a / b - 1.0).abs() < tolerance
    }

    /// The spectral radiance against the module's formulas evaluated independently (Python,
    /// double precision, the tables typed in again from LuxRender's `sun_spect.h`): T = 2 with
    /// the sun overhead, and T = 2 and 6 with the sun 30 degrees high.
    #[test]
    fn spectral_radiance_is_the_papers() {
        let sixty = 60f32.to_radians();
        for (nm, theta_s, turbidity, expected) in [
            (550.0, 0.0, 2.0, 20250.45),
            (450.0, 0.0, 2.0, 20720.1),
            (650.0, 0.0, 2.0, 19130.57),
            (550.0, sixty, 2.0, 16104.69),
            (450.0, sixty, 2.0, 14507.16),
            (550.0, sixty, 6.0, 7242.947),
            (450.0, sixty, 6.0, 5141.704),
            (650.0, sixty, 6.0, 8619.84),
        ] {
            let value = sun_spectral_radiance(nm, theta_s, turbidity);
            assert!(
                close(value, expected, 1e-4),
                "{nm} nm, theta_s {theta_s}, T {turbidity}: {value} against {expected}"
            );
        }
    }

    /// The RGB radiance against the same Python computation projected with Wyman et al.'s CIE
    /// fit (trapezoids every 0.25 nm, where foton takes 1 nm midpoints) and the sRGB matrix:
    /// the sun overhead at T = 2 is about 1.5e9 cd/m^2, the real sun's luminance.
    #[test]
    fn rgb_is_the_papers() {
        let sixty = 60f32.to_radians();
        for (theta_s, turbidity, expected) in [
            (0.0, 2.0, Vec3::new(1.679_863e9, 1.461_176e9, 1.304_442e9)),
            (sixty, 2.0, Vec3::new(1.409_624e9, 1.157_91e9, 0.900_687e9)),
            (sixty, 6.0, Vec3::new(0.731_959e9, 0.513_177e9, 0.309_620e9)),
        ] {
            let rgb = sun_radiance(theta_s, turbidity);
            for (c, e) in rgb.to_array().into_iter().zip(expected.to_array()) {
                assert!(
                    close(c, e, 0.005),
                    "theta_s {theta_s}, T {turbidity}: {rgb}"
                );
            }
        }
    }

    /// Haze and a low sun lengthen the path through the air: the sun is dimmer and redder
    /// (more red than blue in proportion) at higher turbidity and at lower elevation.
    #[test]
    fn haze_and_low_sun_are_redder_and_dimmer() {
        let redness = |c: Vec3| c.x / c.z;
        let high = sun_radiance(30f32.to_radians(), 2.0);
        let hazy = sun_radiance(30f32.to_radians(), 5.0);
        let low = sun_radiance(80f32.to_radians(), 2.0);
        for other in [hazy, low] {
            assert!(luminance(other) < luminance(high), "{other} {high}");
            assert!(redness(other) > redness(high), "{other} {high}");
        }
        assert_eq!(sun_radiance(95f32.to_radians(), 2.0), Vec3::ZERO);
    }

    /// The real sun subtends 0.533 degrees: a cone of half-angle asin(695500 / 149.6e6) =
    /// 0.2664 degrees; the sine grows with relsize, and is refused beyond a hemisphere.
    #[test]
    fn half_angle_of_the_disc() {
        let one = sun_sin_theta_max(1.0).unwrap();
        assert!(close(one.asin().to_degrees(), 0.2664, 1e-3), "{one}");
        assert!(close(sun_sin_theta_max(10.0).unwrap() / one, 10.0, 1e-5));
        assert!(close(sun_sin_theta_max(215.0).unwrap(), 1.0, 0.01));
        assert_eq!(sun_sin_theta_max(0.0), Some(0.0));
        assert_eq!(sun_sin_theta_max(300.0), None);
    }
}
