//! Blender's noise bases and the sums built on them, as LuxRender 1.x evaluates its Blender
//! textures (`textures/blender_noiselib.cpp`, taken from Blender 2.4x's `noise.c`; the tables
//! are in [`super::blender_tables`]).
//!
//! Every basis is a function of a point; each has an unsigned form (roughly [0, 1], used by
//! `BLI_gNoise` and `BLI_gTurbulence`) and a signed one (roughly [-1, 1], used by the Musgrave
//! fractals and the distorted noise):
//!
//! - **Blender original** (`orgBlenderNoise`): gradient noise over `hashvectf`, the cell's eight
//!   corner gradients dotted with the offsets to the corners and weighted by the cubic
//!   1 - 3t^2 + 2|t|^3 of each offset component, plus 1/2, clamped to [0, 1]. It is 1/2 on the
//!   lattice.
//! - **Original Perlin** (`noise3_perlin`): Perlin's 1985 noise over the table `g` (the same
//!   vectors), smoothstep blend, times 1.5.
//! - **Improved Perlin** (`newPerlin`): Perlin's 2002 noise over Blender's `hash` (not Perlin's
//!   permutation), its 12 edge gradients, quintic blend.
//! - **Voronoi** F1..F4 (the distance to the 1st..4th nearest feature point, one feature point
//!   per cell at the cell's `hashpntf` offset, searched over the 27 cells around the point),
//!   F2 - F1, and crackle min(10 (F2 - F1), 1).
//! - **Cell noise**: a per-cell integer hash, constant inside each cell.

use glam::Vec3;

use super::blender_tables::{HASH, HASH_POINTS, HASH_VECTORS};

/// `"noisebasis"` (and distorted noise's `"type"`), LuxRender's names in comments.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NoiseBasis {
    /// "blender_original"
    BlenderOriginal,
    /// "original_perlin"
    OriginalPerlin,
    /// "improved_perlin"
    ImprovedPerlin,
    /// "voronoi_f1"
    VoronoiF1,
    /// "voronoi_f2"
    VoronoiF2,
    /// "voronoi_f3"
    VoronoiF3,
    /// "voronoi_f4"
    VoronoiF4,
    /// "voronoi_f2_f1"
    VoronoiF2F1,
    /// "voronoi_crackle"
    VoronoiCrackle,
    /// "cell_noise"
    CellNoise,
}

/// Voronoi's distance metric (`"distmetric"`); the exponent is used only by `Minkowski`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DistanceMetric {
    /// "actual_distance": |d|.
    Actual,
    /// "distance_squared": |d|^2.
    Squared,
    /// "manhattan": |x| + |y| + |z|.
    Manhattan,
    /// "chebychev": max(|x|, |y|, |z|).
    Chebychev,
    /// "minkovsky_half": (sqrt|x| + sqrt|y| + sqrt|z|)^2.
    MinkowskiHalf,
    /// "minkovsky_four": (x^4 + y^4 + z^4)^(1/4).
    MinkowskiFour,
    /// "minkovsky": (|x|^e + |y|^e + |z|^e)^(1/e).
    Minkowski(f32),
}

impl DistanceMetric {
    fn distance(self, d: Vec3) -> f32 {
        let a = d.abs();
        match self {
            DistanceMetric::Actual => d.length(),
            DistanceMetric::Squared => d.length_squared(),
            DistanceMetric::Manhattan => a.x + a.y + a.z,
            DistanceMetric::Chebychev => a.max_element(),
            DistanceMetric::MinkowskiHalf => {
                let s = a.x.sqrt() + a.y.sqrt() + a.z.sqrt();
                s * s
            }
            DistanceMetric::MinkowskiFour => {
                let q = a * a;
                (q.x * q.x + q.y * q.y + q.z * q.z).sqrt().sqrt()
            }
            DistanceMetric::Minkowski(e) => (a.x.powf(e) + a.y.powf(e) + a.z.powf(e)).powf(1.0 / e),
        }
    }
}

