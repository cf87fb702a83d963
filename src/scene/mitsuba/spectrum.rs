//! Spectra given as wavelength:value pairs, converted to linear sRGB the way Mitsuba 3 (3.9) does in
//! its RGB variants (`spectrum_list_to_srgb` in src/core/spectrum.cpp): the piecewise-linear spectrum
//! is integrated against the CIE 1931 2-degree matching functions at 1000 evenly spaced wavelengths
//! over [360, 830] nm (those outside the given wavelengths count as zero), scaled so that a unit
//! spectrum over the whole range has luminance Y = 1, and mapped XYZ -> linear Rec. 709 / sRGB.
//! A spectrum that is not emission (a reflectance, an index of refraction) is first multiplied by
//! the D65 illuminant normalised to luminance 1: the colour of D65 light it reflects, so that a
//! constant reflectance r gives (r, r, r). Measured against Mitsuba 3.9.1 in the tests.

use glam::DVec3;

const CIE_MIN: f64 = 360.0;
const CIE_MAX: f64 = 830.0;
const STEPS: usize = 1000;

/// 1 / ∫ ȳ(λ) dλ with the tabulated ȳ linearly interpolated, integrated as below; Mitsuba's
/// `MI_CIE_Y_NORMALIZATION`.
const CIE_Y_NORMALIZATION: f64 = 1.0 / 106.750_259_399_414_06;

