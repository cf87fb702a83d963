//! Mitsuba BSDFs and textures as foton materials and image textures. Exact: `diffuse` (seen from
//! the front), `twosided`, `dielectric`, `conductor` with material `none`, `roughconductor` (GGX,
//! material `none`), `null`, `checkerboard`, `bitmap`. Approximated with a warning: named
//! conductors (Fresnel at normal incidence), `plastic`, `roughplastic`, `principled`,
//! `roughdielectric`, `thindielectric`, and Beckmann roughness.

use std::sync::Arc;

use glam::{Vec2, Vec3};

use super::conductors::CONDUCTORS;
use super::convert::Converter;
use super::tree::{Object, Value};
use crate::scene::desc::{
    ColorParam, ImageTexture, MaterialDesc, MaterialId, SceneError, TextureId,
};
use crate::scene::io::image as images;

/// Mitsuba's default surface: diffuse, reflectance 0.5.
pub fn default_material(cx: &mut Converter) -> MaterialId {
    push(
        cx,
        MaterialDesc::Diffuse {
            reflectance: ColorParam::Constant(Vec3::splat(0.5)),
        },
    )
}

fn push(cx: &mut Converter, material: MaterialDesc) -> MaterialId {
    cx.desc.materials.push(material);
    cx.desc.materials.len() - 1
}

/// The material of BSDF `object` (converted once, shared by every reference).
pub fn bsdf(cx: &mut Converter, object: &Object) -> Result<MaterialId, SceneError> {
    let key = cx
        .tree
        .objects
        .iter()
        .position(|o| std::ptr::eq(o, object))
        .unwrap_or(usize::MAX);
    if let Some(&id) = cx.materials.get(&key) {
        return Ok(id);
    }
    let material = convert(cx, object)?;
    let id = match material {
        Converted::New(m) => push(cx, m),
        Converted::Existing(id) => id,
    };
    cx.report_unused(object);
    cx.materials.insert(key, id);
    Ok(id)
}

enum Converted {
    New(MaterialDesc),
    Existing(MaterialId),
}

/// Index of refraction given as a number or a material name (Mitsuba's `lookup_ior` table).
fn ior(cx: &mut Converter, object: &Object, name: &str, default: f32) -> f32 {
    match object.prop(name).map(|p| (p.value.clone(), p.loc.clone())) {
        None => default,
        Some((Value::Float(v), _)) => v as f32,
        Some((Value::String(s), loc)) => match named_ior(&s) {
            Some(v) => v,
            None => {
                cx.warn(
                    &loc,
                    format!("unknown index of refraction \"{s}\": {default} used"),
                );
                default
            }
        },
        Some((Value::Rgb(v) | Value::Spectrum(v), loc)) => {
            cx.warn(&loc, format!("spectral {name} averaged over RGB"));
            ((v.x + v.y + v.z) / 3.0) as f32
        }
        Some(_) => default,
    }
}

/// Mitsuba's table of named indices of refraction (src/render/ior.h, after Hecht, Optics).
fn named_ior(name: &str) -> Option<f32> {
    const TABLE: [(&str, f32); 23] = [
        ("vacuum", 1.0),
        ("helium", 1.000036),
        ("hydrogen", 1.000132),
        ("air", 1.000277),
        ("carbon dioxide", 1.00045),
        ("water", 1.3330),
        ("acetone", 1.36),
        ("ethanol", 1.361),
        ("carbon tetrachloride", 1.461),
        ("glycerol", 1.4729),
        ("benzene", 1.501),
        ("silicone oil", 1.52045),
        ("bromine", 1.661),
        ("water ice", 1.31),
        ("fused quartz", 1.458),
        ("pyrex", 1.470),
        ("acrylic glass", 1.49),
        ("polypropylene", 1.49),
        ("bk7", 1.5046),
        ("sodium chloride", 1.544),
        ("amber", 1.55),
        ("pet", 1.5750),
        ("diamond", 2.419),
    ];
    let lower = name.to_lowercase();
    TABLE.iter().find(|(n, _)| *n == lower).map(|(_, v)| *v)
}

/// Reflectance at normal incidence of a conductor with complex index eta + i k (relative to the
/// outside): ((eta - 1)^2 + k^2) / ((eta + 1)^2 + k^2), per channel.
fn conductor_f0(eta: Vec3, k: Vec3) -> Vec3 {
    let k2 = k * k;
    ((eta - 1.0) * (eta - 1.0) + k2) / ((eta + 1.0) * (eta + 1.0) + k2)
}