/// `hash[i & 255]`: every index into Blender's 512-entry tables is below 512 and the second
/// half repeats the first.
fn hash(i: i32) -> i32 {
    i32::from(HASH[(i & 255) as usize])
}

/// The lattice cell of each coordinate (`(int)floor(x)`), saturating for huge values.
fn cell(p: Vec3) -> [i32; 3] {
    [p.x.floor() as i32, p.y.floor() as i32, p.z.floor() as i32]
}

/// `orgBlenderNoise`: in [0, 1], 1/2 on the lattice.
fn blender_original(p: Vec3) -> f32 {
    let [ix, iy, iz] = cell(p);
    let o = p - p.floor();
    let j = o - Vec3::ONE;
    // The corner weights 1 - 3t^2 + 2|t|^3 for the offsets o (to the lower corner) and j (to
    // the upper one): 1 at the corner, 0 at the next, zero slope at both.
    let near = |t: f32| 1.0 - 3.0 * t * t + 2.0 * t * t * t;
    let far = |t: f32| 1.0 - 3.0 * t * t - 2.0 * t * t * t;
    let wx = [near(o.x), far(j.x)];
    let wy = [near(o.y), far(j.y)];
    let wz = [near(o.z), far(j.z)];
    let dx = [o.x, j.x];
    let dy = [o.y, j.y];
    let dz = [o.z, j.z];
    let mut n = 0.5;
    for a in 0..2 {
        for b in 0..2 {
            let column = hash(hash(ix.wrapping_add(a)) + (iy.wrapping_add(b) & 255));
            for c in 0..2 {
                let g = HASH_VECTORS[hash((iz.wrapping_add(c) & 255) + column) as usize];
                let (a, b, c) = (a as usize, b as usize, c as usize);
                let weight = wx[a] * wy[b] * wz[c];
                n += weight * (g[0] * dx[a] + g[1] * dy[b] + g[2] * dz[c]);
            }
        }
    }
    n.clamp(0.0, 1.0)
}

/// `noise3_perlin`: Perlin's original noise, times 1.5. Each coordinate is offset by 10000 in
/// single precision before its cell and fraction are taken (the `setup` macro), which LuxRender
/// does too: the fraction is quantised to the float spacing near 10000 (2^-10).
fn original_perlin(p: Vec3) -> f32 {
    let setup = |v: f32| {
        let t = (f64::from(v) + 10000.0) as f32;
        let b0 = (t as i32) & 255;
        let r0 = t - (t as i32) as f32;
        (b0, (b0 + 1) & 255, r0, r0 - 1.0)
    };
    let (bx0, bx1, rx0, rx1) = setup(p.x);
    let (by0, by1, ry0, ry1) = setup(p.y);
    let (bz0, bz1, rz0, rz1) = setup(p.z);
    let (i, j) = (hash(bx0), hash(bx1));
    let (b00, b10, b01, b11) = (hash(i + by0), hash(j + by0), hash(i + by1), hash(j + by1));
    let s_curve = |t: f32| t * t * (3.0 - 2.0 * t);
    let (sx, sy, sz) = (s_curve(rx0), s_curve(ry0), s_curve(rz0));
    let at = |k: i32, rx: f32, ry: f32, rz: f32| {
        let q = HASH_VECTORS[(k & 255) as usize];
        rx * q[0] + ry * q[1] + rz * q[2]
    };
    let layer = |bz: i32, rz: f32| {
        let a = lerp(sx, at(b00 + bz, rx0, ry0, rz), at(b10 + bz, rx1, ry0, rz));
        let b = lerp(sx, at(b01 + bz, rx0, ry1, rz), at(b11 + bz, rx1, ry1, rz));
        lerp(sy, a, b)
    };
    1.5 * lerp(sz, layer(bz0, rz0), layer(bz1, rz1))
}

/// `grad` of `newPerlin`: the 4 low bits of the hash pick one of 12 edge gradients
/// (12 to 15 repeat four of them).
fn improved_grad(h: i32, x: f32, y: f32, z: f32) -> f32 {
    let h = h & 15;
    let u = if h < 8 { x } else { y };
    let v = if h < 4 {
        y
    } else if h == 12 || h == 14 {
        x
    } else {
        z
    };
    (if h & 1 == 0 { u } else { -u }) + (if h & 2 == 0 { v } else { -v })
}

