//! Mitsuba BSDFs and textures as foton materials and image textures. Exact: `diffuse` (one-sided,
//! as every reflecting BSDF outside `twosided`), `twosided`, `dielectric`, `roughdielectric`
//! (GGX and Beckmann), `thindielectric`, `plastic`, `roughplastic` (GGX), `conductor` and `roughconductor`
//! (GGX and Beckmann; named materials, `eta`/`k`, the exact complex Fresnel), `null`,
//! `checkerboard`, `bitmap`. Approximated with a warning: `principled`, and Beckmann roughness
//! on plastics.

use std::sync::Arc;

use glam::{Vec2, Vec3};

use super::conductors::CONDUCTORS;
use super::convert::Converter;
use super::tree::{Object, Value};
use crate::material::texels::PaletteTexels;
use crate::scene::desc::{
    ColorParam, ImageTexture, MaterialDesc, MaterialId, MicrofacetDistribution, Roughness,
    SceneError, Texels, TextureId, Wrap,
};
use crate::scene::io::image as images;
use crate::texture::{Mapping2D, TextureNode};

/// Mitsuba's default surface: diffuse, reflectance 0.5 (one-sided, as every `diffuse`).
pub fn default_material(cx: &mut Converter) -> MaterialId {
    one_sided_diffuse(cx, 0.5)
}

/// A one-sided diffuse BSDF of `reflectance`; Mitsuba gives an emitting shape without a BSDF a
/// black one (`Shape::Shape`: `if (m_emitter) props2.set("reflectance", 0.f)`).
pub fn one_sided_diffuse(cx: &mut Converter, reflectance: f32) -> MaterialId {
    let diffuse = push(
        cx,
        MaterialDesc::Diffuse {
            reflectance: ColorParam::Constant(Vec3::splat(reflectance)),
        },
    );
    push(cx, MaterialDesc::OneSided { material: diffuse })
}

