//! LuxRender's `sky` (and the sky of `sunsky`): the analytic daylight model of Preetham,
//! Shirley and Smits 1999, "A Practical Analytic Model for Daylight" (SIGGRAPH), as LuxRender
//! 1.x implements it in `lights/sky.cpp`, tabulated into a latitude-longitude map that the
//! environment light importance-samples.
//!
//! The sky's luminance Y and chromaticity (x, y) in a direction at angle theta from the zenith
//! and gamma from the sun are each the zenith value times the Perez et al. function
//!   F(theta, gamma) = (1 + A e^(B / cos theta)) (1 + C e^(D gamma) + E cos^2 gamma)
//! divided by its value at the zenith, F(0, theta_s) (theta_s: the sun's zenith angle). The
//! coefficients A..E are linear in the turbidity T (the paper's appendix A.2, LuxRender's
//! digits); the zenith luminance, in cd/m^2, is
//!   Y_z = 1000 ((4.0453 T - 4.9710) tan chi - 0.2155 T + 2.4192),
//!   chi = (4/9 - T/120) (pi - 2 theta_s),
//! and x_z, y_z are cubic in theta_s and quadratic in T. Below the horizon LuxRender clamps
//! theta to pi/2 - 0.001 (gamma stays that of the true direction), so the sky does not go black. LuxRender turns (x, y) into a spectrum by
//! the CIE daylight basis and scales it to luminance Y; foton, in RGB, converts xyY to XYZ and
//! to linear sRGB. The light's `gain` multiplies the result (LuxRender's `skyScale`).

use std::f32::consts::PI;

use glam::Vec3;

use crate::texture::blackbody::XYZ_TO_SRGB;

/// The Preetham sky for one sun position and turbidity, in the light's frame (z up).
#[derive(Clone, Debug)]
pub struct PreethamSky {
    sun: Vec3,
    /// Perez coefficients A..E for Y, x and y.
    perez: [[f32; 5]; 3],
    /// Zenith Y, x, y divided by F(0, theta_s), so that the model is zenith value x F / F(0, theta_s).
    zenith: [f32; 3],
}

fn perez_function(c: &[f32; 5], theta: f32, gamma: f32) -> f32 {
    let [a, b, cc, d, e] = *c;
    (1.0 + a * (b / theta.cos()).exp()) * (1.0 + cc * (d * gamma).exp() + e * gamma.cos().powi(2))
}

impl PreethamSky {
    /// `sun_direction`: towards the sun, in the light's frame (need not be normalised);
    /// `constants`: LuxRender's `aconst` .. `econst`, factors on the Perez coefficients A..E
    /// (all 1 by default).
    pub fn new(sun_direction: Vec3, turbidity: f32, constants: [f32; 5]) -> Self {
        let sun = sun_direction.try_normalize().unwrap_or(Vec3::Z);
        let theta_s = sun.z.clamp(-1.0, 1.0).acos();
        let t = turbidity;
        let (s1, s2, s3) = (theta_s, theta_s * theta_s, theta_s * theta_s * theta_s);
        let chi = (4.0 / 9.0 - t / 120.0) * (PI - 2.0 * theta_s);
        let zenith_luminance = 1000.0 * ((4.0453 * t - 4.9710) * chi.tan() - 0.2155 * t + 2.4192);
        let zenith_x = (0.00166 * s3 - 0.00375 * s2 + 0.00209 * s1) * t * t
            + (-0.02903 * s3 + 0.06377 * s2 - 0.03202 * s1 + 0.00394) * t
            + (0.11693 * s3 - 0.21196 * s2 + 0.06052 * s1 + 0.25886);
        let zenith_y = (0.00275 * s3 - 0.00610 * s2 + 0.00317 * s1) * t * t
            + (-0.04214 * s3 + 0.08970 * s2 - 0.04153 * s1 + 0.00516) * t
            + (0.15346 * s3 - 0.26756 * s2 + 0.06670 * s1 + 0.26688);
        let perez = [
            [
                0.1787 * t - 1.4630,
                -0.3554 * t + 0.4275,
                -0.0227 * t + 5.3251,
                0.1206 * t - 2.5771,
                -0.0670 * t + 0.3703,
            ],
            [
                -0.0193 * t - 0.2592,
                -0.0665 * t + 0.0008,
                -0.0004 * t + 0.2125,
                -0.0641 * t - 0.8989,
                -0.0033 * t + 0.0452,
            ],
            [
                -0.0167 * t - 0.2608,
                -0.0950 * t + 0.0092,
                -0.0079 * t + 0.2102,
                -0.0441 * t - 1.6537,
                -0.0109 * t + 0.0529,
            ],
        ];
        let perez = perez.map(|row| {
            let mut row = row;
            row.iter_mut().zip(constants).for_each(|(c, k)| *c *= k);
            row
        });
        let zenith = [zenith_luminance, zenith_x, zenith_y]
            .iter()
            .zip(&perez)
            .map(|(z, c)| z / perez_function(c, 0.0, theta_s))
            .collect::<Vec<_>>();
        Self {
            sun,
            perez,
            zenith: [zenith[0], zenith[1], zenith[2]],
        }
    }

    /// Luminance Y (cd/m^2) and chromaticity x, y of the sky in unit direction `d`.
    pub fn luminance_xy(&self, d: Vec3) -> (f32, f32, f32) {
        let theta = d.z.clamp(-1.0, 1.0).acos().min(PI * 0.5 - 0.001);
        let gamma = d.dot(self.sun).clamp(-1.0, 1.0).acos();
        let [luminance, x, y] =
            [0, 1, 2].map(|i| self.zenith[i] * perez_function(&self.perez[i], theta, gamma));
        (luminance, x, y)
    }

