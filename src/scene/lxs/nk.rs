//! The complex refractive index n + i k of LuxRender's `metal`: its built-in tables and the
//! `.nk` files it reads (LuxRender 1.x `materials/metal.cpp`: `IORFromName`, `ReadSOPRAData`,
//! `ReadLuxpopData`), and their projection to foton's RGB.
//!
//! LuxRender renders spectrally and evaluates n(lambda) and k(lambda) at each wavelength.
//! foton is RGB: each of n and k is treated as a spectrum and projected like a reflectance
//! (integrated against the CIE 1931 colour matching functions, to linear sRGB), with each channel
//! divided by that of a flat spectrum of 1, so that a constant index keeps its value in every
//! channel. The exact complex Fresnel term is then evaluated per channel
//! (`MaterialDesc::Conductor`).

use std::path::Path;

use glam::Vec3;

use crate::texture::blackbody::{XYZ_TO_SRGB, spectrum_xyz};

/// One sample of a measured index: wavelength in nm, n, k.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NkSample {
    pub nm: f32,
    pub n: f32,
    pub k: f32,
}

/// The wavelengths (nm) of LuxRender's SOPRA tables (silver, gold, copper, aluminium), with
/// LuxRender's digits (more than an f32 holds).
#[allow(clippy::excessive_precision)]
const SOPRA_NM: [f32; 56] = [
    298.757_06, 302.400_43, 306.133_77, 309.960_45, 313.884, 317.908_15, 322.036_83, 326.274_15,
    330.624_48, 335.092_37, 339.682_68, 344.400_5, 349.251_2, 354.240_5, 359.374_43, 364.659_35,
    370.102_02, 375.709_63, 381.489_78, 387.450_56, 393.600_56, 399.948_97, 406.505_5, 413.280_6,
    420.285_35, 427.531_65, 435.032_2, 442.800_63, 450.851_56, 459.200_65, 467.864_8, 476.862_22,
    486.212_46, 495.936_7, 506.057_86, 516.600_7, 527.592_25, 539.061_65, 551.040_8, 563.564_45,
    576.670_6, 590.400_85, 604.800_87, 619.920_9, 635.816_3, 652.548_3, 670.184_75, 688.801,
    708.481, 729.318_7, 751.419_25, 774.901_1, 799.897_9, 826.561_2, 855.063_3, 885.601_25,
];

