//! A piecewise-bilinear 2D distribution: the density is the bilinear interpolant of values
//! given at the vertices of a rectangular grid, sampled exactly.
//!
//! A function looked up with bilinear filtering is piecewise bilinear between texel centres;
//! a piecewise-constant distribution over the texels (pbrt-v3 §14.2.4) then puts a texel's
//! density under the interpolant's ramp towards a much brighter neighbour, and the ratio
//! f / p there is as large as the contrast. Sampling the interpolant itself keeps f / p
//! constant. Mitsuba 3's environment map does the same with its `Hierarchical2D` warp over the
//! texels as vertices (`src/emitters/envmap.cpp`).
//!
//! Sampling: a cell is chosen with probability its integral over the total, by one alias table
//! over all cells (O(1); a row from the marginal and then a cell from that row's conditional,
//! as before, took two alias draws, one dependent on the other); `u.x` picks the cell and its
//! remainder, uniform and independent of the choice, is reused inside the cell. There y is
//! drawn from the marginal of the bilinear patch (linear in y) with `u.y`, then x from the
//! patch's conditional at that y (linear in x): pbrt-v4's `SampleBilinear`
//! (`util/sampling.h`).

use std::ops::{Add, Mul, Sub};

use glam::{Vec2, Vec4};

use super::{AliasTable, Divisor, ONE_MINUS_EPSILON};
use crate::math::select_lanes as select;

#[derive(Clone, Debug)]
pub struct Bilinear2D {
    /// Vertex values over the integral, row-major (`ys.len()` rows of `xs.len()`): the
    /// interpolant of these is the density, without a division per sample or lookup.
    density: Vec<f32>,
    xs: Axis,
    ys: Axis,
    /// Over all cells, row-major, by their integrals.
    cells: AliasTable,
    /// Cells per row: a cell's index splits into row and column by multiplication.
    columns: Divisor,
    /// 0 when not finite (the values' f32 sum overflowed): then nothing is sampled.
    integral: f32,
}

impl Bilinear2D {
    /// `values` at the vertices (`xs[i]`, `ys[j]`), row-major; `xs` and `ys` increasing, at
    /// least two each. Negative and non-finite values count as 0.
    pub fn new(values: &[f32], xs: Vec<f32>, ys: Vec<f32>) -> Self {
        assert!(xs.len() >= 2 && ys.len() >= 2 && values.len() == xs.len() * ys.len());
        let values: Vec<f32> = values
            .iter()
            .map(|&v| if v.is_finite() && v > 0.0 { v } else { 0.0 })
            .collect();
        let nx = xs.len();
        let at = |i: usize, j: usize| f64::from(values[j * nx + i]);
        // A bilinear patch's integral is its area times the mean of its four corners.
        let cell_integrals: Vec<Vec<f64>> = (0..ys.len() - 1)
            .map(|j| {
                let height = f64::from(ys[j + 1] - ys[j]);
                (0..nx - 1)
                    .map(|i| {
                        let width = f64::from(xs[i + 1] - xs[i]);
                        let corners = at(i, j) + at(i + 1, j) + at(i, j + 1) + at(i + 1, j + 1);
                        width * height * corners / 4.0
                    })
                    .collect()
            })
            .collect();
        let integral = cell_integrals.iter().flatten().sum::<f64>() as f32;
        let integral = if integral.is_finite() { integral } else { 0.0 };
        let cell_integrals: Vec<f32> = cell_integrals.iter().flatten().map(|&v| v as f32).collect();
        Self {
            cells: AliasTable::new(&cell_integrals),
            columns: Divisor::new((nx - 1) as u32),
            density: if integral > 0.0 {
                values.iter().map(|&v| v / integral).collect()
            } else {
                values
            },
            integral,
            xs: Axis::new(xs),
            ys: Axis::new(ys),
        }
    }