    /// Linear sRGB radiance in unit direction `d` (negative components, outside the gamut, 0).
    pub fn radiance(&self, d: Vec3) -> Vec3 {
        let (luminance, x, y) = self.luminance_xy(d);
        if y.is_nan() || y <= 0.0 {
            return Vec3::ZERO;
        }
        let xyz = Vec3::new(x / y * luminance, luminance, (1.0 - x - y) / y * luminance);
        (XYZ_TO_SRGB * xyz).max(Vec3::ZERO)
    }

    /// The sky as a `width` x `height` latitude-longitude map (row 0 at the zenith, u = phi / 2pi
    /// around +z: the environment light's layout), texel centres sampled.
    pub fn tabulate(&self, width: usize, height: usize) -> Vec<Vec3> {
        (0..width * height)
            .map(|i| {
                let phi = 2.0 * PI * ((i % width) as f32 + 0.5) / width as f32;
                let theta = PI * ((i / width) as f32 + 0.5) / height as f32;
                let (sin_theta, cos_theta) = theta.sin_cos();
                self.radiance(Vec3::new(
                    sin_theta * phi.cos(),
                    sin_theta * phi.sin(),
                    cos_theta,
                ))
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn direction(theta: f32, phi: f32) -> Vec3 {
        Vec3::new(
            theta.sin() * phi.cos(),
            theta.sin() * phi.sin(),
            theta.cos(),
        )
    }

    /// At the zenith the model gives the zenith luminance of the paper's appendix A.2: for
    /// T = 2 and the sun 30 degrees high (theta_s = 60 degrees), by hand: chi =
    /// (4/9 - 2/120) (pi - 2 pi/3) = 0.447 94, tan chi = 0.480 48, Y_z = 1000 (3.1196 x
    /// 0.480 48 + 2.4192 - 0.431) = 3487 cd/m^2. And x_z, y_z for the sun at the zenith (theta_s = 0)
    /// are the constant terms: x_z = 0.00394 T + 0.25886, y_z = 0.00516 T + 0.26688.
    #[test]
    fn zenith_values_are_the_papers() {
        let sky = PreethamSky::new(direction(PI / 3.0, 0.0), 2.0, [1.0; 5]);
        let (luminance, _, _) = sky.luminance_xy(Vec3::Z);
        assert!((luminance - 3487.0).abs() < 2.0, "{luminance}");
        let overhead = PreethamSky::new(Vec3::Z, 3.0, [1.0; 5]);
        let (_, x, y) = overhead.luminance_xy(Vec3::Z);
        assert!((x - (0.00394 * 3.0 + 0.25886)).abs() < 1e-5, "{x}");
        assert!((y - (0.00516 * 3.0 + 0.26688)).abs() < 1e-5, "{y}");
    }

    /// Brightest around the sun, darkest opposite it at the same height (the circumsolar
    /// term C e^(D gamma) falls with gamma), symmetric about the sun's meridian, and below the
    /// horizon theta is clamped: there the theta factor of F is the horizon's, so luminances
    /// below it differ only by the gamma factor 1 + C e^(D gamma) + E cos^2 gamma (C, D, E of
    /// luminance for T = 2.5 from the paper: 5.26835, -2.2756, 0.2028).
    #[test]
    fn shape_of_the_sky() {
        let sun = direction(1.0, 0.5);
        let sky = PreethamSky::new(sun, 2.5, [1.0; 5]);
        let toward = sky.luminance_xy(direction(1.1, 0.5)).0;
        let away = sky.luminance_xy(direction(1.1, 0.5 + PI)).0;
        assert!(toward > 3.0 * away, "{toward} {away}");
        for offset in [0.3f32, 1.0, 2.0] {
            let left = sky.luminance_xy(direction(0.8, 0.5 + offset)).0;
            let right = sky.luminance_xy(direction(0.8, 0.5 - offset)).0;
            assert!((left / right - 1.0).abs() < 1e-4, "{left} {right}");
        }
        let overhead = PreethamSky::new(Vec3::Z, 2.5, [1.0; 5]);
        let gamma_factor = |g: f32| 1.0 + 5.26835 * (-2.2756 * g).exp() + 0.2028 * g.cos().powi(2);
        let below = overhead.luminance_xy(direction(2.5, 1.0)).0;
        let further_below = overhead.luminance_xy(direction(2.9, 1.0)).0;
        assert!(below.is_finite() && below > 0.0, "{below}");
        let expected = gamma_factor(2.9) / gamma_factor(2.5);
        assert!(
            (further_below / below / expected - 1.0).abs() < 1e-4,
            "{below} {further_below} {expected}"
        );
    }

    /// A clear sky is blue: more blue than red away from the sun, and the luminance of the RGB
    /// radiance is the model's Y.
    #[test]
    fn clear_sky_is_blue() {
        let sky = PreethamSky::new(direction(0.9, 0.0), 2.0, [1.0; 5]);
        let d = direction(0.6, PI);
        let rgb = sky.radiance(d);
        assert!(rgb.z > rgb.x, "{rgb}");
        let y = crate::film::luminance(rgb);
        let (luminance, _, _) = sky.luminance_xy(d);
        assert!((y / luminance - 1.0).abs() < 0.01, "{y} {luminance}");
    }
}
