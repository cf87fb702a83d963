//! Thin-film interference on a mirror's Fresnel term, as LuxRender 1.x computes it for
//! `shinymetal`'s `film` and `filmindex` (`core/reflection/bxdf/specularreflection.cpp`,
//! `PhaseDifference`): the reflected spectrum is multiplied, wavelength by wavelength, by
//!
//!   cos^2(4 pi d s / lambda + pi),  s = sqrt(n^2 - sin^2 theta_o),
//!
//! with d the film's thickness (nm), n its index and theta_o the angle of incidence. The two
//! reflections, off the film's top and off what lies under it, differ in optical path by
//! 2 d n cos theta_t = 2 d s (theta_t the refracted angle, n sin theta_t = sin theta_o), a
//! phase of 4 pi d s / lambda, plus pi for the reflection off the denser medium. (Two beams of
//! equal amplitude interfere as cos^2 of half their phase difference; LuxRender squares the
//! cosine of the whole phase, and foton keeps LuxRender's weight.) With n < 1, s is taken as 0
//! past the critical angle (LuxRender's later `max(0, ...)`; 1.x's first version has NaN).
//!
//! LuxRender renders the weight spectrally; foton projects it to linear sRGB as a reflectance
//! spectrum (as `metal`'s n and k are): the CIE 1931 matching functions weight it, XYZ goes to
//! linear sRGB, and each channel is divided by a flat spectrum's, so a weight of 1 at every
//! wavelength stays (1, 1, 1). Wavelengths every 5 nm from 382.5 to 717.5 nm sample the
//! oscillation finely enough for films up to a few micrometres (at d n = 1000 nm the phase
//! moves by 0.25 rad per step at 500 nm).

use std::f32::consts::PI;
use std::sync::OnceLock;

use glam::Vec3;

use crate::texture::blackbody::{XYZ_TO_SRGB, cie_xyz};

/// The wavelengths the weight is sampled at: `COUNT` steps of `STEP` nm from `FIRST`.
const FIRST: f32 = 382.5;
const STEP: f32 = 5.0;
const COUNT: usize = 68;

/// A film of `thickness` nm and index `index` over a mirror.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ThinFilm {
    pub thickness: f32,
    pub index: f32,
}

/// Each wavelength's linear sRGB weight: its matching functions in sRGB, divided by the sum
/// over all wavelengths (a flat spectrum's colour), so the weights sum to (1, 1, 1).
fn rgb_weights() -> &'static [Vec3; COUNT] {
    static WEIGHTS: OnceLock<[Vec3; COUNT]> = OnceLock::new();
    WEIGHTS.get_or_init(|| {
        let rgb: [Vec3; COUNT] =
            std::array::from_fn(|i| XYZ_TO_SRGB * cie_xyz(FIRST + STEP * i as f32));
        let white: Vec3 = rgb.iter().sum();
        rgb.map(|c| c / white)
    })
}

impl ThinFilm {
    /// LuxRender's weight at wavelength `nm` for light incident at `cos_o` to the normal.
    pub fn spectral_weight(&self, cos_o: f32, nm: f32) -> f32 {
        let phase = 4.0 * PI * self.thickness * self.path_factor(cos_o) / nm + PI;
        phase.cos().powi(2)
    }

    /// s = sqrt(n^2 - sin^2 theta_o), 0 past the critical angle.
    fn path_factor(&self, cos_o: f32) -> f32 {
        let sin2 = (1.0 - cos_o * cos_o).max(0.0);
        (self.index * self.index - sin2).max(0.0).sqrt()
    }

    /// The weight projected to linear sRGB as a reflectance (module doc).
    pub fn rgb_weight(&self, cos_o: f32) -> Vec3 {
        let phase_per_inverse_nm = 4.0 * PI * self.thickness * self.path_factor(cos_o);
        rgb_weights()
            .iter()
            .enumerate()
            .map(|(i, &weight)| {
                let phase = phase_per_inverse_nm / (FIRST + STEP * i as f32) + PI;
                weight * phase.cos().powi(2)
            })
            .sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A flat weight keeps its colour: no film (d = 0) gives cos^2(pi) = 1 at every wavelength.
    #[test]
    fn no_film_is_white() {
        let film = ThinFilm {
            thickness: 0.0,
            index: 1.5,
        };
        let rgb = film.rgb_weight(0.7);
        assert!((rgb - Vec3::ONE).abs().max_element() < 1e-5, "{rgb}");
    }
}
