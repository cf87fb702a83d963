//! `foton compare A.exr B.exr`: the error of image A against the reference B.
//!
//! Per channel and over all channels, with a = A's value and b = B's at each pixel:
//! - RMSE = sqrt(mean((a - b)^2));
//! - relMSE = mean((a - b)^2 / (b^2 + 0.01)): the squared error relative to the reference,
//!   the 0.01 keeping black pixels from dominating (Rousselle et al. 2011, and the measure
//!   issue 7 reports);
//! - MAPE = 100 mean(|a - b| / (|b| + 0.01)), in percent, the same guard;
//! - PSNR = 10 log10(peak^2 / MSE) in dB, peak = the reference's largest value.

use std::path::{Path, PathBuf};

use glam::Vec3;

use crate::film::{ImageMetadata, read_exr, write_image};

/// The guard against division by (nearly) black reference pixels.
const EPSILON: f64 = 0.01;

/// Error measures of one channel, or of all three.
#[derive(Clone, Copy, Debug, Default)]
pub struct Errors {
    pub rmse: f64,
    pub rel_mse: f64,
    pub mape: f64,
    pub psnr: f64,
}

/// The errors of R, G, B, and over all channels.
#[derive(Clone, Copy, Debug)]
pub struct Comparison {
    pub channels: [Errors; 3],
    pub overall: Errors,
}

/// Compares `image` with `reference` (same size, linear RGB).
pub fn compare(image: &[Vec3], reference: &[Vec3]) -> Comparison {
    let peak = reference
        .iter()
        .map(|p| f64::from(p.max_element()))
        .fold(0.0, f64::max);
    // Sums of squared error, relative squared error and relative absolute error per channel.
    let mut sums = [[0.0f64; 3]; 3];
    for (a, b) in image.iter().zip(reference) {
        for c in 0..3 {
            let (a, b) = (f64::from(a[c]), f64::from(b[c]));
            let d = a - b;
            sums[c][0] += d * d;
            sums[c][1] += d * d / (b * b + EPSILON);
            sums[c][2] += d.abs() / (b.abs() + EPSILON);
        }
    }
    let n = image.len().min(reference.len()).max(1) as f64;
    let errors = |mse: f64, rel: f64, abs: f64, count: f64| Errors {
        rmse: (mse / count).sqrt(),
        rel_mse: rel / count,
        mape: 100.0 * abs / count,
        psnr: 10.0 * (peak * peak / (mse / count)).log10(),
    };
    let channels = sums.map(|[mse, rel, abs]| errors(mse, rel, abs, n));
    let total = |k: usize| sums.iter().map(|s| s[k]).sum::<f64>();
    Comparison {
        channels,
        overall: errors(total(0), total(1), total(2), 3.0 * n),
    }
}

/// Reads two EXR images of one size.
pub fn read_pair(a: &Path, b: &Path) -> Result<(u32, u32, Vec<Vec3>, Vec<Vec3>), String> {
    let (wa, ha, image) = read_exr(a).map_err(|e| format!("error: {e}"))?;
    let (wb, hb, reference) = read_exr(b).map_err(|e| format!("error: {e}"))?;
    if (wa, ha) != (wb, hb) {
        return Err(format!(
            "error: {} is {wa}x{ha} but {} is {wb}x{hb}",
            a.display(),
            b.display()
        ));
    }
    Ok((wa, ha, image, reference))
}

pub fn run(a: &Path, b: &Path, diff: Option<PathBuf>, json: bool) -> Result<(), String> {
    let (width, height, image, reference) = read_pair(a, b)?;
    let comparison = compare(&image, &reference);
    if json {
        println!("{}", to_json(&comparison));
    } else {
        println!(
            "{:<8} {:>12} {:>12} {:>10} {:>9}",
            "channel", "RMSE", "relMSE", "MAPE %", "PSNR dB"
        );
        let rows = ["R", "G", "B"].iter().zip(&comparison.channels);
        for (name, e) in rows.chain(std::iter::once((&"all", &comparison.overall))) {
            println!(
                "{name:<8} {:>12.6e} {:>12.6e} {:>10.3} {:>9.2}",
                e.rmse, e.rel_mse, e.mape, e.psnr
            );
        }
    }
    if let Some(path) = diff {
        let (pixels, scale) = difference_image(&image, &reference);
        write_image(
            &path,
            width,
            height,
            &pixels,
            1.0,
            &ImageMetadata::default(),
        )
        .map_err(|e| format!("error: {e}"))?;
        if !json {
            println!(
                "{} written: red where A is brighter, blue where darker, full colour at a relative difference of {scale:.3}",
                path.display()
            );
        }
    }
    Ok(())
}