/// The conductor's reflectance at normal incidence, and whether it is exact (material `none`).
fn conductor_reflectance(cx: &mut Converter, object: &Object) -> (Vec3, bool) {
    let loc = object.loc.clone();
    let ext = ior(cx, object, "ext_eta", 1.0);
    if object.prop("eta").is_some() || object.prop("k").is_some() {
        let eta = cx.rgb(object, "eta", Vec3::ZERO);
        let k = cx.rgb(object, "k", Vec3::ONE);
        object.prop("material");
        return (conductor_f0(eta / ext, k / ext), false);
    }
    let material = cx
        .string(object, "material")
        .unwrap_or_else(|| "none".into());
    if material == "none" {
        return (Vec3::ONE, true);
    }
    match CONDUCTORS.iter().find(|(n, _, _)| *n == material) {
        Some((_, eta, k)) => (
            conductor_f0(Vec3::from_array(*eta) / ext, Vec3::from_array(*k) / ext),
            false,
        ),
        None => {
            cx.warn(
                &loc,
                format!("unknown conductor material \"{material}\": a perfect mirror used"),
            );
            (Vec3::ONE, true)
        }
    }
}

/// GGX alphas (`alpha`, or `alpha_u` and `alpha_v`); Beckmann is read as GGX with a warning.
fn alphas(cx: &mut Converter, object: &Object) -> (f32, f32) {
    let distribution = cx
        .string(object, "distribution")
        .unwrap_or_else(|| "beckmann".into());
    if distribution != "ggx" {
        cx.warn(
            &object.loc,
            format!(
                "microfacet distribution \"{distribution}\" approximated by GGX of the same alpha"
            ),
        );
    }
    object.prop("sample_visible");
    if object.prop("alpha_u").is_some() || object.prop("alpha_v").is_some() {
        let u = cx.float(object, "alpha_u", 0.1);
        (u, cx.float(object, "alpha_v", u))
    } else {
        let a = cx.float(object, "alpha", 0.1);
        (a, a)
    }
}

/// A GGX conductor with Schlick's Fresnel from `specular` at normal incidence.
fn metal(specular: ColorParam, (alpha_u, alpha_v): (f32, f32)) -> MaterialDesc {
    MaterialDesc::RoughConductor {
        specular,
        alpha_u,
        alpha_v,
    }
}

fn scaled(c: ColorParam, s: Vec3) -> ColorParam {
    match c {
        ColorParam::Constant(v) => ColorParam::Constant(v * s),
        texture => texture,
    }
}