/// CIE 1931 2-degree colour matching functions, 360 to 830 nm in 5 nm steps (CIE 15:2004 table).
const CIE_X: [f64; 95] = [
    1.299000e-04,
    2.321000e-04,
    4.149000e-04,
    7.416000e-04,
    1.368000e-03,
    2.236000e-03,
    4.243000e-03,
    7.650000e-03,
    1.431000e-02,
    2.319000e-02,
    4.351000e-02,
    7.763000e-02,
    1.343800e-01,
    2.147700e-01,
    2.839000e-01,
    3.285000e-01,
    3.482800e-01,
    3.480600e-01,
    3.362000e-01,
    3.187000e-01,
    2.908000e-01,
    2.511000e-01,
    1.953600e-01,
    1.421000e-01,
    9.564000e-02,
    5.795001e-02,
    3.201000e-02,
    1.470000e-02,
    4.900000e-03,
    2.400000e-03,
    9.300000e-03,
    2.910000e-02,
    6.327000e-02,
    1.096000e-01,
    1.655000e-01,
    2.257499e-01,
    2.904000e-01,
    3.597000e-01,
    4.334499e-01,
    5.120501e-01,
    5.945000e-01,
    6.784000e-01,
    7.621000e-01,
    8.425000e-01,
    9.163000e-01,
    9.786000e-01,
    1.026300e+00,
    1.056700e+00,
    1.062200e+00,
    1.045600e+00,
    1.002600e+00,
    9.384000e-01,
    8.544499e-01,
    7.514000e-01,
    6.424000e-01,
    5.419000e-01,
    4.479000e-01,
    3.608000e-01,
    2.835000e-01,
    2.187000e-01,
    1.649000e-01,
    1.212000e-01,
    8.740000e-02,
    6.360000e-02,
    4.677000e-02,
    3.290000e-02,
    2.270000e-02,
    1.584000e-02,
    1.135916e-02,
    8.110916e-03,
    5.790346e-03,
    4.109457e-03,
    2.899327e-03,
    2.049190e-03,
    1.439971e-03,
    9.999493e-04,
    6.900786e-04,
    4.760213e-04,
    3.323011e-04,
    2.348261e-04,
    1.661505e-04,
    1.174130e-04,
    8.307527e-05,
    5.870652e-05,
    4.150994e-05,
    2.935326e-05,
    2.067383e-05,
    1.455977e-05,
    1.025398e-05,
    7.221456e-06,
    5.085868e-06,
    3.581652e-06,
    2.522525e-06,
    1.776509e-06,
    1.251141e-06,
];
const CIE_Y: [f64; 95] = [
    3.917000e-06,
    6.965000e-06,
    1.239000e-05,
    2.202000e-05,
    3.900000e-05,
    6.400000e-05,
    1.200000e-04,
    2.170000e-04,
    3.960000e-04,
    6.400000e-04,
    1.210000e-03,
    2.180000e-03,
    4.000000e-03,
    7.300000e-03,
    1.160000e-02,
    1.684000e-02,
    2.300000e-02,
    2.980000e-02,
    3.800000e-02,
    4.800000e-02,
    6.000000e-02,
    7.390000e-02,
    9.098000e-02,
    1.126000e-01,
    1.390200e-01,
    1.693000e-01,
    2.080200e-01,
    2.586000e-01,
    3.230000e-01,
    4.073000e-01,
    5.030000e-01,
    6.082000e-01,
    7.100000e-01,
    7.932000e-01,
    8.620000e-01,
    9.148501e-01,
    9.540000e-01,
    9.803000e-01,
    9.949501e-01,
    1.000000e+00,
    9.950000e-01,
    9.786000e-01,
    9.520000e-01,
    9.154000e-01,
    8.700000e-01,
    8.163000e-01,
    7.570000e-01,
    6.949000e-01,
    6.310000e-01,
    5.668000e-01,
    5.030000e-01,
    4.412000e-01,
    3.810000e-01,
    3.210000e-01,
    2.650000e-01,
    2.170000e-01,
    1.750000e-01,
    1.382000e-01,
    1.070000e-01,
    8.160000e-02,
    6.100000e-02,
    4.458000e-02,
    3.200000e-02,
    2.320000e-02,
    1.700000e-02,
    1.192000e-02,
    8.210000e-03,
    5.723000e-03,
    4.102000e-03,
    2.929000e-03,
    2.091000e-03,
    1.484000e-03,
    1.047000e-03,
    7.400000e-04,
    5.200000e-04,
    3.611000e-04,
    2.492000e-04,
    1.719000e-04,
    1.200000e-04,
    8.480000e-05,
    6.000000e-05,
    4.240000e-05,
    3.000000e-05,
    2.120000e-05,
    1.499000e-05,
    1.060000e-05,
    7.465700e-06,
    5.257800e-06,
    3.702900e-06,
    2.607800e-06,
    1.836600e-06,
    1.293400e-06,
    9.109300e-07,
    6.415300e-07,
    4.518100e-07,
];
const CIE_Z: [f64; 95] = [
    6.061000e-04,
    1.086000e-03,
    1.946000e-03,
    3.486000e-03,
    6.450001e-03,
    1.054999e-02,
    2.005001e-02,
    3.621000e-02,
    6.785001e-02,
    1.102000e-01,
    2.074000e-01,
    3.713000e-01,
    6.456000e-01,
    1.039050e+00,
    1.385600e+00,
    1.622960e+00,
    1.747060e+00,
    1.782600e+00,
    1.772110e+00,
    1.744100e+00,
    1.669200e+00,
    1.528100e+00,
    1.287640e+00,
    1.041900e+00,
    8.129501e-01,
    6.162000e-01,
    4.651800e-01,
    3.533000e-01,
    2.720000e-01,
    2.123000e-01,
    1.582000e-01,
    1.117000e-01,
    7.824999e-02,
    5.725001e-02,
    4.216000e-02,
    2.984000e-02,
    2.030000e-02,
    1.340000e-02,
    8.749999e-03,
    5.749999e-03,
    3.900000e-03,
    2.749999e-03,
    2.100000e-03,
    1.800000e-03,
    1.650001e-03,
    1.400000e-03,
    1.100000e-03,
    1.000000e-03,
    8.000000e-04,
    6.000000e-04,
    3.400000e-04,
    2.400000e-04,
    1.900000e-04,
    1.000000e-04,
    4.999999e-05,
    3.000000e-05,
    2.000000e-05,
    1.000000e-05,
    0.000000e+00,
    0.000000e+00,
    0.000000e+00,
    0.000000e+00,
    0.000000e+00,
    0.000000e+00,
    0.000000e+00,
    0.000000e+00,
    0.000000e+00,
    0.000000e+00,
    0.000000e+00,
    0.000000e+00,
    0.000000e+00,
    0.000000e+00,
    0.000000e+00,
    0.000000e+00,
    0.000000e+00,
    0.000000e+00,
    0.000000e+00,
    0.000000e+00,
    0.000000e+00,
    0.000000e+00,
    0.000000e+00,
    0.000000e+00,
    0.000000e+00,
    0.000000e+00,
    0.000000e+00,
    0.000000e+00,
    0.000000e+00,
    0.000000e+00,
    0.000000e+00,
    0.000000e+00,
    0.000000e+00,
    0.000000e+00,
    0.000000e+00,
    0.000000e+00,
    0.000000e+00,
];

