//! The infinite (environment) light: radiance arriving from every direction, constant or from a
//! latitude-longitude map, importance-sampled by the map's luminance.
//!
//! The map is looked up bilinearly between texel centres (wrapping around in phi, clamped at
//! the poles), and sampled by that same interpolant of luminance times sin(theta) (a
//! [`Bilinear2D`] whose vertices are the texel centres), as Mitsuba 3's `envmap` does. A
//! piecewise-constant distribution over the texels (pbrt-v3 §14.2.4) gives the texels beside
//! a small bright patch (a sun) their own low density while the bilinear lookup ramps up to
//! the patch's radiance across them: f / p there reaches the patch's contrast, and those rare
//! samples dominated the error of environment-lit scenes.

use std::f32::consts::PI;

use bevy_ecs::prelude::*;
use glam::{Mat3, Mat3A, Vec2, Vec3, Vec3A, Vec4};

use super::LightSample;

mod sample_lanes;

use crate::film::luminance;
use crate::material::texture::ImageTexture;
use crate::math;
use crate::sampling::warp::{uniform_sphere, uniform_sphere_pdf};
use crate::sampling::{Bilinear2D, BilinearSample, GridCell};
pub use sample_lanes::SkySamples;

/// The entity's component, as the scene gives it.
#[derive(Component, Clone, Debug)]
pub struct InfiniteLight {
    pub radiance: Vec3,
    pub map: Option<ImageTexture>,
    pub light_to_world: Mat3,
}

/// The light, ready for sampling.
#[derive(Clone, Debug)]
pub struct Environment {
    radiance: Vec3,
    /// Boxed: the tables would make every `Light` as large.
    map: Option<Box<EnvironmentMap>>,
}

#[derive(Clone, Debug)]
struct EnvironmentMap {
    image: ImageTexture,
    /// The image's width and height in texels as floats, with the last column's and row's
    /// numbers: the lookup's conversions, once.
    size: Vec2,
    last_column: f32,
    last_row: f32,
    /// The texels with column 0 repeated after the last column, the first row repeated above
    /// the image and the last row below it ((w + 1) x (h + 2)): the lookup's right and lower
    /// neighbours, wrapped in u and clamped in v, are then always at i + 1 and j + 1, and a
    /// grid row's texels (its upper neighbour clamped too) start at the grid row itself,
    /// without a branch or a second pointer to follow. As `Vec3A`, one SSE register each: the
    /// lookup's arithmetic is the same per channel (the same bits as with `Vec3`) in a third of
    /// the instructions.
    padded: Box<[Vec3A]>,
    /// Over the grid of texel centres, in (u - 1 / 2w mod 1, v), so that the seam in phi is a
    /// cell of its own (between the last column and the first, repeated at x = 1).
    distribution: Bilinear2D,
    /// The same over luminance less the sky's mean, for MIS (see [`Environment::sample_for_mis`]);
    /// `None` for a map within 1 % of constant, where nothing would be left.
    compensated: Option<Bilinear2D>,
    /// As `Mat3A`: its product with a `Vec3A` is `Mat3`'s with a `Vec3` (the same products and
    /// sums in the same order), in SSE registers without the gathering of `Vec3`'s lanes.
    light_to_world: Mat3A,
    world_to_light: Mat3A,
    /// The sampling grid's cells' angles, for the direction of a sample in its cell without
    /// range reduction; `None` for a map too coarse for that.
    cell_angles: Option<CellAngles>,
    /// Whether `light_to_world` keeps lengths (M^T M = I within 1e-6: a rotation, as a sky's
    /// transform is): a sampled direction, unit in the map's frame, then stays unit without
    /// the normalisation (a square root and a division in each sample's dependency chain).
    keeps_lengths: bool,
}

impl EnvironmentMap {
    fn new(image: &ImageTexture, light_to_world: Mat3) -> Self {
        let (w, h) = (image.width as usize, image.height as usize);
        // The lookup converts texel coordinates to i32 unchecked within [0, w - 1] and [0, h - 1].
        assert!(
            w <= 1 << 24 && h <= 1 << 24,
            "an environment map of {w} x {h} texels"
        );
        // Vertices: columns at x = i / w for texel column i, then column 0 again at x = 1;
        // rows at the texel centres v = (j + 1/2) / h, with the first and the last row
        // repeated at the poles (v = 0 and 1): the lookup is constant in v beyond them.
        let xs: Vec<f32> = (0..=w).map(|i| i as f32 / w as f32).collect();
        let ys: Vec<f32> = std::iter::once(0.0)
            .chain((0..h).map(|j| (j as f32 + 0.5) / h as f32))
            .chain(std::iter::once(1.0))
            .collect();
        let row_of_vertex = |k: usize| k.saturating_sub(1).min(h - 1);
        // The density in (u, v) is luminance (less `offset`) times sin(theta) (the area
        // element of the sphere); interpolating the product keeps it zero at the poles.
        let vertex_values = |offset: f32| -> Vec<f32> {
            ys.iter()
                .enumerate()
                .flat_map(|(k, &v)| {
                    let (row, sin_theta) = (row_of_vertex(k), (PI * v).sin().max(0.0));
                    (0..=w).map(move |i| {
                        (luminance(image.texels[row * w + i % w]) - offset).max(0.0) * sin_theta
                    })
                })
                .collect()
        };
        // The sky's mean luminance over solid angle (rows weighted by sin theta), and its least.
        let (mut weighted, mut solid_angle, mut least) = (0.0f64, 0.0f64, f32::INFINITY);
        for (t, texel) in image.texels.iter().enumerate() {
            let sin_theta = f64::from((PI * ((t / w) as f32 + 0.5) / h as f32).sin());
            weighted += f64::from(luminance(*texel)) * sin_theta;
            solid_angle += sin_theta;
            least = least.min(luminance(*texel));
        }
        let mean = (weighted / solid_angle) as f32;
        let compensated = (mean - least > 0.01 * mean)
            .then(|| Bilinear2D::new(&vertex_values(mean), xs.clone(), ys.clone()))
            .filter(|table| table.integral() > 0.0);
        let cell_angles = CellAngles::new(w, &ys);
        let padded = (0..=h + 1)
            .flat_map(|j| (0..=w).map(move |i| (i % w, j.saturating_sub(1).min(h - 1))))
            .map(|(i, j)| Vec3A::from(image.texels[j * w + i]))
            .collect();
        Self {
            image: image.clone(),
            size: Vec2::new(w as f32, h as f32),
            last_column: (w - 1) as f32,
            last_row: (h - 1) as f32,
            padded,
            distribution: Bilinear2D::new(&vertex_values(0.0), xs, ys),
            compensated,
            cell_angles,
            light_to_world: Mat3A::from(light_to_world),
            world_to_light: Mat3A::from(light_to_world.inverse()),
            keeps_lengths: (light_to_world.transpose() * light_to_world)
                .abs_diff_eq(Mat3::IDENTITY, 1e-6),
        }
    }

