//! Sample generation: per-path random streams, per-pixel sample patterns, warps from the unit
//! square to the domains light transport integrates over, and tabulated distributions.

pub mod alias;
pub mod bilinear;
pub mod distribution;
mod divisor;
mod first_draws;
mod hash;
mod padded_sobol;
pub mod pixel_sampler;
pub mod rng;
mod sobol;
pub mod spherical_rectangle;
pub mod warp;

pub use alias::AliasTable;
pub use bilinear::{Bilinear2D, BilinearFour, BilinearSample, GridCell};
pub use distribution::Distribution1D;
pub use divisor::Divisor;
pub use first_draws::{FirstDraws, PathDraws};
pub use pixel_sampler::{DimensionSampler, PassSampler, PixelSampler, SamplerKind};
pub use rng::{PADDED_DRAWS, PassStreams, PathRng};

/// The largest f32 below 1 (1 - 2^-24): samples are clamped to it so that they stay in [0, 1).
pub const ONE_MINUS_EPSILON: f32 = 1.0 - f32::EPSILON / 2.0;
