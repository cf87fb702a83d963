//! Perlin's gradient noise and its sums over octaves (fractional Brownian motion, turbulence),
//! as pbrt-v1 §11.6 defines them and LuxRender 1.x copies them (`core/texture.cpp`: `Noise`,
//! `FBm`, `Turbulence`).
//!
//! Noise is Perlin's 2002 "Improving Noise": at each lattice point a gradient chosen by hashing
//! the point's coordinates through a permutation table; inside a cell, the eight dot products
//! of the gradients with the offsets to the corners, blended by the quintic
//! 6t^5 - 15t^4 + 10t^3 (zero first and second derivatives at the lattice). It is 0 on every
//! lattice point and lies in [-1, 1].

use glam::Vec3;

/// Perlin's reference permutation of 0..255 (the table pbrt and LuxRender use).
const PERM: [u8; 256] = [
    151, 160, 137, 91, 90, 15, 131, 13, 201, 95, 96, 53, 194, 233, 7, 225, 140, 36, 103, 30, 69,
    142, 8, 99, 37, 240, 21, 10, 23, 190, 6, 148, 247, 120, 234, 75, 0, 26, 197, 62, 94, 252, 219,
    203, 117, 35, 11, 32, 57, 177, 33, 88, 237, 149, 56, 87, 174, 20, 125, 136, 171, 168, 68, 175,
    74, 165, 71, 134, 139, 48, 27, 166, 77, 146, 158, 231, 83, 111, 229, 122, 60, 211, 133, 230,
    220, 105, 92, 41, 55, 46, 245, 40, 244, 102, 143, 54, 65, 25, 63, 161, 1, 216, 80, 73, 209, 76,
    132, 187, 208, 89, 18, 169, 200, 196, 135, 130, 116, 188, 159, 86, 164, 100, 109, 198, 173,
    186, 3, 64, 52, 217, 226, 250, 124, 123, 5, 202, 38, 147, 118, 126, 255, 82, 85, 212, 207, 206,
    59, 227, 47, 16, 58, 17, 182, 189, 28, 42, 223, 183, 170, 213, 119, 248, 152, 2, 44, 154, 163,
    70, 221, 153, 101, 155, 167, 43, 172, 9, 129, 22, 39, 253, 19, 98, 108, 110, 79, 113, 224, 232,
    178, 185, 112, 104, 218, 246, 97, 228, 251, 34, 242, 193, 238, 210, 144, 12, 191, 179, 162,
    241, 81, 51, 145, 235, 249, 14, 239, 107, 49, 192, 214, 31, 181, 199, 106, 157, 184, 84, 204,
    176, 115, 121, 50, 45, 127, 4, 150, 254, 138, 236, 205, 93, 222, 114, 67, 29, 24, 72, 243, 141,
    128, 195, 78, 66, 215, 61, 156, 180,
];

fn perm(i: i32) -> i32 {
    i32::from(PERM[(i & 255) as usize])
}

/// The dot product of the hashed lattice gradient at (x, y, z) with the offset (dx, dy, dz):
/// the 4 low bits of the hash pick one of 12 edge-centre gradients (Perlin 2002; 12 and 13
/// repeat two of them to fill 16 slots).
fn grad(x: i32, y: i32, z: i32, d: Vec3) -> f32 {
    let h = perm(perm(perm(x) + y) + z) & 15;
    let u = if h < 8 || h == 12 || h == 13 {
        d.x
    } else {
        d.y
    };
    let v = if h < 4 || h == 12 || h == 13 {
        d.y
    } else {
        d.z
    };
    (if h & 1 != 0 { -u } else { u }) + (if h & 2 != 0 { -v } else { v })
}

/// The quintic blend 6t^5 - 15t^4 + 10t^3.
fn weight(t: f32) -> f32 {
    t * t * t * (t * (t * 6.0 - 15.0) + 10.0)
}

fn lerp(t: f32, a: f32, b: f32) -> f32 {
    a + t * (b - a)
}

/// Perlin noise at `p`; 0 for non-finite input.
pub fn noise(p: Vec3) -> f32 {
    if !p.is_finite() {
        return 0.0;
    }
    let cell = p.floor();
    let d = p - cell;
    // Wrapping to the table's period (256) keeps far-away points valid.
    let [ix, iy, iz] = [cell.x, cell.y, cell.z].map(|c| (c.rem_euclid(256.0)) as i32);
    let corner = |i: i32, j: i32, k: i32| {
        grad(
            ix + i,
            iy + j,
            iz + k,
            d - Vec3::new(i as f32, j as f32, k as f32),
        )
    };
    let (wx, wy, wz) = (weight(d.x), weight(d.y), weight(d.z));
    let x00 = lerp(wx, corner(0, 0, 0), corner(1, 0, 0));
    let x10 = lerp(wx, corner(0, 1, 0), corner(1, 1, 0));
    let x01 = lerp(wx, corner(0, 0, 1), corner(1, 0, 1));
    let x11 = lerp(wx, corner(0, 1, 1), corner(1, 1, 1));
    lerp(wz, lerp(wy, x00, x10), lerp(wy, x01, x11))
}

/// Fractional Brownian motion: sum over `octaves` of omega^i noise(1.99^i p) (pbrt-v1 §11.6.2;
/// the lacunarity 1.99 rather than 2 keeps the octaves' lattices from lining up).
///
/// pbrt and LuxRender fade out the octaves finer than a pixel using the ray differentials;
/// LuxRender's `fbm`, `marble` and `windy` textures pass zero differentials, which keeps every
/// octave, as here.
pub fn fbm(p: Vec3, omega: f32, octaves: u32) -> f32 {
    octave_sum(p, omega, octaves, noise)
}