    /// The compensated table when asked for and there is one, else the full one.
    fn table(&self, compensated: bool) -> &Bilinear2D {
        match &self.compensated {
            Some(table) if compensated => table,
            _ => &self.distribution,
        }
    }

    /// The sampling grid's cell holding texture coordinates `uv`, and the fractions across it.
    /// Its columns are the lookup's: texel centres, wrapped in u. Its vertex rows are the texel
    /// centres with the poles added, so between the first and the last centre the grid row is
    /// the lookup's texel row plus one, and beyond them (half a texel from a pole) it is 0 or
    /// h, at the fraction 2 v h or 2 (v h - h + 1/2) of the half-texel cell.
    fn cell_of_uv(&self, uv: Vec2) -> GridCell {
        let x = wrap(uv.x * self.size.x - 0.5, self.size.x);
        let y = uv.y * self.size.y - 0.5;
        let column = clamped_index(x, self.last_column);
        let last = self.last_row;
        let (row, fy) = if y < 0.0 {
            (0, 2.0 * (y + 0.5))
        } else if y > last {
            (self.image.height as usize, 2.0 * (y - last))
        } else {
            let j = clamped_index(y, last);
            (j as usize + 1, y - j as f32)
        };
        GridCell {
            column: column as usize,
            row,
            fraction: Vec2::new(x - column as f32, fy.clamp(0.0, 1.0)),
        }
    }

    /// The map bilinear between texel centres, in a cell of the sampling grid: texel columns
    /// `column` and the next (wrapped, by the padding), texel rows `row` - 1 and `row` between
    /// the centres; beyond the first and the last centre the map is constant in v (clamped).
    /// At the poles it reads the first (last) texel row twice, weighted 1 and 0: the same
    /// result as with any other row weighted 0, for finite texels.
    fn radiance_in(&self, cell: GridCell) -> Vec3 {
        // From the u32 width and height: the slice's bounds and the indices below then cannot
        // overflow, and LLVM checks the slice's once (from `usize` fields, all four).
        let (w, h) = (self.image.width as usize, self.image.height as usize);
        let between_centres = (1..h).contains(&cell.row);
        let (fx, fy) = (
            cell.fraction.x,
            if between_centres {
                cell.fraction.y
            } else {
                0.0
            },
        );
        let row = w + 1;
        let texels = &self.padded[cell.row * row + cell.column..][..row + 2];
        let (fx, fy) = (Vec3A::splat(fx), Vec3A::splat(fy));
        let (gx, gy) = (Vec3A::ONE - fx, Vec3A::ONE - fy);
        Vec3::from(
            (texels[0] * gx + texels[1] * fx) * gy + (texels[row] * gx + texels[row + 1] * fx) * fy,
        )
    }

    /// The map's radiance along `-direction`, and where the direction meets it: a pair that
    /// [`Environment::look_up`] completes into a [`SkyLookup`] (returning the `SkyLookup` from
    /// here took 0.16 % more instructions of the envmap scene's render).
    #[inline(never)]
    fn look_up(&self, direction: Vec3) -> (Vec3, MapPoint) {
        let point = self.point_of(direction);
        (self.radiance_in(point.cell), point)
    }

    /// Where `direction` (world space) meets the map.
    fn point_of(&self, direction: Vec3) -> MapPoint {
        let local = math::normalize_or(
            (self.world_to_light * Vec3A::from(direction)).into(),
            Vec3::Z,
        );
        let (uv, sin_theta) = direction_to_uv(local);
        MapPoint {
            sin_theta,
            cell: self.cell_of_uv(uv),
        }
    }

    /// [`EnvironmentMap::point_of`] of eight directions, four at a time
    /// ([`EnvironmentMap::points_of_four`]).
    fn points_of_lanes(&self, directions: &DirectionLanes) -> [MapPoint; LANES] {
        let half = |half: usize| {
            self.points_of_four(directions.map(|axis| Vec4::from_slice(&axis[4 * half..][..4])))
        };
        let (first, second) = (half(0), half(1));
        std::array::from_fn(|lane| {
            if lane < 4 {
                first[lane]
            } else {
                second[lane - 4]
            }
        })
    }

    /// [`EnvironmentMap::point_of`] of four directions (`d`: their x, y and z components), to the
    /// bit: the same operations on each lane of glam's `Vec4` (one SSE instruction each), its
    /// branches as selects, and both angles of the four by one [`math::atan2_lanes`] each
    /// (the scalar lookup's rotation, normalisation, angles and cell were about 140
    /// instructions of each escaped ray).
    fn points_of_four(&self, d: [Vec4; 3]) -> [MapPoint; 4] {
        use math::select_lanes as select;
        let zero = Vec4::ZERO;
        // glam's `Mat3A * Vec3A`: (x_axis d.x + y_axis d.y) + z_axis d.z, per component.
        let m = &self.world_to_light;
        let component = |c: usize| {
            Vec4::splat(m.x_axis[c]) * d[0]
                + Vec4::splat(m.y_axis[c]) * d[1]
                + Vec4::splat(m.z_axis[c]) * d[2]
        };
        let (x, y, z) = (component(0), component(1), component(2));
        // `math::normalize_or(.., Vec3::Z)`: glam's length, (x x + y y) + z z.
        let rcp = 1.0 / (x * x + y * y + z * z).sqrt();
        let unit = rcp.cmpgt(zero) & rcp.cmple(Vec4::splat(f32::MAX));
        let (x, y, z) = (
            select(unit, x * rcp, zero),
            select(unit, y * rcp, zero),
            select(unit, z * rcp, Vec4::ONE),
        );
        // `direction_to_uv`.
        let sin_theta = (x * x + y * y).sqrt();
        let (phi, theta) = (math::atan2_lanes(y, x), math::atan2_lanes(sin_theta, z));
        let phi = select(phi.cmplt(zero), phi + 2.0 * PI, phi);
        let (u, v) = (phi / (2.0 * PI), theta / PI);
        // `cell_of_uv`, with `wrap` and `clamped_index`.
        let width = Vec4::splat(self.size.x);
        let x = u * self.size.x - 0.5;
        let x = select(
            x.cmplt(zero),
            x + width,
            select(x.cmpge(width), x - width, x),
        );
        let y = v * self.size.y - 0.5;
        let index = |t: Vec4, last: f32| {
            let t = select(t.cmpge(zero), t, zero);
            let last = Vec4::splat(last);
            let t = select(t.cmplt(last), t, last);
            // SAFETY: t is finite, in [0, last], below 2^31 (as in `clamped_index`).
            t.to_array().map(|t| unsafe { t.to_int_unchecked::<i32>() })
        };
        let (columns, rows) = (index(x, self.last_column), index(y, self.last_row));
        let as_floats = |index: [i32; 4]| Vec4::from_array(index.map(|i| i as f32));
        let last = Vec4::splat(self.last_row);
        let (below, above) = (y.cmplt(zero), y.cmpgt(last));
        let fy = select(
            below,
            2.0 * (y + 0.5),
            select(above, 2.0 * (y - last), y - as_floats(rows)),
        );
        // `f32::clamp(0, 1)` (fy is finite).
        let fy = select(
            fy.cmplt(zero),
            zero,
            select(fy.cmpgt(Vec4::ONE), Vec4::ONE, fy),
        );
        let fx = x - as_floats(columns);
        let (below, above) = (below.bitmask(), above.bitmask());
        let h = self.image.height as usize;
        std::array::from_fn(|lane| MapPoint {
            sin_theta: sin_theta[lane],
            cell: GridCell {
                column: columns[lane] as usize,
                row: if below & (1 << lane) != 0 {
                    0
                } else if above & (1 << lane) != 0 {
                    h
                } else {
                    rows[lane] as usize + 1
                },
                fraction: Vec2::new(fx[lane], fy[lane]),
            },
        })
    }

