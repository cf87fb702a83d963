//! LuxRender 1.x's ports of Blender's procedural textures (`textures/blender_base.h`,
//! `blender_*.h`, and the texture functions of `textures/blender_texlib.cpp`, which LuxRender
//! took from Blender 2.4x's `texture.c`): `blender_blend`, `blender_magic`, `blender_wood`,
//! `blender_clouds`, `blender_marble`, `blender_musgrave`, `blender_distortednoise`,
//! `blender_stucci`, `blender_voronoi` and `blender_noise`. The noise bases they read are in
//! [`super::blender_noise`], the Musgrave fractals in [`super::musgrave`].
//!
//! Each gives an intensity f at the mapped point, and the texture is (1 - f) `tex1` + f `tex2`
//! (`BlenderTexture3D::Evaluate`: `Lerp(GetF(P), t1, t2)`, defaults `tex1` 0, `tex2` 1).
//! Blender's brightness and contrast come last: f = (f - 1/2) contrast + bright - 1/2, clamped
//! to [0, 1] for an intensity (`BRICONT`); for a colour (magic, clouds "color", voronoi with a
//! `coltype`) each channel is mapped the same way but only clamped at 0 (`BRICONTRGB`), and the
//! intensity is min(0.35 r + 0.45 g + 0.2 b, 1) (`BlenderTexture3D::GetF`). Stucci applies
//! neither (Blender's `stucci()` returns its noise as is, clamped at 0).
//!
//! The Musgrave, Voronoi and distorted noise patterns divide the point by `noisesize` first
//! (`multitex`: "for Blender convention reason"); the others pass the size to the noise.

use std::f32::consts::PI;

use glam::Vec3;

use super::blender_noise::{self, BlenderNoise, DistanceMetric, NoiseBasis};
use super::musgrave::Musgrave;

/// `blender_blend`'s progression (`"string type"`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BlendKind {
    /// "lin": (1 + x) / 2.
    Linear,
    /// "quad": ((1 + x) / 2)^2, 0 below x = -1.
    Quadratic,
    /// "ease": the smoothstep 3t^2 - 2t^3 of t = (1 + x) / 2 clamped to [0, 1].
    Ease,
    /// "diag": (2 + x + y) / 4.
    Diagonal,
    /// "sphere": 1 - |p|, at least 0.
    Sphere,
    /// "halo": the square of "sphere".
    Halo,
    /// "radial": atan2(y, x) / 2pi + 1/2.
    Radial,
}

/// A wave of Blender's wood (`"string noisebasis2"`): each maps a phase to [0, 1].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Waveform {
    /// "sin": 1/2 + sin(a) / 2.
    Sine,
    /// "saw": a modulo 2pi, over 2pi.
    Saw,
    /// "tri": 1 - 2 |round(a / 2pi) - a / 2pi|.
    Triangle,
}

/// `blender_marble`'s `"type"`: the wave as is ("soft"), or its square root ("sharp") or
/// fourth root ("sharper").
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MarbleSharpness {
    Soft,
    Sharp,
    Sharper,
}

/// `blender_stucci`'s `"type"`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StucciKind {
    /// "plastic": the noise a fixed offset up in z.
    Plastic,
    /// "wall_in": the offset scaled by the square of the noise.
    WallIn,
    /// "wall_out": as "wall_in", then 1 - f.
    WallOut,
}

/// `blender_voronoi`'s `"coltype"`: 0 an intensity, 1 to 3 colours.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VoronoiColor {
    /// 0: the weighted distances.
    Intensity,
    /// 1: the weighted cell colours of the four nearest features.
    Cells,
    /// 2: those colours darkened at the cells' borders, min(10 (F2 - F1), 1).
    CellsEdged,
    /// 3: as 2, also scaled by the intensity.
    CellsEdgedShaded,
}

