//! Pearson's chi-square test of sampled directions against the pdf that claims to describe them.

use std::f64::consts::PI;

use glam::Vec3;

/// The grid of cells: `nz` bands of z in [`z_min`, 1] times `nphi` sectors of azimuth, each
/// cell the same solid angle (dω = dz dφ); `sub` x `sub` midpoints integrate the pdf per cell.
pub struct DirectionGrid {
    pub z_min: f64,
    pub nz: usize,
    pub nphi: usize,
    pub sub: usize,
}

impl DirectionGrid {
    fn cell(&self, w: Vec3) -> usize {
        let z = (f64::from(w.z) - self.z_min) / (1.0 - self.z_min);
        let iz = ((z * self.nz as f64).max(0.0) as usize).min(self.nz - 1);
        let phi = f64::from(w.y.atan2(w.x)).rem_euclid(2.0 * PI);
        iz * self.nphi + ((phi / (2.0 * PI) * self.nphi as f64) as usize).min(self.nphi - 1)
    }

    /// Draws `samples` directions from `sample` (`None`: the sample failed or is not to be
    /// counted), and asserts that their histogram follows `pdf`: cells expecting fewer than 5
    /// are pooled into one, and chi² must stay below its p = 1e-4 quantile (Wilson-Hilferty
    /// approximation, z = 3.72), so a correct sampler fails one time in 10,000.
    pub fn assert_follows_pdf(
        &self,
        label: &str,
        samples: usize,
        mut sample: impl FnMut() -> Option<Vec3>,
        pdf: impl Fn(Vec3) -> f32,
    ) {
        let mut observed = vec![0.0f64; self.nz * self.nphi];
        let mut counted = 0usize;
        for _ in 0..samples {
            if let Some(w) = sample() {
                observed[self.cell(w)] += 1.0;
                counted += 1;
            }
        }
        let dz = (1.0 - self.z_min) / self.nz as f64;
        let dphi = 2.0 * PI / self.nphi as f64;
        let sub = self.sub as f64;
        let (mut chi2, mut dof) = (0.0, 0usize);
        let (mut pooled_obs, mut pooled_exp) = (0.0, 0.0);
        for iz in 0..self.nz {
            for ip in 0..self.nphi {
                let mut integral = 0.0;
                for a in 0..self.sub {
                    let z = self.z_min + (iz as f64 + (a as f64 + 0.5) / sub) * dz;
                    let r = (1.0 - z * z).sqrt();
                    for b in 0..self.sub {
                        let phi = (ip as f64 + (b as f64 + 0.5) / sub) * dphi;
                        let wi =
                            Vec3::new((r * phi.cos()) as f32, (r * phi.sin()) as f32, z as f32);
                        integral += f64::from(pdf(wi));
                    }
                }
                let expected = integral * dz * dphi / (sub * sub) * samples as f64;
                let obs = observed[iz * self.nphi + ip];
                if expected < 5.0 {
                    pooled_obs += obs;
                    pooled_exp += expected;
                } else {
                    chi2 += (obs - expected).powi(2) / expected;
                    dof += 1;
                }
            }
        }
        if pooled_exp >= 5.0 {
            chi2 += (pooled_obs - pooled_exp).powi(2) / pooled_exp;
            dof += 1;
        }
        let k = (dof - 1) as f64;
        let c = 2.0 / (9.0 * k);
        let critical = k * (1.0 - c + 3.72 * c.sqrt()).powi(3);
        println!("{label}: chi2 {chi2} dof {k} critical {critical}, {counted} counted");
        assert!(chi2 < critical, "{label}: chi2 {chi2} >= {critical}");
    }
}