const SILVER_N: [f32; 56] = [
    1.519, 1.496, 1.4325, 1.323, 1.142062, 0.932, 0.719062, 0.526, 0.388125, 0.294, 0.253313,
    0.238, 0.221438, 0.209, 0.194813, 0.186, 0.192063, 0.2, 0.198063, 0.192, 0.182, 0.173,
    0.172625, 0.173, 0.166688, 0.16, 0.1585, 0.157, 0.151063, 0.144, 0.137313, 0.132, 0.13025,
    0.13, 0.129938, 0.13, 0.130063, 0.129, 0.124375, 0.12, 0.119313, 0.121, 0.1255, 0.131,
    0.136125, 0.14, 0.140063, 0.14, 0.144313, 0.148, 0.145875, 0.143, 0.142563, 0.145, 0.151938,
    0.163,
];
const SILVER_K: [f32; 56] = [
    1.08, 0.882, 0.761063, 0.647, 0.550875, 0.504, 0.554375, 0.663, 0.818563, 0.986, 1.120687,
    1.24, 1.34525, 1.44, 1.53375, 1.61, 1.641875, 1.67, 1.735, 1.81, 1.87875, 1.95, 2.029375, 2.11,
    2.18625, 2.26, 2.329375, 2.4, 2.47875, 2.56, 2.64, 2.72, 2.798125, 2.88, 2.97375, 3.07,
    3.159375, 3.25, 3.348125, 3.45, 3.55375, 3.66, 3.76625, 3.88, 4.010625, 4.15, 4.293125, 4.44,
    4.58625, 4.74, 4.908125, 5.09, 5.28875, 5.5, 5.720624, 5.95,
];
const GOLD_N: [f32; 56] = [
    1.795, 1.812, 1.822625, 1.83, 1.837125, 1.84, 1.83425, 1.824, 1.812, 1.798, 1.782, 1.766,
    1.7525, 1.74, 1.727625, 1.716, 1.705875, 1.696, 1.68475, 1.674, 1.666, 1.658, 1.64725, 1.636,
    1.628, 1.616, 1.59625, 1.562, 1.502125, 1.426, 1.345875, 1.242, 1.08675, 0.916, 0.7545, 0.608,
    0.49175, 0.402, 0.3455, 0.306, 0.267625, 0.236, 0.212375, 0.194, 0.17775, 0.166, 0.161, 0.16,
    0.160875, 0.164, 0.1695, 0.176, 0.181375, 0.188, 0.198125, 0.21,
];
const GOLD_K: [f32; 56] = [
    1.920375, 1.92, 1.918875, 1.916, 1.911375, 1.904, 1.891375, 1.878, 1.86825, 1.86, 1.85175,
    1.846, 1.84525, 1.848, 1.852375, 1.862, 1.883, 1.906, 1.9225, 1.936, 1.94775, 1.956, 1.959375,
    1.958, 1.951375, 1.94, 1.9245, 1.904, 1.875875, 1.846, 1.814625, 1.796, 1.797375, 1.84, 1.9565,
    2.12, 2.32625, 2.54, 2.730625, 2.88, 2.940625, 2.97, 3.015, 3.06, 3.07, 3.15, 3.445812, 3.8,
    4.087687, 4.357, 4.610188, 4.86, 5.125813, 5.39, 5.63125, 5.88,
];
const COPPER_N: [f32; 56] = [
    1.400313, 1.38, 1.358438, 1.34, 1.329063, 1.325, 1.3325, 1.34, 1.334375, 1.325, 1.317812, 1.31,
    1.300313, 1.29, 1.281563, 1.27, 1.249062, 1.225, 1.2, 1.18, 1.174375, 1.175, 1.1775, 1.18,
    1.178125, 1.175, 1.172812, 1.17, 1.165312, 1.16, 1.155312, 1.15, 1.142812, 1.135, 1.131562,
    1.12, 1.092437, 1.04, 0.950375, 0.826, 0.645875, 0.468, 0.35125, 0.272, 0.230813, 0.214,
    0.20925, 0.213, 0.21625, 0.223, 0.2365, 0.25, 0.254188, 0.26, 0.28, 0.3,
];
const COPPER_K: [f32; 56] = [
    1.662125, 1.687, 1.703313, 1.72, 1.744563, 1.77, 1.791625, 1.81, 1.822125, 1.834, 1.85175,
    1.872, 1.89425, 1.916, 1.931688, 1.95, 1.972438, 2.015, 2.121562, 2.21, 2.177188, 2.13,
    2.160063, 2.21, 2.249938, 2.289, 2.326, 2.362, 2.397625, 2.433, 2.469187, 2.504, 2.535875,
    2.564, 2.589625, 2.605, 2.595562, 2.583, 2.5765, 2.599, 2.678062, 2.809, 3.01075, 3.24,
    3.458187, 3.67, 3.863125, 4.05, 4.239563, 4.43, 4.619563, 4.817, 5.034125, 5.26, 5.485625,
    5.717,
];
const ALUMINIUM_N: [f32; 56] = [
    0.273375, 0.28, 0.286813, 0.294, 0.301875, 0.31, 0.317875, 0.326, 0.33475, 0.344, 0.353813,
    0.364, 0.374375, 0.385, 0.39575, 0.407, 0.419125, 0.432, 0.445688, 0.46, 0.474688, 0.49,
    0.506188, 0.523, 0.540063, 0.558, 0.577313, 0.598, 0.620313, 0.644, 0.668625, 0.695, 0.72375,
    0.755, 0.789, 0.826, 0.867, 0.912, 0.963, 1.02, 1.08, 1.15, 1.22, 1.3, 1.39, 1.49, 1.6, 1.74,
    1.91, 2.14, 2.41, 2.63, 2.8, 2.74, 2.58, 2.24,
];
// 6.28 is a measured k, not 2 pi.
#[allow(clippy::approx_constant)]
const ALUMINIUM_K: [f32; 56] = [
    3.59375, 3.64, 3.689375, 3.74, 3.789375, 3.84, 3.894375, 3.95, 4.005, 4.06, 4.11375, 4.17,
    4.23375, 4.3, 4.365, 4.43, 4.49375, 4.56, 4.63375, 4.71, 4.784375, 4.86, 4.938125, 5.02,
    5.10875, 5.2, 5.29, 5.38, 5.48, 5.58, 5.69, 5.8, 5.915, 6.03, 6.15, 6.28, 6.42, 6.55, 6.7,
    6.85, 7.0, 7.15, 7.31, 7.48, 7.65, 7.82, 8.01, 8.21, 8.39, 8.57, 8.62, 8.6, 8.45, 8.31, 8.21,
    8.21,
];