    /// The vertices' positions in y.
    pub fn ys(&self) -> &[f32] {
        &self.ys.positions
    }

    /// The interpolant's integral over the grid (0 if it overflows f32).
    pub fn integral(&self) -> f32 {
        self.integral
    }

    /// A point of the grid with density interpolant / integral, by its cell and fractions (see
    /// [`Bilinear2D::point_in`]) with that density; `None` when the interpolant is zero
    /// everywhere. Inline: returned through memory, the sample took a sixth more instructions
    /// (0.7 % of the environment-lit peer scene's render).
    #[inline]
    pub fn sample(&self, u: Vec2) -> Option<BilinearSample> {
        if self.integral <= 0.0 {
            return None;
        }
        let (k, ux) = self.cells.sample_index(u.x);
        let k = k as u32;
        let (j, i) = (
            self.columns.quotient(k) as usize,
            self.columns.remainder(k) as usize,
        );
        let [v00, v10, v01, v11] = self.corners(i, j);
        let ty = sample_linear(u.y, v00 + v10, v01 + v11);
        let (left, right) = (lerp(v00, v01, ty), lerp(v10, v11, ty));
        let tx = sample_linear(ux, left, right);
        Some(BilinearSample {
            pdf: lerp(left, right, tx),
            cell: GridCell {
                column: i,
                row: j,
                fraction: Vec2::new(tx, ty),
            },
        })
    }

    /// [`Bilinear2D::sample`] of four points (`u`: their x and y), to the bit: the alias
    /// table's [`AliasTable::sample_index_four`], each lane's corners read alone, and the two
    /// linear warps and the lerps on the four lanes of glam's `Vec4`, in the same operations.
    /// For the environment map's light samples taken four at a time.
    #[inline]
    pub fn sample_four(&self, u: [Vec4; 2]) -> Option<BilinearFour> {
        if self.integral <= 0.0 {
            return None;
        }
        let (k, ux) = self.cells.sample_index_four(u[0]);
        // Plain loops: `array::map` with a bounds check inside was not inlined.
        let (mut columns, mut rows, mut corners) = ([0; 4], [0; 4], [[0.0; 4]; 4]);
        for lane in 0..4 {
            let k = k[lane] as u32;
            (columns[lane], rows[lane]) = (
                self.columns.remainder(k) as usize,
                self.columns.quotient(k) as usize,
            );
            let values = self.corners(columns[lane], rows[lane]);
            for (corner, value) in corners.iter_mut().zip(values) {
                corner[lane] = value;
            }
        }
        let [v00, v10, v01, v11] = corners.map(Vec4::from_array);
        let ty = sample_linear_four(u[1], v00 + v10, v01 + v11);
        let (left, right) = (lerp(v00, v01, ty), lerp(v10, v11, ty));
        let tx = sample_linear_four(ux, left, right);
        Some(BilinearFour {
            pdf: lerp(left, right, tx),
            columns,
            rows,
            fraction: [tx, ty],
        })
    }

    /// The point at `cell`'s fractions across it.
    pub fn point_in(&self, cell: GridCell) -> Vec2 {
        let (xs, ys) = (&self.xs.positions, &self.ys.positions);
        let (i, j, t) = (cell.column, cell.row, cell.fraction);
        Vec2::new(lerp(xs[i], xs[i + 1], t.x), lerp(ys[j], ys[j + 1], t.y))
    }

    /// The density of `sample` at `p` (clamped to the grid).
    pub fn pdf(&self, p: Vec2) -> f32 {
        let (column, tx) = self.xs.cell_of(p.x);
        let (row, ty) = self.ys.cell_of(p.y);
        self.pdf_in_cell(GridCell {
            column,
            row,
            fraction: Vec2::new(tx, ty),
        })
    }

