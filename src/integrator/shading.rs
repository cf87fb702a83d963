//! What both shading stages share: the scene they read, a path's slots, its shadow ray.

use bevy_ecs::prelude::*;
use bevy_ecs::system::SystemParam;
use glam::Vec3;
use rayon::prelude::*;

use super::batch::{HitBatch, PathBatch, ShadowBatch};
use super::start_pass::FirstDrawsTable;
use crate::accel::Hit;
use crate::bsdf::Bsdf;
use crate::bsdf::frame::Frame;
use crate::light::LightTable;
use crate::material::MaterialTable;
use crate::material::bump::bumped_normal;
use crate::material::texture::TextureTable;
use crate::math::{self, offset_ray_origin};
use crate::sampling::{FirstDraws, PADDED_DRAWS, PathDraws, PathRng};
use crate::settings::{RenderSettings, Techniques};
use crate::shape::geometry::SceneGeometry;
use crate::shape::surface::SurfacePoint;
use crate::shared::Shared;
use crate::texture::ShadingPoint;

/// Chains of pass-through (null material) surfaces longer than this end the path.
pub const MAX_PASS_THROUGH: u32 = 64;

/// What a shading stage reads, as one system parameter.
#[derive(SystemParam)]
pub struct ShadingInputs<'w> {
    geometry: Res<'w, Shared<SceneGeometry>>,
    materials: Res<'w, MaterialTable>,
    textures: Option<Res<'w, TextureTable>>,
    lights: Res<'w, Shared<LightTable>>,
    settings: Res<'w, RenderSettings>,
    techniques: Res<'w, Techniques>,
    hits: Res<'w, HitBatch>,
    first_draws: Res<'w, FirstDrawsTable>,
}

impl ShadingInputs<'_> {
    pub fn scene(&self) -> Scene<'_> {
        Scene {
            geometry: &self.geometry,
            materials: &self.materials,
            textures: self.textures.as_deref(),
            lights: &self.lights,
            max_depth: self.settings.max_depth,
            hide_emitters: self.settings.hide_emitters,
            rr_depth: self.techniques.rr_depth,
        }
    }

    pub fn hits(&self) -> &[Option<Hit>] {
        &self.hits.hit
    }

    fn first_draws(&self) -> &FirstDrawsTable {
        &self.first_draws
    }

    /// How many of a path's first draws the chunk's first bounce computed
    /// (`FirstDrawsTable::draws`): a stage's paths may read no more
    /// ([`PathColumns::slots_reading`]).
    pub fn draws_ahead(&self) -> u32 {
        self.first_draws.draws
    }
}

/// The read-only scene a shading stage sees.
pub struct Scene<'a> {
    pub geometry: &'a SceneGeometry,
    pub materials: &'a MaterialTable,
    pub textures: Option<&'a TextureTable>,
    pub lights: &'a LightTable,
    pub max_depth: u32,
    /// See `RenderSettings::hide_emitters`.
    pub hide_emitters: bool,
    /// Bounces before Russian roulette may end a path.
    pub rr_depth: u32,
}

