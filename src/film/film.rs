//! Per-pixel accumulation of radiance samples, by filter importance sampling or by splatting.

use bevy_ecs::prelude::Resource;

use glam::{DVec3, Vec2, Vec3, Vec3A, Vec4};
use rayon::prelude::*;

use super::PixelFilter;

/// How a sample becomes pixel values.
///
/// - `FilterImportance`: the film position is drawn around the pixel centre with density
///   proportional to the filter (`filter.rs`), and the sample counts for its own pixel only,
///   with weight 1: pixel = mean of its samples.
/// - `Splat`: the film position is uniform in the pixel, and the sample adds f(x - c_j) L and
///   f(x - c_j) to the weighted sum and weight sum of every pixel j whose filter covers it
///   (pbrt-v3 §7.8, Mitsuba 3's `ImageBlock`): pixel = sum f L / sum f. Each sample informs
///   several pixels, so neighbouring pixels share noise and a wide filter smooths more per
///   sample; the ratio is consistent, not unbiased.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Reconstruction {
    FilterImportance,
    #[default]
    Splat,
}

/// Widest footprint a splat covers on one axis (a filter radius up to 7.5 pixels).
const MAX_FOOTPRINT: usize = 16;
/// Entries of the tabulated filter over [0, r] on each axis, read with linear interpolation
/// (Mitsuba 3 tabulates its filters the same way): a splat then costs table reads, not the
/// filter's exponentials. 256, so that an entry's index is a `u8` (see `SplatFilter::value`).
const SPLAT_TABLE: usize = u8::MAX as usize + 1;

/// The filter's two axes, tabulated: f(d, 0) and f(0, d) for d in [0, r].
#[derive(Clone, Debug)]
struct SplatFilter {
    radius: Vec2,
    /// The radius as (rx, ry, rx, ry): the lanes of [`SplatFilter::footprints_with_avx2`]'s
    /// spans, loaded as one register.
    radii: Vec4,
    /// Per axis and entry i: the value at i / SPLAT_TABLE of the radius and the step to the
    /// next entry's, (f_i, f_(i+1) - f_i), side by side so that one 8-byte load reads both.
    /// Fixed-size, so that a `u8` index needs no bounds check.
    tables: [[[f32; 2]; SPLAT_TABLE]; 2],
}

impl SplatFilter {
    fn new(filter: &PixelFilter) -> Self {
        let radius = filter.radius();
        let table = |axis: usize| {
            let value = |i: usize| {
                let mut offset = Vec2::ZERO;
                offset[axis] = radius[axis] * i as f32 / SPLAT_TABLE as f32;
                filter.evaluate(offset)
            };
            std::array::from_fn(|i| [value(i), value(i + 1) - value(i)])
        };
        Self {
            radius,
            radii: Vec4::new(radius.x, radius.y, radius.x, radius.y),
            tables: [table(0), table(1)],
        }
    }

    /// The pixels along `axis` whose centres lie within the radius of `position` (on a film
    /// `size` pixels long), and the filter's value at each: one axis alone, the tests'
    /// reference for [`SplatFilter::footprints`].
    #[cfg(test)]
    fn footprint(&self, axis: usize, position: f32, size: u32) -> AxisFootprint {
        let (first, count) = footprint_span(position, self.radius[axis], size);
        let first_group = self.values(axis, group_offsets(position, first, 0));
        self.footprint_from(axis, position, (first, count), first_group)
    }

    /// Both axes' spans of a splat at `position` on a film of `size` pixels and the filter's
    /// values at the first four pixels of each, as `SplatFilter::footprint` gives them one axis
    /// at a time; with AVX2, both at once ([`SplatFilter::footprints_with_avx2`]).
    #[inline(always)]
    fn footprints(&self, position: &Vec2, size: (u32, u32), avx2: Option<Avx2>) -> Footprint {
        #[cfg(target_arch = "x86_64")]
        if let Some(avx2) = avx2 {
            return self.footprints_with_avx2(avx2, position, size);
        }
        let _ = avx2;
        let (first_x, count_x) = footprint_span(position.x, self.radius.x, size.0);
        let (first_y, count_y) = footprint_span(position.y, self.radius.y, size.1);
        Footprint {
            first: [first_x, first_y],
            count: [count_x, count_y],
            first_groups: [
                self.values(0, group_offsets(position.x, first_x, 0)),
                self.values(1, group_offsets(position.y, first_y, 0)),
            ],
        }
    }

    /// The footprint along `axis` of the pixels `first..first + count`, given the values of its
    /// first four (`first_group`): the other groups of four as needed.
    #[inline(always)]
    fn footprint_from(
        &self,
        axis: usize,
        position: f32,
        (first, count): (usize, usize),
        first_group: Vec4,
    ) -> AxisFootprint {
        // The first group always (a footprint of up to four pixels, the common case, takes no
        // loop; its values are unused when the footprint is empty), the rest as needed.
        let mut weights = [0.0; MAX_FOOTPRINT];
        weights[..4].copy_from_slice(&first_group.to_array());
        for (index, values) in weights.chunks_exact_mut(4).enumerate().skip(1) {
            if 4 * index >= count {
                break;
            }
            values.copy_from_slice(
                &self
                    .values(axis, group_offsets(position, first, index))
                    .to_array(),
            );
        }
        AxisFootprint {
            first,
            count,
            weights,
        }
    }

    /// The filter along `axis` at four `offsets` in pixels (symmetric; 0 beyond the radius),
    /// interpolated in the table: with x = |offset| / r * SPLAT_TABLE and i = floor(x),
    /// f = f_i + (f_(i+1) - f_i) (x - i). Four lanes at once, each lane's arithmetic that of
    /// one value alone (SSE2 has no fused multiply-add: the same roundings).
    #[inline(always)]
    fn values(&self, axis: usize, offsets: Vec4) -> Vec4 {
        let x = offsets.abs() / self.radius[axis] * SPLAT_TABLE as f32;
        // False for NaN as well.
        let inside = x.cmplt(Vec4::splat(SPLAT_TABLE as f32));
        // i = floor(x) = trunc(x) for x >= 0, and the index's low byte, from one packed
        // truncation to integers (`truncate_lanes`); outside, the low byte is still a valid
        // index (its lane is replaced by 0).
        let (whole, index) = truncate_lanes(x);
        let t = x - whole;
        let table = &self.tables[axis];
        let entry = |lane: usize| table[usize::from(index[lane] as u8)];
        // Lane by lane, not `array::map`, which is not always inlined.
        let [e0, e1, e2, e3] = [entry(0), entry(1), entry(2), entry(3)];
        let low = Vec4::new(e0[0], e1[0], e2[0], e3[0]);
        let step = Vec4::new(e0[1], e1[1], e2[1], e3[1]);
        Vec4::select(inside, low + step * t, Vec4::ZERO)
    }

