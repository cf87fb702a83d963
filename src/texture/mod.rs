//! Procedural and composite textures, LuxRender 1.x's set: a texture graph whose nodes name
//! other nodes, evaluated at a shading point. Values are RGB; a float texture holds the same
//! value in all three channels, and a colour read as a float is the mean of its channels
//! (LuxRender's `Filter()` of an RGB colour).
//!
//! The low-level pieces (noise, mappings, each pattern) live one per file; this module only
//! composes them. Image textures stay in `material::texture` (the graph refers to them through
//! [`TextureNode::Image`] with a lookup function supplied by the caller).

pub mod blackbody;
pub mod blender;
pub mod blender_noise;
mod blender_tables;
pub mod checkerboard;
pub mod dots;
pub mod harlequin;
pub mod mapping;
pub mod marble;
pub mod musgrave;
pub mod noise;

use glam::{Vec2, Vec3};

pub use mapping::{Mapping2D, Mapping3D};

/// What a texture may read at a surface point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShadingPoint {
    /// World-space position.
    pub p: Vec3,
    /// Surface parameterisation (mesh uvs; the shape's own for analytic shapes).
    pub uv: Vec2,
    /// Shading normal.
    pub n: Vec3,
    /// Index of the object hit (for `harlequin`).
    pub object: u32,
}

/// A texture's input: a constant or another node of the graph.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum TexParam {
    Value(Vec3),
    Texture(usize),
}

impl TexParam {
    pub fn float(v: f32) -> Self {
        TexParam::Value(Vec3::splat(v))
    }
}

/// One node; the LuxRender type name and parameters (defaults as LuxRender's) in each comment.
#[derive(Clone, Debug, PartialEq)]
pub enum TextureNode {
    /// `constant` `value`.
    Constant(Vec3),
    /// An image texture, by index into the caller's image table, with its 2D mapping.
    Image { image: usize, mapping: Mapping2D },
    /// `scale`: `tex1` x `tex2` (defaults 1, 1).
    Scale { tex1: TexParam, tex2: TexParam },
    /// `mix`: (1 - `amount`) `tex1` + `amount` `tex2` (defaults 0, 1, amount 0.5; `amount` is not
    /// clamped, as in LuxRender's `Lerp`).
    Mix {
        tex1: TexParam,
        tex2: TexParam,
        amount: TexParam,
    },
    /// `checkerboard` `dimension` 2: `tex1` (default 1) on even checks, `tex2` (0) on odd.
    Checkerboard2D {
        mapping: Mapping2D,
        tex1: TexParam,
        tex2: TexParam,
    },
    /// `checkerboard` `dimension` 3.
    Checkerboard3D {
        mapping: Mapping3D,
        tex1: TexParam,
        tex2: TexParam,
    },
    /// `dots`: `inside` within the dots, `outside` elsewhere (LuxRender's parameters arrive
    /// swapped: see `scene::lxs::textures`).
    Dots {
        mapping: Mapping2D,
        inside: TexParam,
        outside: TexParam,
    },
    /// `bilerp`: bilinear in (s, t) between `v00`, `v01`, `v10`, `v11` (defaults 0, 1, 0, 1).
    Bilerp { mapping: Mapping2D, v: [Vec3; 4] },
    /// `fbm`: `octaves` 8, `roughness` 0.5.
    Fbm {
        mapping: Mapping3D,
        octaves: u32,
        roughness: f32,
    },
    /// `wrinkled`: turbulence, `octaves` 8, `roughness` 0.5.
    Wrinkled {
        mapping: Mapping3D,
        octaves: u32,
        roughness: f32,
    },
    /// `windy`: |fbm(p / 10, 0.5, 3)| fbm(p, 0.5, 6) (pbrt-v1 §11.6.3).
    Windy { mapping: Mapping3D },
    /// `marble`: `octaves` 8, `roughness` 0.5, `scale` 1, `variation` 0.2.
    Marble {
        mapping: Mapping3D,
        octaves: u32,
        roughness: f32,
        scale: f32,
        variation: f32,
    },
    /// `blackbody` `temperature` (6500 K), as linear sRGB, computed once.
    Blackbody { rgb: Vec3 },
    /// `harlequin`: a colour per object.
    Harlequin,
    /// The Blender procedurals (`blender_blend`, `blender_clouds`, `blender_distortednoise`,
    /// `blender_magic`, `blender_marble`, `blender_musgrave`, `blender_noise`, `blender_stucci`,
    /// `blender_voronoi`, `blender_wood`): (1 - f) `tex1` + f `tex2` (defaults 0, 1) of the
    /// pattern's intensity f.
    Blender {
        mapping: Mapping3D,
        texture: blender::BlenderTexture,
        tex1: TexParam,
        tex2: TexParam,
    },
}

impl TextureNode {
    /// The `blackbody` node at `kelvin`.
    pub fn blackbody(kelvin: f32) -> Self {
        TextureNode::Blackbody {
            rgb: blackbody::blackbody_rgb(kelvin),
        }
    }
}

/// Graphs nest at most this deep; a deeper chain (only a cycle makes one) evaluates to black.
const MAX_DEPTH: u32 = 32;

