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

#[cfg(test)]
mod tests {
    use super::*;

    /// Each fractal at p / 0.25 for p = (0.31, -0.17, 0.44), from an independent float64
    /// transcription (Python, not foton's code) of `blender_noiselib.cpp`'s `mg_*` functions:
    /// LuxRender's defaults over Blender's original basis (H 1, lacunarity 2, 2 octaves, offset
    /// 1, gain 1), and H 0.5, lacunarity 2.1, 3.5 octaves (a fractional one), offset 0.7,
    /// gain 2 over improved Perlin.
    #[test]
    fn fractals_match_the_c_source() {
        let p = Vec3::new(0.31, -0.17, 0.44) / 0.25;
        let kinds = [
            (MusgraveKind::Fbm, 0.344_422_414_84, -0.497_297_368_25),
            (
                MusgraveKind::Multifractal,
                1.216_207_580_30,
                0.486_966_156_38,
            ),
            (
                MusgraveKind::HeteroTerrain,
                2.000_978_439_21,
                0.388_219_043_94,
            ),
            (
                MusgraveKind::HybridMultifractal,
                1.844_422_414_84,
                0.570_171_957_53,
            ),
            (
                MusgraveKind::RidgedMultifractal,
                0.213_295_788_99,
                0.057_716_774_07,
            ),
        ];
        for (kind, defaults, varied) in kinds {
            let fractal = Musgrave {
                kind,
                h: 1.0,
                lacunarity: 2.0,
                octaves: 2.0,
                offset: 1.0,
                gain: 1.0,
                basis: NoiseBasis::BlenderOriginal,
            };
            let v = fractal.value(p);
            assert!((f64::from(v) - defaults).abs() < 2e-5, "{kind:?}: {v}");
            let fractal = Musgrave {
                h: 0.5,
                lacunarity: 2.1,
                octaves: 3.5,
                offset: 0.7,
                gain: 2.0,
                basis: NoiseBasis::ImprovedPerlin,
                ..fractal
            };
            let v = fractal.value(p);
            assert!((f64::from(v) - varied).abs() < 2e-5, "{kind:?} varied: {v}");
        }
    }
}