impl Scene<'_> {
    /// The BSDF of the surface's material there (`None` for `null`: the ray passes through);
    /// a draw of the path's `rng` picks the side of each mix (at a material that is the same
    /// everywhere, and so has no mix, the draw is counted but not made: about a hash a vertex).
    /// A bump map on the way bends the surface's shading normal (the one hook for bump
    /// mapping). A material's BSDF that is the same everywhere is lent from the table: no
    /// shading point to fill, no copy; any other is built into `built` and lent from there (a
    /// `Cow` in its place copied its 120 bytes, most of them unset, at every vertex). Inlined:
    /// out of line (as rustc's partition into codegen units once left it) it took 3 % more of
    /// the Cornell box's instructions, and the hint `#[inline]` did not bring it back.
    #[inline(always)]
    pub fn bsdf_at<'s, const AHEAD: u32>(
        &'s self,
        surface: &mut SurfacePoint,
        rng: &mut PathDraws<AHEAD>,
        built: &'s mut Option<Bsdf>,
    ) -> Option<&'s Bsdf> {
        if let Some(bsdf) = self.materials.fixed_bsdf(surface.material) {
            rng.skip();
            return Some(bsdf);
        }
        let choice = rng.next_f32();
        let mut point = ShadingPoint {
            p: surface.position,
            uv: surface.uv,
            n: surface.shading_normal,
            object: surface.material,
        };
        let bsdf = self.materials.bsdf_at(
            surface.material,
            &mut point,
            self.textures,
            choice,
            |map, point| {
                let (dpdu, dpdv) = self.geometry.uv_derivatives(surface.prim, point.p);
                let height = |at: &ShadingPoint| {
                    self.textures
                        .map_or(0.0, |table| table.lookup_float(map.height, at))
                };
                point.n = bumped_normal(point, dpdu, dpdv, map.sample_distance, height);
            },
        );
        surface.shading_normal = point.n;
        *built = bsdf;
        built.as_ref()
    }

    /// The BSDF's local frame at the surface: around the shading normal, its x axis along dp/du
    /// where the roughness is anisotropic (Mitsuba's convention), arbitrary otherwise.
    #[inline]
    pub fn shading_frame(&self, surface: &SurfacePoint, bsdf: &Bsdf) -> Frame {
        if bsdf.is_anisotropic() {
            let (dpdu, _) = self.geometry.uv_derivatives(surface.prim, surface.position);
            Frame::from_z_and_tangent(surface.shading_normal, dpdu)
        } else {
            Frame::from_z(surface.shading_normal)
        }
    }
}

/// Declares once the per-path fields the shading stages read and write (each a column of
/// [`PathBatch`] of the same name and type): [`PathSlots`] (one path's), [`PathColumns`] (a
/// block's) and the functions that name every field, from taking the batch's columns and
/// cutting them into blocks to picking one path's slots, are derived from the list. The path's
/// random stream is not in it: its two columns, the batch's `rng` and the first draws computed
/// for the chunk, make one [`PathDraws`] per path.
macro_rules! path_columns {
    ($($field:ident: $ty:ty,)*) => {
        /// One path's slots in the batch, its stream reading the first `AHEAD` of the draws
        /// computed ahead (see [`PathDraws`]).
        pub struct PathSlots<'a, const AHEAD: u32 = PADDED_DRAWS> {
            $(pub $field: &'a mut $ty,)*
            pub rng: PathDraws<'a, AHEAD>,
        }

        /// The block's path fields, one slice each, all of one length: the invariant that lets
        /// [`PathColumns::slots`] check one index against one length. Only this module builds
        /// the struct ([`PathColumns::par_blocks`] cuts every column into blocks of one length,
        /// and [`PathColumns::reborrow`] keeps the slices whole).
        pub struct PathColumns<'a> {
            $($field: &'a mut [$ty],)*
            rng: &'a mut [PathRng],
            /// The padded draws computed for the paths in these slots at the chunk's first bounce.
            first_draws: &'a [FirstDraws],
        }

        impl<'a> PathColumns<'a> {
            /// The batch's live-or-finished paths in blocks of `size` consecutive ones, in
            /// parallel: each block's hits and columns, with their first draws (the chunk's
            /// table, slot for slot). Every column is cut to the batch's length and then into
            /// blocks of one size, so a block's columns have one length.
            fn par_blocks(
                hits: &'a [Option<Hit>],
                first_draws: &'a FirstDrawsTable,
                batch: &'a mut PathBatch,
                size: usize,
            ) -> impl IndexedParallelIterator<Item = (&'a [Option<Hit>], Self)> {
                let n = batch.len;
                (
                    hits[..n].par_chunks(size),
                    $(batch.$field[..n].par_chunks_mut(size),)*
                    batch.rng[..n].par_chunks_mut(size),
                    first_draws.rows[..n].par_chunks(size),
                )
                    .into_par_iter()
                    .map(|(hits, $($field,)* rng, first_draws)| {
                        (hits, PathColumns { $($field,)* rng, first_draws })
                    })
            }
        }

        impl PathColumns<'_> {
            /// The columns again, reborrowed whole (so of one length still).
            #[inline(always)]
            pub fn reborrow(&mut self) -> PathColumns<'_> {
                PathColumns {
                    $($field: self.$field,)*
                    rng: self.rng,
                    first_draws: self.first_draws,
                }
            }

            /// Path `i`'s slots, after one bounds check (not one per column, which the compiler
            /// could not merge where the columns' lengths come from memory: 22 instructions a
            /// path in the queues' write-back and the block's loop). Always inlined: a call per
            /// path cost about 70 instructions, most of them moving the references. The check's
            /// message names no numbers: formatting `i` and `n` had the loops store both to the
            /// stack for every path, for the panic's arguments.
            #[inline(always)]
            pub fn slots(&mut self, i: usize) -> PathSlots<'_> {
                self.slots_reading::<PADDED_DRAWS>(i)
            }

            /// [`PathColumns::slots`] for a stage whose paths read the first `AHEAD` of the
            /// draws computed ahead: no more than the table holds, which the stage checks once
            /// ([`ShadingInputs::draws_ahead`]) rather than here, path by path.
            #[inline(always)]
            pub fn slots_reading<const AHEAD: u32>(&mut self, i: usize) -> PathSlots<'_, AHEAD> {
                let n = self.len();
                assert!(i < n, "a path's slot is within its block");
                debug_assert!(
                    [$(self.$field.len(),)* self.rng.len(), self.first_draws.len()]
                        .iter()
                        .all(|&len| len == n)
                );
                // SAFETY: every column has the length `n` (the invariant of `PathColumns`),
                // and `i < n`.
                unsafe {
                    PathSlots {
                        $($field: self.$field.get_unchecked_mut(i),)*
                        rng: PathDraws::new(
                            self.rng.get_unchecked_mut(i),
                            self.first_draws.get_unchecked(i),
                        ),
                    }
                }
            }
        }
    };
}

