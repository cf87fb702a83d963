//! The film: pixel filtering by importance sampling or splatting, accumulation of radiance, exposure, image
//! output and image comparison.

pub mod checkpoint;
mod exr_zip;
#[allow(clippy::module_inception)]
mod film;
pub mod filter;
pub mod output;
pub mod part;
pub mod tonemap;

pub use film::{Film, FilmSample, Reconstruction};
pub use filter::{FilterKind, PixelFilter};
pub use output::{
    ImageMetadata, check_output, is_linear_output, read_exr, read_png_linear, write_image,
};
pub use tonemap::{ToneMap, apply_display_tone_map, exposure_scale, luminance};