fn convert(cx: &mut Converter, object: &Object) -> Result<Converted, SceneError> {
    let tree = cx.tree;
    let loc = object.loc.clone();
    Ok(Converted::New(match object.plugin.as_str() {
        "diffuse" => {
            if cx.within_twosided == 0 && cx.one_sided.is_none() {
                cx.one_sided = Some(loc);
            }
            MaterialDesc::Diffuse {
                reflectance: cx.color(object, "reflectance", Vec3::splat(0.5)),
            }
        }
        "twosided" | "mask" | "bumpmap" | "normalmap" => {
            let nested: Vec<_> = object
                .children_tagged(tree, "bsdf")
                .map(|(_, b)| b)
                .collect();
            match object.plugin.as_str() {
                "twosided" => {
                    if nested.len() > 1 {
                        cx.warn(
                            &loc,
                            "twosided with two BSDFs: the front one is used on both sides".into(),
                        );
                    }
                }
                "mask" => cx.warn(
                    &loc,
                    "mask: the opacity is ignored (the surface is opaque)".into(),
                ),
                other => cx.warn(&loc, format!("{other}: the perturbation is ignored")),
            }
            for name in ["opacity", "normalmap", "scale"] {
                object.prop(name);
                object.named_child(tree, name);
            }
            for child in &object.children {
                if tree.objects[child.object].tag == "texture" {
                    child.used.set(true);
                }
            }
            let twosided = usize::from(object.plugin == "twosided");
            cx.within_twosided += twosided;
            let inner = match nested.first() {
                Some(inner) => bsdf(cx, inner),
                None => Ok(default_material(cx)),
            };
            cx.within_twosided -= twosided;
            return inner.map(Converted::Existing);
        }
        "dielectric" | "roughdielectric" | "thindielectric" => {
            let int = ior(cx, object, "int_ior", 1.5046);
            let ext = ior(cx, object, "ext_ior", 1.000277);
            match object.plugin.as_str() {
                "roughdielectric" => {
                    let (a, _) = alphas(cx, object);
                    cx.warn(&loc, format!("roughdielectric rendered smooth (alpha {a} ignored)"));
                }
                "thindielectric" => cx.warn(
                    &loc,
                    "thindielectric approximated by a dielectric (rays bend where a thin sheet would \
                     not)"
                        .into(),
                ),
                _ => {}
            }
            MaterialDesc::Dielectric {
                reflectance: cx.color(object, "specular_reflectance", Vec3::ONE),
                transmittance: cx.color(object, "specular_transmittance", Vec3::ONE),
                ior: int / ext,
            }
        }
        "conductor" | "roughconductor" => {
            let (f0, exact) = conductor_reflectance(cx, object);
            if !exact {
                cx.warn(
                    &loc,
                    "conductor's Fresnel term approximated from its reflectance at normal incidence"
                        .into(),
                );
            }
            let kr = scaled(cx.color(object, "specular_reflectance", Vec3::ONE), f0);
            if object.plugin == "conductor" {
                MaterialDesc::Mirror { reflectance: kr }
            } else {
                metal(kr, alphas(cx, object))
            }
        }
        "plastic" | "roughplastic" | "principled" => {
            return plastic(cx, object).map(Converted::Existing);
        }
        "null" => MaterialDesc::Null,
        other => {
            cx.warn(
                &loc,
                format!("BSDF \"{other}\" not supported: diffuse 0.5 used"),
            );
            return Ok(Converted::Existing(default_material(cx)));
        }
    }))
}

/// Plastic (a diffuse base under a dielectric coat) as a mix of the base and a specular coat,
/// weighted by the coat's Fresnel reflectance averaged over the cosine-weighted hemisphere.
/// `principled` goes to a rough metal when mostly metallic, else to this.
fn plastic(cx: &mut Converter, object: &Object) -> Result<MaterialId, SceneError> {
    let loc = object.loc.clone();
    let rough = object.plugin != "plastic";
    if object.plugin == "principled" {
        let base = cx.color(object, "base_color", Vec3::splat(0.5));
        let metallic = cx.float(object, "metallic", 0.0);
        let roughness = cx.float(object, "roughness", 0.5);
        let alpha = (roughness * roughness).max(1e-3);
        cx.warn(
            &loc,
            format!(
                "principled approximated by {} (base_color, metallic, roughness read; the rest ignored)",
                if metallic > 0.5 { "a rough metal" } else { "a rough plastic" }
            ),
        );
        if metallic > 0.5 {
            return Ok(push(cx, metal(base, (alpha, alpha))));
        }
        let eta = cx.float(object, "eta", 1.5);
        let base = push(cx, MaterialDesc::Diffuse { reflectance: base });
        let coat = push(cx, metal(ColorParam::Constant(Vec3::ONE), (alpha, alpha)));
        return Ok(push(cx, mix(base, coat, eta)));
    }
    let int = ior(cx, object, "int_ior", 1.49);
    let ext = ior(cx, object, "ext_ior", 1.000277);
    let diffuse = cx.color(object, "diffuse_reflectance", Vec3::splat(0.5));
    let specular = cx.color(object, "specular_reflectance", Vec3::ONE);
    object.prop("nonlinear");
    let coat = if rough {
        let (a, b) = alphas(cx, object);
        metal(specular, (a, b))
    } else {
        MaterialDesc::Mirror {
            reflectance: specular,
        }
    };
    cx.warn(
        &loc,
        format!(
            "{} approximated by a mix of its diffuse base and a {} coat (no internal reflections)",
            object.plugin,
            if rough { "rough" } else { "mirror" }
        ),
    );
    let base = push(
        cx,
        MaterialDesc::Diffuse {
            reflectance: diffuse,
        },
    );
    let coat = push(cx, coat);
    Ok(push(cx, mix(base, coat, int / ext)))
}

fn mix(base: MaterialId, coat: MaterialId, eta: f32) -> MaterialDesc {
    MaterialDesc::Mix {
        first: base,
        second: coat,
        amount: ColorParam::Constant(Vec3::splat(average_fresnel(eta))),
    }
}

