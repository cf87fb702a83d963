//! The scene's textures at render time: the texture graph (procedural and composite textures)
//! and the images its image nodes read, looked up with bilinear filtering and a wrap mode.

use std::sync::Arc;

use bevy_ecs::prelude::*;
use glam::{Vec2, Vec3};

use crate::material::texels::{ReadTexel, Texels};
use crate::math::floor;
use crate::texture::{Mapping2D, ShadingPoint, TexParam, TextureGraph, TextureNode};

/// An RGB image with its uv mapping, its texels kept as `T` (linear RGB by default).
#[derive(Clone, Debug)]
pub struct ImageTexture<T = Arc<Vec<Vec3>>> {
    pub width: u32,
    pub height: u32,
    /// `width * height` texels, rows from the top.
    pub texels: T,
    /// (u, v) -> (u * scale.x + delta.x, v * scale.y + delta.y), then wrapped by `wrap`.
    pub scale: Vec2,
    pub delta: Vec2,
    pub wrap: Wrap,
}

/// What a lookup reads for texels outside the image: LuxRender 1.x's `wrap` (`repeat`,
/// `black`, `white`, `clamp`; core/mipmap.h applies it to each texel the filter reads, so near
/// an edge the bilinear filter blends the edge texels with black, white or themselves).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Wrap {
    #[default]
    Repeat,
    Black,
    White,
    Clamp,
}

/// Present only when the scene has textures.
#[derive(Resource, Clone, Debug)]
pub struct TextureTable {
    pub textures: Vec<ImageTexture<Texels>>,
    pub graph: TextureGraph,
}

impl TextureTable {
    /// The value of graph node `id` at `sp`. An image read through uv, the common node, is
    /// looked up directly: the graph's walk (`TextureGraph::eval`) computes the same value, with
    /// a node dispatch and a call through `dyn Fn` more.
    pub fn lookup(&self, id: usize, sp: &ShadingPoint) -> Vec3 {
        if let Some(TextureNode::Image {
            image,
            mapping: Mapping2D::Uv { scale, delta },
        }) = self.graph.nodes.get(id)
        {
            let v = self.image(*image, sp.uv * *scale + *delta);
            return if v.is_finite() { v } else { Vec3::ZERO };
        }
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
        let Some(texture) = self.textures.get(id) else {
            return Vec3::ZERO;
        };
        let st = st * texture.scale + texture.delta;
        let (w, h, wrap) = (texture.width, texture.height, texture.wrap);
        // One branch on the storage a lookup, not one a texel.
        match &texture.texels {
            Texels::Linear(texels) => sample_bilinear(texels.as_slice(), w, h, wrap, st),
            Texels::Coded(texels) => sample_bilinear(&**texels, w, h, wrap, st),
            Texels::Palette(texels) => sample_bilinear(&**texels, w, h, wrap, st),
        }
    }
}

/// Bilinear lookup in the `width` x `height` image of `texels`; texel centres at
/// half-integers. Inlined, the wrapped case's few dozen instructions go without a call's saved
/// registers and its result through memory; the bounded case stays a call.
#[inline]
pub fn sample_bilinear<T: ReadTexel + ?Sized>(
    texels: &T,
    width: u32,
    height: u32,
    wrap: Wrap,
    st: Vec2,
) -> Vec3 {
    let (w, h) = (width as i64, height as i64);
    if w == 0 || h == 0 || !st.is_finite() {
        return Vec3::ZERO;
    }
    if wrap != Wrap::Repeat {
        return sample_bilinear_bounded(texels, w, h, wrap, st);
    }
    let x = fraction(st.x) * w as f32 - 0.5;
    let y = fraction(st.y) * h as f32 - 0.5;
    let (x0, y0) = (floor_from_half(x), floor_from_half(y));
    let (fx, fy) = (x - x0 as f32, y - y0 as f32);
    // With s, t in [0, 1], x in [-0.5, w - 0.5] and y likewise: the four texels' columns and
    // rows are at most one past either edge, so wrapping is one comparison each, not the
    // integer division of `rem_euclid`.
    let (i0, i1) = neighbours(x0, w);
    let (j0, j1) = neighbours(y0, h);
    let texel = |i: i64, j: i64| texels.texel((j * w + i) as usize);
    (texel(i0, j0) * (1.0 - fx) + texel(i1, j0) * fx) * (1.0 - fy)
        + (texel(i0, j1) * (1.0 - fx) + texel(i1, j1) * fx) * fy
}