/// "amorphous carbon" has a table of its own. LuxRender's k array holds 14 values for its 15
/// wavelengths (it reads one past the end); foton repeats the last value at 885.571 nm.
const CARBON_NM: [f32; 15] = [
    247.96, 309.95, 326.263, 344.389, 364.647, 387.438, 413.267, 442.786, 476.846, 516.583,
    563.545, 619.9, 688.778, 774.875, 885.571,
];
const CARBON_N: [f32; 15] = [
    1.73, 1.84, 1.9, 1.94, 2.0, 2.06, 2.11, 2.17, 2.24, 2.3, 2.38, 2.43, 2.43, 2.33, 2.24,
];
const CARBON_K: [f32; 15] = [
    0.712, 0.808, 0.91, 0.92, 0.92, 0.91, 0.9, 0.89, 0.88, 0.87, 0.82, 0.75, 0.7, 0.71, 0.71,
];

/// LuxRender's default metal, also what an unknown name becomes.
pub const DEFAULT_METAL: &str = "aluminium";

/// LuxRender's built-in table `name`, if it has one.
pub fn named_metal(name: &str) -> Option<Vec<NkSample>> {
    let (nm, n, k): (&[f32], &[f32], &[f32]) = match name {
        "amorphous carbon" => (&CARBON_NM, &CARBON_N, &CARBON_K),
        "silver" => (&SOPRA_NM, &SILVER_N, &SILVER_K),
        "gold" => (&SOPRA_NM, &GOLD_N, &GOLD_K),
        "copper" => (&SOPRA_NM, &COPPER_N, &COPPER_K),
        "aluminium" => (&SOPRA_NM, &ALUMINIUM_N, &ALUMINIUM_K),
        _ => return None,
    };
    Some(
        nm.iter()
            .zip(n)
            .zip(k)
            .map(|((&nm, &n), &k)| NkSample { nm, n, k })
            .collect(),
    )
}

/// A malformed `.nk` file: the line (1-based) and what is wrong there.
#[derive(Debug, PartialEq)]
pub struct NkError {
    pub line: usize,
    pub message: String,
}

/// Parses an `.nk` file in either of the two formats LuxRender reads (it tries SOPRA first):
///
/// - SOPRA: a header `unit first last count` (unit 1: photon energy in eV, 2: wavelength in
///   micrometres), then `count` lines `n k`, the first at `first`, evenly spaced by
///   (last - first) / count in the file's unit (LuxRender's spacing, kept).
/// - Luxpop: lines `wavelength n k`, the wavelength in Angstroms; lines starting with `;` are
///   comments.
///
/// The samples come back sorted by wavelength.
pub fn parse_nk(text: &str) -> Result<Vec<NkSample>, NkError> {
    let lines: Vec<&str> = text.lines().collect();
    let numbers = |line: &str| -> Option<Vec<f32>> {
        line.split_whitespace()
            .map(|w| w.parse::<f32>().ok())
            .collect()
    };
    let header = lines.first().and_then(|l| numbers(l));
    let mut samples = match header.as_deref() {
        Some(&[unit, first, last, count]) if (unit == 1.0 || unit == 2.0) && count >= 1.0 => {
            parse_sopra(&lines[1..], unit, first, last, count as usize)?
        }
        _ => parse_luxpop(&lines)?,
    };
    if samples.is_empty() {
        return Err(NkError {
            line: lines.len().max(1),
            message: "no n k samples".into(),
        });
    }
    samples.sort_by(|a, b| a.nm.total_cmp(&b.nm));
    Ok(samples)
}