/// Mitsuba's BSDFs that only reflect are black from the back (their `eval` and `sample` need
/// cos theta > 0 on both sides) unless wrapped in `twosided`; dielectrics and `null` are
/// two-sided by nature.
fn is_one_sided(plugin: &str) -> bool {
    matches!(
        plugin,
        "diffuse" | "conductor" | "roughconductor" | "plastic" | "roughplastic" | "principled"
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
    let mut id = match material {
        Converted::New(m) => push(cx, m),
        Converted::Existing(id) => id,
    };
    if is_one_sided(&object.plugin) {
        id = push(cx, MaterialDesc::OneSided { material: id });
    }
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

/// The conductor's complex index of refraction eta + i k (Mitsuba 3's `conductor.cpp` and
/// `roughconductor.cpp`): `eta` and `k` when given (defaults 0 and 1), else the named
/// `material`'s (`none`, the default, is eta 0, k 1: every angle reflects fully). Mitsuba 0.6's
/// `ext_eta` divides both.
fn conductor_index(cx: &mut Converter, object: &Object) -> (Vec3, Vec3) {
    let ext = ior(cx, object, "ext_eta", 1.0);
    let material = cx
        .string(object, "material")
        .unwrap_or_else(|| "none".into());
    let (eta, k) = if object.prop("eta").is_some() || material == "none" {
        (
            cx.rgb(object, "eta", Vec3::ZERO),
            cx.rgb(object, "k", Vec3::ONE),
        )
    } else {
        match CONDUCTORS.iter().find(|(n, _, _)| *n == material) {
            Some((_, eta, k)) => (Vec3::from_array(*eta), Vec3::from_array(*k)),
            None => {
                cx.warn(
                    &object.loc,
                    format!("unknown conductor material \"{material}\": a perfect mirror used"),
                );
                (Vec3::ZERO, Vec3::ONE)
            }
        }
    };
    (eta / ext, k / ext)
}

/// The microfacet distribution (`distribution`, Mitsuba's default `beckmann`) and its alphas
/// (`alpha`, or `alpha_u` and `alpha_v`; default 0.1).
fn roughness(cx: &mut Converter, object: &Object) -> Roughness {
    let name = cx
        .string(object, "distribution")
        .unwrap_or_else(|| "beckmann".into());
    let distribution = match name.to_lowercase().as_str() {
        "ggx" => MicrofacetDistribution::Ggx,
        "beckmann" => MicrofacetDistribution::Beckmann,
        _ => {
            cx.warn(
                &object.loc,
                format!("unknown microfacet distribution \"{name}\": beckmann used"),
            );
            MicrofacetDistribution::Beckmann
        }
    };
    object.prop("sample_visible");
    let (alpha_u, alpha_v) = if object.prop("alpha_u").is_some() || object.prop("alpha_v").is_some()
    {
        let u = cx.float(object, "alpha_u", 0.1);
        (u, cx.float(object, "alpha_v", u))
    } else {
        let a = cx.float(object, "alpha", 0.1);
        (a, a)
    };
    Roughness {
        distribution,
        alpha_u,
        alpha_v,
    }
}

/// GGX alphas for `roughplastic`, which has only GGX; Beckmann is read as GGX with a warning.
fn alphas(cx: &mut Converter, object: &Object) -> (f32, f32) {
    let r = roughness(cx, object);
    if r.distribution != MicrofacetDistribution::Ggx {
        cx.warn(
            &object.loc,
            format!(
                "{}: the beckmann distribution approximated by GGX of the same alpha",
                object.plugin
            ),
        );
    }
    (r.alpha_u, r.alpha_v)
}

/// A GGX conductor with Schlick's Fresnel from `specular` at normal incidence.
fn metal(specular: ColorParam, (alpha_u, alpha_v): (f32, f32)) -> MaterialDesc {
    MaterialDesc::RoughConductor {
        specular,
        alpha_u,
        alpha_v,
    }
}

fn convert(cx: &mut Converter, object: &Object) -> Result<Converted, SceneError> {
    let tree = cx.tree;
    let loc = object.loc.clone();
    Ok(Converted::New(match object.plugin.as_str() {
        "diffuse" => MaterialDesc::Diffuse {
            reflectance: cx.color(object, "reflectance", Vec3::splat(0.5)),
        },
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
            let inner = match nested.first() {
                Some(inner) => bsdf(cx, inner)?,
                None => default_material(cx),
            };
            // `twosided` shows its BSDF's front on both sides: the material without its side.
            let inner = match (object.plugin.as_str(), &cx.desc.materials[inner]) {
                ("twosided", MaterialDesc::OneSided { material }) => *material,
                _ => inner,
            };
            return Ok(Converted::Existing(inner));
        }
        "dielectric" | "roughdielectric" | "thindielectric" => {
            let int = ior(cx, object, "int_ior", 1.5046);
            let ext = ior(cx, object, "ext_ior", 1.000277);
            let reflectance = cx.color(object, "specular_reflectance", Vec3::ONE);
            let transmittance = cx.color(object, "specular_transmittance", Vec3::ONE);
            let ior = int / ext;
            match object.plugin.as_str() {
                "roughdielectric" => MaterialDesc::RoughDielectric {
                    reflectance,
                    transmittance,
                    ior,
                    roughness: roughness(cx, object),
                },
                "thindielectric" => MaterialDesc::ThinDielectric {
                    reflectance,
                    transmittance,
                    ior,
                },
                _ => MaterialDesc::Dielectric {
                    reflectance,
                    transmittance,
                    ior,
                },
            }
        }
        "conductor" | "roughconductor" => {
            let (eta, k) = conductor_index(cx, object);
            MaterialDesc::Conductor {
                reflectance: cx.color(object, "specular_reflectance", Vec3::ONE),
                eta,
                k,
                roughness: (object.plugin == "roughconductor").then(|| roughness(cx, object)),
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

/// `plastic` and `roughplastic` (a diffuse base under a dielectric coating, exact), and
/// `principled`, approximated with a warning: a rough metal when mostly metallic, else a rough
/// plastic of its base colour, roughness and index.
fn plastic(cx: &mut Converter, object: &Object) -> Result<MaterialId, SceneError> {
    let loc = object.loc.clone();
    if object.plugin == "principled" {
        let base = cx.color(object, "base_color", Vec3::splat(0.5));
        let metallic = cx.float(object, "metallic", 0.0);
        let roughness = cx.float(object, "roughness", 0.5);
        let alpha = (roughness * roughness).max(1e-3);
        cx.warn(
            &loc,
            format!(
                "principled approximated by {} (base_color, metallic, roughness, eta, specular \
                 read; the rest ignored)",
                if metallic > 0.5 {
                    "a rough metal"
                } else {
                    "a rough plastic"
                }
            ),
        );
        if metallic > 0.5 {
            return Ok(push(cx, metal(base, (alpha, alpha))));
        }
        // Mitsuba's principled: eta from `specular` when `eta` is not given,
        // specular = ((eta - 1) / (eta + 1))^2 / 0.08.
        let specular = cx.float(object, "specular", 0.5);
        let from_specular = 2.0 / (1.0 - (0.08 * specular).clamp(0.0, 0.99).sqrt()) - 1.0;
        let eta = cx.float(object, "eta", from_specular);
        return Ok(push(
            cx,
            MaterialDesc::Plastic {
                diffuse: base,
                specular: ColorParam::Constant(Vec3::ONE),
                ior: eta,
                alpha: Some(alpha),
                nonlinear: false,
            },
        ));
    }
    let int = ior(cx, object, "int_ior", 1.49);
    let ext = ior(cx, object, "ext_ior", 1.000277);
    let diffuse = cx.color(object, "diffuse_reflectance", Vec3::splat(0.5));
    let specular = cx.color(object, "specular_reflectance", Vec3::ONE);
    let nonlinear = cx.bool(object, "nonlinear", false);
    let alpha = (object.plugin == "roughplastic").then(|| {
        let (u, v) = alphas(cx, object);
        if u != v {
            cx.warn(
                &loc,
                format!(
                    "roughplastic is isotropic (Mitsuba refuses alpha_u != alpha_v): alpha \
                     {} used",
                    (u * v).sqrt()
                ),
            );
        }
        (u * v).sqrt()
    });
    Ok(push(
        cx,
        MaterialDesc::Plastic {
            diffuse,
            specular,
            ior: int / ext,
            alpha,
            nonlinear,
        },
    ))
}

/// The texture-graph node of texture `object` (converted once).
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
    let mut wrap = Wrap::Repeat;
    let image = match object.plugin.as_str() {
        "checkerboard" => {
            let c0 = cx.rgb(object, "color0", Vec3::splat(0.4));
            let c1 = cx.rgb(object, "color1", Vec3::splat(0.2));
            // Mitsuba: color0 where the fractional parts of u and v are both below or both above
            // one half. Sampled finely so that bilinear filtering only blurs a thin seam; each
            // texel one byte naming its colour.
            const N: u32 = 256;
            let indices = (0..N * N)
                .map(|i| {
                    let (x, y) = (i % N, i / N);
                    u8::from((x < N / 2) != (y < N / 2))
                })
                .collect();
            let texels = PaletteTexels::new(indices, &[c0, c1]);
            (
                N,
                N,
                Texels::Palette(Arc::new(texels)),
                "checkerboard".to_string(),
            )
        }
        "bitmap" => {
            let name = cx.string(object, "filename")?;
            let path = cx.tree.resolve(&name);
            let raw = cx.bool(object, "raw", false);
            for p in ["filter_type", "format"] {
                object.prop(p);
            }
            // Mitsuba 3's wrap modes: `repeat` (the default), `clamp` (the edge texel, as
            // LuxRender's), `mirror`.
            match cx.string(object, "wrap_mode").as_deref() {
                None | Some("repeat") => {}
                Some("clamp") => wrap = Wrap::Clamp,
                Some(other) => cx.warn(
                    &loc,
                    format!("bitmap wrap_mode \"{other}\" not supported: repeat used"),
                ),
            }
            // Integer images are sRGB-encoded unless raw; the sRGB curve read as gamma 2.2.
            let gamma = if raw { 1.0 } else { 2.2 };
            match images::decode_texture(&path, gamma, 1.0) {
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
        texels,
        scale,
        delta,
        wrap,
    });
    // A colour parameter names a node of the texture graph: the image looked up at the uv.
    let id = cx.desc.texture_graph.push(TextureNode::Image {
        image: cx.desc.textures.len() - 1,
        mapping: Mapping2D::default(),
    });
    cx.textures.insert(key, id);
    Some(id)
}
