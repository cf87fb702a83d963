//! The environment map's light samples for MIS taken eight at a time, for the vertices a
//! shading stage queues together: [`Environment::sample_for_mis`]'s operations on the four lanes
//! of glam's `Vec4`, twice, with each lane's tables read alone, to the bit (tested in the
//! parent module). One at a time, a sample was about 280 instructions.

use std::f32::consts::PI;

use glam::{Vec2, Vec3, Vec4};

use super::{CellAngle, CellAngles, DirectionLanes, Environment, EnvironmentMap, LANES};
use crate::light::LightSample;
use crate::math;
use crate::sampling::GridCell;

/// Eight light samples for MIS ([`Environment::sample_for_mis_lanes`]): lane by lane, whether
/// [`Environment::sample_for_mis`] gives one, and then its direction, radiance and density
/// (zeros elsewhere).
#[derive(Clone, Copy, Debug, Default)]
pub struct SkySamples {
    pub sampled: [bool; LANES],
    pub wi: DirectionLanes,
    pub radiance: DirectionLanes,
    pub pdf: [f32; LANES],
}

impl SkySamples {
    /// Lane `lane`'s `sample`.
    fn set(&mut self, lane: usize, sample: &LightSample) {
        self.sampled[lane] = true;
        self.pdf[lane] = sample.pdf;
        for axis in 0..3 {
            self.wi[axis][lane] = sample.wi[axis];
            self.radiance[axis][lane] = sample.radiance[axis];
        }
    }
}

impl Environment {
    /// [`Environment::sample_for_mis`] of eight 2D samples (`u`: their x and y), to the bit.
    /// Four at a time
    /// ([`EnvironmentMap::sample_four`]) where the map's cells have angles and its transform
    /// keeps lengths (a sky's rotation), else one by one. For the queued vertices' light
    /// samples, taken together: one at a time they were about 280 instructions each.
    pub fn sample_for_mis_lanes(&self, u: &[[f32; LANES]; 2]) -> SkySamples {
        let mut samples = SkySamples::default();
        let Some(map) = &self.map else {
            return samples;
        };
        match &map.cell_angles {
            Some(angles) if map.keeps_lengths => {
                for half in 0..2 {
                    let u = u.map(|axis| Vec4::from_slice(&axis[4 * half..][..4]));
                    map.sample_four(self.radiance, angles, u, half, &mut samples);
                }
            }
            _ => {
                for (lane, (&x, &y)) in u[0].iter().zip(&u[1]).enumerate() {
                    if let Some(sample) = self.sample_from(Vec2::new(x, y), true) {
                        samples.set(lane, &sample);
                    }
                }
            }
        }
        samples
    }
}

impl EnvironmentMap {
    /// Lanes 4 `half` to 4 `half` + 3 of [`Environment::sample_for_mis_lanes`], from `u` (their
    /// x and y), on the four lanes of glam's `Vec4`: [`Environment::sample_from`]'s operations
    /// for the compensated table, in its order, through [`Bilinear2D::sample_four`], the
    /// cells' angles `angles` (each lane's read alone), [`CellAngle::at`]'s addition formulas and
    /// the rotation into the world (a transform that keeps lengths: no normalisation); each
    /// sampled lane's radiance is read alone ([`EnvironmentMap::radiance_in`]).
    #[inline(never)]
    fn sample_four(
        &self,
        sky_radiance: Vec3,
        angles: &CellAngles,
        u: [Vec4; 2],
        half: usize,
        samples: &mut SkySamples,
    ) {
        let Some(sample) = self.table(true).sample_four(u) else {
            return;
        };
        let at = |angles: &[CellAngle], cells: [usize; 4], t: Vec4| {
            // A plain loop: `array::map` with a bounds check inside was not inlined.
            let (mut sin, mut cos, mut half_width) = ([0.0; 4], [0.0; 4], [0.0; 4]);
            for lane in 0..4 {
                let angle = angles[cells[lane]];
                (sin[lane], cos[lane], half_width[lane]) = (angle.sin, angle.cos, angle.half_width);
            }
            let [sin, cos, half_width] = [sin, cos, half_width].map(Vec4::from_array);
            let (s, c) = math::sin_cos_eighth_turn((2.0 * t - 1.0) * half_width);
            (sin * c + cos * s, cos * c - sin * s)
        };
        let [tx, ty] = sample.fraction;
        let (sin_theta, cos_theta) = at(&angles.rows, sample.rows, ty);
        let (sin_phi, cos_phi) = at(&angles.columns, sample.columns, tx);
        let local = [sin_theta * cos_phi, sin_theta * sin_phi, cos_theta];
        let zero = Vec4::ZERO;
        let sampled = !(sample.pdf.cmple(zero) | sin_theta.cmple(zero)).bitmask();
        // glam's `Mat3A * Vec3A`: (x_axis d.x + y_axis d.y) + z_axis d.z, per component.
        let m = &self.light_to_world;
        let wi = [0, 1, 2].map(|c| {
            Vec4::splat(m.x_axis[c]) * local[0]
                + Vec4::splat(m.y_axis[c]) * local[1]
                + Vec4::splat(m.z_axis[c]) * local[2]
        });
        let pdf = sample.pdf / (2.0 * PI * PI * sin_theta);
        // As arrays: a `Vec4`'s lane by a variable index was a jump table.
        let (wi, pdf, [tx, ty]) = (
            wi.map(|v| v.to_array()),
            pdf.to_array(),
            [tx, ty].map(|v| v.to_array()),
        );
        for lane in (0..4).filter(|lane| sampled & (1 << lane) != 0) {
            let radiance = sky_radiance
                * self.radiance_in(GridCell {
                    column: sample.columns[lane],
                    row: sample.rows[lane],
                    fraction: Vec2::new(tx[lane], ty[lane]),
                });
            samples.set(
                4 * half + lane,
                &LightSample {
                    wi: Vec3::new(wi[0][lane], wi[1][lane], wi[2][lane]),
                    distance: f32::INFINITY,
                    radiance,
                    pdf: pdf[lane],
                    delta: false,
                },
            );
        }
    }
}