/// `newPerlin`: Perlin's improved noise over Blender's hash table.
fn improved_perlin(p: Vec3) -> f32 {
    let [x0, y0, z0] = cell(p).map(|c| c & 255);
    let d = p - p.floor();
    let fade = |t: f32| t * t * t * (t * (t * 6.0 - 15.0) + 10.0);
    let (u, v, w) = (fade(d.x), fade(d.y), fade(d.z));
    let a = hash(x0) + y0;
    let (aa, ab) = (hash(a) + z0, hash(a + 1) + z0);
    let b = hash(x0 + 1) + y0;
    let (ba, bb) = (hash(b) + z0, hash(b + 1) + z0);
    let (x, y, z) = (d.x, d.y, d.z);
    let g = |k: i32, dx: f32, dy: f32, dz: f32| improved_grad(hash(k), x - dx, y - dy, z - dz);
    lerp(
        w,
        lerp(
            v,
            lerp(u, g(aa, 0.0, 0.0, 0.0), g(ba, 1.0, 0.0, 0.0)),
            lerp(u, g(ab, 0.0, 1.0, 0.0), g(bb, 1.0, 1.0, 0.0)),
        ),
        lerp(
            v,
            lerp(u, g(aa + 1, 0.0, 0.0, 1.0), g(ba + 1, 1.0, 0.0, 1.0)),
            lerp(u, g(ab + 1, 0.0, 1.0, 1.0), g(bb + 1, 1.0, 1.0, 1.0)),
        ),
    )
}

fn lerp(t: f32, a: f32, b: f32) -> f32 {
    a + t * (b - a)
}

/// The feature point of lattice cell (x, y, z): the cell's corner plus its `hashpntf` offset
/// (`HASHPNT`, which hashes z first).
fn feature_point(x: i32, y: i32, z: i32) -> Vec3 {
    let q = HASH_POINTS[hash(hash(hash(z) + y) + x) as usize];
    Vec3::new(q[0] + x as f32, q[1] + y as f32, q[2] + z as f32)
}

/// The four nearest feature points to `p` among the 27 cells around it (Blender's `voronoi`,
/// "not pure Worley, but virtually the same"): their distances, nearest first, and positions.
pub fn voronoi(p: Vec3, metric: DistanceMetric) -> ([f32; 4], [Vec3; 4]) {
    let [xi, yi, zi] = cell(p);
    let mut distances = [1e10f32; 4];
    let mut points = [Vec3::ZERO; 4];
    for x in xi.saturating_sub(1)..=xi.saturating_add(1) {
        for y in yi.saturating_sub(1)..=yi.saturating_add(1) {
            for z in zi.saturating_sub(1)..=zi.saturating_add(1) {
                let f = feature_point(x, y, z);
                let d = metric.distance(p - f);
                // Insert into the sorted four, dropping the farthest (strict comparisons,
                // as Blender: ties keep the earlier point).
                if let Some(slot) = distances.iter().position(|&known| d < known) {
                    for k in (slot + 1..4).rev() {
                        distances[k] = distances[k - 1];
                        points[k] = points[k - 1];
                    }
                    distances[slot] = d;
                    points[slot] = f;
                }
            }
        }
    }
    (distances, points)
}

/// `cellNoiseU`: a hash of the point's cell in [0, 1].
fn cell_noise(p: Vec3) -> f32 {
    let [x, y, z] = cell(p).map(|c| c as u32);
    let mut n = x
        .wrapping_add(y.wrapping_mul(1301))
        .wrapping_add(z.wrapping_mul(314_159));
    n ^= n << 13;
    let h = n
        .wrapping_mul(n.wrapping_mul(n).wrapping_mul(15731).wrapping_add(789_221))
        .wrapping_add(1_376_312_589);
    h as f32 / 4_294_967_296.0
}