    /// The texture coordinates of a point of the sampling grid.
    fn uv_of_grid(&self, p: Vec2) -> Vec2 {
        let half_texel = 0.5 / self.image.width as f32;
        Vec2::new(wrap(p.x + half_texel, 1.0), p.y)
    }

    /// The unit direction (in the map's frame) of a sample of the distribution, and its
    /// sin(theta): from its cell's angles where the map has them, else from its grid point.
    fn direction_of(&self, sample: &BilinearSample) -> (Vec3, f32) {
        let Some(angles) = &self.cell_angles else {
            // Both tables share the grid: either gives the point of the cell.
            let point = self.distribution.point_in(sample.cell);
            return uv_to_direction(self.uv_of_grid(point));
        };
        let GridCell {
            column,
            row,
            fraction,
        } = sample.cell;
        let (sin_theta, cos_theta) = angles.rows[row].at(fraction.y);
        let (sin_phi, cos_phi) = angles.columns[column].at(fraction.x);
        (
            Vec3::new(sin_theta * cos_phi, sin_theta * sin_phi, cos_theta),
            sin_theta,
        )
    }
}

/// Per column and per row of the sampling grid's cells, the angle at the cell's centre (phi
/// and theta) by its sine and cosine, and half its width: a point's angle in the cell is the
/// centre's plus an offset of at most half the width, whose sine and cosine
/// [`math::sin_cos_eighth_turn`] gives without range reduction when it is within pi/4, and the
/// angle addition formulas turn into the point's. [`math::sin_cos_pi`] of the point's (u, v)
/// reduced the angle and picked its quadrant with a branch for each of the two angles.
#[derive(Clone, Debug)]
struct CellAngles {
    columns: Vec<CellAngle>,
    rows: Vec<CellAngle>,
}

#[derive(Clone, Copy, Debug)]
struct CellAngle {
    sin: f32,
    cos: f32,
    half_width: f32,
}

impl CellAngles {
    /// For a map `w` texels wide whose grid rows are at `ys` (theta = pi y): cell i spans phi
    /// from texel i's centre to texel i + 1's, 2 pi (i + 1/2) / w to 2 pi (i + 3/2) / w. `None`
    /// below 4 columns or above a row of pi/2, where an offset could exceed pi/4.
    fn new(w: usize, ys: &[f32]) -> Option<Self> {
        use std::f64::consts::PI;
        let spans = |start: f64, end: f64| {
            let (sin, cos) = ((start + end) / 2.0).sin_cos();
            CellAngle {
                sin: sin as f32,
                cos: cos as f32,
                half_width: ((end - start) / 2.0) as f32,
            }
        };
        let width = 2.0 * PI / w as f64;
        let columns: Vec<CellAngle> = (0..w)
            .map(|i| spans((i as f64 + 0.5) * width, (i as f64 + 1.5) * width))
            .collect();
        let rows: Vec<CellAngle> = ys
            .windows(2)
            .map(|y| spans(PI * f64::from(y[0]), PI * f64::from(y[1])))
            .collect();
        let within = |angles: &[CellAngle]| {
            angles
                .iter()
                .all(|a| a.half_width <= std::f32::consts::FRAC_PI_4)
        };
        (within(&columns) && within(&rows)).then_some(Self { columns, rows })
    }
}

impl CellAngle {
    /// (sin, cos) of the angle at fraction `t` across the cell: centre + (2t - 1) half width.
    fn at(self, t: f32) -> (f32, f32) {
        let (sin, cos) = math::sin_cos_eighth_turn((2.0 * t - 1.0) * self.half_width);
        (
            self.sin * cos + self.cos * sin,
            self.cos * cos - self.sin * sin,
        )
    }
}

/// The radiance arriving along an escaped ray, and where its direction meets the map (none
/// for a constant sky): what [`Environment::pdf_for_mis_of`] needs for the same direction,
/// so that an escaped ray's rotation into the map and `direction_to_uv` are done once.
#[derive(Clone, Copy, Debug)]
pub struct SkyLookup {
    pub radiance: Vec3,
    point: Option<MapPoint>,
}

/// Directions looked up together by [`Environment::look_up_lanes`].
pub const LANES: usize = 8;

/// [`LANES`] directions: their x, y and z components, an array of each.
pub type DirectionLanes = [[f32; LANES]; 3];

/// Eight escaped rays' points on the map ([`Environment::look_up_lanes`]).
pub struct SkyLanes<'a> {
    radiance: Vec3,
    map: &'a EnvironmentMap,
    points: [MapPoint; LANES],
}

impl SkyLanes<'_> {
    /// Lane `lane`'s [`Environment::look_up`].
    #[inline(always)]
    pub fn look_up(&self, lane: usize) -> SkyLookup {
        let point = self.points[lane];
        SkyLookup {
            radiance: self.radiance * self.map.radiance_in(point.cell),
            point: Some(point),
        }
    }
}

#[derive(Clone, Copy, Debug)]
struct MapPoint {
    /// Of the direction in the light's frame.
    sin_theta: f32,
    /// Where it falls on the sampling grid: the lookup and the density read the same cell.
    cell: GridCell,
}

