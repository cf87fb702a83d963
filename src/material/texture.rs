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
    let x = fraction(st.x) * w as f32 - 0.5;
    let y = fraction(st.y) * h as f32 - 0.5;
    let (x0, y0) = (x.floor(), y.floor());
    let (fx, fy) = (x - x0, y - y0);
    // With s, t in [0, 1], x in [-0.5, w - 0.5] and y likewise: the four texels' columns and
    // rows are at most one past either edge, so wrapping is one comparison each, not the
    // integer division of `rem_euclid`.
    let (i0, i1) = neighbours(x0 as i64, w);
    let (j0, j1) = neighbours(y0 as i64, h);
    let texel = |i: i64, j: i64| texture.texels[(j * w + i) as usize];
    (texel(i0, j0) * (1.0 - fx) + texel(i1, j0) * fx) * (1.0 - fy)
        + (texel(i0, j1) * (1.0 - fx) + texel(i1, j1) * fx) * fy
}

/// `x.rem_euclid(1.0)` for finite `x`, without its call to `fmodf`: the exact value of
/// x - floor(x) is x's fractional part (or, below 0, that plus 1), which `rem_euclid` also
/// computes exactly and rounds once, so the two agree to the bit (but for -0.0 against +0.0
/// at negative integers, which the caller's multiply and subtract make the same -0.5).
fn fraction(x: f32) -> f32 {
    x - x.floor()
}

/// Column (or row) `i` in -1..=n - 1 and the next one, wrapped into 0..n.
fn neighbours(i: i64, n: i64) -> (i64, i64) {
    let first = if i < 0 { i + n } else { i };
    let next = if i + 1 >= n { i + 1 - n } else { i + 1 };
    (first, next)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The lookup as written with `rem_euclid` throughout (the definition of repeat wrapping).
    fn by_rem_euclid(texture: &ImageTexture, st: Vec2) -> Vec3 {
        let (w, h) = (texture.width as i64, texture.height as i64);
        let x = st.x.rem_euclid(1.0) * w as f32 - 0.5;
        let y = st.y.rem_euclid(1.0) * h as f32 - 0.5;
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let texel =
            |i: i64, j: i64| texture.texels[(j.rem_euclid(h) * w + i.rem_euclid(w)) as usize];
        let (i, j) = (x0 as i64, y0 as i64);
        (texel(i, j) * (1.0 - fx) + texel(i + 1, j) * fx) * (1.0 - fy)
            + (texel(i, j + 1) * (1.0 - fx) + texel(i + 1, j + 1) * fx) * fy
    }

    #[test]
    fn wrapping_matches_rem_euclid_to_the_bit() {
        let (width, height) = (5u32, 3u32);
        let texels = (0..width * height)
            .map(|k| Vec3::new(k as f32, (k * k % 7) as f32 + 0.25, 1.0 / (k + 1) as f32))
            .collect();
        let texture = ImageTexture {
            width,
            height,
            texels: Arc::new(texels),
            scale: Vec2::ONE,
            delta: Vec2::ZERO,
        };
        // A grid over [-3, 3] that lands on texel centres, edges and integers, plus values
        // next to integers, where the fraction rounds to 0 or to 1.
        let mut coords: Vec<f32> = (-60..=60).map(|k| k as f32 * 0.05).collect();
        for k in -3..=3 {
            let k = k as f32;
            coords.extend([k - 1e-7, k + 1e-7, k - 1e-9, k + 1e-9, -0.0]);
        }
        for &s in &coords {
            for &t in &coords {
                let st = Vec2::new(s, t);
                let (got, want) = (sample_bilinear(&texture, st), by_rem_euclid(&texture, st));
                assert_eq!(
                    got.to_array().map(f32::to_bits),
                    want.to_array().map(f32::to_bits)
                );
            }
        }
    }
}