/// `cellNoiseV`: the `hashpntf` offset of the point's cell, as a colour.
pub fn cell_color(p: Vec3) -> Vec3 {
    let [x, y, z] = cell(p);
    let q = HASH_POINTS[hash(hash(hash(z) + y) + x) as usize];
    Vec3::from_array(q)
}

impl NoiseBasis {
    /// LuxRender's name of each basis (`blender_base.cpp`); "voronoi_f2f1" is the older
    /// spelling of "voronoi_f2_f1" (LuxRender before 1.0).
    pub fn from_name(name: &str) -> Option<Self> {
        Some(match name {
            "blender_original" => NoiseBasis::BlenderOriginal,
            "original_perlin" => NoiseBasis::OriginalPerlin,
            "improved_perlin" => NoiseBasis::ImprovedPerlin,
            "voronoi_f1" => NoiseBasis::VoronoiF1,
            "voronoi_f2" => NoiseBasis::VoronoiF2,
            "voronoi_f3" => NoiseBasis::VoronoiF3,
            "voronoi_f4" => NoiseBasis::VoronoiF4,
            "voronoi_f2_f1" | "voronoi_f2f1" => NoiseBasis::VoronoiF2F1,
            "voronoi_crackle" => NoiseBasis::VoronoiCrackle,
            "cell_noise" => NoiseBasis::CellNoise,
            _ => return None,
        })
    }

    /// The Voronoi distance this basis reads, if it is one of F1..F4 (index 0..3).
    fn voronoi_rank(self) -> Option<usize> {
        match self {
            NoiseBasis::VoronoiF1 => Some(0),
            NoiseBasis::VoronoiF2 => Some(1),
            NoiseBasis::VoronoiF3 => Some(2),
            NoiseBasis::VoronoiF4 => Some(3),
            _ => None,
        }
    }

    /// F2 - F1 at `p` (Euclidean).
    fn voronoi_gap(p: Vec3) -> f32 {
        let (d, _) = voronoi(p, DistanceMetric::Actual);
        d[1] - d[0]
    }

    /// The unsigned basis (`orgBlenderNoise`, `orgPerlinNoiseU`, `newPerlinU`, `voronoi_F1`..,
    /// `voronoi_Cr`, `cellNoiseU`).
    pub fn unsigned(self, p: Vec3) -> f32 {
        if let Some(rank) = self.voronoi_rank() {
            return voronoi(p, DistanceMetric::Actual).0[rank];
        }
        match self {
            NoiseBasis::BlenderOriginal => blender_original(p),
            NoiseBasis::OriginalPerlin => 0.5 + 0.5 * original_perlin(p),
            NoiseBasis::ImprovedPerlin => 0.5 + 0.5 * improved_perlin(p),
            NoiseBasis::VoronoiF2F1 => Self::voronoi_gap(p),
            NoiseBasis::VoronoiCrackle => (10.0 * Self::voronoi_gap(p)).min(1.0),
            _ => cell_noise(p),
        }
    }

    /// The signed basis (`orgBlenderNoiseS`, `orgPerlinNoise`, `newPerlin`, `voronoi_F1S`..,
    /// `voronoi_CrS`, `cellNoise`): 2 u - 1 of the unsigned one, except that the two Perlin
    /// noises are signed to begin with and crackle's clamped value 1 stays 1.
    pub fn signed(self, p: Vec3) -> f32 {
        match self {
            NoiseBasis::OriginalPerlin => original_perlin(p),
            NoiseBasis::ImprovedPerlin => improved_perlin(p),
            NoiseBasis::VoronoiCrackle => {
                let t = 10.0 * Self::voronoi_gap(p);
                if t > 1.0 { 1.0 } else { 2.0 * t - 1.0 }
            }
            _ => 2.0 * self.unsigned(p) - 1.0,
        }
    }