    /// [`SplatFilter::footprints`] with AVX2: both axes' spans ([`footprint_span`]) in one
    /// register's lanes, and the first four values of both axes ([`SplatFilter::values`]) in
    /// eight lanes, their table entries read by two gathers rather than eight index extractions
    /// and sixteen loads. The same operations lane by lane as one axis at a time, so the same
    /// bits (SSE's `max` and `min` give their second operand for a NaN, as the scalar code's
    /// give the number).
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    fn footprints_with_avx2(
        &self,
        _: Avx2,
        position: &Vec2,
        (width, height): (u32, u32),
    ) -> Footprint {
        use std::arch::x86_64::*;
        const ENTRIES: f32 = SPLAT_TABLE as f32;
        // SAFETY: the CPU has AVX2 (`Avx2`). `position`'s eight bytes are read as one unaligned
        // i64. The gathers read the entries (i & 255) + 256 axis of the two tables, which lie
        // side by side: within the 2 x 256 entries.
        unsafe {
            // Lanes (x, y, x, y): the spans' low bounds in the first two, high in the last two.
            // (x, y) as one 64-bit lane, twice: one load rather than a load a lane (a `Vec2` is
            // `repr(C)`, x then y, eight bytes).
            let xy = std::ptr::from_ref(position).cast::<i64>().read_unaligned();
            let position4 = Vec4::from(_mm_castsi128_ps(_mm_set1_epi64x(xy)));
            let radius = self.radii;
            let centred = position4 - 0.5;
            let (low, high) = (centred - radius, centred + radius);
            let size = Vec4::new(width as f32, height as f32, 0.0, 0.0);
            let first = _mm_min_ps(
                _mm_max_ps(_mm_ceil_ps(low.into()), _mm_setzero_ps()),
                size.into(),
            );
            let last = _mm_min_ps(_mm_floor_ps(high.into()), (size - 1.0).into());
            let count = _mm_min_ps(
                _mm_max_ps(
                    _mm_sub_ps(_mm_add_ps(last, _mm_set1_ps(1.0)), first),
                    _mm_setzero_ps(),
                ),
                _mm_set1_ps(MAX_FOOTPRINT as f32),
            );
            // Both finite integers in [0, 2^24] (see `footprint_span`).
            let (first_index, count) = (_mm_cvttps_epi32(first), _mm_cvttps_epi32(count));
            let [first_x, first_y, ..] = std::mem::transmute::<__m128i, [i32; 4]>(first_index);
            let [count_x, count_y, ..] = std::mem::transmute::<__m128i, [i32; 4]>(count);
            // Lanes 0-3 the x axis's first four pixels, 4-7 the y axis's.
            let axis_of_lane = _mm256_setr_epi32(0, 0, 0, 0, 1, 1, 1, 1);
            let by_axis =
                |v: __m128| _mm256_permutevar8x32_ps(_mm256_castps128_ps256(v), axis_of_lane);
            let lane_centre = _mm256_setr_ps(0.5, 1.5, 2.5, 3.5, 0.5, 1.5, 2.5, 3.5);
            let centres = _mm256_add_ps(by_axis(first), lane_centre);
            let offsets = _mm256_sub_ps(by_axis(position4.into()), centres);
            let magnitude = _mm256_andnot_ps(_mm256_set1_ps(-0.0), offsets);
            let x = _mm256_mul_ps(
                _mm256_div_ps(magnitude, by_axis(radius.into())),
                _mm256_set1_ps(ENTRIES),
            );
            // False for NaN as well.
            let inside = _mm256_cmp_ps::<_CMP_LT_OQ>(x, _mm256_set1_ps(ENTRIES));
            let whole = _mm256_cvttps_epi32(x);
            let t = _mm256_sub_ps(x, _mm256_cvtepi32_ps(whole));
            let entries = _mm256_add_epi32(
                _mm256_and_si256(whole, _mm256_set1_epi32(u8::MAX.into())),
                _mm256_slli_epi32::<8>(axis_of_lane),
            );
            // The entries' 64-bit pairs (x0 x1, x2 x3, y0 y1, y2 y3) as (x0 x1, y0 y1, x2 x3,
            // y2 y3): a gather reads four 8-byte entries into both halves of a register, and
            // the halves' values and steps then unpack in place.
            let entries = _mm256_permute4x64_epi64::<0b11_01_10_00>(entries);
            let tables = self.tables.as_ptr().cast::<i64>();
            let gather =
                |entries| _mm256_castsi256_ps(_mm256_i32gather_epi64::<8>(tables, entries));
            let first_pairs = gather(_mm256_castsi256_si128(entries));
            let second_pairs = gather(_mm256_extracti128_si256::<1>(entries));
            // Each half: lanes 0 and 2 of the first pairs then of the second hold the four
            // values, lanes 1 and 3 the steps.
            let low = _mm256_shuffle_ps::<0b10_00_10_00>(first_pairs, second_pairs);
            let step = _mm256_shuffle_ps::<0b11_01_11_01>(first_pairs, second_pairs);
            let values = _mm256_and_ps(inside, _mm256_add_ps(low, _mm256_mul_ps(step, t)));
            Footprint {
                first: [first_x as usize, first_y as usize],
                count: [count_x as usize, count_y as usize],
                first_groups: [
                    Vec4::from(_mm256_castps256_ps128(values)),
                    Vec4::from(_mm256_extractf128_ps::<1>(values)),
                ],
            }
        }
    }
}

/// The offsets from `position` of the centres j + 0.5 of the pixels j = first + 4 group + lane
/// along one axis, each centre as the group's first index plus (lane + 0.5): exact, and so the
/// same bits, below 2^22 pixels.
#[inline(always)]
fn group_offsets(position: f32, first: usize, group: usize) -> Vec4 {
    let group_first = (first + 4 * group) as i32 as f32;
    let centres = Vec4::splat(group_first) + Vec4::new(0.5, 1.5, 2.5, 3.5);
    Vec4::splat(position) - centres
}