/// Like [`fbm`] with |noise| (pbrt-v1 §11.6.2): creases where the noise crosses 0. With all
/// octaves kept, LuxRender's correction term for the faded octaves is 0.
pub fn turbulence(p: Vec3, omega: f32, octaves: u32) -> f32 {
    octave_sum(p, omega, octaves, |q| noise(q).abs())
}

fn octave_sum(p: Vec3, omega: f32, octaves: u32, f: impl Fn(Vec3) -> f32) -> f32 {
    let (mut sum, mut lambda, mut o) = (0.0, 1.0, 1.0);
    for _ in 0..octaves {
        sum += o * f(lambda * p);
        lambda *= 1.99;
        o *= omega;
    }
    sum
}

#[cfg(test)]
mod tests {
    use super::*;

    fn points() -> impl Iterator<Item = Vec3> {
        (0..4000).map(|i| {
            let t = i as f32;
            Vec3::new(
                (t * 0.618_034).fract() * 40.0 - 20.0,
                (t * 0.754_878).fract() * 40.0 - 20.0,
                (t * 0.569_840).fract() * 40.0 - 20.0,
            )
        })
    }

    #[test]
    fn noise_vanishes_on_the_lattice() {
        for p in points() {
            assert_eq!(noise(p.floor()), 0.0, "{p}");
        }
    }

    /// Each corner term |g . d| <= 2 max|d| over the 12 gradients (two unit components), but the
    /// blend of eight of them stays within [-1, 1]; the noise is not identically 0, has mean
    /// near 0, and is continuous: the blend's derivative is bounded, so nearby points differ
    /// by at most a small multiple of their distance.
    #[test]
    fn noise_is_bounded_continuous_and_centred() {
        let (mut sum, mut max) = (0.0f64, 0.0f32);
        for p in points() {
            let n = noise(p);
            assert!((-1.0..=1.0).contains(&n), "{p}: {n}");
            sum += f64::from(n);
            max = max.max(n.abs());
            let step = Vec3::new(1e-3, -2e-3, 1.5e-3);
            assert!((noise(p + step) - n).abs() < 10.0 * step.length(), "{p}");
        }
        assert!(max > 0.3, "{max}");
        assert!((sum / 4000.0).abs() < 0.05, "{}", sum / 4000.0);
    }

    #[test]
    fn noise_repeats_with_the_table_period() {
        for p in points().take(200) {
            let q = p + Vec3::new(256.0, -512.0, 256.0);
            assert!((noise(p) - noise(q)).abs() < 1e-4, "{p}");
        }
        assert_eq!(noise(Vec3::NAN), 0.0);
    }

    /// At a cell's centre every blend weight is 1/2, so the noise is the mean of the eight
    /// corner terms +-u +-v, each offset component +-1/2. In the cell at the origin the
    /// corners' hashes P[P[P[x] + y] + z] & 15 through LuxRender's table are, for
    /// (x, y, z) = 000, 100, 010, 110, 001, 101, 011, 111: 4, 6, 12, 0, 7, 4, 14, 3, giving
    /// dx + dz = 1, -dx + dz = -1, dx + dy = 0, -dx - dy = -1, -dx - dz = 0, dx - dz = -1,
    /// -dy + dz = 0 and -dx - dy = 1: a mean of -1/8.
    #[test]
    fn noise_at_a_cell_centre_is_the_mean_of_its_corner_gradients() {
        assert_eq!(noise(Vec3::splat(0.5)), -0.125);
        // The centre of cell (2, 3, 0), by the same rule: 3/8 (the dots texture reads it).
        assert_eq!(noise(Vec3::new(2.5, 3.5, 0.5)), 0.375);
    }

    /// Values of LuxRender 1.x's `Noise`, `FBm` and `Turbulence` (`core/texture.cpp`, all
    /// octaves kept) off the lattice, from an independent float64 transcription of those
    /// functions (Python, not foton's code); f32 rounding allows 1e-5.
    #[test]
    fn noise_and_octave_sums_match_luxrenders_formulas() {
        let close = |a: f32, b: f64| (f64::from(a) - b).abs() < 1e-5;
        let p = Vec3::new(0.3, 1.7, -2.2);
        assert!(close(noise(p), -0.473_803_163_85), "{}", noise(p));
        let q = Vec3::new(10.25, -3.75, 0.5);
        assert!(close(noise(q), 0.186_642_169_95), "{}", noise(q));
        assert!(
            close(fbm(p, 0.5, 8), -0.572_996_009_93),
            "{}",
            fbm(p, 0.5, 8)
        );
        // Roughness 1 keeps the finest octave (lambda = 1.99^7, points near 360) at full weight:
        // there an f32 ulp of the point is 3e-5 and the noise's slope up to about 2, so f32
        // (LuxRender's precision too) may differ from float64 by 1e-4.
        let r = Vec3::new(1.1, 2.9, 0.4);
        let f = fbm(r, 1.0, 8);
        assert!((f64::from(f) - 1.277_768_666_77).abs() < 1e-4, "{f}");
        let t = turbulence(p, 0.5, 8);
        assert!(close(t, 0.711_215_660_40), "{t}");
    }

    #[test]
    fn octave_sums() {
        let p = Vec3::new(0.3, 1.7, -2.2);
        assert_eq!(fbm(p, 0.5, 1), noise(p));
        let expected = noise(p) + 0.5 * noise(1.99 * p) + 0.25 * noise(1.99 * 1.99 * p);
        assert!((fbm(p, 0.5, 3) - expected).abs() < 1e-6);
        let expected = noise(p).abs() + 0.7 * noise(1.99 * p).abs();
        assert!((turbulence(p, 0.7, 2) - expected).abs() < 1e-6);
        assert_eq!(fbm(p, 0.5, 0), 0.0);
    }
}