/// Bilinear lookup where texels outside the image are black, white or the nearest edge texel.
#[inline(never)]
fn sample_bilinear_bounded<T: ReadTexel + ?Sized>(
    texels: &T,
    w: i64,
    h: i64,
    wrap: Wrap,
    st: Vec2,
) -> Vec3 {
    let x = st.x * w as f32 - 0.5;
    let y = st.y * h as f32 - 0.5;
    let (x0, y0) = (floor(x), floor(y));
    let (fx, fy) = (x - x0, y - y0);
    // `as` saturates, so a far-away st stays far outside (and `+ 1` cannot overflow).
    let (i0, j0) = ((x0 as i64).clamp(-2, w + 1), (y0 as i64).clamp(-2, h + 1));
    let texel = |i: i64, j: i64| {
        let inside = (0..w).contains(&i) && (0..h).contains(&j);
        match wrap {
            Wrap::Black if !inside => Vec3::ZERO,
            Wrap::White if !inside => Vec3::ONE,
            _ => texels.texel((j.clamp(0, h - 1) * w + i.clamp(0, w - 1)) as usize),
        }
    };
    (texel(i0, j0) * (1.0 - fx) + texel(i0 + 1, j0) * fx) * (1.0 - fy)
        + (texel(i0, j0 + 1) * (1.0 - fx) + texel(i0 + 1, j0 + 1) * fx) * fy
}

/// `x.rem_euclid(1.0)` for finite `x`, without its call to `fmodf`: the exact value of
/// x - floor(x) is x's fractional part (or, below 0, that plus 1), which `rem_euclid` also
/// computes exactly and rounds once, so the two agree to the bit (but for -0.0 against +0.0
/// at negative integers, which the caller's multiply and subtract make the same -0.5).
fn fraction(x: f32) -> f32 {
    x - floor(x)
}