/// Both axes of a splat's footprint as [`SplatFilter::footprints`] gives them: per axis, the
/// pixels `first..first + count` and the filter's values at the first four (those from `count`
/// on unused). Small enough to stay in registers: a footprint of at most four pixels on each
/// axis, the common one, needs nothing more.
#[derive(Clone, Copy)]
struct Footprint {
    first: [usize; 2],
    count: [usize; 2],
    first_groups: [Vec4; 2],
}

impl Footprint {
    /// The footprint along `axis` with the filter's values at all its pixels, for a splat at
    /// `position`.
    #[inline(always)]
    fn axis(&self, filter: &SplatFilter, axis: usize, position: Vec2) -> AxisFootprint {
        let span = (self.first[axis], self.count[axis]);
        filter.footprint_from(axis, position[axis], span, self.first_groups[axis])
    }
}

/// One axis of a splat's footprint: pixels `first..first + count` and the filter's value at
/// each (in `weights[..count]`).
struct AxisFootprint {
    first: usize,
    count: usize,
    weights: [f32; MAX_FOOTPRINT],
}

/// A pixel's weighted radiance sums and weight sum, (sum w r, sum w g, sum w b, sum w).
type WeightedSum = [f64; 4];
/// The same sums over one pass, in f32, side by side so that a sample adds (r, g, b, 1) w to
/// them in one 4-lane step.
type PassSum = [f32; 4];

/// Weighted radiance sums and weight sums per pixel, rows from the top.
///
/// When splatting, a pass's samples are summed in f32 and each pass's sums folded into f64 sums
/// when the next pass begins ([`Film::begin_pass`]); otherwise a sample adds to its pixel's f64
/// sums at once (one sample per pixel and pass: an f32 pass sum would round nothing). After
/// 1e5 samples of similar magnitude an f32 sum would keep only ~7 of its 24 bits for each new
/// sample; f64 keeps ~36. Within one pass a pixel gets a few contributions (one sample per
/// pixel, over a footprint of k pixels: about k), so the f32 sum's relative error is at most
/// about k 2^-24 of the sum of its terms' magnitudes (Higham, *Accuracy and Stability of
/// Numerical Algorithms*, §4.2): 1e-6 for a 4x4 footprint, far below a pass's noise. Half the
/// bytes per pixel to add to, and to cache, than f64.
#[derive(Resource, Clone, Debug)]
pub struct Film {
    width: u32,
    height: u32,
    /// The sums of the passes before `pass`.
    sums: Vec<WeightedSum>,
    /// The sums of pass `pass` so far (splatting only; zero otherwise).
    pass_sums: Vec<PassSum>,
    pass: u32,
    /// Samples whose film position lies in the pixel.
    counts: Vec<u64>,
    rejected: u64,
    /// The filter samples are splatted with; `None` for filter importance sampling.
    splat: Option<SplatFilter>,
    /// The largest component a sample may have (`--clamp`); `None`: samples are not clamped.
    max_component: Option<f32>,
}

impl Film {
    pub fn new(width: u32, height: u32) -> Self {
        let n = width as usize * height as usize;
        Self {
            width,
            height,
            sums: written(n, [0.0; 4]),
            pass_sums: written(n, [0.0; 4]),
            pass: 0,
            counts: written(n, 0),
            rejected: 0,
            splat: None,
            max_component: None,
        }
    }

    /// From now on, a sample whose largest component exceeds `max_component` is scaled down to
    /// it (`None`: no clamping), as pbrt-v4's `RGBFilm::AddSample` does with its
    /// `maxcomponentvalue`. Scaling the whole colour keeps the sample's hue. This removes
    /// fireflies at the price of bias: the energy above the limit is lost, so the image is
    /// darker where rare bright paths (caustics, small bright lights seen by reflection) matter.
    pub fn clamp_samples(&mut self, max_component: Option<f32>) {
        self.max_component = max_component;
    }

    /// The limit of [`Film::clamp_samples`] (for checkpoints).
    pub fn max_component(&self) -> Option<f32> {
        self.max_component
    }

    /// From now on, samples are splatted with `filter` (their positions must then be uniform
    /// in their pixels).
    ///
    /// The one-pixel box is not splatted: its footprint is the sample's own pixel with weight
    /// f(dx) f(dy) = 1 (a neighbour's centre is at least 0.5 away, where the table reads 0), so
    /// the sums are those of adding the sample to its pixel with weight 1, without the
    /// footprint's work. The one difference: a position exactly on a pixel edge (the f32 sum
    /// of the centre and an offset of -0.5 + ε rounds there, about one sample in 10^5 at
    /// x ~ 100) counts with weight 1 in its own pixel, where splatting gave it weight 0 (at
    /// 1 spp such a pixel stayed black).
    pub fn splat_with(&mut self, filter: PixelFilter) {
        self.splat = (!filter.is_pixel_box()).then(|| SplatFilter::new(&filter));
    }

    /// A film from its saved sums, weights and counts (a checkpoint); `None` if the sizes
    /// disagree. Its reconstruction is filter importance sampling until [`Film::restore`] moves
    /// the sums into a film that splats.
    pub fn from_parts(
        width: u32,
        height: u32,
        sums: Vec<DVec3>,
        weights: Vec<f64>,
        counts: Vec<u64>,
        rejected: u64,
        max_component: Option<f32>,
    ) -> Option<Self> {
        let n = width as usize * height as usize;
        (sums.len() == n && weights.len() == n && counts.len() == n).then_some(Self {
            width,
            height,
            sums: (sums.iter().zip(weights))
                .map(|(sum, weight)| sum.extend(weight).to_array())
                .collect(),
            pass_sums: written(n, [0.0; 4]),
            pass: 0,
            counts,
            rejected,
            splat: None,
            max_component,
        })
    }

    /// Takes `saved`'s sums, weights and counts (a checkpoint of a film of the same size),
    /// keeping this film's reconstruction; false, and nothing taken, if the sizes differ.
    pub fn restore(&mut self, mut saved: Film) -> bool {
        if (saved.width, saved.height) != (self.width, self.height) {
            return false;
        }
        saved.fold_pass();
        self.sums = saved.sums;
        self.pass_sums = saved.pass_sums;
        self.counts = saved.counts;
        self.rejected = saved.rejected;
        true
    }

