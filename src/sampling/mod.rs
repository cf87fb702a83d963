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
pub use first_draws::{
    FirstDraws, LIGHT_CHOICE_DRAW, LIGHT_POINT_DRAW, LOBE_DRAW, MATERIAL_CHOICE_DRAW, PathDraws,
};
pub use pixel_sampler::{
    DimensionLanes, DimensionSampler, PassSampler, PixelSampler, SampleLanes, SamplerKind,
};
pub use rng::{PADDED_DRAWS, PassStreams, PathRng};

/// The largest f32 below 1 (1 - 2^-24): samples are clamped to it so that they stay in [0, 1).
pub const ONE_MINUS_EPSILON: f32 = 1.0 - f32::EPSILON / 2.0;

/// 2D samples for tests that compare two ways of warping them: 4,000 points spread over the unit
/// square, then every pair of edge values (0, -0, 1, just below 1, tiny, negative, above 1,
/// NaN, infinity, a half).
#[cfg(test)]
pub(crate) fn test_samples_with_edges() -> Vec<glam::Vec2> {
    use glam::Vec2;
    let edges = [
        0.0,
        -0.0,
        1.0,
        ONE_MINUS_EPSILON,
        1e-30,
        -0.25,
        1.5,
        f32::NAN,
        f32::INFINITY,
        0.5,
    ];
    let spread =
        (0..4000).map(|k| Vec2::new((k as f32 * 0.618_034).fract(), (k as f32 + 0.5) / 4000.0));
    let pairs = edges.iter().flat_map(|&x| edges.map(|y| Vec2::new(x, y)));
    spread.chain(pairs).collect()
}