fn bad_line(line: usize, expected: &str, text: &str) -> NkError {
    NkError {
        line,
        message: format!("expected {expected}, found \"{}\"", text.trim()),
    }
}

fn parse_sopra(
    lines: &[&str],
    unit: f32,
    first: f32,
    last: f32,
    count: usize,
) -> Result<Vec<NkSample>, NkError> {
    // lambda (nm) = h c / E = 1239.84 / E(eV); or micrometres x 1000.
    let to_nm = |x: f32| {
        if unit == 1.0 {
            4.135_667e-15 * 299_792_458.0 * 1e9 / x
        } else {
            x * 1000.0
        }
    };
    (0..count)
        .map(|i| {
            let line_number = i + 2;
            let text = lines.get(i).ok_or_else(|| NkError {
                line: line_number,
                message: format!("the header announces {count} lines of n k; the file ends"),
            })?;
            let mut words = text.split_whitespace().map(str::parse::<f32>);
            match (words.next(), words.next()) {
                (Some(Ok(n)), Some(Ok(k))) if n.is_finite() && k.is_finite() => Ok(NkSample {
                    nm: to_nm(first + (last - first) * i as f32 / count as f32),
                    n,
                    k,
                }),
                _ => Err(bad_line(line_number, "two numbers \"n k\"", text)),
            }
        })
        .collect()
}

fn parse_luxpop(lines: &[&str]) -> Result<Vec<NkSample>, NkError> {
    lines
        .iter()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty() && !l.starts_with(';'))
        .map(|(i, text)| {
            let mut words = text.split_whitespace().map(str::parse::<f32>);
            match (words.next(), words.next(), words.next()) {
                (Some(Ok(angstrom)), Some(Ok(n)), Some(Ok(k)))
                    if angstrom > 0.0 && n.is_finite() && k.is_finite() =>
                {
                    Ok(NkSample {
                        nm: angstrom * 0.1,
                        n,
                        k,
                    })
                }
                _ => Err(bad_line(
                    i + 1,
                    "\"wavelength(A) n k\" or a SOPRA header \"unit first last count\"",
                    text,
                )),
            }
        })
        .collect()
}

/// Reads and parses an `.nk` file; errors name the file's line.
pub fn read_nk_file(path: &Path) -> Result<Vec<NkSample>, NkError> {
    let text = std::fs::read_to_string(path).map_err(|e| NkError {
        line: 0,
        message: format!("cannot read: {e}"),
    })?;
    parse_nk(&text)
}

/// The samples' value at `nm`, linearly interpolated, held constant beyond the ends.
fn interpolate(samples: &[NkSample], nm: f32, value: fn(&NkSample) -> f32) -> f32 {
    let upper = samples.partition_point(|s| s.nm < nm);
    match (
        upper.checked_sub(1).map(|i| &samples[i]),
        samples.get(upper),
    ) {
        (Some(a), Some(b)) if b.nm > a.nm => {
            let t = (nm - a.nm) / (b.nm - a.nm);
            value(a) + (value(b) - value(a)) * t
        }
        (_, Some(b)) => value(b),
        (Some(a), None) => value(a),
        (None, None) => 0.0,
    }
}