    /// The weighted radiance sum of `pixel` (y * width + x; for checkpoints and parts).
    pub fn sum(&self, pixel: usize) -> DVec3 {
        let [r, g, b, _] = self.total(pixel);
        DVec3::new(r, g, b)
    }

    /// The weight sum of `pixel` (for checkpoints and parts).
    pub fn weight(&self, pixel: usize) -> f64 {
        self.total(pixel)[3]
    }

    /// `pixel`'s sums over all passes: the earlier passes' and the current one's, added as
    /// [`Film::fold_pass`] will add them.
    fn total(&self, pixel: usize) -> WeightedSum {
        let mut sum = self.sums[pixel];
        fold(&mut sum, self.pass_sums[pixel]);
        sum
    }

    /// Starts pass `pass` (a pass index; the film's first is 0): if it is not the pass the film
    /// is in, that one's sums are folded into the f64 sums first. The sums are then the same
    /// whatever the chunks and threads a pass is traced in.
    pub fn begin_pass(&mut self, pass: u32) {
        if pass != self.pass {
            if self.splat.is_some() {
                self.fold_pass();
            }
            self.pass = pass;
        }
    }

    /// Adds the current pass's sums to the f64 sums and clears them.
    fn fold_pass(&mut self) {
        const PIXELS_PER_TASK: usize = 4096;
        (
            self.sums.par_chunks_mut(PIXELS_PER_TASK),
            self.pass_sums.par_chunks_mut(PIXELS_PER_TASK),
        )
            .into_par_iter()
            .for_each(|(sums, pass_sums)| {
                with_avx2_if_present(
                    #[inline(always)]
                    |_| {
                        for (sum, pass_sum) in sums.iter_mut().zip(pass_sums) {
                            fold(sum, *pass_sum);
                            *pass_sum = [0.0; 4];
                        }
                    },
                )
            });
    }

    /// Samples per pixel received (for checkpoints).
    pub fn counts(&self) -> &[u64] {
        &self.counts
    }

    pub fn width(&self) -> u32 {
        self.width
    }

    pub fn height(&self) -> u32 {
        self.height
    }

    /// Adds one sample, taken at raster position `position`, to `pixel` (y * width + x), the
    /// pixel that position lies in; splatted over the filter's footprint when splatting. A
    /// sample with a NaN, infinite or negative component, or for a pixel outside the film, is
    /// dropped and counted.
    pub fn add_sample(&mut self, pixel: u32, position: Vec2, radiance: Vec3) {
        self.add_samples(&[FilmSample {
            pixel,
            position,
            radiance,
        }]);
    }

    /// Adds `samples` as [`Film::add_sample`] would one after the other, in their order: every
    /// pixel sums its contributions in the order the samples come, so the sums depend only on
    /// that order. On one thread: the renderer splats a chunk while other threads trace other
    /// chunks (see `integrator::in_flight`), which is where its parallelism lies.
    pub fn add_samples(&mut self, samples: &[FilmSample]) {
        let n = self.counts.len();
        let splat = self.splat.as_ref();
        let film_size = (self.width, self.height);
        let mut sums = FilmSums {
            sums: &mut self.sums,
            pass_sums: &mut self.pass_sums,
            counts: &mut self.counts,
            max_component: self.max_component,
        };
        let rejected = with_avx2_if_present(
            #[inline(always)]
            |avx2| {
                let mut rejected = 0;
                for sample in samples {
                    if (sample.pixel as usize) >= n || !sums.add(film_size, splat, sample, avx2) {
                        rejected += 1;
                    }
                }
                rejected
            },
        );
        self.rejected += rejected as u64;
    }

    /// The estimate of every pixel (weighted sum over weight sum); black where nothing arrived.
    pub fn mean(&self) -> Vec<Vec3> {
        (&self.sums, &self.pass_sums)
            .into_par_iter()
            .map(|(&sum, &pass_sum)| {
                let mut total = sum;
                fold(&mut total, pass_sum);
                let [r, g, b, weight] = total;
                if weight > 0.0 {
                    (DVec3::new(r, g, b) / weight).as_vec3()
                } else {
                    Vec3::ZERO
                }
            })
            .collect()
    }

    /// The fewest samples any pixel has received (0 for an empty film).
    pub fn samples_per_pixel_min(&self) -> u64 {
        self.counts.iter().copied().min().unwrap_or(0)
    }

    /// Samples dropped for being non-finite or negative, or outside the film.
    pub fn rejected_samples(&self) -> u64 {
        self.rejected
    }
}

/// A radiance sample for the film: its pixel, its raster position, its radiance.
#[derive(Clone, Copy, Debug)]
pub struct FilmSample {
    pub pixel: u32,
    pub position: Vec2,
    pub radiance: Vec3,
}

/// The film's sums and counts, borrowed apart from its filter.
struct FilmSums<'a> {
    sums: &'a mut [WeightedSum],
    pass_sums: &'a mut [PassSum],
    counts: &'a mut [u64],
    /// The film's `--clamp` limit on a sample's largest component.
    max_component: Option<f32>,
}

