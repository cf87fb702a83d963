//! What the user asked of this render: the scene file's settings with the command line's on top.

use std::time::Duration;

use bevy_ecs::prelude::Resource;

use crate::film::Reconstruction;
use crate::light::LightSelection;
use crate::sampling::SamplerKind;

/// The two integrators; each is a choice of shading stage over the same batches.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum IntegratorKind {
    /// Unbiased path tracing with next-event estimation and MIS.
    PathTracer,
    /// Whitted-style ray casting: direct light, Lambert + Phong, mirror and refraction.
    RayCaster,
}

#[derive(Resource, Clone, Debug)]
pub struct RenderSettings {
    pub width: u32,
    pub height: u32,
    pub samples_per_pixel: u32,
    /// Path vertices after the camera's: 1 is direct light only.
    pub max_depth: u32,
    /// A camera path that reaches an emitter (an area light or the environment) before it
    /// scatters contributes nothing (Mitsuba's `hide_emitters`).
    pub hide_emitters: bool,
    pub seed: u64,
    pub sampler: SamplerKind,
    pub integrator: IntegratorKind,
    /// Stop after the pass that crosses this wall-clock time.
    pub time_limit: Option<Duration>,
    /// Only these pixels (y * width + x, ascending) get paths, for `--crop` and `--pixel`; every
    /// pixel when `None`.
    pub pixels: Option<Vec<u32>>,
}

impl RenderSettings {
    pub fn pixel_count(&self) -> usize {
        self.width as usize * self.height as usize
    }

    /// Camera paths in one pass: one per rendered pixel.
    pub fn path_count(&self) -> usize {
        self.pixels.as_ref().map_or(self.pixel_count(), Vec::len)
    }
}

/// How the path tracer spends its samples; each default is the one measured best
/// (docs/error-per-second.md). A resource of its own, so a render without it gets the defaults.
#[derive(Resource, Clone, Copy, Debug)]
pub struct Techniques {
    pub light_selection: LightSelection,
    /// Bounces before Russian roulette may end a path.
    pub rr_depth: u32,
    pub film: Reconstruction,
    /// Rectangle lamps sampled by the solid angle they subtend rather than by area (off by
    /// default: on the measured scenes it cost more time than it saved error, README).
    pub solid_angle_rectangles: bool,
}

impl Default for Techniques {
    fn default() -> Self {
        Self {
            light_selection: LightSelection::default(),
            rr_depth: DEFAULT_RR_DEPTH,
            film: Reconstruction::default(),
            solid_angle_rectangles: false,
        }
    }
}

/// Mitsuba 3's default; see `Techniques::rr_depth`.
pub const DEFAULT_RR_DEPTH: u32 = 5;