/// 2 ∫ F(cos θ) cos θ sin θ dθ over the hemisphere: the share of cosine-weighted incident light a
/// smooth dielectric of relative index `eta` reflects (midpoint rule, 256 steps).
fn average_fresnel(eta: f32) -> f32 {
    let n = 256;
    (0..n)
        .map(|i| {
            let cos_i = (i as f32 + 0.5) / n as f32;
            2.0 * crate::bsdf::fresnel::fr_dielectric(cos_i, eta) * cos_i / n as f32
        })
        .sum()
}

/// The image texture for texture `object` (converted once).
pub fn texture(cx: &mut Converter, object: &Object) -> Option<TextureId> {
    let key = cx
        .tree
        .objects
        .iter()
        .position(|o| std::ptr::eq(o, object))?;
    if let Some(&id) = cx.textures.get(&key) {
        return Some(id);
    }
    let loc = object.loc.clone();
    let to_uv = cx.transform(object, "to_uv");
    // foton maps uv by a scale and an offset: the transform's diagonal and translation.
    let scale = Vec2::new(to_uv.x_axis.x as f32, to_uv.y_axis.y as f32);
    let delta = Vec2::new(to_uv.w_axis.x as f32, to_uv.w_axis.y as f32);
    if to_uv.x_axis.y != 0.0 || to_uv.y_axis.x != 0.0 {
        cx.warn(
            &loc,
            "to_uv rotation or shear ignored (only scale and translation apply)".into(),
        );
    }
    let image = match object.plugin.as_str() {
        "checkerboard" => {
            let c0 = cx.rgb(object, "color0", Vec3::splat(0.4));
            let c1 = cx.rgb(object, "color1", Vec3::splat(0.2));
            // Mitsuba: color0 where the fractional parts of u and v are both below or both above
            // one half. Sampled finely so that bilinear filtering only blurs a thin seam.
            const N: u32 = 256;
            let texels = (0..N * N)
                .map(|i| {
                    let (x, y) = (i % N, i / N);
                    if (x < N / 2) == (y < N / 2) { c0 } else { c1 }
                })
                .collect();
            (N, N, texels, "checkerboard".to_string())
        }
        "bitmap" => {
            let name = cx.string(object, "filename")?;
            let path = cx.tree.resolve(&name);
            let raw = cx.bool(object, "raw", false);
            for p in ["filter_type", "wrap_mode", "format"] {
                object.prop(p);
            }
            // Integer images are sRGB-encoded unless raw; the sRGB curve read as gamma 2.2.
            let gamma = if raw { 1.0 } else { 2.2 };
            match images::decode(&path, gamma, 1.0) {
                Ok(img) => (img.width, img.height, img.texels, name),
                Err(e) => {
                    cx.warn(
                        &loc,
                        format!("cannot read bitmap \"{}\": {e}; grey used", path.display()),
                    );
                    return None;
                }
            }
        }
        other => {
            cx.warn(
                &loc,
                format!("texture \"{other}\" not supported: its parameter's default used"),
            );
            return None;
        }
    };
    cx.report_unused(object);
    let (width, height, texels, name) = image;
    cx.desc.textures.push(ImageTexture {
        name: name.clone(),
        path: name.into(),
        width,
        height,
        texels: Arc::new(texels),
        scale,
        delta,
    });
    let id = cx.desc.textures.len() - 1;
    cx.textures.insert(key, id);
    Some(id)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normal_incidence_reflectance_of_a_conductor() {
        // k = 0 is a dielectric: ((n - 1) / (n + 1))^2.
        let f = conductor_f0(Vec3::splat(1.5), Vec3::ZERO);
        assert!((f.x - 0.04).abs() < 1e-6);
        // A perfect conductor (k -> inf) reflects everything.
        assert!(conductor_f0(Vec3::ONE, Vec3::splat(1e4)).min_element() > 0.9999);
    }

    #[test]
    fn average_fresnel_of_glass() {
        // A known value: about 9.2 % for n = 1.5 (hemispherical-average Fresnel reflectance).
        assert!(
            (average_fresnel(1.5) - 0.092).abs() < 0.003,
            "{}",
            average_fresnel(1.5)
        );
        assert!(average_fresnel(1.0) < 1e-6);
    }
}