impl FilmSums<'_> {
    /// Adds `sample` (whose pixel is in the film): its weighted radiance in the pixels under
    /// its footprint and its count in its own pixel. Returns false, adding nothing, if the
    /// sample is invalid (NaN, infinite or negative). Inlined into both versions of
    /// [`with_avx2_if_present`].
    #[inline(always)]
    fn add(
        &mut self,
        (width, height): (u32, u32),
        splat: Option<&SplatFilter>,
        sample: &FilmSample,
        avx2: Option<Avx2>,
    ) -> bool {
        let w = width as usize;
        let pixel = sample.pixel as usize;
        // Finite and not negative: 0 <= c < inf, false for NaN; three lanes in one compare each.
        let lanes = Vec3A::from(sample.radiance);
        let valid = (lanes.cmpge(Vec3A::ZERO) & lanes.cmplt(Vec3A::INFINITY)).all();
        if !valid {
            return false;
        }
        self.counts[pixel] += 1;
        // The largest component only when clamping (without it, the compiler computed the
        // scale max / largest for every sample and selected).
        let radiance = match self.max_component {
            Some(max) => {
                let largest = sample.radiance.max_element();
                if largest > max {
                    sample.radiance * (max / largest)
                } else {
                    sample.radiance
                }
            }
            None => sample.radiance,
        };
        // (r, g, b, 1): times a weight w, the radiance and the weight a pixel adds.
        let radiance = radiance.extend(1.0);
        match splat {
            None => add_to_pixel(&mut self.sums[pixel], radiance),
            Some(filter) => {
                // The pixels whose centres c = (x + 0.5, y + 0.5) lie within the radius: the
                // filter's values along each axis once per sample, then the footprint's rows
                // (within the film).
                let footprint = filter.footprints(&sample.position, (width, height), avx2);
                let ([first_x, first_y], [count_x, rows]) = (footprint.first, footprint.count);
                if rows == 0 || count_x == 0 {
                    return true;
                }
                // The filter is separable: f(dx, 0) f(0, dy) = f(dx, dy) f(0, 0), and the
                // constant f(0, 0) cancels in sum / weight.
                if count_x == 4 && rows <= 4 {
                    let start = first_y * w + first_x;
                    // The common footprint, four pixels wide and at most four tall: its weights
                    // are the first groups, a row is one group of four, without `add_to_row`'s
                    // loop and remainder.
                    let [wx, wy] = footprint.first_groups;
                    // The pixels from the footprint's first to its last, bounds checked once.
                    let block = &mut self.pass_sums[start..start + (rows - 1) * w + 4];
                    // Not in a build for AVX-512 (`target-cpu=native` on such a CPU): there the
                    // compiler adds each row's 16 sums below as one 512-bit operation, which
                    // took less time than the 256-bit pairs (`perf` on dof-sky, 1.3x less in
                    // `add_samples`); without it, the pairs take fewer instructions.
                    #[cfg(target_arch = "x86_64")]
                    if !cfg!(target_feature = "avx512f")
                        && let Some(avx2) = avx2
                        && rows == 4
                    {
                        // All four rows (the film's edge cuts off the others).
                        add_to_four_by_four_with_avx2(avx2, block, w, (wx, wy), radiance);
                        return true;
                    }
                    // SAFETY: row < rows, so the row's four pixels, from row w, end at most at
                    // (rows - 1) w + 4, the block's length.
                    let mut row_at = |row: usize| unsafe {
                        &mut *block.as_mut_ptr().add(row * w).cast::<[PassSum; 4]>()
                    };
                    let wy = wy.to_array();
                    for (row, &fy) in wy[..rows].iter().enumerate() {
                        add_to_four(row_at(row), wx, fy, radiance);
                    }
                    return true;
                }
                let xs = footprint.axis(filter, 0, sample.position);
                let ys = footprint.axis(filter, 1, sample.position);
                let (wx, wy) = (&xs.weights[..xs.count], &ys.weights[..ys.count]);
                let start = ys.first * w + xs.first;
                for (row, &fy) in wy.iter().enumerate() {
                    let sums = &mut self.pass_sums[start + row * w..start + row * w + wx.len()];
                    add_to_row(sums, wx, fy, radiance);
                }
            }
        }
        true
    }
}

/// `n` copies of `value`, each written, where `vec![value; n]` of zeros would allocate zeroed
/// memory: fresh pages that the kernel maps to its shared zero page, so that the splat's first
/// read-modify-write of each faults twice, the second time (copy on write) flushing the TLBs of
/// the CPUs running the render's other threads with an interprocessor interrupt, dear in a
/// virtual machine (`perf`: 10 % of the ray caster's time at two threads, its film 17 MB).
/// Written here, before the render, each page faults once. `black_box` keeps the compiler from
/// turning the allocation and its zeros back into one zeroed allocation.
fn written<T: Clone>(n: usize, value: T) -> Vec<T> {
    let mut values = Vec::with_capacity(n);
    std::hint::black_box(values.as_mut_ptr());
    values.resize(n, value);
    values
}

/// Proof that the CPU has AVX2: only [`with_avx2_if_present`] makes one, for its AVX2 version,
/// so that code holding one may use AVX2 intrinsics (they inline into that version).
#[derive(Clone, Copy)]
struct Avx2(());

/// Runs `body` compiled for AVX2 if the CPU has it (given `Some(Avx2)`), else as compiled for
/// the baseline (SSE2; given `None`); `body` must be `#[inline(always)]` to be compiled into
/// each version. The same operations on the same values either way (no FMA: Rust never fuses a
/// product and a sum on its own), so the same bits; with AVX, two pixels' sums are one 256-bit
/// add and VEX's three-operand forms save the copies. The film's own copy of `accel`'s
/// dispatch, so that the two modules stay independent.
#[inline(always)]
fn with_avx2_if_present<R>(body: impl FnOnce(Option<Avx2>) -> R) -> R {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU has the feature `with_avx2` is compiled for.
        return unsafe { with_avx2(body) };
    }
    body(None)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn with_avx2<R>(body: impl FnOnce(Option<Avx2>) -> R) -> R {
    body(Some(Avx2(())))
}

/// Adds a sample's share to the pixels of one row of its footprint: to pixel i, (r, g, b, 1) w_i
/// with w_i = f(dx_i, 0) f(0, dy) = `wx[i] * fy`. Four pixels at a time, the rest one by one.
#[inline(always)]
fn add_to_row(sums: &mut [PassSum], wx: &[f32], fy: f32, radiance: Vec4) {
    let mut pixels = sums.chunks_exact_mut(4);
    let mut weights = wx.chunks_exact(4);
    for (pixels, weights) in (&mut pixels).zip(&mut weights) {
        add_to_four(
            pixels.try_into().unwrap(),
            Vec4::from_slice(weights),
            fy,
            radiance,
        );
    }
    for (sum, &fx) in pixels.into_remainder().iter_mut().zip(weights.remainder()) {
        add_weighted(sum, radiance, fx * fy);
    }
}

/// Adds a sample's share to four pixels of a row: their four weights `wx * fy` in one product,
/// then the 16 sums as one run of lanes, lane 4 i + c adding radiance_c w_i (with AVX, two
/// 8-lane products and sums; each lane one f32 product and one sum, as one pixel alone).
#[inline(always)]
fn add_to_four(pixels: &mut [PassSum; 4], wx: Vec4, fy: f32, radiance: Vec4) {
    let weights = (wx * fy).to_array();
    let radiance = radiance.to_array();
    for (lane, sum) in pixels.as_flattened_mut().iter_mut().enumerate() {
        *sum += radiance[lane % 4] * weights[lane / 4];
    }
}