/// The textures of a scene; nodes refer to each other by index.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TextureGraph {
    pub nodes: Vec<TextureNode>,
}

impl TextureGraph {
    /// Adds a node and returns its index.
    pub fn push(&mut self, node: TextureNode) -> usize {
        self.nodes.push(node);
        self.nodes.len() - 1
    }

    /// The value of `param` at `sp`; `image` looks up (image index, st).
    pub fn eval(
        &self,
        param: TexParam,
        sp: &ShadingPoint,
        image: &dyn Fn(usize, Vec2) -> Vec3,
    ) -> Vec3 {
        self.eval_depth(param, sp, image, 0)
    }

    /// The value of `param` read as a float: the mean of its channels.
    pub fn eval_float(
        &self,
        param: TexParam,
        sp: &ShadingPoint,
        image: &dyn Fn(usize, Vec2) -> Vec3,
    ) -> f32 {
        let v = self.eval(param, sp, image);
        (v.x + v.y + v.z) / 3.0
    }

    fn eval_depth(
        &self,
        param: TexParam,
        sp: &ShadingPoint,
        image: &dyn Fn(usize, Vec2) -> Vec3,
        depth: u32,
    ) -> Vec3 {
        let id = match param {
            TexParam::Value(v) => return v,
            TexParam::Texture(id) => id,
        };
        let Some(node) = self.nodes.get(id) else {
            return Vec3::ZERO;
        };
        if depth >= MAX_DEPTH {
            return Vec3::ZERO;
        }
        let sub = |p: TexParam| self.eval_depth(p, sp, image, depth + 1);
        let pick = |first: bool, a: TexParam, b: TexParam| sub(if first { a } else { b });
        let v = match node {
            TextureNode::Constant(c) => *c,
            TextureNode::Image { image: i, mapping } => image(*i, mapping.map(sp)),
            TextureNode::Scale { tex1, tex2 } => sub(*tex1) * sub(*tex2),
            TextureNode::Mix { tex1, tex2, amount } => {
                let a = sub(*amount);
                let a = (a.x + a.y + a.z) / 3.0;
                sub(*tex1) * (1.0 - a) + sub(*tex2) * a
            }
            TextureNode::Checkerboard2D {
                mapping,
                tex1,
                tex2,
            } => pick(checkerboard::checker_2d(mapping.map(sp)), *tex1, *tex2),
            TextureNode::Checkerboard3D {
                mapping,
                tex1,
                tex2,
            } => pick(checkerboard::checker_3d(mapping.map(sp)), *tex1, *tex2),
            TextureNode::Dots {
                mapping,
                inside,
                outside,
            } => pick(dots::inside_dot(mapping.map(sp)), *inside, *outside),
            TextureNode::Bilerp { mapping, v } => {
                let st = mapping.map(sp);
                let (s, t) = (st.x, st.y);
                (1.0 - s) * (1.0 - t) * v[0]
                    + (1.0 - s) * t * v[1]
                    + s * (1.0 - t) * v[2]
                    + s * t * v[3]
            }
            TextureNode::Fbm {
                mapping,
                octaves,
                roughness,
            } => Vec3::splat(noise::fbm(mapping.map(sp), *roughness, *octaves)),
            TextureNode::Wrinkled {
                mapping,
                octaves,
                roughness,
            } => Vec3::splat(noise::turbulence(mapping.map(sp), *roughness, *octaves)),
            TextureNode::Windy { mapping } => {
                let p = mapping.map(sp);
                let strength = noise::fbm(0.1 * p, 0.5, 3);
                Vec3::splat(strength.abs() * noise::fbm(p, 0.5, 6))
            }
            TextureNode::Marble {
                mapping,
                octaves,
                roughness,
                scale,
                variation,
            } => marble::marble(mapping.map(sp), *octaves, *roughness, *scale, *variation),
            TextureNode::Blackbody { rgb } => *rgb,
            TextureNode::Harlequin => harlequin::harlequin(sp.object),
            TextureNode::Blender {
                mapping,
                texture,
                tex1,
                tex2,
            } => {
                let f = texture.intensity(mapping.map(sp));
                sub(*tex1) * (1.0 - f) + sub(*tex2) * f
            }
        };
        if v.is_finite() { v } else { Vec3::ZERO }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Affine3A;

    fn at(p: Vec3, uv: Vec2) -> ShadingPoint {
        ShadingPoint {
            p,
            uv,
            n: Vec3::Z,
            object: 3,
        }
    }

    fn no_images(_: usize, _: Vec2) -> Vec3 {
        Vec3::ZERO
    }

    /// texture-examples.lxs's pattern: a float checkerboard (uscale 8) driving a colour mix.
    #[test]
    fn graph_mixes_by_a_checkerboard() {
        let mut g = TextureGraph::default();
        let checks = g.push(TextureNode::Checkerboard2D {
            mapping: Mapping2D::Uv {
                scale: Vec2::splat(8.0),
                delta: Vec2::ZERO,
            },
            tex1: TexParam::float(1.0),
            tex2: TexParam::float(0.0),
        });
        let (orange, blue) = (Vec3::new(1.0, 0.65, 0.0), Vec3::new(0.19, 0.15, 0.48));
        let mix = g.push(TextureNode::Mix {
            tex1: TexParam::Value(orange),
            tex2: TexParam::Value(blue),
            amount: TexParam::Texture(checks),
        });
        let eval = |uv: Vec2| g.eval(TexParam::Texture(mix), &at(Vec3::ZERO, uv), &no_images);
        // uv (0.01, 0.01) -> st (0.08, 0.08): even check, amount 1 -> tex2.
        assert_eq!(eval(Vec2::splat(0.01)), blue);
        // uv (0.14, 0.01) -> st (1.12, 0.08): odd, amount 0 -> tex1.
        assert_eq!(eval(Vec2::new(0.14, 0.01)), orange);
        // A half amount blends.
        let half = g.push(TextureNode::Mix {
            tex1: TexParam::Value(orange),
            tex2: TexParam::Value(blue),
            amount: TexParam::float(0.5),
        });
        let v = g.eval(
            TexParam::Texture(half),
            &at(Vec3::ZERO, Vec2::ZERO),
            &no_images,
        );
        assert!((v - (orange + blue) / 2.0).length() < 1e-6);
    }

    #[test]
    fn scale_bilerp_and_images() {
        let mut g = TextureGraph::default();
        let image = g.push(TextureNode::Image {
            image: 7,
            mapping: Mapping2D::Uv {
                scale: Vec2::new(2.0, 1.0),
                delta: Vec2::ZERO,
            },
        });
        let scaled = g.push(TextureNode::Scale {
            tex1: TexParam::Texture(image),
            tex2: TexParam::Value(Vec3::new(0.5, 2.0, 1.0)),
        });
        let lookup = |i: usize, st: Vec2| Vec3::new(i as f32, st.x, st.y);
        let v = g.eval(
            TexParam::Texture(scaled),
            &at(Vec3::ZERO, Vec2::new(0.25, 0.5)),
            &lookup,
        );
        assert_eq!(v, Vec3::new(3.5, 1.0, 0.5));
        let bilerp = g.push(TextureNode::Bilerp {
            mapping: Mapping2D::default(),
            v: [
                Vec3::splat(0.0),
                Vec3::splat(1.0),
                Vec3::splat(0.0),
                Vec3::splat(1.0),
            ],
        });
        // With LuxRender's defaults the value is t.
        let v = g.eval_float(
            TexParam::Texture(bilerp),
            &at(Vec3::ZERO, Vec2::new(0.3, 0.7)),
            &no_images,
        );
        assert!((v - 0.7).abs() < 1e-6);
    }

    #[test]
    fn noise_textures_and_cycles() {
        let mut g = TextureGraph::default();
        let mapping = Mapping3D::Global {
            world_to_texture: Affine3A::IDENTITY,
        };
        let fbm = g.push(TextureNode::Fbm {
            mapping,
            octaves: 8,
            roughness: 0.5,
        });
        let wrinkled = g.push(TextureNode::Wrinkled {
            mapping,
            octaves: 8,
            roughness: 0.5,
        });
        let windy = g.push(TextureNode::Windy { mapping });
        let p = Vec3::new(1.3, -0.2, 4.7);
        let sp = at(p, Vec2::ZERO);
        assert_eq!(
            g.eval_float(TexParam::Texture(fbm), &sp, &no_images),
            noise::fbm(p, 0.5, 8)
        );
        assert_eq!(
            g.eval_float(TexParam::Texture(wrinkled), &sp, &no_images),
            noise::turbulence(p, 0.5, 8)
        );
        let w = noise::fbm(0.1 * p, 0.5, 3).abs() * noise::fbm(p, 0.5, 6);
        assert_eq!(g.eval_float(TexParam::Texture(windy), &sp, &no_images), w);
        // LuxRender's `WindyTexture::Evaluate` (`textures/windy.h`) at (2.5, -1.25, 7.75), from
        // an independent float64 transcription (Python) of it and `FBm`: 0.0519371.
        let q = at(Vec3::new(2.5, -1.25, 7.75), Vec2::ZERO);
        let w = g.eval_float(TexParam::Texture(windy), &q, &no_images);
        assert!((w - 0.051_937_05).abs() < 1e-6, "{w}");
        // A node naming itself (only a malformed graph does) evaluates to black, not forever.
        let cycle = g.push(TextureNode::Scale {
            tex1: TexParam::Texture(3),
            tex2: TexParam::float(2.0),
        });
        assert_eq!(cycle, 3);
        assert_eq!(
            g.eval(TexParam::Texture(cycle), &sp, &no_images),
            Vec3::ZERO
        );
        assert_eq!(g.eval(TexParam::Texture(99), &sp, &no_images), Vec3::ZERO);
        assert_eq!(
            g.eval(TexParam::Texture(g.nodes.len()), &sp, &no_images),
            Vec3::ZERO
        );
        let h = g.push(TextureNode::Harlequin);
        assert_eq!(
            g.eval(TexParam::Texture(h), &sp, &no_images),
            harlequin::harlequin(3)
        );
    }
}