    /// The point at which `BLI_gNoise` and `BLI_gTurbulence` evaluate: Blender's original
    /// basis is shifted by 1 in each coordinate (to agree with the older `BLI_hnoise`), then
    /// every basis is scaled by 1 / `noise_size` unless the size is 0.
    fn scaled(self, noise_size: f32, p: Vec3) -> Vec3 {
        let p = if self == NoiseBasis::BlenderOriginal {
            p + Vec3::ONE
        } else {
            p
        };
        if noise_size != 0.0 {
            p * (1.0 / noise_size)
        } else {
            p
        }
    }
}

/// The noise shared by clouds, marble, wood and stucci: a basis, its `"noisesize"` and
/// `"noisetype"` ("hard_noise" folds the unsigned value as |2 n - 1|).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BlenderNoise {
    pub basis: NoiseBasis,
    pub size: f32,
    pub hard: bool,
}

impl BlenderNoise {
    fn fold(&self, n: f32) -> f32 {
        if self.hard { (2.0 * n - 1.0).abs() } else { n }
    }

    /// `BLI_gNoise`.
    pub fn noise(&self, p: Vec3) -> f32 {
        self.fold(self.basis.unsigned(self.basis.scaled(self.size, p)))
    }

    /// `BLI_gTurbulence`: octaves 0..=`depth` of doubling frequency and halving amplitude,
    /// normalised by 2^depth / (2^(depth + 1) - 1) so that a constant noise keeps its value.
    pub fn turbulence(&self, p: Vec3, depth: u32) -> f32 {
        let q = self.basis.scaled(self.size, p);
        let (mut sum, mut amplitude, mut frequency) = (0.0, 1.0, 1.0);
        for _ in 0..=depth {
            sum += amplitude * self.fold(self.basis.unsigned(frequency * q));
            amplitude *= 0.5;
            frequency *= 2.0;
        }
        let top = 2f32.powi(depth as i32);
        sum * top / (2.0 * top - 1.0)
    }
}

/// `mg_VLNoise`, Blender's distorted noise: `basis` at `p` displaced by `distortion` times the
/// signed `distortion_basis` at three shifted copies of `p`.
pub fn distorted_noise(
    p: Vec3,
    distortion: f32,
    distortion_basis: NoiseBasis,
    basis: NoiseBasis,
) -> f32 {
    let shift = Vec3::splat(13.5);
    let offset = Vec3::new(
        distortion_basis.signed(p + shift),
        distortion_basis.signed(p),
        distortion_basis.signed(p - shift),
    ) * distortion;
    basis.signed(p + offset)
}