/// [`add_to_four`] on each row of a footprint four pixels square (rows `stride` pixels apart in
/// `block`), with AVX2: the 16 weights wx_i fy_j in two 8-lane products, then each pair of
/// pixels' eight sums in one 8-lane product and sum, lane 4 k + c adding radiance_c w_k. Each
/// lane the same product and sum as `add_to_four`'s (f32 products and sums commute exactly).
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn add_to_four_by_four_with_avx2(
    _: Avx2,
    block: &mut [PassSum],
    stride: usize,
    (wx, wy): (Vec4, Vec4),
    radiance: Vec4,
) {
    use std::arch::x86_64::*;
    assert!(
        block.len() >= 3 * stride + 4,
        "the block holds the four rows"
    );
    // SAFETY: the CPU has AVX2 (`Avx2`). Row j's pixel pair k, from j stride + 2 k, ends at
    // most at 3 stride + 4, within the block.
    unsafe {
        let wx = _mm256_broadcast_ps(&wx.into());
        let wy = _mm256_castps128_ps256(wy.into());
        let rows = |j: i32| _mm256_setr_epi32(j, j, j, j, j + 1, j + 1, j + 1, j + 1);
        // Rows 0 and 1, then rows 2 and 3: row j's weight wx_i fy_j in lane 4 (j % 2) + i.
        let weights = [
            _mm256_mul_ps(wx, _mm256_permutevar8x32_ps(wy, rows(0))),
            _mm256_mul_ps(wx, _mm256_permutevar8x32_ps(wy, rows(2))),
        ];
        let radiance = _mm256_broadcast_ps(&radiance.into());
        let pixels = block.as_mut_ptr().cast::<f32>();
        for row in 0..4 {
            for pair in 0..2 {
                // Pixels k and k + 1 of the row: w_k in lanes 0-3, w_(k+1) in lanes 4-7.
                let k = (4 * (row % 2) + 2 * pair) as i32;
                let pair_weights = _mm256_permutevar8x32_ps(
                    weights[row / 2],
                    _mm256_setr_epi32(k, k, k, k, k + 1, k + 1, k + 1, k + 1),
                );
                let sums = pixels.add(4 * (row * stride + 2 * pair));
                let added = _mm256_mul_ps(radiance, pair_weights);
                _mm256_storeu_ps(sums, _mm256_add_ps(_mm256_loadu_ps(sums), added));
            }
        }
    }
}

/// sum += radiance w, lane by lane.
#[inline(always)]
fn add_weighted(sum: &mut PassSum, radiance: Vec4, w: f32) {
    *sum = (Vec4::from_array(*sum) + radiance * w).to_array();
}

/// sum += radiance with weight 1, each lane widened to f64 (exactly) and added.
#[inline(always)]
fn add_to_pixel(sum: &mut WeightedSum, radiance: Vec4) {
    fold(sum, radiance.to_array());
}

/// sum += pass_sum, each lane widened to f64 (exactly) and added.
#[inline(always)]
fn fold(sum: &mut WeightedSum, pass_sum: PassSum) {
    for (sum, value) in sum.iter_mut().zip(pass_sum) {
        *sum += f64::from(value);
    }
}

/// The pixels along one axis whose centres lie within `radius` of `position`, as (first, count).
#[inline(always)]
fn footprint_span(position: f32, radius: f32, size: u32) -> (usize, usize) {
    let (low, high) = (position - 0.5 - radius, position - 0.5 + radius);
    // In f32, exact below 2^24 pixels; one instruction each for ceil and floor with SSE4.1
    // (`with_avx2_if_present`). `max` and `min` also turn a NaN bound into the film's edge.
    // `first` is also kept at most `size` (beyond the film the count is 0 either way), so
    // that both are finite and in [0, 2^24].
    let size = size as f32;
    let first = low.ceil().max(0.0).min(size);
    let last = high.floor().min(size - 1.0);
    let count = (last + 1.0 - first).clamp(0.0, MAX_FOOTPRINT as f32);
    // SAFETY: both are finite integers in [0, 2^24], which i32 holds; unchecked, the
    // conversion is one instruction rather than `as`'s saturation of NaN and overflow.
    unsafe {
        (
            first.to_int_unchecked::<i32>() as usize,
            count.to_int_unchecked::<i32>() as usize,
        )
    }
}