path_columns! {
    origin: Vec3,
    direction: Vec3,
    vertex: Vec3,
    throughput: Vec3,
    radiance: Vec3,
    depth: u32,
    pass_through: u32,
    scatter_pdf: f32,
    alive: bool,
}

impl<const AHEAD: u32> PathSlots<'_, AHEAD> {
    /// Adds `light` to the path's radiance; a non-finite value (a bug, never a feature of the
    /// scene) is dropped rather than let through to the film. Always inline: left to the
    /// compiler, a change elsewhere in the crate (stop 42's shadow-ray packing) once left it
    /// out of line in `shade_vertex`, a call for every radiance a path adds.
    #[inline(always)]
    pub fn add_radiance(&mut self, light: Vec3) {
        if math::is_finite_vec3(light) {
            *self.radiance += light;
        }
    }

    /// Continues the ray straight through a null-material surface; the last scattering vertex
    /// stays where it was.
    pub fn pass_through(&mut self, surface: &SurfacePoint) {
        *self.origin =
            offset_ray_origin(surface.position, surface.geometric_normal, *self.direction);
        *self.pass_through += 1;
        if *self.pass_through > MAX_PASS_THROUGH {
            *self.alive = false;
        }
    }

    /// Follows `direction` from `surface` with the throughput scaled by `weight`.
    #[inline]
    pub fn scatter(&mut self, surface: &SurfacePoint, direction: Vec3, weight: Vec3) {
        let origin = offset_ray_origin(surface.position, surface.geometric_normal, direction);
        self.continue_from(
            surface.position,
            origin,
            direction,
            *self.throughput * weight,
        );
    }

    /// The path's next segment: the ray (`origin`, `direction`) leaving the scattering vertex
    /// `vertex`, with the path's new `throughput`, one bounce deeper; a path whose throughput
    /// is zero or not finite ends. The one place these fields are written after a bounce.
    #[inline(always)]
    pub fn continue_from(&mut self, vertex: Vec3, origin: Vec3, direction: Vec3, throughput: Vec3) {
        let carries = math::is_finite_vec3(throughput) && throughput != Vec3::ZERO;
        self.continue_carrying(vertex, origin, direction, throughput, carries);
    }

    /// [`PathSlots::continue_from`] with its test of the throughput done by the caller:
    /// `carries`, the throughput finite and not zero (the lanes test eight at once).
    #[inline(always)]
    pub fn continue_carrying(
        &mut self,
        vertex: Vec3,
        origin: Vec3,
        direction: Vec3,
        throughput: Vec3,
        carries: bool,
    ) {
        *self.throughput = throughput;
        *self.origin = origin;
        *self.direction = direction;
        *self.vertex = vertex;
        *self.depth += 1;
        if !carries {
            *self.alive = false;
        }
    }
}

