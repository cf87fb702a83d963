//! Image comparison for tests and convergence charts. Images of different sizes do not compare:
//! the error is infinite.

use glam::{DVec3, Vec3};

/// Root of the mean squared difference over all channels.
pub fn rmse(a: &[Vec3], b: &[Vec3]) -> f32 {
    mean_over_channels(a, b, |x, y| (x - y) * (x - y)).sqrt()
}

/// Mean over all channels of (a - b)^2 / (b^2 + 0.01): relative error with `b` the reference,
/// the 0.01 keeping dark pixels from dominating (as in Rousselle et al. 2011).
pub fn relative_mse(a: &[Vec3], b: &[Vec3]) -> f32 {
    mean_over_channels(a, b, |x, y| (x - y) * (x - y) / (y * y + 1e-2))
}

/// The mean pixel (zero for an empty image), summed in f64.
pub fn mean(a: &[Vec3]) -> Vec3 {
    let sum: DVec3 = a.iter().map(|p| p.as_dvec3()).sum();
    (sum / a.len().max(1) as f64).as_vec3()
}

fn mean_over_channels(a: &[Vec3], b: &[Vec3], term: impl Fn(f64, f64) -> f64) -> f32 {
    if a.len() != b.len() {
        return f32::INFINITY;
    }
    let sum: f64 = a
        .iter()
        .zip(b)
        .flat_map(|(p, q)| (0..3).map(move |c| (f64::from(p[c]), f64::from(q[c]))))
        .map(|(x, y)| term(x, y))
        .sum();
    (sum / (3 * a.len()).max(1) as f64) as f32
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn metrics_on_known_images() {
        let a = [Vec3::new(1.0, 2.0, 3.0), Vec3::ZERO];
        let b = [Vec3::new(1.0, 2.0, 5.0), Vec3::ONE];
        // Squared differences: 0, 0, 4, 1, 1, 1 -> mean 7/6.
        assert!((rmse(&a, &b) - (7.0f32 / 6.0).sqrt()).abs() < 1e-6);
        let rel = (4.0 / 25.01 + 3.0 / 1.01) / 6.0;
        assert!((relative_mse(&a, &b) - rel).abs() < 1e-6);
        assert_eq!(rmse(&a, &a), 0.0);
        assert_eq!(mean(&a), Vec3::new(0.5, 1.0, 1.5));
        assert_eq!(mean(&[]), Vec3::ZERO);
        assert_eq!(rmse(&[], &[]), 0.0);
        assert_eq!(rmse(&a, &b[..1]), f32::INFINITY);
    }
}
