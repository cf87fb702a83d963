//! The wavefront batches: structure-of-arrays state of the live paths of one chunk, allocated
//! once per render and reused by every chunk and bounce. Slot `i` of each array belongs to path
//! `i`; live paths are kept contiguous in `0..len` by [`PathBatch::retire`].

use bevy_ecs::prelude::Resource;
use glam::{Vec2, Vec3};

use crate::accel::Hit;
use crate::film::FilmSample;
use crate::sampling::PathRng;

/// Declares the per-path fields once: those kept in place (`kept`) and those compaction moves to
/// the front (`moved`); the batch, its spare columns (the target of compaction), `resize` and the
/// compaction's gather are all derived from these lists.
macro_rules! path_batch {
    (
        kept { $($(#[$kept_doc:meta])* $kept:ident: $kept_ty:ty = $kept_init:expr,)* }
        moved { $($(#[$doc:meta])* $field:ident: $ty:ty = $init:expr,)* }
    ) => {
        /// One path per slot.
        #[derive(Resource, Default)]
        pub struct PathBatch {
            /// Live paths are `0..len`.
            pub len: usize,
            $($(#[$kept_doc])* pub $kept: Vec<$kept_ty>,)*
            $($(#[$doc])* pub $field: Vec<$ty>,)*
            /// Where compaction gathers the live paths to, swapped in afterwards.
            spare: SpareColumns,
            partition: Partition,
            /// The film samples of the chunk's finished paths so far.
            finished: FinishedSamples,
        }

        #[derive(Default)]
        struct SpareColumns {
            $($field: Vec<$ty>,)*
        }

        impl PathBatch {
            /// Sizes the batch for a chunk of `count` paths, reusing the allocations (the spare
            /// columns too, so that compaction allocates nothing), and numbers each slot's
            /// camera path; the chunk's first stage then sets every other field of every slot.
            /// The columns keep that length while `len` shrinks, so that the chunks of a pass
            /// size nothing anew.
            pub fn resize(&mut self, count: usize) {
                self.len = count;
                $(resize(&mut self.$kept, count, $kept_init);)*
                $(
                    resize(&mut self.$field, count, $init);
                    resize(&mut self.spare.$field, count, $init);
                )*
                for (slot, path) in self.camera_path.iter_mut().enumerate() {
                    *path = slot as u32;
                }
            }

            /// Partitions the first `len` slots into live and finished paths: the live ones move
            /// to the front in their order, the finished ones' film samples go to `finished`
            /// from `first_finished` on, in slot order (see [`Partition::split`]). Returns how
            /// many are live.
            fn split_live(&mut self, finished: &mut Vec<FilmSample>, first_finished: usize) -> usize {
                let n = self.len;
                let sources = LiveSources {
                    $($field: &self.$field[..n],)*
                };
                // Slices moved into the closure, not references to the vectors: read through
                // the closure's shared reference, their pointers and lengths then stay in
                // registers across the samples' writes rather than being reloaded at each.
                let (pixel, film_position) = (&self.pixel[..], &self.film_position[..]);
                let sample = move |slot: usize| {
                    let path = sources.camera_path[slot] as usize;
                    FilmSample {
                        pixel: pixel[path],
                        position: film_position[path],
                        radiance: sources.radiance[slot],
                    }
                };
                let live = self.partition.split(
                    &self.alive[..n],
                    (finished, first_finished),
                    &sample,
                    |live| Gather {
                        sources,
                        targets: LiveTargets {
                            $($field: &mut self.spare.$field[..live],)*
                        },
                    },
                );
                if live < n {
                    $(std::mem::swap(&mut self.$field, &mut self.spare.$field);)*
                    // Every path moved to the front lives.
                    self.alive[..live].fill(true);
                }
                self.len = live;
                live
            }
        }

        /// The columns the live paths are read from.
        #[derive(Clone, Copy)]
        struct LiveSources<'a> {
            $($field: &'a [$ty],)*
        }

        /// The spare columns' slots a run of partition blocks moves its live paths to.
        struct LiveTargets<'a> {
            $($field: &'a mut [$ty],)*
        }

        /// A run of partition blocks' live paths: where they are read from and moved to.
        struct Gather<'a> {
            sources: LiveSources<'a>,
            targets: LiveTargets<'a>,
        }

        impl GatherLive for Gather<'_> {
            fn split_at(self, mid: usize) -> (Self, Self) {
                $(let $field = self.targets.$field.split_at_mut(mid);)*
                (
                    Gather {
                        sources: self.sources,
                        targets: LiveTargets { $($field: $field.0,)* },
                    },
                    Gather {
                        sources: self.sources,
                        targets: LiveTargets { $($field: $field.1,)* },
                    },
                )
            }

            /// Run by run, each run in groups of [`GROUP`] slots, all the group's fields
            /// together: a group of a column is one or a few vector moves, where slot by slot
            /// each of its lanes was a load and a store. A run's last group may reach past its
            /// end, into the next runs' targets, which are written after it, in order; where it
            /// would leave the task's targets (at its last run) or the columns, the run's tail
            /// goes slot by slot. The columns are resliced to their common lengths first, so
            /// that one comparison per group stands for every column's bounds checks.
            fn gather(self, runs: &[Run]) {
                let (n, live) = (self.sources.camera_path.len(), self.targets.camera_path.len());
                $(let $field = (&self.sources.$field[..n], &mut self.targets.$field[..live]);)*
                let mut target = 0;
                for run in runs {
                    let (mut from, mut to) = (run.from as usize, target);
                    let (from_end, to_end) = (from + run.len as usize, target + run.len as usize);
                    assert!(from_end <= n && to_end <= live, "the run is within the columns");
                    while from < from_end && to + GROUP <= live && from + GROUP <= n {
                        $(copy_group($field.0, from, $field.1, to);)*
                        (from, to) = (from + GROUP, to + GROUP);
                    }
                    for (to, from) in (to..to_end).zip(from..from_end) {
                        $($field.1[to] = $field.0[from].clone();)*
                    }
                    target = to_end;
                }
            }
        }
    };
}

path_batch! {
    kept {
        /// The pixel of each camera path (the chunk's slots as the chunk starts, see
        /// `camera_path`): only its film sample needs it, at the path's end, so it is not moved.
        pixel: u32 = 0,
        /// Raster position of each camera path's sample (pixel centre plus the filter offset),
        /// indexed as `pixel`.
        film_position: Vec2 = Vec2::ZERO,
        /// Cleared by a stage when the path ends; `retire` removes it (and sets it again for
        /// the paths it moves to the front, all live, rather than moving it).
        alive: bool = true,
    }
    moved {
        /// The path's camera path: its slot when the chunk started, where its `pixel` and
        /// `film_position` stay.
        camera_path: u32 = 0,
        /// The ray the path follows next (camera space between ray generation and the lens stages).
        origin: Vec3 = Vec3::ZERO,
        direction: Vec3 = Vec3::Z,
        /// The last scattering vertex, where the current ray's direction was sampled (a pass through
        /// a null surface moves `origin`, not this): the point light sampling would have sampled
        /// from, for the MIS weight of an emitter the ray hits. Set by the first scattering.
        vertex: Vec3 = Vec3::ZERO,
        /// Product of f |cos| / pdf along the path.
        throughput: Vec3 = Vec3::ONE,
        /// Radiance gathered so far.
        radiance: Vec3 = Vec3::ZERO,
        /// Bounces taken.
        depth: u32 = 0,
        /// Surfaces passed through without scattering (null material), to bound such chains.
        pass_through: u32 = 0,
        rng: PathRng = PathRng::new(0, 0, 0),
        /// Solid-angle pdf of the BSDF sample that made the current ray; 0 for the camera ray and delta
        /// lobes (their emitter hits take no MIS weight).
        scatter_pdf: f32 = 0.0,
    }
}

impl PathBatch {
    /// Removes the finished paths and moves the live ones to the front in their order; keeps
    /// the finished paths' film samples (see [`PathBatch::take_finished`]) after those of the
    /// chunk's earlier bounces, in slot order, so that they do not depend on scheduling.
    /// Returns how many live. The partition moves each block's live paths as it finds them, so
    /// the slots are read once, while in the cache.
    pub fn retire(&mut self) -> usize {
        let n = self.len;
        let mut finished = std::mem::take(&mut self.finished.samples);
        let live = self.split_live(&mut finished, self.finished.len);
        self.finished.samples = finished;
        self.finished.len += n - live;
        live
    }

    /// Swaps the samples kept since the last call (a chunk's, in (bounce, slot) order) into
    /// `into`, and `into`'s allocation, emptied, back into the batch.
    pub fn take_finished(&mut self, into: &mut FinishedSamples) {
        std::mem::swap(&mut self.finished, into);
        self.finished.clear();
    }
}

/// The film samples of a chunk's finished paths, bounce after bounce, each bounce's in slot
/// order.
#[derive(Default)]
pub struct FinishedSamples {
    /// The samples are the first `len` (the vector only grows, to the chunk's size; see
    /// [`Partition::split`]).
    samples: Vec<FilmSample>,
    len: usize,
}

impl FinishedSamples {
    pub fn samples(&self) -> &[FilmSample] {
        &self.samples[..self.len]
    }

    pub fn clear(&mut self) {
        self.len = 0;
    }
}

/// A stable partition of the slots into live and finished: each block of slots counts its live
/// paths, a prefix sum over the counts gives every block its place among the live and among the
/// finished, and the blocks then move, in parallel, the live paths and write the finished
/// paths' film samples there.
#[derive(Default)]
struct Partition {
    /// Live counts per block.
    counts: Vec<usize>,
    /// The runs of live slots (scratch: at most one a live slot, in order).
    runs: Vec<Run>,
}

/// A run of consecutive live slots: its first slot and length. The runs of a task move to
/// consecutive targets.
#[derive(Clone, Copy, Default)]
struct Run {
    from: u32,
    len: u32,
}

/// Slots a run is copied by at a time (see `GatherLive::gather`).
const GROUP: usize = 8;

/// Copies `GROUP` slots of a column from `from` on to `to` on.
#[inline(always)]
fn copy_group<T: Clone>(source: &[T], from: usize, target: &mut [T], to: usize) {
    target[to..to + GROUP].clone_from_slice(&source[from..from + GROUP]);
}

/// Slots per block of the partition: small enough to share among threads, large enough that
/// the per-block bookkeeping is negligible.
const PARTITION_BLOCK: usize = 4096;

impl Partition {
    /// Partitions `alive`'s slots: the finished ones' film samples (`sample(slot)`) to
    /// `finished` from index `first_finished` on, in slot order, and the live ones gathered, in
    /// order, by the target `gather_to(live)` makes for the first `live` slots of the spare
    /// columns (nothing is moved when all are live). Returns how many are live.
    fn split<G: GatherLive>(
        &mut self,
        alive: &[bool],
        (finished, first_finished): (&mut Vec<FilmSample>, usize),
        sample: &(impl Fn(usize) -> FilmSample + Sync),
        gather_to: impl FnOnce(usize) -> G,
    ) -> usize {
        // Counted on this thread: a chunk's flags are a few kilobytes, counted (vectorised) in
        // about a microsecond, less than a fork-join costs, which would also be one more point
        // per bounce where the other threads wait.
        self.counts.clear();
        self.counts.extend(
            alive
                .chunks(PARTITION_BLOCK)
                .map(|block| block.iter().filter(|a| **a).count()),
        );
        let live = self.counts.iter().sum();
        if live == alive.len() {
            return live;
        }
        // Both only grow (to the chunk's size, over the first chunk), and only `runs`' first
        // `live` and `finished`'s first `finished_end` entries are used: setting their lengths
        // anew at every bounce would write each entry on one thread before the parallel writes
        // below.
        grow(&mut self.runs, live, Run::default());
        let placeholder = FilmSample {
            pixel: 0,
            position: Vec2::ZERO,
            radiance: Vec3::ZERO,
        };
        let finished_end = first_finished + alive.len() - live;
        grow(finished, finished_end, placeholder);
        let slots = Slots {
            alive,
            counts: &self.counts,
            first: 0,
        };
        slots.write(
            &mut self.runs[..live],
            &mut finished[first_finished..finished_end],
            sample,
            gather_to(live),
        );
        live
    }
}

/// A run of whole partition blocks of the slots: their live flags, the live count of each
/// block, and the first slot's number.
struct Slots<'a> {
    alive: &'a [bool],
    counts: &'a [usize],
    first: usize,
}

impl Slots<'_> {
    /// Writes the runs of live slots to `runs` (scratch, one entry per live slot) and has
    /// `target` gather those paths; writes the film samples of the others to `finished`; all in
    /// order. Halves the blocks between two tasks until one is left.
    fn write(
        self,
        runs: &mut [Run],
        finished: &mut [FilmSample],
        sample: &(impl Fn(usize) -> FilmSample + Sync),
        target: impl GatherLive,
    ) {
        if self.counts.len() <= 1 {
            let (alive, m) = (self.alive, self.alive.len());
            let (mut slot, mut r, mut f) = (0, 0, 0);
            while slot < m {
                let start = first_flag(alive, slot, true);
                for dead in slot..start {
                    finished[f] = sample(self.first + dead);
                    f += 1;
                }
                if start == m {
                    break;
                }
                let end = first_flag(alive, start, false);
                runs[r] = Run {
                    from: (self.first + start) as u32,
                    len: (end - start) as u32,
                };
                (slot, r) = (end, r + 1);
            }
            target.gather(&runs[..r]);
            return;
        }
        let half = self.counts.len() / 2;
        let split = half * PARTITION_BLOCK;
        let live_left: usize = self.counts[..half].iter().sum();
        let (runs_left, runs_right) = runs.split_at_mut(live_left);
        let (finished_left, finished_right) = finished.split_at_mut(split - live_left);
        let (target_left, target_right) = target.split_at(live_left);
        let left = Slots {
            alive: &self.alive[..split],
            counts: &self.counts[..half],
            first: self.first,
        };
        let right = Slots {
            alive: &self.alive[split..],
            counts: &self.counts[half..],
            first: self.first + split,
        };
        rayon::join(
            || left.write(runs_left, finished_left, sample, target_left),
            || right.write(runs_right, finished_right, sample, target_right),
        );
    }
}

/// The first slot from `from` on whose flag is `value` (`alive.len()` if none), eight flags at
/// a time as the bytes of a word (a `bool` is one byte, 0 or 1): the lowest byte that differs
/// from the other value's is the word's lowest set bit over 8.
#[inline(always)]
fn first_flag(alive: &[bool], from: usize, value: bool) -> usize {
    let other = if value { 0 } else { u64::from_le_bytes([1; 8]) };
    let mut i = from;
    while let Some(flags) = alive.get(i..i + 8) {
        let bytes: [bool; 8] = flags.try_into().expect("eight flags");
        let differing = u64::from_le_bytes(bytes.map(u8::from)) ^ other;
        if differing != 0 {
            return i + differing.trailing_zeros() as usize / 8;
        }
        i += 8;
    }
    (alive[i..].iter().position(|&a| a == value)).map_or(alive.len(), |k| i + k)
}

/// Where a run of partition blocks moves its live paths (the spare columns' slots for them),
/// split along with the blocks.
trait GatherLive: Send + Sized {
    /// The targets of the first `mid` live paths and of the rest.
    fn split_at(self, mid: usize) -> (Self, Self);
    /// Moves the paths of `runs`, in order, to the target's slots.
    fn gather(self, runs: &[Run]);
}

/// Closest hits of the path rays, slot for slot: the first `PathBatch::len` slots are this
/// bounce's.
#[derive(Resource, Default)]
pub struct HitBatch {
    pub hit: Vec<Option<Hit>>,
    /// Ray extents for the trace: infinite for a live path, 0 for one that ended.
    pub t_max: Vec<f32>,
}

impl HitBatch {
    /// Lengthens the columns to at least `paths` slots, never shortening them: the trace writes
    /// the first `paths` of each, and a chunk's first bounce, longer than the last one before
    /// it, then refills nothing.
    pub fn grow(&mut self, paths: usize) {
        grow(&mut self.hit, paths, None);
        grow(&mut self.t_max, paths, 0.0);
    }
}

/// Shadow rays: `rays_per_path` slots for each path, path `i` owning
/// `i * rays_per_path .. (i + 1) * rays_per_path`. A slot with a `t_max` of 0 is empty.
#[derive(Resource, Default)]
pub struct ShadowBatch {
    pub rays_per_path: usize,
    /// The slots of this bounce's paths, at the front of each column; the columns only grow,
    /// so past these they hold an earlier bounce's rays.
    pub slots: usize,
    /// Slot `k` of every path holds the ray to light `k` (the ray caster's layout): the rays
    /// of neighbouring paths in one slot then run side by side to the same light, and are
    /// traced as packets. The path tracer's slot holds a ray to a light drawn at random.
    pub slot_per_light: bool,
    pub origin: Vec<Vec3>,
    pub direction: Vec<Vec3>,
    /// The last scattering vertex, where the current ray's direction was sampled (a pass through
    /// a null surface moves `origin`, not this): the point light sampling would have sampled
    /// from, for the MIS weight of an emitter the ray hits. Set by the first scattering.
    pub vertex: Vec<Vec3>,
    /// The ray is tested on (t_min, t_max); 0 marks an empty slot.
    pub t_max: Vec<f32>,
    /// Radiance the path gains when the ray is unoccluded.
    pub contribution: Vec<Vec3>,
    pub occluded: Vec<bool>,
    /// The slots holding a ray (t_max > 0), counted by the shading stage that fills them.
    pub rays: usize,
}

impl ShadowBatch {
    pub fn new(rays_per_path: usize, slot_per_light: bool) -> Self {
        Self {
            rays_per_path,
            slot_per_light,
            ..Default::default()
        }
    }

    /// Sizes the batch for `paths` paths, lengthening the columns where they are shorter and
    /// never shortening them (a chunk's first bounce, longer than the last one before it, then
    /// refills nothing). The slots keep what they held: the shading stage empties each block's
    /// (a `t_max` of 0) before filling them, and the trace writes every slot's `occluded`.
    pub fn resize(&mut self, paths: usize) {
        let count = paths * self.rays_per_path;
        grow(&mut self.origin, count, Vec3::ZERO);
        grow(&mut self.direction, count, Vec3::Z);
        grow(&mut self.contribution, count, Vec3::ZERO);
        grow(&mut self.occluded, count, false);
        grow(&mut self.t_max, count, 0.0);
        self.slots = count;
        self.rays = 0;
    }
}

/// Sets the length to `count`, reusing the allocation; new slots take `value`, old ones keep theirs.
fn resize<T: Clone>(values: &mut Vec<T>, count: usize, value: T) {
    values.truncate(count);
    values.resize(count, value);
}

/// Lengthens `values` to at least `count`, new slots taking `value`; never shortens it.
fn grow<T: Clone>(values: &mut Vec<T>, count: usize, value: T) {
    if values.len() < count {
        values.resize(count, value);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The pixel of the path in `slot`, kept with its camera path.
    fn pixel_at(batch: &PathBatch, slot: usize) -> u32 {
        batch.pixel[batch.camera_path[slot] as usize]
    }

    /// The pixels of the paths in the first `len` slots.
    fn pixels_at(batch: &PathBatch, len: usize) -> Vec<u32> {
        (0..len).map(|slot| pixel_at(batch, slot)).collect()
    }

    /// Three bounces, each finishing fewer paths than the one before, on 1 and 2 threads: the
    /// chunk's samples are kept in (bounce, slot) order until taken. The buffers keep their
    /// lengths from chunk to chunk: a second chunk's samples are its own only.
    #[test]
    fn retire_keeps_the_chunk_in_bounce_order() {
        let n = 3 * PARTITION_BLOCK;
        for threads in [1, 2] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let mut batch = PathBatch::default();
            let mut taken = FinishedSamples::default();
            for _chunk in 0..2 {
                batch.resize(n);
                for i in 0..n {
                    batch.pixel[i] = i as u32;
                    batch.alive[i] = i % 2 == 0;
                }
                let retire = |batch: &mut PathBatch| pool.install(|| batch.retire());
                let live = retire(&mut batch);
                // Of the live paths (even pixels), those whose pixel is a multiple of 6 finish.
                for slot in 0..live {
                    batch.alive[slot] = !pixel_at(&batch, slot).is_multiple_of(6);
                }
                let still_live = retire(&mut batch);
                assert_eq!(retire(&mut batch), still_live);
                let odd: Vec<u32> = (1..n as u32).step_by(2).collect();
                let sixes: Vec<u32> = (0..n as u32).step_by(6).collect();
                assert_eq!(still_live, live - sixes.len());
                batch.alive[..still_live].fill(false);
                let rest = pixels_at(&batch, still_live);
                assert_eq!(retire(&mut batch), 0);
                batch.take_finished(&mut taken);
                let pixels: Vec<u32> = taken.samples().iter().map(|s| s.pixel).collect();
                assert_eq!(pixels, [odd, sixes, rest].concat(), "{threads} threads");
            }
        }
    }

    #[test]
    fn first_flag_is_the_first_slot_with_the_value() {
        // Every pattern of 12 flags (a word and a tail, or a tail alone), from every start.
        const N: usize = 12;
        for pattern in 0u32..1 << N {
            let alive: Vec<bool> = (0..N).map(|k| pattern >> k & 1 == 1).collect();
            for from in 0..=N {
                for value in [false, true] {
                    let expected = (from..N).find(|&k| alive[k] == value).unwrap_or(N);
                    assert_eq!(
                        first_flag(&alive, from, value),
                        expected,
                        "{alive:?} {from}"
                    );
                }
            }
        }
    }

    /// Runs of live slots of every length from 1 to past two groups, apart by gaps of 1 to 3
    /// finished ones, then a block where all live: each run's groups that reach past its end
    /// are overwritten by the next runs, and the tasks' last runs end slot by slot.
    #[test]
    fn retire_moves_runs_of_every_length() {
        let n = 3 * PARTITION_BLOCK;
        let mut alive = vec![true; n];
        let (mut slot, mut len) = (0, 1);
        while slot < 2 * PARTITION_BLOCK {
            let gap = slot + len..slot + len + 1 + len % 3;
            alive[gap.clone()].fill(false);
            (slot, len) = (gap.end, len % (2 * GROUP + 3) + 1);
        }
        let expected: Vec<u32> = (0..n as u32).filter(|&i| alive[i as usize]).collect();
        for threads in [1, 2] {
            let mut batch = PathBatch::default();
            batch.resize(n);
            for i in 0..n {
                batch.pixel[i] = i as u32;
                batch.depth[i] = 7 * i as u32;
                batch.origin[i] = Vec3::new(i as f32, 1.0, -(i as f32));
            }
            batch.alive.copy_from_slice(&alive);
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let live = pool.install(|| batch.retire());
            assert_eq!(pixels_at(&batch, live), expected);
            for i in 0..live {
                let path = pixel_at(&batch, i);
                assert_eq!(batch.depth[i], 7 * path);
                assert_eq!(batch.origin[i], Vec3::new(path as f32, 1.0, -(path as f32)));
            }
        }
    }

    #[test]
    fn retire_keeps_live_paths_in_order_and_the_samples_of_the_rest() {
        // More than two partition blocks, with a pattern that differs between them.
        let n = 2 * PARTITION_BLOCK + 123;
        let mut batch = PathBatch::default();
        batch.resize(n);
        for i in 0..n {
            batch.pixel[i] = i as u32;
            batch.radiance[i] = Vec3::splat(i as f32);
            batch.depth[i] = 3 * i as u32;
            batch.alive[i] = i % 3 == 0 || (PARTITION_BLOCK..PARTITION_BLOCK + 50).contains(&i);
        }
        let expected_live: Vec<u32> = (0..n as u32).filter(|&i| batch.alive[i as usize]).collect();
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .unwrap();
        let live = pool.install(|| batch.retire());
        assert_eq!(live, expected_live.len());
        assert_eq!(batch.len, live);
        assert_eq!(pixels_at(&batch, live), expected_live);
        for i in 0..live {
            assert_eq!(batch.depth[i], 3 * pixel_at(&batch, i));
            assert_eq!(batch.radiance[i], Vec3::splat(pixel_at(&batch, i) as f32));
            assert!(batch.alive[i]);
        }
        batch.alive[..live].fill(false);
        let none_live = pool.install(|| batch.retire());
        let mut taken = FinishedSamples::default();
        batch.take_finished(&mut taken);
        let finished: Vec<(u32, Vec3)> = (taken.samples().iter())
            .map(|s| (s.pixel, s.radiance))
            .collect();
        assert_eq!(none_live, 0);
        let expected_finished: Vec<u32> = (0..n as u32)
            .filter(|i| !expected_live.contains(i))
            .chain(expected_live.iter().copied())
            .collect();
        assert_eq!(
            finished,
            expected_finished
                .iter()
                .map(|&i| (i, Vec3::splat(i as f32)))
                .collect::<Vec<_>>()
        );
    }
}