impl Environment {
    /// A map of one colour is the constant sky it amounts to: no map, its colour in the radiance.
    pub fn new(light: &InfiniteLight) -> Self {
        let image = light
            .map
            .as_ref()
            .filter(|image| image.width > 0 && image.height > 0);
        match image {
            Some(image) if image.texels.iter().all(|t| *t == image.texels[0]) => Self {
                radiance: light.radiance * image.texels[0],
                map: None,
            },
            _ => Self {
                radiance: light.radiance,
                map: image.map(|image| Box::new(EnvironmentMap::new(image, light.light_to_world))),
            },
        }
    }

    /// A sky of one radiance in every direction: next-event estimation under MIS leaves it to
    /// BSDF sampling ([`Environment::sample_for_mis`]).
    pub fn is_constant(&self) -> bool {
        self.map.is_none()
    }

    /// The radiance from every direction of a constant sky; `None` for a map.
    pub fn constant_radiance(&self) -> Option<Vec3> {
        self.is_constant().then_some(self.radiance)
    }

    /// Radiance arriving along `-direction` (from `direction`).
    pub fn radiance(&self, direction: Vec3) -> Vec3 {
        self.look_up(direction).radiance
    }

    /// Radiance arriving along `-direction`, with what `pdf_for_mis_of` needs. Inline, with the
    /// map's lookup out of line ([`EnvironmentMap::look_up`]): the escaped ray's branch of the
    /// integrator's vertex then stays small for a constant sky, where inlining the map's
    /// lookup too took up to 1.5 % more instructions of the whole render (the furnace scene).
    #[inline]
    pub fn look_up(&self, direction: Vec3) -> SkyLookup {
        match &self.map {
            None => SkyLookup {
                radiance: self.radiance,
                point: None,
            },
            Some(map) => {
                let (radiance, point) = map.look_up(direction);
                SkyLookup {
                    radiance: self.radiance * radiance,
                    point: Some(point),
                }
            }
        }
    }

    /// [`Environment::look_up`] of eight directions, to the bit, for a
    /// sky with a map (none for a constant one, which has nothing to look up): where they meet
    /// the map, found in lanes; each lane's radiance is read when asked for
    /// ([`SkyLanes::look_up`]), so that the eight lookups are not held at once.
    pub fn look_up_lanes(&self, directions: &DirectionLanes) -> Option<SkyLanes<'_>> {
        let map = self.map.as_ref()?;
        Some(SkyLanes {
            radiance: self.radiance,
            map,
            points: map.points_of_lanes(directions),
        })
    }

    /// A direction with density proportional to the map's luminance (uniform without a map).
    pub fn sample(&self, u: Vec2) -> Option<LightSample> {
        self.sample_from(u, false)
    }

    /// For a light sample that MIS combines with BSDF sampling: the density follows the
    /// luminance less the sky's mean, zero where the sky is dimmer than its mean. MIS
    /// compensation (Karlík et al. 2019, "MIS Compensation: Optimizing Sampling Techniques in
    /// Multiple Importance Sampling"; pbrt-v4's `ImageInfiniteLight` `compensatedDistribution`
    /// with `allowIncompletePDF`): BSDF sampling already covers the dim sky well, so light
    /// samples are better spent on what stands out. Unbiased as long as BSDF sampling covers
    /// every direction light sampling now misses, which holds where MIS is used (non-delta
    /// BSDFs; `tests/bsdf_sampling_coverage.rs` checks each kind); `pdf_for_mis_of` is the matching
    /// density for the BSDF sample's MIS weight.
    ///
    /// A constant sky less its mean is nothing: no sample, density 0 everywhere (pbrt-v4's
    /// `UniformInfiniteLight::SampleLi` and `PDF_Li` with `allowIncompletePDF`). A BSDF-sampled
    /// ray that escapes then has MIS weight 1, and the sky's share of the light samples goes
    /// to the other lights ([`super::LightTable`]). The estimate of the sky's light is then
    /// L f cos / p_bsdf alone: for a Lambertian surface, sampled by cos / pi, exactly L times
    /// its albedo wherever the sky is unoccluded, with no variance left.
    pub fn sample_for_mis(&self, u: Vec2) -> Option<LightSample> {
        if self.is_constant() {
            return None;
        }
        self.sample_from(u, true)
    }

    fn sample_from(&self, u: Vec2, compensated: bool) -> Option<LightSample> {
        let (wi, radiance, pdf) = match &self.map {
            None => (uniform_sphere(u), self.radiance, uniform_sphere_pdf()),
            Some(map) => {
                let sample = map.table(compensated).sample(u)?;
                let (local, sin_theta) = map.direction_of(&sample);
                if sample.pdf <= 0.0 || sin_theta <= 0.0 {
                    return None;
                }
                // The radiance is read in the sampled cell at the sampled fractions: the round
                // trip through the direction (a rotation, atan2 and acos) cost half of the
                // sample and only moved (u, v) by rounding, and the cell is the lookup's. The
                // (u, v) -> direction map has Jacobian 2 pi^2 sin(theta). With M^T M = I + E,
                // |E_ij| <= 1e-6, |M d|^2 = 1 + d^T E d: a unit d stays unit within 2e-6.
                let wi = Vec3::from(map.light_to_world * Vec3A::from(local));
                (
                    if map.keeps_lengths {
                        wi
                    } else {
                        math::normalize_or(wi, Vec3::Z)
                    },
                    self.radiance * map.radiance_in(sample.cell),
                    sample.pdf / (2.0 * PI * PI * sin_theta),
                )
            }
        };
        Some(LightSample {
            wi,
            distance: f32::INFINITY,
            radiance,
            pdf,
            delta: false,
        })
    }

    /// Solid-angle density of `sample` choosing `direction`.
    pub fn pdf(&self, direction: Vec3) -> f32 {
        self.pdf_from(direction, false)
    }

    /// Solid-angle density of `sample_for_mis` choosing the direction of `lookup`.
    #[inline]
    pub fn pdf_for_mis_of(&self, lookup: &SkyLookup) -> f32 {
        if self.is_constant() {
            return 0.0;
        }
        self.pdf_at(lookup.point, true)
    }

    fn pdf_from(&self, direction: Vec3, compensated: bool) -> f32 {
        let point = self.map.as_ref().map(|map| map.point_of(direction));
        self.pdf_at(point, compensated)
    }

    /// The density at a direction's `point` on the map (none for a constant sky). Inline: out
    /// of line, its call for each escaped ray took 0.8 % more instructions of the envmap
    /// scene's render.
    #[inline]
    fn pdf_at(&self, point: Option<MapPoint>, compensated: bool) -> f32 {
        match (&self.map, point) {
            (Some(map), Some(point)) => {
                if point.sin_theta <= 0.0 {
                    return 0.0;
                }
                map.table(compensated).pdf_in_cell(point.cell) / (2.0 * PI * PI * point.sin_theta)
            }
            _ => uniform_sphere_pdf(),
        }
    }

    /// The power that reaches the scene: the flux through the bounding sphere's cross-section
    /// (a disk of radius r lit from one side by mean radiance L receives pi L * pi r^2). pbrt-v4
    /// counts all the flux through the sphere (4 pi^2 r^2 L), four times more, most of which
    /// passes the scene by; the cross-section is what a distant light's power counts too.
    pub fn power(&self, scene_radius: f32) -> f32 {
        let mean = match &self.map {
            None => luminance(self.radiance),
            Some(map) => {
                let texels = &map.image.texels;
                let total: f32 = texels.iter().map(|t| luminance(*t)).sum();
                total / texels.len().max(1) as f32 * luminance(self.radiance)
            }
        };
        PI * PI * scene_radius * scene_radius * mean
    }
}

