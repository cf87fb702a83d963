//! An image's texels as the renderer keeps them: linear RGB in f32, or, for an image stored
//! with 8 bits a channel, its codes with a table of the 256 codes' linear values, as pbrt-v4
//! keeps 8-bit images (`Image` in `PixelFormat::U256`, read through a lookup table of the
//! decoded values). A lookup through the table gives the very f32 the decoder would have
//! stored, in a quarter of the memory: a 512 x 512 RGB image is 768 KB, not 3 MB, and fits a
//! core's L2 cache (1 MB here), where the texel loads of a lookup were mostly misses. A
//! generated pattern of few colours (Mitsuba's checkerboard) keeps one byte a texel naming its
//! colour: 64 KB for a 256 x 256 checkerboard, not 768 KB.

use std::sync::Arc;

use glam::Vec3;

/// Reads texel `index` (row-major, rows from the top) as linear RGB.
pub trait ReadTexel {
    fn texel(&self, index: usize) -> Vec3;
}

/// The texels of one image, in one of the ways they are kept.
#[derive(Clone, Debug)]
pub enum Texels {
    /// Linear RGB, f32 a channel: float images (EXR, HDR), deeper integer images and images
    /// made in memory.
    Linear(Arc<Vec<Vec3>>),
    /// 8 bits a channel, decoded through a table.
    Coded(Arc<CodedTexels>),
    /// One of at most 256 colours.
    Palette(Arc<PaletteTexels>),
}

impl Texels {
    /// Every texel as linear RGB; shares the texels when they already are.
    pub fn to_linear(&self) -> Arc<Vec<Vec3>> {
        match self {
            Texels::Linear(texels) => texels.clone(),
            Texels::Coded(texels) => Arc::new((0..texels.len()).map(|i| texels.texel(i)).collect()),
            Texels::Palette(texels) => {
                Arc::new((0..texels.indices.len()).map(|i| texels.texel(i)).collect())
            }
        }
    }
}

impl From<Arc<Vec<Vec3>>> for Texels {
    fn from(texels: Arc<Vec<Vec3>>) -> Self {
        Texels::Linear(texels)
    }
}

/// An image's 8-bit RGB codes and the linear value of each code (the same for the three
/// channels: gamma and gain apply alike to each).
#[derive(Clone, Debug)]
pub struct CodedTexels {
    /// Three codes a texel (red, green, blue), then one padding byte, so that every texel
    /// reads as one unaligned 4-byte word.
    codes: Vec<u8>,
    values: [f32; 256],
}

impl CodedTexels {
    /// The texels of `rgb` (three codes a texel) decoded through `values`.
    pub fn new(mut rgb: Vec<u8>, values: [f32; 256]) -> Self {
        assert_eq!(rgb.len() % 3, 0, "three codes a texel");
        rgb.push(0);
        Self { codes: rgb, values }
    }

    fn len(&self) -> usize {
        self.codes.len() / 3
    }
}

impl ReadTexel for CodedTexels {
    #[inline]
    fn texel(&self, index: usize) -> Vec3 {
        let at = 3 * index;
        let word = u32::from_le_bytes(self.codes[at..at + 4].try_into().expect("four bytes"));
        let value = |shift: u32| self.values[usize::from((word >> shift) as u8)];
        Vec3::new(value(0), value(8), value(16))
    }
}

/// Texels of at most 256 distinct colours: each texel the index of its colour.
#[derive(Clone, Debug)]
pub struct PaletteTexels {
    indices: Vec<u8>,
    /// The colours, then black up to 256 (so that every byte indexes without a bounds test).
    colors: Box<[Vec3; 256]>,
}

impl PaletteTexels {
    /// The texels whose colours are `colors[indices[i]]`.
    pub fn new(indices: Vec<u8>, colors: &[Vec3]) -> Self {
        assert!(colors.len() <= 256, "at most 256 colours");
        let mut table = Box::new([Vec3::ZERO; 256]);
        table[..colors.len()].copy_from_slice(colors);
        assert!(
            indices.iter().all(|&i| usize::from(i) < colors.len()),
            "every index names a colour"
        );
        Self {
            indices,
            colors: table,
        }
    }
}

impl ReadTexel for PaletteTexels {
    #[inline]
    fn texel(&self, index: usize) -> Vec3 {
        self.colors[usize::from(self.indices[index])]
    }
}

impl ReadTexel for [Vec3] {
    #[inline]
    fn texel(&self, index: usize) -> Vec3 {
        self[index]
    }
}

impl ReadTexel for Texels {
    #[inline]
    fn texel(&self, index: usize) -> Vec3 {
        match self {
            Texels::Linear(texels) => texels[index],
            Texels::Coded(texels) => texels.texel(index),
            Texels::Palette(texels) => texels.texel(index),
        }
    }
}