/// The CIE D65 illuminant, 360 to 830 nm in 5 nm steps, relative to 100 at 560 nm (CIE 15:2004).
const CIE_D65: [f64; 95] = [
    46.6383, 49.3637, 52.0891, 51.0323, 49.9755, 52.3118, 54.6482, 68.7015, 82.7549, 87.1204,
    91.486, 92.4589, 93.4318, 90.057, 86.6823, 95.7736, 104.865, 110.936, 117.008, 117.41, 117.812,
    116.336, 114.861, 115.392, 115.923, 112.367, 108.811, 109.082, 109.354, 108.578, 107.802,
    106.296, 104.79, 106.239, 107.689, 106.047, 104.405, 104.225, 104.046, 102.023, 100.0, 98.1671,
    96.3342, 96.0611, 95.788, 92.2368, 88.6856, 89.3459, 90.0062, 89.8026, 89.5991, 88.6489,
    87.6987, 85.4936, 83.2886, 83.4939, 83.6992, 81.863, 80.0268, 80.1207, 80.2146, 81.2462,
    82.2778, 80.281, 78.2842, 74.0027, 69.7213, 70.6652, 71.6091, 72.979, 74.349, 67.9765, 61.604,
    65.7448, 69.8856, 72.4863, 75.087, 69.3398, 63.5927, 55.0054, 46.4182, 56.6118, 66.8054,
    65.0941, 63.3828, 63.8434, 64.304, 61.8779, 59.4519, 55.7054, 51.959, 54.6998, 57.4406,
    58.8765, 60.3125,
];

/// 1 / ∫ D65(λ) ȳ(λ) dλ / ∫ ȳ(λ) dλ, so that D65 has luminance 1 (Mitsuba's `MI_CIE_D65_NORMALIZATION`).
const CIE_D65_NORMALIZATION: f64 = 1.0 / 98.997_417_518_762_55;

/// The matching functions at `lambda` nm, linearly interpolated between the 5 nm samples.
fn cie_xyz(lambda: f64) -> DVec3 {
    if !(CIE_MIN..=CIE_MAX).contains(&lambda) {
        return DVec3::ZERO;
    }
    DVec3::new(
        interpolate(&CIE_X, lambda),
        interpolate(&CIE_Y, lambda),
        interpolate(&CIE_Z, lambda),
    )
}

/// A 5 nm table at `lambda` in [360, 830] nm, linearly interpolated.
fn interpolate(table: &[f64; 95], lambda: f64) -> f64 {
    let t = (lambda - CIE_MIN) * ((table.len() - 1) as f64 / (CIE_MAX - CIE_MIN));
    let i = (t as usize).min(table.len() - 2);
    let f = t - i as f64;
    (1.0 - f) * table[i] + f * table[i + 1]
}

/// XYZ to linear sRGB (Rec. 709 primaries, D65 white), the matrix Mitsuba uses.
pub fn xyz_to_linear_srgb(xyz: DVec3) -> DVec3 {
    DVec3::new(
        3.240479 * xyz.x - 1.537150 * xyz.y - 0.498535 * xyz.z,
        -0.969256 * xyz.x + 1.875991 * xyz.y + 0.041556 * xyz.z,
        0.055648 * xyz.x - 0.204043 * xyz.y + 1.057311 * xyz.z,
    )
}

/// What a spectrum measures, which decides how it is converted.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SpectrumKind {
    /// A reflectance: weighted by D65, clamped to [0, 1].
    Reflectance,
    /// An index of refraction (`eta`, `k`, `int_ior`, `ext_ior`): weighted by D65, negative
    /// components clamped to 0.
    Unbounded,
    /// Emitted radiance (inside an `<emitter>`): not weighted, negative components clamped to 0.
    Emission,
}