/// `x` wrapped into [0, `period`): `rem_euclid` to the bit for x in (-period, 2 period) (one
/// exact addition or subtraction, by Sterbenz's lemma for the latter) without its `fmod` call,
/// which was a tenth of each lookup; the callers' values lie within half a texel of that range.
fn wrap(x: f32, period: f32) -> f32 {
    if x < 0.0 {
        x + period
    } else if x >= period {
        x - period
    } else {
        x
    }
}

/// `t` truncated to an integer and clamped to [0, `last`] (NaN to 0), for `last` an integer
/// below 2^31: what `(t as i32).max(0).min(last)` gives, with the clamp on the float, which
/// makes the conversion an unchecked one instruction (`as i32` saturates, in five more).
fn clamped_index(t: f32, last: f32) -> i32 {
    let t = if t >= 0.0 { t } else { 0.0 };
    let t = if t < last { t } else { last };
    // SAFETY: t is finite, in [0, last], below 2^31.
    unsafe { t.to_int_unchecked::<i32>() }
}

/// Latitude-longitude: u = phi / 2pi around +z, v = theta / pi from +z; and sin(theta) (of a
/// unit `d`). theta = acos(z) taken as atan2(sqrt(x^2 + y^2), z), accurate at the poles too,
/// and both angles by [`math::atan2_lanes`], in two lanes of one evaluation: libm's `atan2f`
/// and `acosf` were about 180 instructions of each escaped ray's lookup, two
/// [`math::atan2`]s 70.
fn direction_to_uv(d: Vec3) -> (Vec2, f32) {
    let sin_theta = (d.x * d.x + d.y * d.y).sqrt();
    let angles = math::atan2_lanes(
        Vec4::new(d.y, sin_theta, 0.0, 0.0),
        Vec4::new(d.x, d.z, 1.0, 1.0),
    );
    let (phi, theta) = (angles.x, angles.y);
    let phi = if phi < 0.0 { phi + 2.0 * PI } else { phi };
    (Vec2::new(phi / (2.0 * PI), theta / PI), sin_theta)
}