    /// The density of `sample` in `cell` at its fractions across it: [`Bilinear2D::pdf`] for a
    /// caller that knows the cell already (one whose data shares the grid), without the search.
    pub fn pdf_in_cell(&self, cell: GridCell) -> f32 {
        if self.integral <= 0.0 {
            return 0.0;
        }
        let [v00, v10, v01, v11] = self.corners(cell.column, cell.row);
        let (tx, ty) = (cell.fraction.x, cell.fraction.y);
        lerp(lerp(v00, v10, tx), lerp(v01, v11, tx), ty)
    }

    /// Cell (i, j)'s corner densities: (x0, y0), (x1, y0), (x0, y1), (x1, y1); one bounds check
    /// for the four, on the slice from the first to the last.
    fn corners(&self, i: usize, j: usize) -> [f32; 4] {
        let nx = self.xs.positions.len();
        let values = &self.density[j * nx + i..][..nx + 2];
        [values[0], values[1], values[nx], values[nx + 1]]
    }
}

/// A point drawn by [`Bilinear2D::sample`]: its density, and its cell, so that data laid out on
/// the same grid (the environment map's texels) is read there without a search. The point
/// itself ([`Bilinear2D::point_in`]) is left to the caller that needs it: the environment map
/// takes its direction from the cell's angles.
#[derive(Clone, Copy, Debug)]
pub struct BilinearSample {
    pub pdf: f32,
    pub cell: GridCell,
}

/// Four points drawn by [`Bilinear2D::sample_four`]: lane by lane, what [`BilinearSample`]
/// holds.
#[derive(Clone, Copy, Debug)]
pub struct BilinearFour {
    pub pdf: Vec4,
    pub columns: [usize; 4],
    pub rows: [usize; 4],
    /// In x and in y.
    pub fraction: [Vec4; 2],
}

/// A cell of the grid, between vertices (`column`, `row`) and (`column` + 1, `row` + 1), and a
/// point's fractions across it in x and y, each in [0, 1].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GridCell {
    pub column: usize,
    pub row: usize,
    pub fraction: Vec2,
}

/// One axis of the grid: its vertex positions, and the map from a position to a first guess of
/// its cell for [`Axis::cell_of`].
#[derive(Clone, Debug)]
struct Axis {
    positions: Vec<f32>,
    first: f32,
    /// Cells per unit length over the whole axis: (n - 1) / (last - first).
    cells_per_unit: f32,
}

impl Axis {
    fn new(positions: Vec<f32>) -> Self {
        let (first, last) = (positions[0], positions[positions.len() - 1]);
        let cells_per_unit = (positions.len() - 1) as f32 / (last - first);
        Self {
            positions,
            first,
            cells_per_unit: if cells_per_unit.is_finite() {
                cells_per_unit
            } else {
                0.0
            },
        }
    }

    /// The cell of `x` and its fraction in it, both clamped: the cell k - 1 for k the number
    /// of positions at or below x (`partition_point`), found by stepping from the cell x would
    /// be in were the positions evenly spaced. The steps give exactly the binary search's k
    /// (positions[k - 1] <= x < positions[k]); on a grid near even spacing, such as the
    /// environment map's (texel centres, and the poles half a texel beyond), there are none or
    /// one, where the binary search took a dozen dependent loads. A NaN x fails every
    /// comparison, as in the binary search, and lands in cell 0 with fraction 0 as there.
    fn cell_of(&self, x: f32) -> (usize, f32) {
        let positions = &self.positions;
        let n = positions.len();
        // Through i32, saturating (NaN to 0): f32 -> usize costs a dozen instructions.
        let guess = ((x - self.first) * self.cells_per_unit) as i32;
        let mut k = (guess.max(0) as usize + 1).min(n);
        while k < n && positions[k] <= x {
            k += 1;
        }
        while k > 0 && positions[k - 1] > x {
            k -= 1;
        }
        let cell = k.saturating_sub(1).min(n - 2);
        let (x0, x1) = (positions[cell], positions[cell + 1]);
        let t = if x1 > x0 { (x - x0) / (x1 - x0) } else { 0.0 };
        (cell, if t.is_nan() { 0.0 } else { t.clamp(0.0, 1.0) })
    }
}