fn to_json(c: &Comparison) -> String {
    let object = |e: &Errors| {
        format!(
            "{{\"rmse\": {}, \"rel_mse\": {}, \"mape\": {}, \"psnr\": {}}}",
            number(e.rmse),
            number(e.rel_mse),
            number(e.mape),
            number(e.psnr)
        )
    };
    format!(
        "{{\"r\": {}, \"g\": {}, \"b\": {}, \"overall\": {}}}",
        object(&c.channels[0]),
        object(&c.channels[1]),
        object(&c.channels[2]),
        object(&c.overall)
    )
}

/// JSON has no infinities (identical images have infinite PSNR): those become null.
fn number(x: f64) -> String {
    if x.is_finite() {
        format!("{x:e}")
    } else {
        "null".into()
    }
}

/// A false-colour image of the signed relative difference (a - b) / (b + 0.01) of the mean
/// of the channels: white where equal, red where A is brighter, blue where darker, at full
/// colour from the 99th percentile of its magnitude (returned) up.
fn difference_image(image: &[Vec3], reference: &[Vec3]) -> (Vec<Vec3>, f32) {
    let relative: Vec<f32> = image
        .iter()
        .zip(reference)
        .map(|(a, b)| {
            let (a, b) = (a.element_sum() / 3.0, b.element_sum() / 3.0);
            (a - b) / (b.abs() + EPSILON as f32)
        })
        .collect();
    let mut magnitudes: Vec<f32> = relative
        .iter()
        .map(|r| r.abs())
        .filter(|r| r.is_finite())
        .collect();
    magnitudes.sort_by(f32::total_cmp);
    let scale = magnitudes
        .get(magnitudes.len() * 99 / 100)
        .copied()
        .filter(|s| *s > 0.0)
        .unwrap_or(1.0);
    let pixels = relative
        .iter()
        .map(|r| {
            let t = (r / scale).clamp(-1.0, 1.0);
            let t = if t.is_nan() { 0.0 } else { t };
            // Linear values; the PNG encoding makes them sRGB.
            if t >= 0.0 {
                Vec3::new(1.0, 1.0 - t, 1.0 - t)
            } else {
                Vec3::new(1.0 + t, 1.0 + t, 1.0)
            }
        })
        .collect();
    (pixels, scale)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn errors_match_their_definitions() {
        let reference = [Vec3::new(1.0, 0.0, 2.0), Vec3::new(0.5, 0.5, 0.5)];
        let image = [Vec3::new(1.5, 0.1, 2.0), Vec3::new(0.5, 0.5, 0.0)];
        let c = compare(&image, &reference);
        // Red: errors 0.5 and 0 over 2 pixels.
        assert!((c.channels[0].rmse - (0.25f64 / 2.0).sqrt()).abs() < 1e-7);
        assert!((c.channels[0].rel_mse - 0.25 / 1.01 / 2.0).abs() < 1e-7);
        assert!((c.channels[0].mape - 100.0 * 0.5 / 1.01 / 2.0).abs() < 1e-5);
        // Green: 0.1 against black, the guard's case.
        assert!((c.channels[1].rel_mse - 0.01 / 0.01 / 2.0).abs() < 1e-5);
        // Overall: all six values; peak 2.
        let mse = (0.25 + 0.01 + 0.25) / 6.0;
        assert!((c.overall.rmse - f64::sqrt(mse)).abs() < 1e-7);
        assert!((c.overall.psnr - 10.0 * (4.0 / mse).log10()).abs() < 1e-5);
        let same = compare(&reference, &reference);
        assert_eq!(same.overall.rel_mse, 0.0);
        assert!(to_json(&same).contains("\"psnr\": null"));
    }
}
