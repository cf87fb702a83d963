//! Musgrave's fractal sums over a signed Blender noise basis (`blender_musgrave`), as LuxRender
//! 1.x computes them (`textures/blender_noiselib.cpp`: `mg_fBm`, `mg_MultiFractal`,
//! `mg_HeteroTerrain`, `mg_HybridMultiFractal`, `mg_RidgedMultiFractal`, which Blender took from
//! Musgrave's code in Ebert et al., "Texturing and Modeling: A Procedural Approach").
//!
//! Octave i samples the noise at lacunarity^i p with weight lacunarity^(-H i). `octaves` may be
//! fractional: the integer part gives full octaves and the remainder weights one more (except
//! in the ridged multifractal, which ignores it, as Blender does).

use glam::Vec3;

use super::blender_noise::NoiseBasis;

/// `"type"` of `blender_musgrave`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MusgraveKind {
    /// "multifractal": the product of (1 + w_i n_i).
    Multifractal,
    /// "ridged_multifractal": squared ridges offset - |n|, each weighted by the previous.
    RidgedMultifractal,
    /// "hybrid_multifractal": additive, each octave weighted by the running signal.
    HybridMultifractal,
    /// "hetero_terrain": each octave scaled by the value so far.
    HeteroTerrain,
    /// "fbm": the sum of w_i n_i.
    Fbm,
}

/// A Musgrave fractal: `h` (dimension, default 1), `lacunarity` (2), `octaves` (2), `offset`
/// (1), `gain` (1) over the signed `basis`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Musgrave {
    pub kind: MusgraveKind,
    pub h: f32,
    pub lacunarity: f32,
    pub octaves: f32,
    pub offset: f32,
    pub gain: f32,
    pub basis: NoiseBasis,
}

impl Musgrave {
    /// The fractal at `p` (already divided by the noise size).
    pub fn value(&self, p: Vec3) -> f32 {
        let noise = |q: Vec3| self.basis.signed(q);
        let step = self.lacunarity.powf(-self.h);
        let whole = self.octaves.max(0.0) as u32;
        let remainder = self.octaves - self.octaves.floor();
        let mut p = p;
        match self.kind {
            MusgraveKind::Fbm => {
                let (mut value, mut weight) = (0.0, 1.0);
                for _ in 0..whole {
                    value += noise(p) * weight;
                    weight *= step;
                    p *= self.lacunarity;
                }
                if remainder != 0.0 {
                    value += remainder * noise(p) * weight;
                }
                value
            }
            MusgraveKind::Multifractal => {
                let (mut value, mut weight) = (1.0, 1.0);
                for _ in 0..whole {
                    value *= weight * noise(p) + 1.0;
                    weight *= step;
                    p *= self.lacunarity;
                }
                if remainder != 0.0 {
                    value *= remainder * noise(p) * weight + 1.0;
                }
                value
            }
            MusgraveKind::HeteroTerrain => {
                // The first octave is unscaled; later ones start at weight lacunarity^-H.
                let mut value = self.offset + noise(p);
                let mut weight = step;
                p *= self.lacunarity;
                for _ in 1..whole {
                    value += (noise(p) + self.offset) * weight * value;
                    weight *= step;
                    p *= self.lacunarity;
                }
                if remainder != 0.0 {
                    value += remainder * (noise(p) + self.offset) * weight * value;
                }
                value
            }
            MusgraveKind::HybridMultifractal => {
                let mut result = noise(p) + self.offset;
                let mut signal_weight = self.gain * result;
                let mut weight = step;
                p *= self.lacunarity;
                let mut octave = 1;
                while signal_weight > 0.001 && octave < whole {
                    signal_weight = signal_weight.min(1.0);
                    let signal = (noise(p) + self.offset) * weight;
                    weight *= step;
                    result += signal_weight * signal;
                    signal_weight *= self.gain * signal;
                    p *= self.lacunarity;
                    octave += 1;
                }
                if remainder != 0.0 {
                    result += remainder * (noise(p) + self.offset) * weight;
                }
                result
            }
            MusgraveKind::RidgedMultifractal => {
                let ridge = |q: Vec3| {
                    let s = self.offset - noise(q).abs();
                    s * s
                };
                let mut signal = ridge(p);
                let mut result = signal;
                let mut weight = step;
                for _ in 1..whole {
                    p *= self.lacunarity;
                    let previous = (signal * self.gain).clamp(0.0, 1.0);
                    signal = ridge(p) * previous;
                    result += signal * weight;
                    weight *= step;
                }
                result
            }
        }
    }
}