/// `floor(x)` for finite x >= -0.5 (a texel coordinate of a wrapped lookup), without `floor`'s
/// general case: truncation toward zero is the floor at x >= 0, and every x in [-0.5, 0) has
/// floor -1. Its value as f32 is exact, so x minus it is x - floor(x) to the bit.
fn floor_from_half(x: f32) -> i64 {
    if x < 0.0 { -1 } else { x as i64 }
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
    use crate::material::texels::{CodedTexels, PaletteTexels};

    /// `texture` looked up at `st` (its scale and offset not applied).
    fn sample(texture: &ImageTexture<Vec<Vec3>>, st: Vec2) -> Vec3 {
        let (w, h) = (texture.width, texture.height);
        sample_bilinear(texture.texels.as_slice(), w, h, texture.wrap, st)
    }

    /// The lookup as written with `rem_euclid` throughout (the definition of repeat wrapping).
    fn by_rem_euclid(texture: &ImageTexture<Vec<Vec3>>, st: Vec2) -> Vec3 {
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
            texels,
            scale: Vec2::ONE,
            delta: Vec2::ZERO,
            wrap: Wrap::Repeat,
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
                let (got, want) = (sample(&texture, st), by_rem_euclid(&texture, st));
                assert_eq!(
                    got.to_array().map(f32::to_bits),
                    want.to_array().map(f32::to_bits)
                );
            }
        }
    }

    #[test]
    fn a_uv_image_node_looks_up_as_the_graph_walks_it() {
        // A 3x2 image with a NaN texel (a lookup reading it is not finite: black), read through
        // a uv node with an offset scale, beside a node the graph must still evaluate.
        let mut texels: Vec<Vec3> = (0..6)
            .map(|k| Vec3::new(k as f32, 0.5, 1.0 - k as f32 * 0.1))
            .collect();
        texels[4] = Vec3::new(f32::NAN, 0.0, 0.0);
        let mut graph = TextureGraph::default();
        let image = graph.push(TextureNode::Image {
            image: 0,
            mapping: Mapping2D::Uv {
                scale: Vec2::new(1.7, -0.6),
                delta: Vec2::new(0.3, 0.05),
            },
        });
        let scaled = graph.push(TextureNode::Scale {
            tex1: TexParam::Texture(image),
            tex2: TexParam::Value(Vec3::splat(0.5)),
        });
        let table = TextureTable {
            textures: vec![ImageTexture {
                width: 3,
                height: 2,
                texels: Arc::new(texels).into(),
                scale: Vec2::new(1.0, 2.0),
                delta: Vec2::new(0.25, 0.0),
                wrap: Wrap::Repeat,
            }],
            graph,
        };
        let (mut black, mut lit) = (0, 0);
        for k in 0..400 {
            let sp = ShadingPoint {
                p: Vec3::ZERO,
                uv: Vec2::new(k as f32 * 0.0371 - 3.0, (k * 7 % 23) as f32 * 0.113 - 1.0),
                n: Vec3::Z,
                object: 0,
            };
            for id in [image, scaled] {
                let walked = table
                    .graph
                    .eval(TexParam::Texture(id), &sp, &|i, st| table.image(i, st));
                let got = table.lookup(id, &sp);
                assert_eq!(
                    got.to_array().map(f32::to_bits),
                    walked.to_array().map(f32::to_bits)
                );
            }
            if table.lookup(image, &sp) == Vec3::ZERO {
                black += 1
            } else {
                lit += 1
            }
        }
        // Both cases met: lookups that read the NaN texel, and others.
        assert!(black > 0 && lit > 0, "{black} black, {lit} lit");
    }

    /// Asserts that lookups in `width` x `height` images of `linear` and of `kept` (the same
    /// texels kept otherwise) agree to the bit, over many st and with every wrap.
    fn assert_same_lookups(width: u32, height: u32, linear: Vec<Vec3>, kept: Texels) {
        let image = |texels: Texels, wrap| ImageTexture {
            width,
            height,
            texels,
            scale: Vec2::new(1.3, -0.7),
            delta: Vec2::new(0.1, 0.2),
            wrap,
        };
        for wrap in [Wrap::Repeat, Wrap::Black, Wrap::White, Wrap::Clamp] {
            let table = TextureTable {
                textures: vec![
                    image(Arc::new(linear.clone()).into(), wrap),
                    image(kept.clone(), wrap),
                ],
                graph: TextureGraph::default(),
            };
            for k in 0..20_000 {
                let st = Vec2::new(
                    k as f32 * 0.000731 - 3.0,
                    (k * 37 % 1009) as f32 * 0.0049 - 2.0,
                );
                let (want, got) = (table.image(0, st), table.image(1, st));
                assert_eq!(
                    got.to_array().map(f32::to_bits),
                    want.to_array().map(f32::to_bits),
                    "{wrap:?} at {st}"
                );
            }
        }
    }

    #[test]
    fn an_8bit_image_looks_up_as_its_linear_texels_do_to_the_bit() {
        // Every code in some channel, at unlike texels and channels, each code with a value
        // of its own (a table read one code off gives another value).
        let (width, height) = (16u32, 11u32);
        let rgb: Vec<u8> = (0..3 * width * height)
            .map(|k| (k * 97 + 13) as u8)
            .collect();
        let values: [f32; 256] =
            std::array::from_fn(|code| (code as f32 / 255.0).powf(2.2) * 1.7 + 0.01);
        let linear = rgb
            .chunks(3)
            .map(|c| Vec3::from_array([c[0], c[1], c[2]].map(|code| values[usize::from(code)])))
            .collect();
        let coded = Texels::Coded(Arc::new(CodedTexels::new(rgb, values)));
        assert_same_lookups(width, height, linear, coded);
    }

    #[test]
    fn a_palette_image_looks_up_as_its_linear_texels_do_to_the_bit() {
        // 200 colours of distinct channels, named in a scrambled order by texels that use
        // them all.
        let (width, height) = (23u32, 13u32);
        let colors: Vec<Vec3> = (0..200)
            .map(|k| {
                Vec3::new(
                    k as f32 * 0.01,
                    2.0 - k as f32 * 0.007,
                    (k * k % 211) as f32,
                )
            })
            .collect();
        let indices: Vec<u8> = (0..width * height).map(|k| (k * 71 % 200) as u8).collect();
        let linear = indices.iter().map(|&i| colors[usize::from(i)]).collect();
        let palette = Texels::Palette(Arc::new(PaletteTexels::new(indices, &colors)));
        assert_same_lookups(width, height, linear, palette);
    }

    #[test]
    fn black_white_and_clamp_read_outside_texels_as_luxrender_does() {
        let t = [
            Vec3::new(1.0, 2.0, 3.0),
            Vec3::new(4.0, 5.0, 6.0),
            Vec3::new(7.0, 8.0, 9.0),
            Vec3::new(10.0, 11.0, 12.0),
        ];
        let texture = |wrap| ImageTexture {
            width: 2,
            height: 2,
            texels: t.to_vec(),
            scale: Vec2::ONE,
            delta: Vec2::ZERO,
            wrap,
        };
        let (black, white, clamp) = (
            texture(Wrap::Black),
            texture(Wrap::White),
            texture(Wrap::Clamp),
        );
        // At a texel's centre the filter reads that texel alone, whatever the wrap.
        for image in [&black, &white, &clamp] {
            assert_eq!(sample(image, Vec2::new(0.75, 0.25)), t[1]);
        }
        // At the image's corner (0, 0) the filter weighs four texels by 1/4, three outside.
        let corner = Vec2::ZERO;
        assert_eq!(sample(&black, corner), t[0] * 0.25);
        assert_eq!(sample(&white, corner), Vec3::splat(0.75) + t[0] * 0.25);
        assert_eq!(sample(&clamp, corner), t[0]);
        // Halfway between the two top texels' centres, on the top edge: two rows, one outside.
        let top = Vec2::new(0.5, 0.0);
        assert_eq!(sample(&black, top), (t[0] + t[1]) * 0.25);
        assert_eq!(sample(&clamp, top), (t[0] + t[1]) * 0.5);
        // Far outside (and past the i64 range): black, white, the nearest corner texel.
        for st in [Vec2::new(5.0, 7.0), Vec2::new(1e30, 1e30)] {
            assert_eq!(sample(&black, st), Vec3::ZERO);
            assert_eq!(sample(&white, st), Vec3::ONE);
            assert_eq!(sample(&clamp, st), t[3]);
        }
        assert_eq!(sample(&clamp, Vec2::new(-1e30, -3.0)), t[0]);
    }
}
