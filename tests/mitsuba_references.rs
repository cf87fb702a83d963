//! foton against Mitsuba 3 on the small scenes of scenes/mitsuba/ (references rendered by
//! scripts/peers/mitsuba_references.py at `spp_ref` samples, recorded in references.json).
//!
//! For each scene foton renders two independent images A and B (different seeds) at `SPP`. With
//! R the reference, per pixel and channel (weights w = 1 / (R^2 + 0.01), the relative error):
//!   E[w (A - R)^2] = w (var_A + var_R + bias^2),   E[w (A - B)^2 / 2] = w var_A.
//! R's variance is bounded from two more foton renders C and D with the independent sampler, the
//! reference's kind: Mitsuba's per-sample variance taken as at most twice foton's with the same
//! sampler, var_R <= 2 var_C SPP / spp_ref, with E[w (C - D)^2 / 2] = w var_C. (foton's default
//! sampler's variance is no bound for it: its padded Sobol' draws make var_A several times smaller
//! than an independent sampler's on some scenes.) Without bias the first mean is then at most the
//! second plus that bound. The test computes the difference of the two means over all
//! pixels and its standard error from the same pixels, and fails if the error exceeds the noise
//! by more than 4 standard errors. A second check compares the image means per channel, with
//! their standard errors from the A - B differences (and R's, scaled the same way).

use std::path::{Path, PathBuf};

use foton::integrator::Renderer;
use foton::sampling::SamplerKind::{self, Independent};
use foton::scene::build::{RenderOptions, build_world};
use glam::Vec3;

const SPP: u32 = 64;
const EPS: f32 = 0.01;

fn folder() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/mitsuba")
}

fn reference_spp(name: &str) -> f64 {
    let text = std::fs::read_to_string(folder().join("references.json")).unwrap();
    // {"name": {..., "spp": N, ...}}: the number after "spp" in the scene's entry.
    let entry = &text[text.find(&format!("\"{name}\"")).unwrap()..];
    let after = &entry[entry.find("\"spp\":").unwrap() + 6..];
    after
        .split([',', '}'])
        .next()
        .unwrap()
        .trim()
        .parse()
        .unwrap()
}

fn read_exr(path: &Path) -> (u32, u32, Vec<Vec3>) {
    let image = image::open(path).unwrap().to_rgb32f();
    let pixels = image.pixels().map(|p| Vec3::from_array(p.0)).collect();
    (image.width(), image.height(), pixels)
}

fn render(name: &str, seed: u64, sampler: SamplerKind) -> Vec<Vec3> {
    let desc = foton::scene::load(&folder().join(format!("{name}.xml"))).unwrap();
    let options = RenderOptions {
        samples_per_pixel: Some(SPP),
        seed,
        sampler,
        ..RenderOptions::default()
    };
    let (world, _) = build_world(desc, &options);
    let mut renderer = Renderer::new(world);
    renderer.render(|_| true);
    renderer.image()
}

fn mean_and_sd(x: &[f64]) -> (f64, f64) {
    let n = x.len() as f64;
    let mean = x.iter().sum::<f64>() / n;
    let var = x.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (mean, var.sqrt())
}

fn agrees(name: &str) {
    let (_, _, reference) = read_exr(&folder().join(format!("{name}.exr")));
    let sobol = RenderOptions::default().sampler;
    let (a, b) = (render(name, 1, sobol), render(name, 2, sobol));
    let (c_img, d_img) = (render(name, 3, Independent), render(name, 4, Independent));
    assert_eq!(a.len(), reference.len(), "{name}: image size");
    let k = 2.0 * SPP as f64 / reference_spp(name);
    // Per pixel-channel: excess = w (A - R)^2 - w (A - B)^2 / 2 - k w (C - D)^2 / 2, at most
    // zero-mean without bias.
    let mut excess = Vec::new();
    let (mut error, mut noise) = (0.0, 0.0);
    let independent = c_img.iter().zip(&d_img);
    for (((a, b), (c, d)), r) in a.iter().zip(&b).zip(independent).zip(&reference) {
        for ch in 0..3 {
            let [a, b, c, d, r] = [a, b, c, d, r].map(|v| v[ch] as f64);
            let w = 1.0 / (r * r + EPS as f64);
            let e = w * (a - r).powi(2);
            let noise_here = w * (a - b).powi(2) / 2.0 + k * w * (c - d).powi(2) / 2.0;
            error += e;
            noise += noise_here;
            excess.push(e - noise_here);
        }
    }
    let n = excess.len() as f64;
    let (mean, sd) = mean_and_sd(&excess);
    let z = mean / (sd / n.sqrt());
    eprintln!(
        "{name}: relMSE {:.5}, noise alone {:.5}, ratio {:.3}, z = {z:.2}",
        error / n,
        noise / n,
        error / noise
    );
    assert!(
        z < 4.0,
        "{name}: foton's error exceeds its noise: z = {z:.2}"
    );
    // Image means per channel: mean((A + B) / 2) - mean(R), against the noise of both.
    let half_differences = |x: &[Vec3], y: &[Vec3], ch: usize| -> f64 {
        x.iter()
            .zip(y)
            .map(|(x, y)| ((x[ch] - y[ch]) as f64 / 2.0).powi(2))
            .sum::<f64>()
    };
    for c in 0..3 {
        let pixels = a.len() as f64;
        // var((A + B) / 2) = var(A - B) / 4 per pixel; R's per-pixel variance is at most twice
        // var_C SPP / spp_ref, var_C = 2 var((C - D) / 2).
        let var_ab = half_differences(&a, &b, c) / pixels;
        let var_cd = half_differences(&c_img, &d_img, c) / pixels;
        let var_r = 2.0 * (2.0 * var_cd) * SPP as f64 / reference_spp(name);
        let sd = ((var_ab + var_r) / pixels).sqrt();
        let ours = a
            .iter()
            .zip(&b)
            .map(|(a, b)| (a[c] + b[c]) as f64 / 2.0)
            .sum::<f64>()
            / pixels;
        let theirs = reference.iter().map(|r| r[c] as f64).sum::<f64>() / pixels;
        let z = (ours - theirs) / sd;
        eprintln!("{name}: channel {c}: mean {ours:.5} vs {theirs:.5}, z = {z:.2}");
        assert!(
            z.abs() < 4.0,
            "{name}: channel {c} mean {ours} vs Mitsuba's {theirs}: z = {z:.2}"
        );
    }
}

#[test]
fn cornell_box_matches_mitsuba() {
    agrees("cbox");
}

/// Its disk light has no BSDF: Mitsuba gives an emitter a black one, not its default diffuse 0.5
/// (which once made foton 0.3 % brighter under the disk).
#[test]
fn dielectric_conductors_and_textures_match_mitsuba() {
    agrees("materials");
}

#[test]
fn point_and_directional_lights_match_mitsuba() {
    agrees("lights");
}

#[test]
fn environment_map_matches_mitsuba() {
    agrees("envmap");
}

/// Its rectangle light has no BSDF either: with the default diffuse 0.5 on it, foton's floor was
/// 1.3 % brighter than Mitsuba's (mean z about 9 at 64 spp).
#[test]
fn rough_glass_plastics_and_thin_glass_match_mitsuba() {
    agrees("coatings");
}

/// Named conductors (Cu smooth, Au rough) and `eta`/`k` through the exact complex Fresnel,
/// Mitsuba's default Beckmann distribution, and anisotropic alphas along dp/du (a GGX sphere, a
/// Beckmann floor).
#[test]
fn conductors_beckmann_and_anisotropy_match_mitsuba() {
    agrees("metals");
}
