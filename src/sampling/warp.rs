//! Warps from [0,1)^2 to the domains of light transport, with their densities.

use std::f32::consts::{FRAC_1_PI, FRAC_PI_4, PI};

use glam::{Vec2, Vec3};

use crate::math::sin_cos_eighth_turn;

/// Shirley & Chiu 1997, "A Low Distortion Map Between Disk and Square": maps concentric squares
/// of [-1,1]^2 to concentric circles, a uniform point on the unit disk (pbrt-v3 §13.6.2).
///
/// Without branches (both arms' choices are selects, the centre's zero too), so that a loop
/// over several points, as the thin lens's, runs in the lanes of vector registers, each point
/// the same value as on its own.
#[inline]
pub fn concentric_disk(u: Vec2) -> Vec2 {
    let o = 2.0 * u - Vec2::ONE;
    // The angle is theta = pi/4 (y / x) where |x| > |y|, else pi/2 - pi/4 (x / y), whose cosine
    // and sine are the sine and cosine of pi/4 (x / y): either way a cosine and a sine on
    // [-pi/4, pi/4], from polynomials rather than a library call, times the radius x or y.
    let wide = o.x.abs() > o.y.abs();
    let (radius, other) = if wide { (o.x, o.y) } else { (o.y, o.x) };
    let (sin, cos) = sin_cos_eighth_turn(FRAC_PI_4 * (other / radius));
    let (x, y) = if wide { (cos, sin) } else { (sin, cos) };
    // The centre (0 / 0 above) maps to itself.
    let centre = (o.x == 0.0) & (o.y == 0.0);
    if centre {
        Vec2::ZERO
    } else {
        Vec2::new(radius * x, radius * y)
    }
}

/// Malley's method: a uniform disk point lifted to the hemisphere (z up) has density
/// cos(theta) / pi in solid angle.
#[inline]
pub fn cosine_hemisphere(u: Vec2) -> Vec3 {
    let d = concentric_disk(u);
    Vec3::new(d.x, d.y, (1.0 - d.length_squared()).max(0.0).sqrt())
}

pub fn cosine_hemisphere_pdf(cos_theta: f32) -> f32 {
    cos_theta.max(0.0) * FRAC_1_PI
}