/// One path's shadow-ray slots.
pub struct ShadowSlots<'a> {
    origin: &'a mut [Vec3],
    direction: &'a mut [Vec3],
    t_max: &'a mut [f32],
    contribution: &'a mut [Vec3],
}

impl ShadowSlots<'_> {
    /// Puts `ray` in slot `slot` (slots left alone stay empty).
    pub fn emit(&mut self, slot: usize, ray: ShadowRay) {
        self.origin[slot] = ray.origin;
        self.direction[slot] = ray.direction;
        self.t_max[slot] = ray.t_max;
        self.contribution[slot] = ray.contribution;
    }
}

/// Paths per task of a shading stage. Tasks are blocks of consecutive paths, each shaded by a
/// plain loop over its slices: zipping the eleven path fields and four shadow fields path by
/// path through rayon cost more per path than a diffuse vertex's BSDF sample.
const SHADE_BLOCK: usize = 256;

/// One block of consecutive live-or-finished paths: their hits, their slots in the batch and
/// their shadow-ray slots, every field resliced to the block's length (the compiler then knows
/// each index is in bounds and drops the checks).
pub struct PathBlock<'a> {
    pub hits: &'a [Option<Hit>],
    pub paths: PathColumns<'a>,
    pub shadows: ShadowColumns<'a>,
}

/// The block's shadow-ray fields, `rays_per_path` slots per path.
pub struct ShadowColumns<'a> {
    origin: &'a mut [Vec3],
    direction: &'a mut [Vec3],
    t_max: &'a mut [f32],
    contribution: &'a mut [Vec3],
    rays_per_path: usize,
}

impl PathBlock<'_> {
    pub fn is_alive(&self, i: usize) -> bool {
        self.paths.alive[i]
    }

    /// The block again, for a call (a queue's flush) to take by reference in place of the
    /// block itself: as the block's own address then never leaves its loop, the compiler keeps
    /// its slices' lengths in registers and drops the loop's per-column bounds checks, which a
    /// callee that could reassign the block's slices would force it to reload and redo.
    #[inline(always)]
    pub fn reborrow(&mut self) -> PathBlock<'_> {
        PathBlock {
            hits: self.hits,
            paths: self.paths.reborrow(),
            shadows: self.shadows.cut_to_one_length(),
        }
    }
}

impl PathColumns<'_> {
    /// The columns' one length (see [`PathColumns`]).
    #[inline(always)]
    fn len(&self) -> usize {
        self.alive.len()
    }
}

impl ShadowColumns<'_> {
    /// The columns, each cut to the same length (a check per column, once): the compiler then
    /// knows an index in bounds of one column is in bounds of all, and checks it once, not once
    /// per column.
    #[inline(always)]
    pub fn cut_to_one_length(&mut self) -> ShadowColumns<'_> {
        let n = self.t_max.len();
        ShadowColumns {
            origin: &mut self.origin[..n],
            direction: &mut self.direction[..n],
            t_max: &mut self.t_max[..n],
            contribution: &mut self.contribution[..n],
            rays_per_path: self.rays_per_path,
        }
    }

    /// Path `i`'s (emptied) shadow-ray slots.
    #[inline(always)]
    pub fn slots(&mut self, i: usize) -> ShadowSlots<'_> {
        let k = self.rays_per_path;
        let slots = i * k..(i + 1) * k;
        ShadowSlots {
            origin: &mut self.origin[slots.clone()],
            direction: &mut self.direction[slots.clone()],
            t_max: &mut self.t_max[slots.clone()],
            contribution: &mut self.contribution[slots],
        }
    }

    /// Puts `ray` in path `i`'s first shadow-ray slot: [`ShadowSlots::emit`] without forming
    /// the path's slices, for the paths that have a ray (no slice is formed for the others).
    #[inline(always)]
    pub fn emit_first(&mut self, i: usize, ray: ShadowRay) {
        let slot = i * self.rays_per_path;
        self.origin[slot] = ray.origin;
        self.direction[slot] = ray.direction;
        self.t_max[slot] = ray.t_max;
        self.contribution[slot] = ray.contribution;
    }
}