/// (1 - t) a + t b, on numbers or on glam's `Vec4` lanes.
fn lerp<T>(a: T, b: T, t: T) -> T
where
    T: Copy + Add<Output = T> + Mul<Output = T>,
    f32: Sub<T, Output = T>,
{
    (1.0 - t) * a + t * b
}

/// t in [0, 1) with density proportional to (1 - t) a + t b (a, b >= 0): the CDF
/// (a t + (b - a) t^2 / 2) / ((a + b) / 2) = u solved for t, written as
/// u (a + b) / (a + sqrt((1 - u) a^2 + u b^2)) so that a = b and a near b lose no precision
/// (pbrt-v4 `SampleLinear`).
fn sample_linear(u: f32, a: f32, b: f32) -> f32 {
    let denominator = a + ((1.0 - u) * a * a + u * b * b).sqrt();
    if denominator <= 0.0 {
        return u.min(ONE_MINUS_EPSILON);
    }
    (u * (a + b) / denominator).clamp(0.0, ONE_MINUS_EPSILON)
}

/// [`sample_linear`] on four lanes, to the bit: both of its results computed and one selected;
/// `f32::min` (a NaN u gives the other operand) and `f32::clamp` (a NaN stays NaN) as selects.
fn sample_linear_four(u: Vec4, a: Vec4, b: Vec4) -> Vec4 {
    let (zero, below_one) = (Vec4::ZERO, Vec4::splat(ONE_MINUS_EPSILON));
    let denominator = a + ((1.0 - u) * a * a + u * b * b).sqrt();
    let t = u * (a + b) / denominator;
    let t = select(t.cmplt(zero), zero, t);
    let t = select(t.cmpgt(below_one), below_one, t);
    select(
        denominator.cmple(zero),
        select(u.cmplt(below_one), u, below_one),
        t,
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::PathRng;

    /// A 4 x 3 vertex grid with uneven spacing, a zero corner and a bright vertex.
    fn grid() -> Bilinear2D {
        let values = [
            1.0, 0.0, 2.0, 0.5, //
            0.2, 9.0, 1.0, 0.0, //
            3.0, 1.0, 0.0, 0.0,
        ];
        Bilinear2D::new(&values, vec![0.0, 0.1, 0.5, 1.0], vec![0.0, 0.7, 1.0])
    }

    #[test]
    fn sampled_density_is_the_pdf_and_integrates_to_one() {
        let d = grid();
        let mut rng = PathRng::new(3, 0, 0);
        for _ in 0..10_000 {
            let BilinearSample { pdf, cell } = d.sample(rng.next_2d()).unwrap();
            let p = d.point_in(cell);
            assert!((0.0..=1.0).contains(&p.x) && (0.0..=1.0).contains(&p.y));
            assert!((pdf - d.pdf(p)).abs() <= 1e-4 * pdf.max(1.0), "{p} {pdf}");
            // The sample's fractions locate a point in its cell.
            let (xs, ys) = (&d.xs.positions, &d.ys.positions);
            let (i, j) = (cell.column, cell.row);
            assert!(
                (xs[i]..=xs[i + 1]).contains(&p.x) && (ys[j]..=ys[j + 1]).contains(&p.y),
                "{p} outside {cell:?}"
            );
            // The same bilinear form, interpolated in the other order.
            assert!(
                (d.pdf_in_cell(cell) - pdf).abs() <= 1e-5 * pdf.max(1.0),
                "{cell:?}"
            );
        }
        // Midpoint rule on a fine grid (exact up to cells straddling a vertex line).
        let n = 400;
        let sum: f32 = (0..n * n)
            .map(|k| d.pdf((Vec2::new((k % n) as f32, (k / n) as f32) + 0.5) / n as f32))
            .sum();
        assert!((sum / (n * n) as f32 - 1.0).abs() < 1e-3, "{sum}");
    }

    #[test]
    fn histogram_matches_the_interpolant() {
        // Each cell split in 2 x 2 sub-rectangles: a bilinear patch's mean over an aligned
        // rectangle is its value at the rectangle's centre, so each bin's probability is
        // area * pdf(centre). 24 bins: chi-square with at most 23 degrees of freedom, whose
        // 0.999 quantile is 49.7 (a correct sampler fails with probability 1e-3 at most; the
        // seed is fixed). A bin of zero probability must stay empty.
        let d = grid();
        let (xs, ys) = (
            [0.0, 0.05, 0.1, 0.3, 0.5, 0.75, 1.0],
            [0.0, 0.35, 0.7, 0.85, 1.0],
        );
        let bins = (xs.len() - 1) * (ys.len() - 1);
        let probs: Vec<f64> = (0..bins)
            .map(|b| {
                let (i, j) = (b % (xs.len() - 1), b / (xs.len() - 1));
                let centre = Vec2::new(xs[i] + xs[i + 1], ys[j] + ys[j + 1]) / 2.0;
                f64::from((xs[i + 1] - xs[i]) * (ys[j + 1] - ys[j]) * d.pdf(centre))
            })
            .collect();
        assert!((probs.iter().sum::<f64>() - 1.0).abs() < 1e-5);
        let n = 200_000u32;
        let mut counts = vec![0u32; bins];
        let mut rng = PathRng::new(4, 0, 0);
        let (x_bins, y_bins) = (Axis::new(xs.to_vec()), Axis::new(ys.to_vec()));
        for _ in 0..n {
            let p = d.point_in(d.sample(rng.next_2d()).unwrap().cell);
            let (i, _) = x_bins.cell_of(p.x);
            let (j, _) = y_bins.cell_of(p.y);
            counts[j * (xs.len() - 1) + i] += 1;
        }
        assert!(counts.iter().zip(&probs).all(|(&c, &p)| p > 0.0 || c == 0));
        let chi2: f64 = counts
            .iter()
            .zip(&probs)
            .filter(|(_, p)| **p > 0.0)
            .map(|(&c, &p)| (f64::from(c) - p * f64::from(n)).powi(2) / (p * f64::from(n)))
            .sum();
        assert!(chi2 < 49.7, "chi2 {chi2}");
    }

    /// The stepping search against the binary search it replaces, on an even grid, the
    /// environment map's (texel centres and the poles), two very uneven ones (crowded at the
    /// start, where the guess falls short, and at the end, where it overshoots), one with a
    /// repeated position and one of one cell: the same cell and fraction to the bit, for points
    /// on and beside every vertex, across and outside the range, infinite and NaN.
    #[test]
    fn cell_search_is_the_binary_search() {
        fn binary_search(positions: &[f32], x: f32) -> (usize, f32) {
            let last = positions.len() - 2;
            let cell = positions
                .partition_point(|&p| p <= x)
                .saturating_sub(1)
                .min(last);
            let (x0, x1) = (positions[cell], positions[cell + 1]);
            let t = if x1 > x0 { (x - x0) / (x1 - x0) } else { 0.0 };
            (cell, if t.is_nan() { 0.0 } else { t.clamp(0.0, 1.0) })
        }
        let h = 32;
        let grids = [
            (0..=64).map(|i| i as f32 / 64.0).collect::<Vec<f32>>(),
            std::iter::once(0.0)
                .chain((0..h).map(|j| (j as f32 + 0.5) / h as f32))
                .chain(std::iter::once(1.0))
                .collect(),
            vec![-3.0, -2.9, 0.0, 0.001, 0.002, 5.0, 100.0],
            vec![0.0, 99.0, 99.5, 100.0],
            vec![0.0, 0.25, 0.25, 0.5, 1.0],
            vec![2.0, 7.0],
        ];
        for positions in grids {
            let axis = Axis::new(positions.clone());
            let (first, last) = (positions[0], positions[positions.len() - 1]);
            let mut xs: Vec<f32> = (-1000..=2000)
                .map(|k| first + (last - first) * k as f32 / 1000.0)
                .collect();
            for &p in &positions {
                xs.extend([p, p.next_up(), p.next_down()]);
            }
            xs.extend([
                f32::INFINITY,
                f32::NEG_INFINITY,
                f32::MAX,
                f32::MIN,
                f32::NAN,
            ]);
            for x in xs {
                let (expected, got) = (binary_search(&positions, x), axis.cell_of(x));
                assert!(
                    got.0 == expected.0 && got.1.to_bits() == expected.1.to_bits(),
                    "{positions:?} at {x:e}: {got:?}, binary search {expected:?}"
                );
            }
        }
    }

    /// Four samples in lanes are `sample`'s to the bit (density, cell, fractions), on the
    /// uneven grid with its zero corner, for points all over the square, on and beside its
    /// edges, outside it and NaN; through the alias table's lanes (`sample_index_four`) and both
    /// linear warps, whose degenerate case (both ends zero) the zero corner reaches.
    #[test]
    fn samples_in_lanes_are_the_scalar_ones_to_the_bit() {
        let d = grid();
        let us = crate::sampling::test_samples_with_edges();
        let bits = |x: f32| if x.is_nan() { u32::MAX } else { x.to_bits() };
        for chunk in us.chunks(4) {
            let u = [0, 1].map(|axis| {
                Vec4::from_array(std::array::from_fn(|lane| {
                    chunk.get(lane).map_or(0.5, |u| u.to_array()[axis])
                }))
            });
            let got = d.sample_four(u).unwrap();
            for lane in 0..4 {
                let expected = d.sample(Vec2::new(u[0][lane], u[1][lane])).unwrap();
                let cell = expected.cell;
                assert_eq!(
                    (
                        bits(got.pdf[lane]),
                        got.columns[lane],
                        got.rows[lane],
                        got.fraction.map(|t| bits(t[lane]))
                    ),
                    (
                        bits(expected.pdf),
                        cell.column,
                        cell.row,
                        cell.fraction.to_array().map(bits)
                    ),
                    "{u:?} {lane}"
                );
            }
        }
        let zero = Bilinear2D::new(&[0.0; 4], vec![0.0, 1.0], vec![0.0, 1.0]);
        assert!(zero.sample_four([Vec4::splat(0.5); 2]).is_none());
    }

    #[test]
    fn zero_everywhere_never_samples() {
        let d = Bilinear2D::new(&[0.0, f32::NAN, -1.0, 0.0], vec![0.0, 1.0], vec![0.0, 1.0]);
        assert!(d.sample(Vec2::splat(0.5)).is_none());
        assert_eq!(d.pdf(Vec2::splat(0.5)), 0.0);
        // Finite values whose integral overflows f32: nothing to normalise by either.
        let d = Bilinear2D::new(&[f32::MAX; 4], vec![0.0, 4.0], vec![0.0, 4.0]);
        assert!(d.sample(Vec2::splat(0.5)).is_none());
        assert_eq!(d.pdf(Vec2::splat(0.5)), 0.0);
    }

    #[test]
    fn linear_warp_inverts_its_cdf() {
        for (a, b) in [(1.0f32, 1.0f32), (0.0, 2.0), (3.0, 0.0), (0.5, 4.0)] {
            for u in [0.0, 0.1, 0.5, 0.9] {
                let t = sample_linear(u, a, b);
                let cdf = (a * t + (b - a) * t * t / 2.0) / ((a + b) / 2.0);
                assert!((cdf - u).abs() < 1e-5, "{a} {b} {u}: {t}");
            }
        }
    }
}