/// Uniform on the unit sphere: z uniform in [-1, 1] (Archimedes' hat-box theorem).
pub fn uniform_sphere(u: Vec2) -> Vec3 {
    let z = 1.0 - 2.0 * u.x;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * PI * u.y;
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

pub fn uniform_sphere_pdf() -> f32 {
    1.0 / (4.0 * PI)
}

/// Uniform over the cone of directions around +z with cos(theta) >= `cos_max`:
/// cos(theta) uniform in [cos_max, 1] (pbrt-v3 §13.6.4).
pub fn uniform_cone(u: Vec2, cos_max: f32) -> Vec3 {
    let cos_theta = (1.0 - u.x) + u.x * cos_max;
    let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
    let phi = 2.0 * PI * u.y;
    Vec3::new(sin_theta * phi.cos(), sin_theta * phi.sin(), cos_theta)
}

/// 1 / solid angle of the cone; a degenerate cone (cos_max = 1) gives a large finite value.
pub fn uniform_cone_pdf(cos_max: f32) -> f32 {
    1.0 / (2.0 * PI * (1.0 - cos_max).max(f32::MIN_POSITIVE))
}

/// Uniform barycentrics (b1, b2) on a triangle (b0 = 1 - b1 - b2): Heitz 2019, "A Low-Distortion
/// Map Between Triangle and Square", which folds the square along its diagonal.
pub fn uniform_triangle(u: Vec2) -> (f32, f32) {
    if u.x < u.y {
        let b1 = u.x / 2.0;
        (b1, u.y - b1)
    } else {
        let b2 = u.y / 2.0;
        (u.x - b2, b2)
    }
}

/// Veach 1997, §9.2.4: the power heuristic with beta = 2 for `nf` samples of a strategy with
/// density `f_pdf` combined with `ng` samples of one with density `g_pdf`.
pub fn power_heuristic(nf: u32, f_pdf: f32, ng: u32, g_pdf: f32) -> f32 {
    let f = nf as f32 * f_pdf;
    let g = ng as f32 * g_pdf;
    if f.is_infinite() {
        return 1.0;
    }
    let (f2, g2) = (f * f, g * g);
    if f2 + g2 > 0.0 { f2 / (f2 + g2) } else { 0.0 }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::PathRng;

    const N: u32 = 200_000;

    /// Monte Carlo check that a pdf integrates to 1 over its domain's measure: directions drawn
    /// uniformly on the sphere, E[pdf(w) * 4 pi] = 1. Std. error ~ sqrt(Var/N) < 0.01 here.
    fn sphere_integral(pdf: impl Fn(Vec3) -> f32) -> f64 {
        let mut rng = PathRng::new(1, 2, 3);
        let sum: f64 = (0..N)
            .map(|_| f64::from(pdf(uniform_sphere(rng.next_2d())) / uniform_sphere_pdf()))
            .sum();
        sum / f64::from(N)
    }

    #[test]
    fn polynomial_sin_cos_match_libm() {
        // The polynomials' error is about 1 ulp on [-pi/4, pi/4] (6e-8 near 1); 2.5e-7 allows 4.
        for i in 0..=10_000 {
            let x = FRAC_PI_4 * (i as f32 / 5_000.0 - 1.0);
            let (sin, cos) = sin_cos_eighth_turn(x);
            assert!(
                (sin - x.sin()).abs() <= 2.5e-7,
                "sin {x}: {sin} vs {}",
                x.sin()
            );
            assert!(
                (cos - x.cos()).abs() <= 2.5e-7,
                "cos {x}: {cos} vs {}",
                x.cos()
            );
        }
    }

    #[test]
    fn warps_map_into_their_domains() {
        let mut rng = PathRng::new(5, 0, 0);
        let eps = 1e-5;
        let mut corners = vec![
            Vec2::ZERO,
            Vec2::new(0.0, 0.99999994),
            Vec2::splat(0.99999994),
        ];
        corners.extend((0..N).map(|_| rng.next_2d()));
        for u in corners {
            assert!(concentric_disk(u).length() <= 1.0 + eps);
            let w = cosine_hemisphere(u);
            assert!((w.length() - 1.0).abs() < eps && w.z >= 0.0);
            assert!((uniform_sphere(u).length() - 1.0).abs() < eps);
            let c = uniform_cone(u, 0.8);
            assert!((c.length() - 1.0).abs() < eps && c.z >= 0.8 - eps);
            let (b1, b2) = uniform_triangle(u);
            assert!(b1 >= 0.0 && b2 >= 0.0 && b1 + b2 <= 1.0 + eps);
        }
    }

    /// The polynomial cosine and sine give Shirley and Chiu's map as the library's trigonometry
    /// does (computed in f64), to a few f32 roundings over the square and at its corners and
    /// diagonals (the angles ±pi/4, where the series are at their worst).
    #[test]
    fn concentric_disk_matches_the_trigonometric_map() {
        let mut rng = PathRng::new(9, 0, 0);
        let mut points: Vec<Vec2> = (0..N).map(|_| rng.next_2d()).collect();
        points.extend((0..=100).map(|i| Vec2::splat(i as f32 / 100.0)));
        points.extend((0..=100).map(|i| Vec2::new(i as f32 / 100.0, 1.0 - i as f32 / 100.0)));
        let mut worst = 0.0f64;
        for u in points {
            let o = (2.0 * u - Vec2::ONE).as_dvec2();
            if o == glam::DVec2::ZERO {
                continue;
            }
            let quarter = std::f64::consts::FRAC_PI_4;
            let (r, theta) = if o.x.abs() > o.y.abs() {
                (o.x, quarter * (o.y / o.x))
            } else {
                (o.y, 2.0 * quarter - quarter * (o.x / o.y))
            };
            let exact = r * glam::DVec2::new(theta.cos(), theta.sin());
            worst = worst.max((concentric_disk(u).as_dvec2() - exact).abs().max_element());
        }
        assert!(worst < 2e-7, "{worst}");
    }

    #[test]
    fn disk_and_triangle_are_uniform() {
        // Histograms over equal-area regions: 4 quadrants x 2 rings of the disk (inner radius
        // 1/sqrt 2), and the 4 sub-triangles of the midpoint subdivision. Each bin expects
        // N/8 or N/4 with std ~ sqrt(N/8) ~ 160; allow 5 sigma.
        let mut rng = PathRng::new(6, 0, 0);
        let (mut disk, mut tri) = ([0i32; 8], [0i32; 4]);
        for _ in 0..N {
            let u = rng.next_2d();
            let d = concentric_disk(u);
            let ring = usize::from(d.length_squared() > 0.5);
            disk[ring * 4 + usize::from(d.x > 0.0) * 2 + usize::from(d.y > 0.0)] += 1;
            let (b1, b2) = uniform_triangle(u);
            let b0 = 1.0 - b1 - b2;
            let bin = if b0 > 0.5 {
                0
            } else if b1 > 0.5 {
                1
            } else if b2 > 0.5 {
                2
            } else {
                3
            };
            tri[bin] += 1;
        }
        let (d_exp, t_exp) = (N as i32 / 8, N as i32 / 4);
        assert!(disk.iter().all(|&c| (c - d_exp).abs() < 800), "{disk:?}");
        assert!(tri.iter().all(|&c| (c - t_exp).abs() < 1100), "{tri:?}");
    }

    #[test]
    fn direction_pdfs_integrate_to_one() {
        let hemi = sphere_integral(|w| cosine_hemisphere_pdf(w.z));
        let cone = sphere_integral(|w| {
            if w.z >= 0.6 {
                uniform_cone_pdf(0.6)
            } else {
                0.0
            }
        });
        assert!((hemi - 1.0).abs() < 0.02, "{hemi}");
        assert!((cone - 1.0).abs() < 0.03, "{cone}");
    }

    #[test]
    fn cosine_hemisphere_matches_its_pdf() {
        // Histogram of cos(theta) in 10 bins: P(cos in [a, b]) = b^2 - a^2 under cos/pi.
        let mut rng = PathRng::new(8, 0, 0);
        let mut bins = [0u32; 10];
        for _ in 0..N {
            let z = cosine_hemisphere(rng.next_2d()).z;
            bins[((z * 10.0) as usize).min(9)] += 1;
        }
        for (i, &c) in bins.iter().enumerate() {
            let (a, b) = (i as f64 / 10.0, (i + 1) as f64 / 10.0);
            let expected = (b * b - a * a) * f64::from(N);
            assert!((f64::from(c) - expected).abs() < 5.0 * expected.sqrt() + 1.0);
        }
    }

    #[test]
    fn power_heuristic_weights() {
        assert_eq!(power_heuristic(1, 1.0, 1, 1.0), 0.5);
        assert!((power_heuristic(1, 3.0, 1, 1.0) - 0.9).abs() < 1e-6);
        let sum = power_heuristic(1, 2.0, 3, 0.5) + power_heuristic(3, 0.5, 1, 2.0);
        assert!((sum - 1.0).abs() < 1e-6);
        assert_eq!(power_heuristic(1, 0.0, 1, 0.0), 0.0);
        assert_eq!(power_heuristic(1, f32::INFINITY, 1, 1.0), 1.0);
    }
}