/// Runs `shade` on the blocks of [`SHADE_BLOCK`] consecutive paths, in parallel; each block
/// holds live and finished paths (see [`PathBlock::is_alive`]) and its emptied shadow slots.
/// Counts the shadow rays made into [`ShadowBatch::rays`], each block its own while they are in
/// the cache (rather than a serial pass over all the slots after the stage).
pub fn shade_live_blocks(
    inputs: &ShadingInputs,
    batch: &mut PathBatch,
    shadows: &mut ShadowBatch,
    shade: impl Fn(PathBlock) + Sync,
) {
    let (hits, first_draws) = (inputs.hits(), inputs.first_draws());
    let n = batch.len;
    shadows.resize(n);
    let k = shadows.rays_per_path;
    let slots = shadows.slots;
    let shadow_slots = (
        shadows.origin[..slots].par_chunks_mut(SHADE_BLOCK * k),
        shadows.direction[..slots].par_chunks_mut(SHADE_BLOCK * k),
        shadows.t_max[..slots].par_chunks_mut(SHADE_BLOCK * k),
        shadows.contribution[..slots].par_chunks_mut(SHADE_BLOCK * k),
    );
    shadows.rays = PathColumns::par_blocks(hits, first_draws, batch, SHADE_BLOCK)
        .zip(shadow_slots.into_par_iter())
        .map(
            |(
                (hits, paths),
                (shadow_origin, shadow_direction, shadow_t_max, shadow_contribution),
            )| {
                let m = hits.len();
                // Emptied here, by the block's task, rather than all at once before the stage:
                // the slots still hold the last bounce's rays (see `ShadowBatch::resize`).
                shadow_t_max[..m * k].fill(0.0);
                shade(PathBlock {
                    hits,
                    paths,
                    shadows: ShadowColumns {
                        origin: &mut shadow_origin[..m * k],
                        direction: &mut shadow_direction[..m * k],
                        t_max: &mut shadow_t_max[..m * k],
                        contribution: &mut shadow_contribution[..m * k],
                        rays_per_path: k,
                    },
                });
                shadow_t_max[..m * k].iter().filter(|t| **t > 0.0).count()
            },
        )
        .sum();
}

/// A shadow ray to test and the radiance it carries if unoccluded.
#[derive(Clone, Copy, Debug)]
pub struct ShadowRay {
    pub origin: Vec3,
    pub direction: Vec3,
    pub t_max: f32,
    pub contribution: Vec3,
}

impl ShadowRay {
    /// A ray from `surface` towards a light `distance` away along `wi`, stopping just short of it.
    pub fn towards(surface: &SurfacePoint, wi: Vec3, distance: f32, contribution: Vec3) -> Self {
        let origin = offset_ray_origin(surface.position, surface.geometric_normal, wi);
        // Stop short of the light's own surface (an emitter must not shadow itself).
        let t_max = distance * (1.0 - 1e-3);
        Self {
            origin,
            direction: wi,
            t_max,
            contribution,
        }
    }
}

/// Turns the surface's normals to face `wo` when the BSDF only reflects, so one-sided meshes
/// shade the same from both sides; a dielectric keeps them, as their side tells in from out.
/// A `one_sided` material keeps them too, and scatters nothing when seen from the back: false
/// then. Mitsuba's reflecting BSDFs are zero unless cos theta > 0 in the shading frame on both
/// sides (`diffuse.cpp`: `active &= cos_theta_i > 0.f && cos_theta_o > 0.f`).
pub fn face_forward(surface: &mut SurfacePoint, bsdf: &Bsdf, wo: Vec3, one_sided: bool) -> bool {
    if one_sided {
        return surface.shading_normal.dot(wo) > 0.0;
    }
    if !bsdf.has_inside() && surface.geometric_normal.dot(wo) < 0.0 {
        surface.geometric_normal = -surface.geometric_normal;
        surface.shading_normal = -surface.shading_normal;
    }
    true
}