/// The unit direction of texture coordinates `uv`, and its sin(theta): phi = 2 pi u and
/// theta = pi v by [`math::sin_cos_pi`] (libm's `sinf`, `cosf` and `sincosf` were a fifth
/// of each light sample).
fn uv_to_direction(uv: Vec2) -> (Vec3, f32) {
    let (sin_theta, cos_theta) = math::sin_cos_pi(uv.y);
    let (sin_phi, cos_phi) = math::sin_cos_pi(2.0 * uv.x);
    (
        Vec3::new(sin_theta * cos_phi, sin_theta * sin_phi, cos_theta),
        sin_theta,
    )
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use super::*;
    use crate::sampling::PathRng;

    /// A `w` x `h` image of `texels`, rows from the top, unscaled and unwrapped.
    fn image_of(w: usize, h: usize, texels: Vec<Vec3>) -> ImageTexture {
        ImageTexture {
            width: w as u32,
            height: h as u32,
            texels: Arc::new(texels),
            scale: Vec2::ONE,
            delta: Vec2::ZERO,
            wrap: Default::default(),
        }
    }

    /// A 64 x 32 map constant along each column: grey 0.5 with a band of three columns at 40
    /// (a sun's contrast), 0.5 / 40 / 0.5 steps that the bilinear lookup ramps across.
    fn banded_sky() -> Environment {
        let (w, h) = (64, 32);
        let texels = (0..w * h)
            .map(|i| {
                Vec3::splat(if (20..23).contains(&(i % w)) {
                    40.0
                } else {
                    0.5
                })
            })
            .collect();
        let image = image_of(w, h, texels);
        Environment::new(&InfiniteLight {
            radiance: Vec3::ONE,
            map: Some(image),
            light_to_world: Mat3::from_rotation_x(0.3),
        })
    }

    /// `clamped_index` is `(t as i32).max(0).min(last)`: on and beside every integer up to
    /// `last` and beyond it, negatives, huge values, the infinities and NaN.
    #[test]
    fn clamped_index_is_the_saturating_conversion_clamped() {
        for last in [0.0f32, 1.0, 31.0, 63.0, 16_777_215.0] {
            let mut ts = vec![
                -0.0,
                -0.5,
                -1e30,
                3e9,
                f32::MAX,
                f32::INFINITY,
                f32::NEG_INFINITY,
                f32::NAN,
            ];
            for k in -2..=(last.min(100.0) as i32 + 2) {
                let k = k as f32;
                ts.extend([k, k.next_up(), k.next_down(), k + 0.5]);
            }
            ts.extend([last, last.next_up(), last.next_down(), last + 1.0]);
            for t in ts {
                let expected = (t as i32).max(0).min(last as i32);
                assert_eq!(clamped_index(t, last), expected, "{t:e} in [0, {last}]");
            }
        }
    }

    /// The lookup (padded texels) against the bilinear formula written out: u wrapped by
    /// `rem_euclid`, the neighbour column (i + 1) mod w, rows clamped to the image, on a map of
    /// distinct texels, at points all over it and at the seam and the poles. The same
    /// operations in the same order: equal up to a few ulps (1e-6 relative); a wrong neighbour
    /// is off by a whole texel step.
    #[test]
    fn lookup_is_the_wrapped_and_clamped_bilinear_formula() {
        let (w, h) = (5usize, 4usize);
        let texels: Vec<Vec3> = (0..w * h)
            .map(|t| Vec3::new(t as f32 + 1.0, (t * t % 7) as f32 + 0.5, 20.0 - t as f32))
            .collect();
        let image = image_of(w, h, texels.clone());
        let map = EnvironmentMap::new(&image, Mat3::IDENTITY);
        let formula = |uv: Vec2| {
            let x = (uv.x * w as f32 - 0.5).rem_euclid(w as f32);
            let y = (uv.y * h as f32 - 0.5).clamp(0.0, (h - 1) as f32);
            let (i, j) = ((x as usize).min(w - 1), (y as usize).min(h - 1));
            let (fx, fy) = (x - i as f32, y - j as f32);
            let (i1, j1) = ((i + 1) % w, (j + 1).min(h - 1));
            let at = |i: usize, j: usize| texels[j * w + i];
            (at(i, j) * (1.0 - fx) + at(i1, j) * fx) * (1.0 - fy)
                + (at(i, j1) * (1.0 - fx) + at(i1, j1) * fx) * fy
        };
        let mut points: Vec<Vec2> = (0..=60)
            .flat_map(|a| (0..=40).map(move |b| Vec2::new(a as f32 / 60.0, b as f32 / 40.0)))
            .collect();
        points.extend([
            Vec2::new(0.0, 0.0),
            Vec2::new(0.999_999_9, 0.999_999_9),
            Vec2::new(0.1 / w as f32, 0.5),
            Vec2::new(1.0 - 0.1 / w as f32, 0.01),
        ]);
        for uv in points {
            let (got, expected) = (map.radiance_in(map.cell_of_uv(uv)), formula(uv));
            assert!(
                (got - expected).abs().max_element() <= 1e-6 * expected.abs().max_element(),
                "{uv}: {got} against {expected}"
            );
        }
    }

    /// The lookup in lanes is the scalar one to the bit (radiance, sin theta, cell and
    /// fractions) on a map of distinct texels under a sky rotated about all three axes (a
    /// rotation about one leaves zeros that hid the rotation's sum reassociated, tried), for
    /// directions all over the sphere, along the seam, at the poles, on the axes, unnormalised,
    /// zero and not finite; a lane's operation out of order or a select the wrong way round
    /// moves some bits.
    #[test]
    fn lookup_in_lanes_is_the_scalar_lookup_to_the_bit() {
        let texels = (0..64 * 32)
            .map(|i| Vec3::new(((i * 7919) % 13) as f32 + 0.25, (i % 64) as f32, 1.0))
            .collect();
        let light_to_world =
            Mat3::from_rotation_y(0.6) * Mat3::from_rotation_x(0.3) * Mat3::from_rotation_z(0.2);
        let sky = Environment::new(&InfiniteLight {
            radiance: Vec3::new(1.5, 1.0, 0.5),
            map: Some(image_of(64, 32, texels)),
            light_to_world,
        });
        let mut directions: Vec<Vec3> = (0..4000)
            .map(|k| {
                let (u, v) = ((k as f32 * 0.618_034).fract(), (k as f32 + 0.5) / 4000.0);
                uv_to_direction(Vec2::new(u, v)).0 * (1.0 + (k % 3) as f32)
            })
            .collect();
        for k in 0..200 {
            let seam = uv_to_direction(Vec2::new(0.5 / 64.0, k as f32 / 200.0)).0;
            directions.extend([light_to_world * seam, light_to_world * -seam]);
        }
        directions.extend([
            Vec3::X,
            -Vec3::X,
            Vec3::Y,
            -Vec3::Y,
            Vec3::Z,
            -Vec3::Z,
            light_to_world * Vec3::Z,
            light_to_world * -Vec3::Z,
            Vec3::ZERO,
            Vec3::new(f32::NAN, 0.0, 1.0),
            Vec3::new(f32::INFINITY, 1.0, 0.0),
        ]);
        let bits = |l: &SkyLookup| {
            let point = l.point.expect("a map's point");
            let cell = point.cell;
            (
                l.radiance.to_array().map(f32::to_bits),
                point.sin_theta.to_bits(),
                (cell.column, cell.row),
                cell.fraction.to_array().map(f32::to_bits),
            )
        };
        for chunk in directions.chunks(LANES) {
            let mut lanes = DirectionLanes::default();
            for (lane, d) in chunk.iter().enumerate() {
                (lanes[0][lane], lanes[1][lane], lanes[2][lane]) = (d.x, d.y, d.z);
            }
            let got = sky.look_up_lanes(&lanes).expect("a map");
            for (lane, &d) in chunk.iter().enumerate() {
                assert_eq!(bits(&got.look_up(lane)), bits(&sky.look_up(d)), "{d}");
            }
        }
    }

    /// Light samples in lanes are `sample_for_mis`'s to the bit (whether there is one, its
    /// direction, radiance and density), four at a time under a rotation (about all three axes)
    /// and one by one under a transform that scales or on a map too narrow for cell angles, for
    /// 2D samples all over the square, on and beside its edges, outside it and NaN, on a map of
    /// distinct texels with black ones (densities of 0, and compensated zeros) and on one that
    /// is black but for one texel. A lane's operation out of order or a select the wrong way
    /// round moves some bits.
    #[test]
    fn light_samples_in_lanes_are_the_scalar_ones_to_the_bit() {
        let rotation =
            Mat3::from_rotation_y(0.6) * Mat3::from_rotation_x(0.3) * Mat3::from_rotation_z(0.2);
        let distinct = |w: usize, h: usize| {
            image_of(
                w,
                h,
                (0..w * h)
                    .map(|i| {
                        let v = ((i * 7919) % 13) as f32;
                        Vec3::new(if v < 3.0 { 0.0 } else { v + 0.25 }, (i % w) as f32, 1.0)
                    })
                    .collect(),
            )
        };
        let mut one_texel = vec![Vec3::ZERO; 64 * 32];
        one_texel[5 * 64 + 17] = Vec3::new(30.0, 20.0, 10.0);
        let skies = [
            (distinct(64, 32), rotation, true),
            (image_of(64, 32, one_texel), rotation, true),
            (distinct(64, 32), rotation * 2.0, false),
            (distinct(3, 4), rotation, false),
        ];
        let us = crate::sampling::test_samples_with_edges();
        for (image, light_to_world, in_fours) in skies {
            let sky = Environment::new(&InfiniteLight {
                radiance: Vec3::new(1.5, 1.0, 0.5),
                map: Some(image),
                light_to_world,
            });
            let map = sky.map.as_ref().expect("a map");
            assert_eq!(map.cell_angles.is_some() && map.keeps_lengths, in_fours);
            let mut sampled = 0;
            for chunk in us.chunks(LANES) {
                let mut u = [[0.5; LANES]; 2];
                for (lane, v) in chunk.iter().enumerate() {
                    (u[0][lane], u[1][lane]) = (v.x, v.y);
                }
                let lanes = sky.sample_for_mis_lanes(&u);
                let got: [Option<LightSample>; LANES] = std::array::from_fn(|lane| {
                    lanes.sampled[lane].then(|| LightSample {
                        wi: Vec3::from_array([0, 1, 2].map(|axis| lanes.wi[axis][lane])),
                        distance: f32::INFINITY,
                        radiance: Vec3::from_array(
                            [0, 1, 2].map(|axis| lanes.radiance[axis][lane]),
                        ),
                        pdf: lanes.pdf[lane],
                        delta: false,
                    })
                });
                // Bits, any NaN as one (from a NaN sample; which NaN an operation passes on
                // may depend on its operands' order, and the path drops it).
                let bits = |sample: Option<LightSample>| {
                    let bits = |x: f32| if x.is_nan() { u32::MAX } else { x.to_bits() };
                    sample.map(|s| {
                        (
                            [s.wi, s.radiance].map(|v| v.to_array().map(bits)),
                            [s.pdf, s.distance].map(bits),
                            s.delta,
                        )
                    })
                };
                for (lane, got) in got.into_iter().enumerate() {
                    let expected = sky.sample_for_mis(Vec2::new(u[0][lane], u[1][lane]));
                    assert_eq!(bits(got), bits(expected), "{u:?} {lane}");
                    sampled += usize::from(expected.is_some());
                }
            }
            assert!(sampled > 3000, "{sampled}");
        }
    }

    /// The density read in the lookup's cell (`cell_of_uv`, as escaped rays do) against the
    /// distribution's own search (`Bilinear2D::pdf` at the grid point of (u, v)), for both
    /// tables of a map of distinct texels: at points all over it, beside the seam, the texel
    /// centres and the poles, where the half-texel rows are not the lookup's. Equal up to the
    /// rounding of the fractions (1e-4 relative, and 1e-5 of the mean density 1 where the
    /// density nears 0 at the poles); a wrong cell or pole fraction is off by a texel's step,
    /// a hundredth of the mean density or more.
    #[test]
    fn density_in_the_lookups_cell_is_the_distributions() {
        let (w, h) = (6usize, 5usize);
        let texels: Vec<Vec3> = (0..w * h)
            .map(|t| Vec3::splat(((t * 7919) % 13) as f32 + 0.25))
            .collect();
        let image = image_of(w, h, texels);
        let map = EnvironmentMap::new(&image, Mat3::IDENTITY);
        let mut points: Vec<Vec2> = (0..=120)
            .flat_map(|a| (0..=100).map(move |b| Vec2::new(a as f32 / 120.0, b as f32 / 100.0)))
            .collect();
        for k in 0..=2 * h {
            let v = k as f32 / (2 * h) as f32;
            for u in [0.0, 0.3, 0.5 / w as f32, 1.0 - 0.01 / w as f32] {
                points.extend([Vec2::new(u, v), Vec2::new(u, v.next_up())]);
                points.push(Vec2::new(u, v.next_down().max(0.0)));
            }
        }
        let tables = [Some(&map.distribution), map.compensated.as_ref()];
        assert!(tables[1].is_some());
        for table in tables.into_iter().flatten() {
            for &uv in &points {
                let grid = Vec2::new((uv.x - 0.5 / w as f32).rem_euclid(1.0), uv.y);
                let (got, expected) = (table.pdf_in_cell(map.cell_of_uv(uv)), table.pdf(grid));
                assert!(
                    (got - expected).abs() <= 1e-4 * expected + 1e-5,
                    "{uv}: {got} against {expected}"
                );
            }
        }
    }

    /// Sampled directions are unit within 2e-6 (the bound derived at `keeps_lengths`) whether
    /// the sky's transform is a rotation, whose product keeps them unit without normalising,
    /// or scales (a scene may give one), where they must be normalised; a scaled transform
    /// taken for a rotation gives lengths of 2 or 0.5.
    #[test]
    fn sampled_directions_are_unit_under_any_transform() {
        let texels = (0..64 * 32)
            .map(|i| Vec3::splat(((i * 7919) % 13) as f32 + 0.25))
            .collect();
        let image = image_of(64, 32, texels);
        let rotation = Mat3::from_rotation_y(0.6) * Mat3::from_rotation_x(0.3);
        for (light_to_world, rotates) in [
            (rotation, true),
            (rotation * 2.0, false),
            (
                Mat3::from_diagonal(Vec3::new(1.0, 0.5, 1.0)) * rotation,
                false,
            ),
        ] {
            let sky = Environment::new(&InfiniteLight {
                radiance: Vec3::ONE,
                map: Some(image.clone()),
                light_to_world,
            });
            assert_eq!(sky.map.as_ref().unwrap().keeps_lengths, rotates);
            let mut rng = PathRng::new(5, 0, 0);
            for _ in 0..10_000 {
                for sample in [sky.sample(rng.next_2d()), sky.sample_for_mis(rng.next_2d())] {
                    let wi = sample.expect("a sample").wi;
                    assert!((wi.length() - 1.0).abs() <= 2e-6, "{light_to_world}: {wi}");
                }
            }
        }
    }

    /// A sample's direction from its cell's angles against `uv_to_direction` of its grid
    /// point (within 1.2e-7 of exact, tested in math): on a 64 x 32 map at fractions 0, 1 and
    /// between in every cell (the poles' half rows too), within 4e-7 in each component and in
    /// sin(theta) (the tables' rounding, an ulp from the polynomial, two from the addition
    /// formulas); a wrong centre or width is off by a cell's angle. Maps of fewer than 4
    /// columns have no tables.
    #[test]
    fn direction_from_the_cells_angles_is_the_grid_points() {
        let (w, h) = (64usize, 32usize);
        let image = image_of(w, h, vec![Vec3::ONE; w * h]);
        let map = EnvironmentMap::new(&image, Mat3::IDENTITY);
        assert!(map.cell_angles.is_some());
        let ys = map.distribution.ys();
        let xs: Vec<f32> = (0..=w).map(|i| i as f32 / w as f32).collect();
        for row in 0..ys.len() - 1 {
            for column in 0..w {
                for (tx, ty) in [
                    (0.0, 0.0),
                    (1.0, 1.0),
                    (0.3, 0.7),
                    (0.999, 0.5),
                    (0.5, 0.01),
                ] {
                    let lerp = |a: f32, b: f32, t: f32| (1.0 - t) * a + t * b;
                    let point = Vec2::new(
                        lerp(xs[column], xs[column + 1], tx),
                        lerp(ys[row], ys[row + 1], ty),
                    );
                    let sample = BilinearSample {
                        pdf: 1.0,
                        cell: GridCell {
                            column,
                            row,
                            fraction: Vec2::new(tx, ty),
                        },
                    };
                    let (got, sin_got) = map.direction_of(&sample);
                    let (expected, sin_expected) = uv_to_direction(map.uv_of_grid(point));
                    assert!(
                        (got - expected).abs().max_element() <= 4e-7
                            && (sin_got - sin_expected).abs() <= 4e-7,
                        "{sample:?}: {got} {sin_got} against {expected} {sin_expected}"
                    );
                }
            }
        }
        let narrow = image_of(3, 4, vec![Vec3::ONE; 12]);
        assert!(
            EnvironmentMap::new(&narrow, Mat3::IDENTITY)
                .cell_angles
                .is_none()
        );
    }

    /// Light sampling alone estimates the sky's integral over the sphere, X = Y(L) / pdf.
    ///
    /// With the map constant along each column, the density is l(u) S(v) / I in (u, v)
    /// (l the lookup's luminance, piecewise linear in u; S the piecewise-linear interpolant of
    /// sin(pi v) through the vertex rows), so X = 2 pi^2 I sin(theta) / S(v): the map cancels
    /// and only rho(v) = sin(pi v) / S(v) varies. sin is concave, so each chord lies below it:
    /// 1 <= rho <= rho_max (found below by scanning v). By Popoviciu's inequality
    /// Var(rho) <= (rho_max - 1)^2 / 4, and E(rho) >= 1, so the relative variance of X is at most
    /// (rho_max - 1)^2 / 4 (about 4e-7 for 32 rows) at any sample count: a deterministic bound
    /// on the sample variance too. A piecewise-constant distribution over the texels puts the
    /// grey texels' density under the lookup's ramps towards the band, where X is up to 40
    /// times its mean: relative variance above 0.1.
    #[test]
    fn sampling_the_bilinear_lookup_leaves_only_the_sine_interpolation_error() {
        let sky = banded_sky();
        let h = 32;
        let rows: Vec<f32> = std::iter::once(0.0)
            .chain((0..h).map(|j| (j as f32 + 0.5) / h as f32))
            .chain(std::iter::once(1.0))
            .collect();
        let rho_max = (1..100_000)
            .map(|k| {
                let v = k as f32 / 100_000.0;
                let j = rows.partition_point(|&r| r <= v) - 1;
                let t = (v - rows[j]) / (rows[j + 1] - rows[j]);
                let chord = (1.0 - t) * (PI * rows[j]).sin() + t * (PI * rows[j + 1]).sin();
                (PI * v).sin() / chord
            })
            .fold(1.0f32, f32::max);
        let bound = f64::from((rho_max - 1.0).powi(2) / 4.0);

        let n = 20_000;
        let mut rng = PathRng::new(7, 0, 0);
        let values: Vec<f64> = (0..n)
            .map(|_| {
                let sample = sky.sample(rng.next_2d()).expect("a sample");
                let pdf = sky.pdf(sample.wi);
                assert!(
                    (pdf - sample.pdf).abs() <= 1e-3 * sample.pdf,
                    "{pdf} {}",
                    sample.pdf
                );
                f64::from(luminance(sample.radiance) / sample.pdf)
            })
            .collect();
        let mean = values.iter().sum::<f64>() / n as f64;
        let variance = values.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1) as f64;
        // f32 rounding of directions and densities adds ~1e-6 relative noise: 1e-11 variance.
        assert!(
            variance / (mean * mean) <= bound + 1e-10,
            "relative variance {:e} above the bound {bound:e}",
            variance / (mean * mean)
        );
        // Unbiased: the integral of a map constant in theta is 4 pi times its mean texel (the
        // piecewise-linear interpolant in u has the texels' mean). Four standard deviations of
        // the mean under the bound, plus f32 rounding.
        let exact = 4.0 * std::f64::consts::PI * (61.0 * 0.5 + 3.0 * 40.0) / 64.0;
        let tolerance = 4.0 * (bound / n as f64).sqrt() + 1e-5;
        assert!(
            (mean / exact - 1.0).abs() < tolerance,
            "mean {mean}, exact {exact}, tolerance {tolerance:e}"
        );
    }

    /// MIS compensation keeps the estimator unbiased: irradiance at a point under the banded
    /// sky, by light samples from `sample_for_mis` and cosine-weighted BSDF samples combined
    /// with the power heuristic (each weighted with the other's density, `pdf_for_mis_of` for the
    /// light), against the integral by quadrature. The light density is zero over the grey sky
    /// (below the mean), which BSDF sampling alone then covers with weight 1.
    #[test]
    fn compensated_light_sampling_under_mis_is_unbiased() {
        use crate::bsdf::frame::Frame;
        use crate::sampling::warp::{cosine_hemisphere, power_heuristic};

        let sky = banded_sky();
        let normal = Vec3::new(0.3, 0.5, 0.8).normalize();
        let frame = Frame::from_z(normal);
        // Midpoint quadrature over (u, v), d omega = 2 pi^2 sin(theta) du dv.
        let (nu, nv) = (2048, 1024);
        let light_to_world = Mat3::from_rotation_x(0.3);
        let mut exact = 0.0f64;
        for k in 0..nu * nv {
            let uv = Vec2::new((k % nu) as f32 + 0.5, (k / nu) as f32 + 0.5)
                / Vec2::new(nu as f32, nv as f32);
            let (local, sin_theta) = uv_to_direction(uv);
            let wi = light_to_world * local;
            let cos = wi.dot(normal).max(0.0);
            exact += f64::from(luminance(sky.radiance(wi)) * cos / PI * sin_theta);
        }
        exact *= 2.0 * std::f64::consts::PI.powi(2) / (nu * nv) as f64;

        let n = 200_000;
        let mut rng = PathRng::new(11, 0, 0);
        let values: Vec<f64> = (0..n)
            .map(|_| {
                let mut total = 0.0;
                if let Some(sample) = sky.sample_for_mis(rng.next_2d()) {
                    let cos = sample.wi.dot(normal);
                    if cos > 0.0 {
                        let weight = power_heuristic(1, sample.pdf, 1, cos / PI);
                        total += luminance(sample.radiance) * cos / PI * weight / sample.pdf;
                    }
                }
                let wi = frame.to_world(cosine_hemisphere(rng.next_2d()));
                let bsdf_pdf = wi.dot(normal) / PI;
                if bsdf_pdf > 0.0 {
                    let seen = sky.look_up(wi);
                    let weight = power_heuristic(1, bsdf_pdf, 1, sky.pdf_for_mis_of(&seen));
                    // f cos / pdf = 1 for a white diffuse surface.
                    total += luminance(seen.radiance) * weight;
                }
                f64::from(total)
            })
            .collect();
        let mean = values.iter().sum::<f64>() / n as f64;
        let variance = values.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1) as f64;
        // Four standard errors, plus the quadrature's error (kinks of the bilinear lookup and
        // of the horizon, well under 1e-4 relative at this resolution).
        let tolerance = 4.0 * (variance / n as f64).sqrt() + 1e-4 * exact;
        assert!(
            (mean - exact).abs() < tolerance,
            "mean {mean}, exact {exact}, tolerance {tolerance}"
        );
    }
}