/// n and k in linear sRGB (see the module's comment); `samples` sorted by wavelength.
pub fn nk_to_rgb(samples: &[NkSample]) -> (Vec3, Vec3) {
    let white = XYZ_TO_SRGB * spectrum_xyz(|_| 1.0);
    let project = |value: fn(&NkSample) -> f32| {
        (XYZ_TO_SRGB * spectrum_xyz(|nm| interpolate(samples, nm, value))) / white
    };
    (
        project(|s| s.n).max(Vec3::ZERO),
        project(|s| s.k).max(Vec3::ZERO),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::fresnel::fr_conductor;

    /// A constant index projects to itself in every channel.
    #[test]
    fn flat_index_keeps_its_value() {
        let flat = [
            NkSample {
                nm: 300.0,
                n: 1.5,
                k: 3.0,
            },
            NkSample {
                nm: 900.0,
                n: 1.5,
                k: 3.0,
            },
        ];
        let (n, k) = nk_to_rgb(&flat);
        assert!((n - Vec3::splat(1.5)).abs().max_element() < 1e-4, "{n}");
        assert!((k - Vec3::splat(3.0)).abs().max_element() < 1e-4, "{k}");
    }

    /// The named metals' normal-incidence reflectance has the colours known of them: gold and
    /// copper reflect red more than blue, silver and aluminium are nearly neutral and bright
    /// (over 0.85), and amorphous carbon is dark (under 0.25).
    #[test]
    fn named_metals_have_their_colours() {
        let reflectance = |name: &str| {
            let (n, k) = nk_to_rgb(&named_metal(name).unwrap());
            fr_conductor(1.0, n, k)
        };
        for name in ["gold", "copper"] {
            let r = reflectance(name);
            assert!(
                r.x > r.y && r.y > r.z && r.x > 0.8 && r.z < 0.6,
                "{name} {r}"
            );
        }
        for name in ["silver", "aluminium"] {
            let r = reflectance(name);
            assert!(r.min_element() > 0.85, "{name} {r}");
            assert!(r.max_element() - r.min_element() < 0.06, "{name} {r}");
        }
        let carbon = reflectance("amorphous carbon");
        assert!(carbon.max_element() < 0.25, "{carbon}");
        assert!(named_metal("unobtainium").is_none());
    }

    #[test]
    fn reads_sopra_files() {
        // Photon energies 2 eV to 3 eV in 2 lines: samples at 2 eV (619.9 nm) and 2.5 eV.
        let samples = parse_nk("1 2.0 3.0 2\n0.2 3.0\n0.4 2.0\n").unwrap();
        assert_eq!(samples.len(), 2);
        let ev = |nm: f32| 1_239.841_9 / nm;
        assert!((ev(samples[1].nm) - 2.0).abs() < 1e-3, "{samples:?}");
        assert!((ev(samples[0].nm) - 2.5).abs() < 1e-3, "{samples:?}");
        assert_eq!((samples[1].n, samples[1].k), (0.2, 3.0));
        // Micrometres: 0.4 to 0.8 in 2 lines, sample at 0.4 and 0.6 um.
        let um = parse_nk("2 0.4 0.8 2\n1 2\n3 4\n").unwrap();
        assert_eq!((um[0].nm, um[1].nm), (400.0, 600.0));
    }

    #[test]
    fn reads_luxpop_files() {
        let samples =
            parse_nk("; a comment\n5000 0.5 2.5\n4000 0.4 2.4\n\n6000 0.6 2.6\n").unwrap();
        let nm: Vec<f32> = samples.iter().map(|s| s.nm).collect();
        assert_eq!(nm, [400.0, 500.0, 600.0]);
        assert_eq!((samples[0].n, samples[0].k), (0.4, 2.4));
    }

    /// Malformed files say which line is wrong.
    #[test]
    fn errors_name_the_line() {
        let error = parse_nk("; header\n5000 0.5 2.5\n6000 0.6 oops\n").unwrap_err();
        assert_eq!(error.line, 3, "{error:?}");
        assert!(error.message.contains("oops"), "{error:?}");
        let short = parse_nk("2 0.4 0.8 3\n1 2\n3 4\n").unwrap_err();
        assert_eq!(short.line, 4, "{short:?}");
        let bad_pair = parse_nk("2 0.4 0.8 2\n1 2\n3\n").unwrap_err();
        assert_eq!(bad_pair.line, 3, "{bad_pair:?}");
        assert!(parse_nk("; only a comment\n").is_err());
    }
}