/// A white noise in [0, 1) per point: the 31 bits Blender's `texnoise` draws from `BLI_rand`,
/// here a hash of the point's coordinates (LuxRender draws anew at every evaluation; both
/// average to the same value over a pixel's samples).
pub fn point_bits(p: Vec3) -> u32 {
    // MurmurHash3's 32-bit finaliser over each coordinate's bits in turn.
    let mix = |mut h: u32| {
        h ^= h >> 16;
        h = h.wrapping_mul(0x85eb_ca6b);
        h ^= h >> 13;
        h = h.wrapping_mul(0xc2b2_ae35);
        h ^ (h >> 16)
    };
    let h = [p.x, p.y, p.z]
        .iter()
        .fold(0x9e37_79b9u32, |h, v| mix(h ^ v.to_bits()));
    h >> 1
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The transcription of the tables: `hash` is a permutation of 0..255, the gradients have
    /// unit length to the source's six digits, the feature offsets lie in [0, 1).
    #[test]
    fn tables_are_transcribed_whole() {
        let mut seen = [false; 256];
        HASH.iter().for_each(|&h| seen[h as usize] = true);
        assert!(seen.iter().all(|&s| s));
        for (i, g) in HASH_VECTORS.iter().enumerate() {
            let len = Vec3::from_array(*g).length();
            assert!((len - 1.0).abs() < 2e-3, "row {i}: {len}");
        }
        assert!(HASH_POINTS.iter().flatten().all(|v| (0.0..1.0).contains(v)));
    }

    /// On the lattice only the lower corner's weight is 1 and its offset is 0, so Blender's
    /// original noise is 1/2 there; the improved Perlin noise is 0 there.
    #[test]
    fn lattice_values() {
        for p in [
            Vec3::ZERO,
            Vec3::new(3.0, -7.0, 12.0),
            Vec3::new(-1.0, 5.0, 255.0),
        ] {
            assert_eq!(blender_original(p), 0.5, "{p}");
            assert_eq!(improved_perlin(p), 0.0, "{p}");
        }
    }

    /// At the centre of cell (0, 0, 0) all corner weights of Blender's original noise are
    /// 1 - 3/4 + 1/4 = 1/2, so n = 1/2 + (1/8) sum over corners of g . (+-1/2, +-1/2, +-1/2),
    /// each corner's gradient the `hashvectf` row hash[hash[hash[x] + y] + z]: by hand from the
    /// tables (rows 219, 124, 86, 239, 233, 230, 224, 41 for corners 000, 001, 010, 011, 100,
    /// 101, 110, 111), 0.5 + (1/16) (sum of signed components) = 0.314285; the float64
    /// transcription of the C source gives the same.
    #[test]
    fn blender_original_at_a_cell_centre() {
        let corners = [
            (0, 0, 0),
            (0, 0, 1),
            (0, 1, 0),
            (0, 1, 1),
            (1, 0, 0),
            (1, 0, 1),
            (1, 1, 0),
            (1, 1, 1),
        ];
        let mut expected = 0.5f64;
        for (x, y, z) in corners {
            let row = hash(hash(hash(x) + y) + z) as usize;
            let g = HASH_VECTORS[row];
            let s = |c: i32| if c == 0 { 0.5 } else { -0.5 };
            expected +=
                (f64::from(g[0]) * s(x) + f64::from(g[1]) * s(y) + f64::from(g[2]) * s(z)) / 8.0;
        }
        let n = blender_original(Vec3::splat(0.5));
        assert!((f64::from(n) - expected).abs() < 1e-6, "{n} {expected}");
        assert!((f64::from(n) - 0.314_285_25).abs() < 1e-6, "{n}");
    }

    fn close(a: f32, b: f64, tolerance: f64) -> bool {
        (f64::from(a) - b).abs() < tolerance
    }

    /// Values of the bases off the lattice from an independent float64 transcription (Python,
    /// not foton's code) of LuxRender 1.x's `blender_noiselib.cpp` (`orgBlenderNoise`,
    /// `noise3_perlin` with its single-precision `setup`, `newPerlin`, `voronoi` under each
    /// metric with exponent 2.5, `cellNoiseU`, `cellNoiseV`).
    #[test]
    fn bases_match_the_c_source() {
        let p = Vec3::new(0.3, 1.7, -2.2);
        let q = Vec3::new(10.25, -3.75, 0.5);
        let r = Vec3::new(-4.6, 2.35, 7.9);
        let cases = [
            (original_perlin(p), 0.318_223_630_73),
            (original_perlin(q), 0.098_835_476_81),
            (improved_perlin(p), -0.504_358_264_18),
            (improved_perlin(q), 0.158_460_617_07),
            (blender_original(p), 0.459_983_332_27),
            (blender_original(r), 0.717_790_740_99),
            (cell_noise(p), 0.266_620_367_77),
            (cell_noise(r), 0.562_630_772_59),
            (cell_noise(Vec3::new(-3.2, -0.5, 100.1)), 0.265_495_330_10),
        ];
        for (i, (value, expected)) in cases.into_iter().enumerate() {
            assert!(close(value, expected, 1e-5), "case {i}: {value} {expected}");
        }
        assert_eq!(
            cell_color(Vec3::new(-4.5, 2.1, 7.9)),
            Vec3::new(0.085_726, 0.796_024, 0.665_075)
        );
        let metrics: [(DistanceMetric, [f64; 4]); 7] = [
            (
                DistanceMetric::Actual,
                [0.564_556_85, 0.594_049_92, 0.621_326_32, 0.723_997_20],
            ),
            (
                DistanceMetric::Squared,
                [0.318_724_44, 0.352_895_31, 0.386_046_39, 0.524_171_95],
            ),
            (
                DistanceMetric::Manhattan,
                [0.823_927, 0.897_808, 0.995_223, 1.004_623],
            ),
            (
                DistanceMetric::Chebychev,
                [0.443_439, 0.446_024, 0.509_084, 0.543_284],
            ),
            (
                DistanceMetric::MinkowskiHalf,
                [2.118_915_50, 2.147_052_25, 2.207_042_77, 2.377_654_26],
            ),
            (
                DistanceMetric::MinkowskiFour,
                [0.478_393_71, 0.514_242_99, 0.522_262_19, 0.611_215_54],
            ),
            (
                DistanceMetric::Minkowski(2.5),
                [0.537_676_60, 0.540_703_48, 0.579_492_32, 0.676_185_90],
            ),
        ];
        for (metric, expected) in metrics {
            let (d, points) = voronoi(r, metric);
            for k in 0..4 {
                assert!(
                    close(d[k], expected[k], 2e-5),
                    "{metric:?} F{}: {}",
                    k + 1,
                    d[k]
                );
                // Each feature point is at its distance.
                assert!((metric.distance(r - points[k]) - d[k]).abs() < 1e-6);
            }
        }
    }

    /// `BLI_gTurbulence` (noise size 0.25, depth 2) over each basis, soft and hard, and
    /// `BLI_gNoise`, from the same transcription.
    #[test]
    fn turbulence_and_noise_match_the_c_source() {
        let p = Vec3::new(0.3, 1.7, -2.2);
        let cases = [
            (
                NoiseBasis::BlenderOriginal,
                0.411_894_200_83,
                0.286_596_891_37,
            ),
            (
                NoiseBasis::OriginalPerlin,
                0.602_255_509_41,
                0.204_511_018_81,
            ),
            (
                NoiseBasis::ImprovedPerlin,
                0.595_821_290_04,
                0.245_890_276_91,
            ),
            (NoiseBasis::VoronoiF1, 0.380_558_765_63, 0.371_432_257_95),
            (NoiseBasis::VoronoiF2F1, 0.149_593_649_95, 0.700_812_700_09),
            (
                NoiseBasis::VoronoiCrackle,
                0.737_413_460_16,
                0.865_263_047_21,
            ),
            (NoiseBasis::CellNoise, 0.563_673_658_03, 0.404_900_670_05),
        ];
        for (basis, soft, hard) in cases {
            let noise = |hard| BlenderNoise {
                basis,
                size: 0.25,
                hard,
            };
            let t = noise(false).turbulence(p, 2);
            assert!(close(t, soft, 2e-5), "{basis:?} soft: {t}");
            let t = noise(true).turbulence(p, 2);
            assert!(close(t, hard, 2e-5), "{basis:?} hard: {t}");
        }
        let soft = BlenderNoise {
            basis: NoiseBasis::BlenderOriginal,
            size: 0.25,
            hard: false,
        };
        assert!(close(soft.noise(p), 0.297_521_285_75, 1e-5));
        let hard = BlenderNoise {
            basis: NoiseBasis::ImprovedPerlin,
            size: 0.5,
            hard: true,
        };
        let r = Vec3::new(-4.6, 2.35, 7.9);
        assert!(close(hard.noise(r), 0.379_802_408_25, 1e-5));
    }

    /// `mg_VLNoise` from the same transcription: Blender's original basis distorting itself,
    /// and cell noise distorting Voronoi F1 by 2.5.
    #[test]
    fn distorted_noise_matches_the_c_source() {
        let p = Vec3::new(1.2, -0.7, 2.9);
        let original = NoiseBasis::BlenderOriginal;
        let v = distorted_noise(p, 1.0, original, original);
        assert!(close(v, -0.689_983_023_96, 1e-5), "{v}");
        let v = distorted_noise(p, 2.5, NoiseBasis::CellNoise, NoiseBasis::VoronoiF1);
        assert!(close(v, -0.356_997_309_75, 1e-5), "{v}");
    }
}