/// Blender's procedural pattern, with its parameters (LuxRender's names and defaults).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum BlenderPattern {
    /// `blender_blend`: `type` ("lin"), `flipxy` (false) swaps x and y.
    Blend { kind: BlendKind, flip_xy: bool },
    /// `blender_magic`: `noisedepth` (2) folds of sines and cosines, `turbulence` (5).
    Magic { depth: u32, turbulence: f32 },
    /// `blender_wood` "bands" (waves along x + y + z, 10 per unit) or "rings" (about the
    /// origin, 20 per unit of radius); "bandnoise" and "ringnoise" add `turbulence` (5) times
    /// the noise to the wave's phase.
    Wood {
        rings: bool,
        wave: Waveform,
        noise: Option<BlenderNoise>,
        turbulence: f32,
    },
    /// `blender_clouds`: turbulence of `noisedepth` (2) octaves; `type` "color" draws three
    /// turbulences at permuted coordinates.
    Clouds {
        noise: BlenderNoise,
        depth: u32,
        color: bool,
    },
    /// `blender_marble`: the wave `noisebasis2` ("sin") of 5 (x + y + z) plus `turbulence`
    /// (5) times a turbulence of `noisedepth` (2) octaves.
    Marble {
        noise: BlenderNoise,
        depth: u32,
        turbulence: f32,
        wave: Waveform,
        sharpness: MarbleSharpness,
    },
    /// `blender_musgrave`: `outscale` (1) times the fractal of p / `noisesize` (0.25).
    Musgrave {
        fractal: Musgrave,
        size: f32,
        outscale: f32,
    },
    /// `blender_distortednoise`: the basis `type` at p / `noisesize` displaced by `distamount`
    /// (1) times the basis `noisebasis`.
    DistortedNoise {
        size: f32,
        amount: f32,
        distortion: NoiseBasis,
        basis: NoiseBasis,
    },
    /// `blender_stucci`: `turbulence` (5) / 200 sets the offset.
    Stucci {
        noise: BlenderNoise,
        turbulence: f32,
        kind: StucciKind,
    },
    /// `blender_voronoi`: `outscale` / sum |w| times |w1 F1 + w2 F2 + w3 F3 + w4 F4| at
    /// p / `noisesize` under `distmetric` (weights 1, 0, 0, 0).
    Voronoi {
        metric: DistanceMetric,
        weights: [f32; 4],
        size: f32,
        outscale: f32,
        color: VoronoiColor,
    },
    /// `blender_noise`: white noise, the product of `noisedepth` + 1 (2 + 1) random values in
    /// {0, 1, 2, 3} over 3^(depth + 1).
    Noise { depth: u32 },
}

/// A pattern with Blender's `bright` (1) and `contrast` (1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BlenderTexture {
    pub pattern: BlenderPattern,
    pub bright: f32,
    pub contrast: f32,
}

/// What a Blender texture function returns (`TEX_INT` or `TEX_RGB`), before brightness and
/// contrast; stucci's value skips them.
enum PatternValue {
    Intensity(f32),
    Color(Vec3),
    Unadjusted(f32),
}

impl BlenderTexture {
    /// The intensity f in [0, 1] at texture-space point `p`.
    pub fn intensity(&self, p: Vec3) -> f32 {
        let adjust = |v: f32| (v - 0.5) * self.contrast + self.bright - 0.5;
        match self.pattern.value(p) {
            PatternValue::Intensity(f) => adjust(f).clamp(0.0, 1.0),
            PatternValue::Color(rgb) => {
                let rgb = Vec3::new(adjust(rgb.x), adjust(rgb.y), adjust(rgb.z)).max(Vec3::ZERO);
                (0.35 * rgb.x + 0.45 * rgb.y + 0.2 * rgb.z).min(1.0)
            }
            PatternValue::Unadjusted(f) => f,
        }
    }
}

/// `p` over a noise size, unless the size is 0.
fn over_size(p: Vec3, size: f32) -> Vec3 {
    if size != 0.0 { p / size } else { p }
}

