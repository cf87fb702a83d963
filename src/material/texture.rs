//! The scene's textures at render time: the texture graph (procedural and composite textures)
//! and the images its image nodes read, looked up with bilinear filtering and repeat wrapping.

use std::sync::Arc;

use bevy_ecs::prelude::*;
use glam::{Vec2, Vec3};

use crate::texture::{ShadingPoint, TexParam, TextureGraph};

/// A linear RGB image with its uv mapping.
#[derive(Clone, Debug)]
pub struct ImageTexture {
    pub width: u32,
    pub height: u32,
    /// `width * height` texels, rows from the top.
    pub texels: Arc<Vec<Vec3>>,
    /// (u, v) -> (u * scale.x + delta.x, v * scale.y + delta.y), then wrapped (repeat).
    pub scale: Vec2,
    pub delta: Vec2,
}

/// Present only when the scene has textures.
#[derive(Resource, Clone, Debug)]
pub struct TextureTable {
    pub textures: Vec<ImageTexture>,
    pub graph: TextureGraph,
}

impl TextureTable {
    /// The value of graph node `id` at `sp`.
    pub fn lookup(&self, id: usize, sp: &ShadingPoint) -> Vec3 {
        self.graph.eval(TexParam::Texture(id), sp, &|image, st| {
            self.image(image, st)
        })
    }

    /// The value of graph node `id` at `sp` read as a float (the mean of its channels).
    pub fn lookup_float(&self, id: usize, sp: &ShadingPoint) -> f32 {
        let v = self.lookup(id, sp);
        (v.x + v.y + v.z) / 3.0
    }

    /// Image `id` at `st`. The image's first row is t = 0 (LuxRender's convention; LuxBlend
    /// writes vscale -1, vdelta 1 to put Blender's v = 0 at the bottom).
    fn image(&self, id: usize, st: Vec2) -> Vec3 {
        match self.textures.get(id) {
            Some(texture) => sample_bilinear(texture, st * texture.scale + texture.delta),
            None => Vec3::ZERO,
        }
    }
}

/// Bilinear lookup with repeat wrapping; texel centres at half-integers.
pub fn sample_bilinear(texture: &ImageTexture, st: Vec2) -> Vec3 {
    let (w, h) = (texture.width as i64, texture.height as i64);
    if w == 0 || h == 0 || !st.is_finite() {
        return Vec3::ZERO;
    }
    let x = st.x.rem_euclid(1.0) * w as f32 - 0.5;
    let y = st.y.rem_euclid(1.0) * h as f32 - 0.5;
    let (x0, y0) = (x.floor(), y.floor());
    let (fx, fy) = (x - x0, y - y0);
    let texel = |i: i64, j: i64| texture.texels[(j.rem_euclid(h) * w + i.rem_euclid(w)) as usize];
    let (i, j) = (x0 as i64, y0 as i64);
    (texel(i, j) * (1.0 - fx) + texel(i + 1, j) * fx) * (1.0 - fy)
        + (texel(i, j + 1) * (1.0 - fx) + texel(i + 1, j + 1) * fx) * fy
}