/// trunc(x) lane by lane, as floats and as integers, for lanes in [0, 2^31): one packed
/// conversion to integers and one back (glam's `trunc` takes six instructions without SSE4.1,
/// and its integer conversion goes lane by lane). Lanes beyond (NaN, infinite, large) give
/// values that callers must not use.
#[inline(always)]
fn truncate_lanes(x: Vec4) -> (Vec4, [i32; 4]) {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{__m128, _mm_cvtepi32_ps, _mm_cvttps_epi32};
        // SAFETY: SSE2, which x86-64 always has.
        let (whole, index) = unsafe {
            let index = _mm_cvttps_epi32(__m128::from(x));
            (_mm_cvtepi32_ps(index), index)
        };
        // SAFETY: four i32 lanes, the same size and layout as [i32; 4].
        (Vec4::from(whole), unsafe {
            std::mem::transmute::<std::arch::x86_64::__m128i, [i32; 4]>(index)
        })
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        let whole = x.trunc();
        (whole, whole.to_array().map(|lane| lane as i32))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn film_means_and_rejects_invalid_samples() {
        let mut film = Film::new(3, 2);
        film.add_sample(0, Vec2::splat(0.5), Vec3::new(1.0, 2.0, 3.0));
        film.add_sample(0, Vec2::splat(0.5), Vec3::new(3.0, 2.0, 1.0));
        film.add_sample(1, Vec2::new(1.5, 0.5), Vec3::new(f32::NAN, 0.0, 0.0));
        film.add_sample(1, Vec2::new(1.5, 0.5), Vec3::new(0.0, f32::INFINITY, 0.0));
        film.add_sample(1, Vec2::new(1.5, 0.5), Vec3::new(0.0, 0.0, -1.0));
        film.add_sample(6, Vec2::new(0.5, 2.5), Vec3::ONE);
        let mean = film.mean();
        assert_eq!(mean[0], Vec3::splat(2.0));
        assert_eq!(mean[1], Vec3::ZERO);
        assert_eq!(film.rejected_samples(), 4);
        assert_eq!(film.samples_per_pixel_min(), 0);
        assert_eq!((film.width(), film.height()), (3, 2));
    }

    /// The one-pixel box skips the footprint (and the f32 pass sums): the same sums, weights and
    /// counts to the bit as splatting it through the tabulated filter, for positions inside
    /// their pixels.
    #[test]
    fn pixel_box_splats_as_its_own_pixel() {
        let (width, height) = (19, 11);
        let mut rng = crate::sampling::PathRng::new(4, 5, 6);
        let mut next = || rng.next_f32();
        let samples: Vec<FilmSample> = (0..5_000)
            .map(|_| {
                let pixel = (next() * (width * height) as f32) as u32;
                let (x, y) = (pixel % width, pixel / width);
                // Strictly inside the pixel, off its edges.
                let inside = |u: f32| 0.001 + 0.998 * u;
                FilmSample {
                    pixel,
                    position: Vec2::new(x as f32 + inside(next()), y as f32 + inside(next())),
                    radiance: Vec3::new(next(), next() * 10.0, next() * 1e-3),
                }
            })
            .collect();
        let mut fast = Film::new(width, height);
        fast.splat_with(PixelFilter::pixel_box());
        assert!(fast.splat.is_none());
        let mut splatted = Film::new(width, height);
        splatted.splat = Some(SplatFilter::new(&PixelFilter::pixel_box()));
        // A pass per sample: the f32 pass sum is then the sample's radiance times 1, exact.
        for (pass, sample) in (1..).zip(&samples) {
            for film in [&mut fast, &mut splatted] {
                film.add_samples(std::slice::from_ref(sample));
                film.begin_pass(pass);
            }
        }
        assert_eq!(fast.sums, splatted.sums);
        assert_eq!(fast.counts, splatted.counts);
    }

    /// The four-lane table reads against the interpolation done one value at a time from the
    /// filter itself (the splat's arithmetic before it took four lanes and paired each entry
    /// with its step): the same bits for offsets inside, on and beyond the radius, negative,
    /// NaN, and for filters with negative lobes and radii that are not powers of two.
    #[test]
    fn four_lane_filter_values_match_one_at_a_time() {
        use crate::film::FilterKind;
        let scalar = |filter: &PixelFilter, axis: usize, offset: f32| {
            let r = filter.radius()[axis];
            let x = offset.abs() / r * SPLAT_TABLE as f32;
            if x.is_nan() || x >= SPLAT_TABLE as f32 {
                return 0.0;
            }
            let i = x as usize;
            let entry = |i: usize| {
                let mut offset = Vec2::ZERO;
                offset[axis] = r * i as f32 / SPLAT_TABLE as f32;
                filter.evaluate(offset)
            };
            entry(i) + (entry(i + 1) - entry(i)) * (x - i as f32)
        };
        let mut rng = crate::sampling::PathRng::new(7, 8, 9);
        let filters = [
            (FilterKind::Gaussian { alpha: 2.0 }, Vec2::new(2.0, 1.5)),
            (FilterKind::BlackmanHarris, Vec2::new(1.5, 0.7)),
            (
                FilterKind::Mitchell { b: 0.75, c: 0.125 },
                Vec2::new(2.0, 3.3),
            ),
            (FilterKind::Sinc { tau: 3.0 }, Vec2::new(4.0, 4.0)),
        ];
        for (kind, radius) in filters {
            let pixel_filter = PixelFilter::new(kind, radius);
            let filter = SplatFilter::new(&pixel_filter);
            for axis in 0..2 {
                let r = radius[axis];
                let mut offsets = vec![0.0, -0.0, r, -r, r.next_up(), f32::NAN, f32::INFINITY];
                offsets.extend((0..4_000).map(|_| (rng.next_f32() * 2.0 - 1.0) * 1.2 * r));
                for lanes in offsets.chunks(4) {
                    let mut group = [0.0; 4];
                    group[..lanes.len()].copy_from_slice(lanes);
                    let values = filter.values(axis, Vec4::from_array(group)).to_array();
                    for (&offset, value) in group.iter().zip(values) {
                        let expected = scalar(&pixel_filter, axis, offset);
                        assert_eq!(value.to_bits(), expected.to_bits(), "{kind:?} {offset}");
                    }
                }
            }
        }
    }

    /// The 4x4 footprint added with AVX2 against four rows of `add_to_four`: the same sums to
    /// the bit, in a block whose rows are further apart than four pixels (pixels between rows
    /// untouched). Built for AVX-512, the film does not take this path, so this is what runs it.
    #[cfg(target_arch = "x86_64")]
    #[test]
    fn four_by_four_with_avx2_matches_four_rows() {
        let Some(avx2) = with_avx2_if_present(|avx2| avx2) else {
            return;
        };
        let stride = 7;
        let mut rng = crate::sampling::PathRng::new(3, 1, 4);
        let mut next = || rng.next_f32() * 10.0 - 1.0;
        for _ in 0..1_000 {
            let block: Vec<PassSum> = (0..3 * stride + 4)
                .map(|_| [next(), next(), next(), next()])
                .collect();
            let wx = Vec4::new(next(), next(), next(), next());
            let wy = Vec4::new(next(), next(), next(), next());
            let radiance = Vec4::new(next(), next(), next(), 1.0);
            let mut rows = block.clone();
            for (row, fy) in wy.to_array().into_iter().enumerate() {
                let pixels = (&mut rows[row * stride..row * stride + 4])
                    .try_into()
                    .unwrap();
                add_to_four(pixels, wx, fy, radiance);
            }
            let mut square = block;
            add_to_four_by_four_with_avx2(avx2, &mut square, stride, (wx, wy), radiance);
            let bits = |sums: &[PassSum]| {
                sums.as_flattened()
                    .iter()
                    .map(|v| v.to_bits())
                    .collect::<Vec<_>>()
            };
            assert_eq!(bits(&square), bits(&rows));
        }
    }

    /// Both axes' footprints at once with AVX2 against one axis at a time with four lanes: the
    /// same spans and the same weights to the bit, for positions inside the film, on pixel
    /// edges, near and beyond its borders, NaN and infinite, and filters whose footprints take
    /// more than four pixels.
    #[test]
    fn both_axes_with_avx2_match_one_axis_at_a_time() {
        use crate::film::FilterKind;
        let Some(avx2) = with_avx2_if_present(|avx2| avx2) else {
            return;
        };
        let size = (37, 53);
        let mut rng = crate::sampling::PathRng::new(13, 14, 15);
        let mut next = || rng.next_f32();
        let mut positions = vec![
            Vec2::ZERO,
            Vec2::new(37.0, 53.0),
            Vec2::new(f32::NAN, 3.5),
            Vec2::new(3.5, f32::INFINITY),
            Vec2::new(-1e9, 1e9),
            Vec2::new(12.0, 7.0),
        ];
        positions.extend((0..20_000).map(|i| {
            let p = Vec2::new(next() * 45.0 - 4.0, next() * 61.0 - 4.0);
            // Every 5th on a pixel edge along x, every 7th along y.
            let x = if i % 5 == 0 { p.x.round() } else { p.x };
            let y = if i % 7 == 0 { p.y.round() } else { p.y };
            Vec2::new(x, y)
        }));
        let filters = [
            PixelFilter::new(FilterKind::Gaussian { alpha: 2.0 }, Vec2::splat(2.0)),
            PixelFilter::new(
                FilterKind::Mitchell { b: 0.75, c: 0.125 },
                Vec2::new(0.7, 3.3),
            ),
            PixelFilter::new(FilterKind::Sinc { tau: 3.0 }, Vec2::new(5.5, 1.2)),
        ];
        for filter in filters {
            let filter = SplatFilter::new(&filter);
            for &position in &positions {
                let with_avx2 = filter.footprints(&position, size, Some(avx2));
                let without = filter.footprints(&position, size, None);
                let one_at_a_time = [
                    filter.footprint(0, position.x, size.0),
                    filter.footprint(1, position.y, size.1),
                ];
                for (axis, one) in one_at_a_time.iter().enumerate() {
                    for both in [&with_avx2, &without].map(|f| f.axis(&filter, axis, position)) {
                        assert_eq!(
                            (both.first, both.count),
                            (one.first, one.count),
                            "{position}"
                        );
                        let bits = |f: &AxisFootprint| {
                            f.weights[..f.count]
                                .iter()
                                .map(|w| w.to_bits())
                                .collect::<Vec<_>>()
                        };
                        assert_eq!(bits(&both), bits(one), "{position}");
                    }
                }
            }
        }
    }

    /// Samples add to f64 sums, splatted ones through the passes' f32 sums: with f32 sums
    /// throughout the mean would be off by about 0.1.
    #[test]
    fn film_keeps_precision_over_many_samples() {
        use crate::film::FilterKind;
        let gaussian = PixelFilter::new(FilterKind::Gaussian { alpha: 2.0 }, Vec2::splat(2.0));
        for filter in [PixelFilter::pixel_box(), gaussian] {
            // 1e5 samples alternating 1e3 and 1e-3 per pixel, one pass each: exact mean
            // 500.0005.
            let mut film = Film::new(1, 1);
            film.splat_with(filter);
            for i in 0..100_000 {
                film.begin_pass(i);
                film.add_sample(
                    0,
                    Vec2::splat(0.5),
                    Vec3::splat(if i % 2 == 0 { 1e3 } else { 1e-3 }),
                );
            }
            let m = film.mean()[0].x;
            assert!((m - 500.0005).abs() < 1e-4, "{m}");
        }
    }

    /// A pass's f32 sums against the same samples summed in f64: within the bound of recursive
    /// summation, |error| <= (n - 1) u sum |terms| (Higham, §4.2; u = 2^-24, n the terms), with
    /// n the most samples a pixel's footprint took (16 x 16 here: the f32 products of weight and
    /// radiance add one rounding each, counted as a term more). Then the next pass's fold gives
    /// the f64 sums those f32 sums: the total before the fold and after are the same bits.
    #[test]
    fn a_pass_in_f32_stays_within_its_rounding_bound() {
        use crate::film::FilterKind;
        let (width, height) = (23, 17);
        let filter = PixelFilter::new(FilterKind::Gaussian { alpha: 2.0 }, Vec2::splat(2.0));
        let tables = SplatFilter::new(&filter);
        let mut rng = crate::sampling::PathRng::new(10, 11, 12);
        let mut next = || rng.next_f32();
        let mut film = Film::new(width, height);
        film.splat_with(filter);
        // The reference: every sample's terms in f64, and the sum of their magnitudes.
        let n = (width * height) as usize;
        let (mut exact, mut magnitude) = (vec![[0.0f64; 4]; n], vec![[0.0f64; 4]; n]);
        for _ in 0..16 {
            for pixel in 0..width * height {
                let position = Vec2::new((pixel % width) as f32, (pixel / width) as f32)
                    + Vec2::new(next(), next());
                let radiance = Vec3::new(next(), next() * 1e3, next() * 1e-3);
                film.add_sample(pixel, position, radiance);
                let xs = tables.footprint(0, position.x, width);
                let ys = tables.footprint(1, position.y, height);
                for (j, &fy) in ys.weights[..ys.count].iter().enumerate() {
                    for (i, &fx) in xs.weights[..xs.count].iter().enumerate() {
                        let p = (ys.first + j) * width as usize + xs.first + i;
                        let w = f64::from(fx) * f64::from(fy);
                        for (c, value) in radiance.extend(1.0).to_array().into_iter().enumerate() {
                            exact[p][c] += f64::from(value) * w;
                            magnitude[p][c] += (f64::from(value) * w).abs();
                        }
                    }
                }
            }
        }
        let bound = |p: usize, c: usize| 256.0 * f64::from(f32::EPSILON) / 2.0 * magnitude[p][c];
        let mut largest_error = 0.0f64;
        for p in 0..n {
            let total = film.total(p);
            for c in 0..4 {
                let error = (total[c] - exact[p][c]).abs();
                assert!(
                    error <= bound(p, c),
                    "pixel {p} lane {c}: {error} > {}",
                    bound(p, c)
                );
                largest_error = largest_error.max(error / magnitude[p][c]);
            }
        }
        assert!(largest_error > 0.0, "the f32 sums round");
        let before: Vec<WeightedSum> = (0..n).map(|p| film.total(p)).collect();
        film.begin_pass(1);
        assert_eq!(film.sums, before);
        assert!(film.pass_sums.iter().all(|sum| *sum == [0.0; 4]));
    }
}