impl BlenderPattern {
    fn value(&self, p: Vec3) -> PatternValue {
        use PatternValue::{Color, Intensity, Unadjusted};
        match *self {
            BlenderPattern::Blend { kind, flip_xy } => Intensity(blend(kind, flip_xy, p)),
            BlenderPattern::Magic { depth, turbulence } => Color(magic(p, depth, turbulence)),
            BlenderPattern::Wood {
                rings,
                wave,
                noise,
                turbulence,
            } => {
                let phase = if rings {
                    p.length() * 20.0
                } else {
                    (p.x + p.y + p.z) * 10.0
                };
                let distortion = noise.map_or(0.0, |n| turbulence * n.noise(p));
                Intensity(wave.at(phase + distortion))
            }
            BlenderPattern::Clouds {
                noise,
                depth,
                color,
            } => {
                let r = noise.turbulence(p, depth);
                if color {
                    let g = noise.turbulence(Vec3::new(p.y, p.x, p.z), depth);
                    let b = noise.turbulence(Vec3::new(p.y, p.z, p.x), depth);
                    Color(Vec3::new(r, g, b))
                } else {
                    Intensity(r)
                }
            }
            BlenderPattern::Marble {
                noise,
                depth,
                turbulence,
                wave,
                sharpness,
            } => {
                let phase = 5.0 * (p.x + p.y + p.z) + turbulence * noise.turbulence(p, depth);
                let m = wave.at(phase);
                Intensity(match sharpness {
                    MarbleSharpness::Soft => m,
                    MarbleSharpness::Sharp => m.sqrt(),
                    MarbleSharpness::Sharper => m.sqrt().sqrt(),
                })
            }
            BlenderPattern::Musgrave {
                fractal,
                size,
                outscale,
            } => Intensity(outscale * fractal.value(over_size(p, size))),
            BlenderPattern::DistortedNoise {
                size,
                amount,
                distortion,
                basis,
            } => Intensity(blender_noise::distorted_noise(
                over_size(p, size),
                amount,
                distortion,
                basis,
            )),
            BlenderPattern::Stucci {
                noise,
                turbulence,
                kind,
            } => {
                let base = noise.noise(p);
                let mut offset = turbulence / 200.0;
                if kind != StucciKind::Plastic {
                    offset *= base * base;
                }
                let f = noise.noise(p + Vec3::new(0.0, 0.0, offset));
                let f = if kind == StucciKind::WallOut {
                    1.0 - f
                } else {
                    f
                };
                Unadjusted(f.max(0.0))
            }
            BlenderPattern::Voronoi {
                metric,
                weights,
                size,
                outscale,
                color,
            } => voronoi_texture(over_size(p, size), metric, weights, outscale, color),
            BlenderPattern::Noise { depth } => {
                let mut bits = blender_noise::point_bits(p);
                let mut value = bits & 3;
                let mut divisor = 3.0f32;
                for _ in 0..depth {
                    bits >>= 2;
                    value *= bits & 3;
                    divisor *= 3.0;
                }
                Intensity(value as f32 / divisor)
            }
        }
    }
}

/// Blender's `voronoiTex`.
fn voronoi_texture(
    p: Vec3,
    metric: DistanceMetric,
    weights: [f32; 4],
    outscale: f32,
    color: VoronoiColor,
) -> PatternValue {
    let (distances, points) = blender_noise::voronoi(p, metric);
    let total: f32 = weights.iter().map(|w| w.abs()).sum();
    let scale = if total != 0.0 {
        outscale / total
    } else {
        total
    };
    let weighted: f32 = weights.iter().zip(distances).map(|(w, d)| w * d).sum();
    let intensity = scale * weighted.abs();
    if color == VoronoiColor::Intensity {
        return PatternValue::Intensity(intensity);
    }
    let rgb: Vec3 = weights
        .iter()
        .zip(points)
        .map(|(w, f)| w.abs() * blender_noise::cell_color(f))
        .sum();
    let factor = match color {
        VoronoiColor::CellsEdged => ((distances[1] - distances[0]) * 10.0).min(1.0) * scale,
        VoronoiColor::CellsEdgedShaded => {
            ((distances[1] - distances[0]) * 10.0).min(1.0) * intensity
        }
        _ => scale,
    };
    PatternValue::Color(rgb * factor)
}