/// The linear sRGB colour of the piecewise-linear spectrum through (`wavelengths[i]`, `values[i]`),
/// and whether it had to be clamped into gamut. `wavelengths` must increase and hold at least two.
pub fn sampled_to_rgb(wavelengths: &[f64], values: &[f64], kind: SpectrumKind) -> (DVec3, bool) {
    debug_assert!(wavelengths.len() >= 2 && wavelengths.len() == values.len());
    let (first, last) = (wavelengths[0], wavelengths[wavelengths.len() - 1]);
    let mut xyz = DVec3::ZERO;
    for i in 0..STEPS {
        let lambda = CIE_MIN + (i as f64 / (STEPS - 1) as f64) * (CIE_MAX - CIE_MIN);
        if lambda < first || lambda > last {
            continue;
        }
        // The interval [w0, w1] holding lambda: the last sample at or below it, not the last one.
        let k = (wavelengths.partition_point(|&w| w <= lambda) - 1).min(wavelengths.len() - 2);
        let (w0, w1) = (wavelengths[k], wavelengths[k + 1]);
        let (v0, v1) = (values[k], values[k + 1]);
        let mut v = v0 + (v1 - v0) * (lambda - w0) / (w1 - w0);
        if kind != SpectrumKind::Emission {
            v *= interpolate(&CIE_D65, lambda) * CIE_D65_NORMALIZATION;
        }
        xyz += cie_xyz(lambda) * (v * CIE_Y_NORMALIZATION);
    }
    xyz *= (CIE_MAX - CIE_MIN) / STEPS as f64;
    let rgb = xyz_to_linear_srgb(xyz);
    let clamped = match kind {
        SpectrumKind::Reflectance => rgb.clamp(DVec3::ZERO, DVec3::ONE),
        SpectrumKind::Unbounded | SpectrumKind::Emission => rgb.max(DVec3::ZERO),
    };
    (clamped, clamped != rgb)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn luminance(rgb: DVec3) -> f64 {
        // Rec. 709 luminance: the Y row of the inverse of the matrix above.
        0.212671 * rgb.x + 0.715160 * rgb.y + 0.072169 * rgb.z
    }

    #[test]
    fn unit_spectrum_over_the_whole_range_has_unit_luminance() {
        let (rgb, _) = sampled_to_rgb(&[CIE_MIN, CIE_MAX], &[1.0, 1.0], SpectrumKind::Emission);
        assert!((luminance(rgb) - 1.0).abs() < 1e-3, "{rgb}");
    }

    #[test]
    fn luminance_scales_linearly_and_clamps_by_gamut() {
        let (half, _) = sampled_to_rgb(&[CIE_MIN, CIE_MAX], &[0.5, 0.5], SpectrumKind::Emission);
        let (full, _) = sampled_to_rgb(&[CIE_MIN, CIE_MAX], &[1.0, 1.0], SpectrumKind::Emission);
        assert!((half * 2.0 - full).length() < 1e-9);
        // Flat emission is slightly red in sRGB (equal-energy white is not D65); a flat reflectance
        // reflects D65 unchanged, which is white.
        assert!(full.x > 1.01 && full.z < 0.99, "{full}");
        let (white, _) =
            sampled_to_rgb(&[CIE_MIN, CIE_MAX], &[0.5, 0.5], SpectrumKind::Reflectance);
        assert!(
            (white - DVec3::splat(0.5)).abs().max_element() < 2e-3,
            "{white}"
        );
        // A reflectance is clamped to 1, an emission is not.
        let (one, clamped) =
            sampled_to_rgb(&[CIE_MIN, CIE_MAX], &[1.5, 1.5], SpectrumKind::Reflectance);
        assert!(clamped && one.max_element() == 1.0, "{one}");
    }

    #[test]
    fn only_the_given_range_counts() {
        // A spike between 595 and 605 nm is orange-red: R > G > B, and nothing outside it.
        let (rgb, _) = sampled_to_rgb(
            &[595.0, 600.0, 605.0],
            &[0.0, 1.0, 0.0],
            SpectrumKind::Emission,
        );
        let y = luminance(rgb);
        // Y of a triangle of height 1 and base 10 nm at ȳ(600) = 0.631: about 5 * 0.631 / 106.75.
        assert!(
            (y - 5.0 * 0.631 * CIE_Y_NORMALIZATION).abs() < 0.1 * y,
            "{y}"
        );
        assert!(rgb.x > rgb.y && rgb.y >= rgb.z, "{rgb}");
    }
}