/// Blender's `blend()`, before brightness and contrast.
fn blend(kind: BlendKind, flip_xy: bool, p: Vec3) -> f32 {
    let (x, y) = if flip_xy { (p.y, p.x) } else { (p.x, p.y) };
    let t = (1.0 + x) / 2.0;
    match kind {
        BlendKind::Linear => t,
        BlendKind::Quadratic => {
            if t < 0.0 {
                0.0
            } else {
                t * t
            }
        }
        BlendKind::Ease => {
            if t <= 0.0 {
                0.0
            } else if t >= 1.0 {
                1.0
            } else {
                t * t * (3.0 - 2.0 * t)
            }
        }
        BlendKind::Diagonal => (2.0 + x + y) / 4.0,
        BlendKind::Radial => y.atan2(x) / (2.0 * PI) + 0.5,
        BlendKind::Sphere | BlendKind::Halo => {
            let s = (1.0 - (x * x + y * y + p.z * p.z).sqrt()).max(0.0);
            if kind == BlendKind::Halo { s * s } else { s }
        }
    }
}

impl Waveform {
    /// Blender's `tex_sin`, `tex_saw`, `tex_tri`.
    fn at(self, a: f32) -> f32 {
        let period = 2.0 * PI;
        match self {
            Waveform::Sine => 0.5 + 0.5 * a.sin(),
            Waveform::Saw => {
                // a - trunc(a / 2pi) 2pi, moved into [0, 2pi) when negative.
                let r = a - (a / period).trunc() * period;
                (if r < 0.0 { r + period } else { r }) / period
            }
            Waveform::Triangle => {
                let cycles = a / period;
                1.0 - 2.0 * ((cycles + 0.5).floor() - cycles).abs()
            }
        }
    }
}

/// One fold of Blender's `magic()`: component `target` (0 x, 1 y, 2 z) becomes
/// `sign` x trig(sx x + sy y + sz z), with cos where `cosine`.
struct Fold {
    target: usize,
    sign: f32,
    cosine: bool,
    signs: [f32; 3],
}

/// The ten folds of `magic()` in order, applied while `noisedepth` allows
/// (y = -cos(x - y + z), x = cos(x - y - z), z = sin(-x - y - z), ...).
const FOLDS: [Fold; 10] = [
    Fold {
        target: 1,
        sign: -1.0,
        cosine: true,
        signs: [1.0, -1.0, 1.0],
    },
    Fold {
        target: 0,
        sign: 1.0,
        cosine: true,
        signs: [1.0, -1.0, -1.0],
    },
    Fold {
        target: 2,
        sign: 1.0,
        cosine: false,
        signs: [-1.0, -1.0, -1.0],
    },
    Fold {
        target: 0,
        sign: -1.0,
        cosine: true,
        signs: [-1.0, 1.0, -1.0],
    },
    Fold {
        target: 1,
        sign: -1.0,
        cosine: false,
        signs: [-1.0, 1.0, 1.0],
    },
    Fold {
        target: 1,
        sign: -1.0,
        cosine: true,
        signs: [-1.0, 1.0, 1.0],
    },
    Fold {
        target: 0,
        sign: 1.0,
        cosine: true,
        signs: [1.0, 1.0, 1.0],
    },
    Fold {
        target: 2,
        sign: 1.0,
        cosine: false,
        signs: [1.0, 1.0, -1.0],
    },
    Fold {
        target: 0,
        sign: -1.0,
        cosine: true,
        signs: [-1.0, -1.0, 1.0],
    },
    Fold {
        target: 1,
        sign: -1.0,
        cosine: false,
        signs: [1.0, -1.0, 1.0],
    },
];

/// Blender's `magic()` colour before brightness and contrast: three waves of the point, each
/// fold replacing one component by a wave of a signed sum of all three, scaled by
/// turbulence / 5 after each step; then (1/2 - x, 1/2 - y, 1/2 - z) of the components over
/// 2 turbulence / 5.
fn magic(p: Vec3, depth: u32, turbulence: f32) -> Vec3 {
    let turb = turbulence / 5.0;
    let mut c = [
        ((p.x + p.y + p.z) * 5.0).sin(),
        ((-p.x + p.y - p.z) * 5.0).cos(),
        -((-p.x - p.y + p.z) * 5.0).cos(),
    ];
    if depth > 0 {
        c.iter_mut().for_each(|v| *v *= turb);
        for fold in FOLDS.iter().take(depth as usize) {
            let arg = fold.signs[0] * c[0] + fold.signs[1] * c[1] + fold.signs[2] * c[2];
            let wave = if fold.cosine { arg.cos() } else { arg.sin() };
            c[fold.target] = fold.sign * wave * turb;
        }
    }
    if turb != 0.0 {
        c.iter_mut().for_each(|v| *v /= 2.0 * turb);
    }
    Vec3::new(0.5 - c[0], 0.5 - c[1], 0.5 - c[2])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::texture::blender_noise::{BlenderNoise, DistanceMetric, NoiseBasis};

    fn plain(pattern: BlenderPattern) -> BlenderTexture {
        BlenderTexture {
            pattern,
            bright: 1.0,
            contrast: 1.0,
        }
    }

    /// Blender's `blend()` by hand at p = (0.2, -0.6, 0.4): lin (1 + 0.2) / 2 = 0.6; quad 0.36;
    /// ease 3 (0.36) - 2 (0.216) = 0.648; diag (2 + 0.2 - 0.6) / 4 = 0.4; sphere
    /// 1 - sqrt(0.56) = 0.251669; halo its square 0.063337; radial atan2(-0.6, 0.2) / 2pi + 1/2
    /// = 0.301208; flipped lin (1 - 0.6) / 2 = 0.2.
    #[test]
    fn blend_progressions() {
        let p = Vec3::new(0.2, -0.6, 0.4);
        let at = |kind, flip_xy| plain(BlenderPattern::Blend { kind, flip_xy }).intensity(p);
        let cases = [
            (BlendKind::Linear, false, 0.6),
            (BlendKind::Quadratic, false, 0.36),
            (BlendKind::Ease, false, 0.648),
            (BlendKind::Diagonal, false, 0.4),
            (BlendKind::Sphere, false, 0.251_669),
            (BlendKind::Halo, false, 0.063_337),
            (BlendKind::Radial, false, 0.301_208),
            (BlendKind::Linear, true, 0.2),
        ];
        for (kind, flip, expected) in cases {
            let v = at(kind, flip);
            assert!((v - expected).abs() < 1e-5, "{kind:?} {flip}: {v}");
        }
        // Brightness and contrast: (0.6 - 0.5) 2 + 1.2 - 0.5 = 0.9; then clamped to 1.
        let lin = BlenderPattern::Blend {
            kind: BlendKind::Linear,
            flip_xy: false,
        };
        let bricont = |bright, contrast| {
            BlenderTexture {
                pattern: lin,
                bright,
                contrast,
            }
            .intensity(p)
        };
        assert!((bricont(1.2, 2.0) - 0.9).abs() < 1e-6);
        assert_eq!(bricont(1.5, 2.0), 1.0);
    }

    /// `wood_int` by hand. Bands at x + y + z = 0.05: phase 0.5, sin 1/2 + sin(0.5) / 2 =
    /// 0.739713; saw 0.5 / 2pi = 0.079577; tri 1 - 2 |0 - 0.079577| = 0.840845. Rings at
    /// radius 0.3: phase 6, sin 1/2 + sin(6) / 2 = 0.360292; a negative phase wraps the saw
    /// into [0, 1): -0.5 gives 1 - 0.079577.
    #[test]
    fn wood_waves() {
        let wood = |rings, wave, p: Vec3| {
            plain(BlenderPattern::Wood {
                rings,
                wave,
                noise: None,
                turbulence: 5.0,
            })
            .intensity(p)
        };
        let band = Vec3::new(0.02, 0.01, 0.02);
        assert!((wood(false, Waveform::Sine, band) - 0.739_713).abs() < 1e-5);
        assert!((wood(false, Waveform::Saw, band) - 0.079_577).abs() < 1e-5);
        assert!((wood(false, Waveform::Triangle, band) - 0.840_845).abs() < 1e-5);
        let ring = Vec3::new(0.0, 0.3, 0.0);
        assert!((wood(true, Waveform::Sine, ring) - 0.360_292).abs() < 1e-5);
        let saw = wood(false, Waveform::Saw, -band);
        assert!((saw - (1.0 - 0.079_577)).abs() < 1e-5, "{saw}");
    }

    /// `magic()` by hand at the origin with depth 1 and turbulence 5 (turb 1): x = sin 0 = 0,
    /// y = cos 0 = 1, z = -cos 0 = -1; the first fold y = -cos(x - y + z) = -cos(-2) = 0.416147;
    /// over 2 turb: (0, 0.208073, -0.5), so the colour is (0.5, 0.291927, 1.0) and the
    /// intensity 0.35 (0.5) + 0.45 (0.291927) + 0.2 (1.0) = 0.506367. With depth 0 there is
    /// no fold: (0.5, 0, 1) gives 0.375.
    #[test]
    fn magic_folds() {
        let magic = |depth| {
            plain(BlenderPattern::Magic {
                depth,
                turbulence: 5.0,
            })
            .intensity(Vec3::ZERO)
        };
        assert!((magic(1) - 0.506_367).abs() < 1e-5, "{}", magic(1));
        assert!((magic(0) - 0.375).abs() < 1e-6, "{}", magic(0));
        // Every depth up to 10 applies one more fold (and the value stays in [0, 1]).
        let p = Vec3::new(0.3, -0.2, 0.7);
        let values: Vec<f32> = (0..=10)
            .map(|depth| {
                plain(BlenderPattern::Magic {
                    depth,
                    turbulence: 5.0,
                })
                .intensity(p)
            })
            .collect();
        assert!(values.iter().all(|v| (0.0..=1.0).contains(v)));
        assert!(values.windows(2).all(|w| w[0] != w[1]), "{values:?}");
    }

    fn noise(basis: NoiseBasis, size: f32, hard: bool) -> BlenderNoise {
        BlenderNoise { basis, size, hard }
    }

    /// The noisy patterns' intensities at p = (0.31, -0.17, 0.44), from an independent float64
    /// transcription (Python, not foton's code) of `blender_texlib.cpp`'s `clouds`, `marble`,
    /// `wood`, `stucci`, `voronoiTex` and `BlenderTexture3D::GetF`, with LuxRender's defaults
    /// (noise size 0.25, depth 2, turbulence 5) unless named.
    #[test]
    fn noisy_patterns_match_the_c_source() {
        let p = Vec3::new(0.31, -0.17, 0.44);
        let original = noise(NoiseBasis::BlenderOriginal, 0.25, false);
        let wood = |rings, noise| BlenderPattern::Wood {
            rings,
            wave: Waveform::Sine,
            noise: Some(noise),
            turbulence: 5.0,
        };
        let voronoi = |weights, outscale, metric, color| BlenderPattern::Voronoi {
            metric,
            weights,
            size: 0.25,
            outscale,
            color,
        };
        let cases = [
            (
                "clouds",
                BlenderPattern::Clouds {
                    noise: original,
                    depth: 2,
                    color: false,
                },
                0.240_812_221_09,
            ),
            (
                "clouds color, improved Perlin, hard, depth 3",
                BlenderPattern::Clouds {
                    noise: noise(NoiseBasis::ImprovedPerlin, 0.25, true),
                    depth: 3,
                    color: true,
                },
                0.232_236_937_81,
            ),
            (
                "marble",
                BlenderPattern::Marble {
                    noise: original,
                    depth: 2,
                    turbulence: 5.0,
                    wave: Waveform::Sine,
                    sharpness: MarbleSharpness::Soft,
                },
                0.089_697_611_21,
            ),
            (
                "marble sharper, original Perlin, hard, size 0.5, turbulence 3",
                BlenderPattern::Marble {
                    noise: noise(NoiseBasis::OriginalPerlin, 0.5, true),
                    depth: 2,
                    turbulence: 3.0,
                    wave: Waveform::Sine,
                    sharpness: MarbleSharpness::Sharper,
                },
                0.743_447_624_18,
            ),
            ("wood bandnoise", wood(false, original), 0.817_093_681_69),
            (
                "wood ringnoise, improved Perlin",
                wood(true, noise(NoiseBasis::ImprovedPerlin, 0.25, false)),
                0.453_414_062_27,
            ),
            (
                "stucci plastic",
                BlenderPattern::Stucci {
                    noise: original,
                    turbulence: 5.0,
                    kind: StucciKind::Plastic,
                },
                0.233_832_180_55,
            ),
            (
                "stucci wall in, hard",
                BlenderPattern::Stucci {
                    noise: noise(NoiseBasis::BlenderOriginal, 0.25, true),
                    turbulence: 5.0,
                    kind: StucciKind::WallIn,
                },
                0.537_103_611_93,
            ),
            (
                "stucci wall out, improved Perlin, turbulence 20",
                BlenderPattern::Stucci {
                    noise: noise(NoiseBasis::ImprovedPerlin, 0.25, false),
                    turbulence: 20.0,
                    kind: StucciKind::WallOut,
                },
                0.759_445_367_76,
            ),
            (
                "voronoi F1",
                voronoi(
                    [1.0, 0.0, 0.0, 0.0],
                    1.0,
                    DistanceMetric::Actual,
                    VoronoiColor::Intensity,
                ),
                0.490_543_159_15,
            ),
            (
                "voronoi weighted, Minkowski 2.5, outscale 1.5",
                voronoi(
                    [1.0, -0.5, 0.3, 0.0],
                    1.5,
                    DistanceMetric::Minkowski(2.5),
                    VoronoiColor::Intensity,
                ),
                0.266_296_569_17,
            ),
            (
                "voronoi cell colours",
                voronoi(
                    [1.0, 0.0, 0.0, 0.0],
                    1.0,
                    DistanceMetric::Actual,
                    VoronoiColor::Cells,
                ),
                0.729_323_25,
            ),
            (
                "voronoi edged colours",
                voronoi(
                    [0.8, 0.4, 0.0, 0.0],
                    1.0,
                    DistanceMetric::Actual,
                    VoronoiColor::CellsEdged,
                ),
                0.648_529_933_33,
            ),
            (
                "voronoi edged shaded colours",
                voronoi(
                    [0.8, 0.4, 0.0, 0.0],
                    1.0,
                    DistanceMetric::Actual,
                    VoronoiColor::CellsEdgedShaded,
                ),
                0.452_150_127_71,
            ),
        ];
        for (name, pattern, expected) in cases {
            let v = plain(pattern).intensity(p);
            assert!((f64::from(v) - expected).abs() < 2e-5, "{name}: {v}");
        }
    }

    /// `blender_noise` is white: every depth gives values k / 3^(depth + 1) for k a product of
    /// depth + 1 factors in {0, 1, 2, 3}, with mean (3/2)^(depth + 1) / 3^(depth + 1) =
    /// 2^-(depth + 1); over 20000 points the mean of depth 2 (1/8, standard deviation of one
    /// value sqrt(E[v^2] - 1/64) with E[v^2] = (14/4)^3 / 3^6 = 0.0588, so 0.21) is within
    /// 4 sigma / sqrt(20000) = 0.006 of 1/8.
    #[test]
    fn noise_is_white_with_blenders_distribution() {
        let pattern = plain(BlenderPattern::Noise { depth: 2 });
        let n = 20_000;
        let mut sum = 0.0f64;
        for i in 0..n {
            let t = i as f32;
            let p = Vec3::new(t * 0.013, (t * 0.618_034).fract(), -t * 0.007);
            let v = pattern.intensity(p);
            let k = v * 27.0;
            assert!((k - k.round()).abs() < 1e-4 && k.round() <= 27.0, "{v}");
            sum += f64::from(v);
        }
        let mean = sum / f64::from(n);
        assert!((mean - 0.125).abs() < 0.006, "{mean}");
    }
}
