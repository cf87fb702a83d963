//! Eight `f32` lanes, one path each: the value type of the shading stage's SIMD kernels.
//!
//! Each operation is a loop over the eight lanes of one IEEE operation (sum, product,
//! quotient, square root, comparison, bit select), which the compiler turns into one vector
//! instruction: two SSE2 ones in the baseline build, one AVX one in the build that
//! `accel::vex::run` picks on CPUs with AVX2. Either way each lane gets exactly the operation
//! scalar code would do (no fused multiply-add, no reassociation), so a kernel written with
//! these types in the scalar code's order gives its bits.
//!
//! Below the types, the lane forms of the scalar helpers that the kernels share (the shading
//! frame, normalisation, the ray origin's offset, the power heuristic, the disk warp).

use std::f32::consts::FRAC_PI_4;
use std::ops::{Add, BitAnd, BitOr, Div, Mul, Neg, Not, Sub};

use glam::Vec3;

use crate::math::sin_cos_eighth_turn;
use crate::sampling::ONE_MINUS_EPSILON;

/// Lanes per value.
pub const LANES: usize = 8;

/// Eight `f32`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct F8(pub [f32; LANES]);

/// Eight lane masks: all bits set (true) or clear (false).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct M8([u32; LANES]);

/// Eight 3-vectors, one component per field.
#[derive(Clone, Copy, Debug, Default)]
pub struct V8 {
    pub x: F8,
    pub y: F8,
    pub z: F8,
}

#[inline(always)]
fn map(f: impl Fn(usize) -> f32) -> F8 {
    let mut out = [0.0; LANES];
    for (lane, value) in out.iter_mut().enumerate() {
        *value = f(lane);
    }
    F8(out)
}

#[inline(always)]
fn mask(f: impl Fn(usize) -> bool) -> M8 {
    let mut out = [0; LANES];
    for (lane, value) in out.iter_mut().enumerate() {
        *value = if f(lane) { u32::MAX } else { 0 };
    }
    M8(out)
}

impl F8 {
    #[inline(always)]
    pub fn splat(v: f32) -> Self {
        Self([v; LANES])
    }

    #[inline(always)]
    pub fn sqrt(self) -> Self {
        map(|i| self.0[i].sqrt())
    }

    #[inline(always)]
    pub fn abs(self) -> Self {
        map(|i| self.0[i].abs())
    }

    /// `f32::max` per lane (a NaN lane takes the other operand).
    #[inline(always)]
    pub fn max(self, other: Self) -> Self {
        map(|i| self.0[i].max(other.0[i]))
    }

    /// `f32::min` per lane.
    #[inline(always)]
    pub fn min(self, other: Self) -> Self {
        map(|i| self.0[i].min(other.0[i]))
    }

    /// `f32::copysign` per lane.
    #[inline(always)]
    pub fn copysign(self, sign: Self) -> Self {
        map(|i| self.0[i].copysign(sign.0[i]))
    }

    #[inline(always)]
    pub fn gt(self, other: Self) -> M8 {
        mask(|i| self.0[i] > other.0[i])
    }

    #[inline(always)]
    pub fn ge(self, other: Self) -> M8 {
        mask(|i| self.0[i] >= other.0[i])
    }

    #[inline(always)]
    pub fn lt(self, other: Self) -> M8 {
        mask(|i| self.0[i] < other.0[i])
    }

    #[inline(always)]
    pub fn le(self, other: Self) -> M8 {
        mask(|i| self.0[i] <= other.0[i])
    }

    #[inline(always)]
    pub fn eq(self, other: Self) -> M8 {
        mask(|i| self.0[i] == other.0[i])
    }

    #[inline(always)]
    pub fn is_finite(self) -> M8 {
        mask(|i| self.0[i].is_finite())
    }

    /// `math::is_positive_finite` per lane: `x > 0` and `x <= f32::MAX` (false for NaN), the
    /// mask of `is_finite() & gt(0)`. Written as two comparisons because LLVM folds that pair
    /// into a floating-point class test, which it then computes lane by lane in scalar code
    /// (about 120 instructions a mask, Cornell box: 3 % of the render's instructions in the
    /// lanes' normalisations), where these two stay two vector comparisons.
    #[inline(always)]
    pub fn is_positive_finite(self) -> M8 {
        self.gt(Self::splat(0.0)) & self.le(Self::splat(f32::MAX))
    }

    #[inline(always)]
    pub fn is_infinite(self) -> M8 {
        mask(|i| self.0[i].is_infinite())
    }
}

impl M8 {
    /// `if self { a } else { b }` per lane, by bits.
    #[inline(always)]
    pub fn select(self, a: F8, b: F8) -> F8 {
        map(|i| f32::from_bits((self.0[i] & a.0[i].to_bits()) | (!self.0[i] & b.0[i].to_bits())))
    }

    /// [`M8::select`] on each component.
    #[inline(always)]
    pub fn select_v(self, a: V8, b: V8) -> V8 {
        V8 {
            x: self.select(a.x, b.x),
            y: self.select(a.y, b.y),
            z: self.select(a.z, b.z),
        }
    }

    #[inline(always)]
    pub fn lane(&self, lane: usize) -> bool {
        self.0[lane] != 0
    }

    /// Lanes equal as masks (both true or both false).
    #[inline(always)]
    pub fn eq(self, other: Self) -> Self {
        self.zip(other, |a, b| !(a ^ b))
    }

    /// `op` on the bits of each pair of lanes.
    #[inline(always)]
    fn zip(self, other: Self, op: impl Fn(u32, u32) -> u32) -> Self {
        let mut out = [0; LANES];
        for (lane, value) in out.iter_mut().enumerate() {
            *value = op(self.0[lane], other.0[lane]);
        }
        M8(out)
    }
}

impl BitAnd for M8 {
    type Output = Self;
    #[inline(always)]
    fn bitand(self, other: Self) -> Self {
        self.zip(other, |a, b| a & b)
    }
}

impl BitOr for M8 {
    type Output = Self;
    #[inline(always)]
    fn bitor(self, other: Self) -> Self {
        self.zip(other, |a, b| a | b)
    }
}

impl Not for M8 {
    type Output = Self;
    #[inline(always)]
    fn not(self) -> Self {
        self.zip(self, |a, _| !a)
    }
}

impl From<[bool; LANES]> for M8 {
    #[inline(always)]
    fn from(flags: [bool; LANES]) -> Self {
        mask(|i| flags[i])
    }
}

impl From<f32> for F8 {
    #[inline(always)]
    fn from(v: f32) -> Self {
        Self::splat(v)
    }
}

macro_rules! lane_op {
    ($trait:ident, $method:ident, $op:tt) => {
        impl $trait for F8 {
            type Output = Self;
            #[inline(always)]
            fn $method(self, other: Self) -> Self {
                map(|i| self.0[i] $op other.0[i])
            }
        }
        impl $trait<f32> for F8 {
            type Output = Self;
            #[inline(always)]
            fn $method(self, other: f32) -> Self {
                map(|i| self.0[i] $op other)
            }
        }
        impl $trait<F8> for f32 {
            type Output = F8;
            #[inline(always)]
            fn $method(self, other: F8) -> F8 {
                map(|i| self $op other.0[i])
            }
        }
    };
}

lane_op!(Add, add, +);
lane_op!(Sub, sub, -);
lane_op!(Mul, mul, *);
lane_op!(Div, div, /);

impl Neg for F8 {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        map(|i| -self.0[i])
    }
}

impl Sub for V8 {
    type Output = Self;
    /// glam's `Vec3` difference, per component.
    #[inline(always)]
    fn sub(self, other: Self) -> Self {
        V8 {
            x: self.x - other.x,
            y: self.y - other.y,
            z: self.z - other.z,
        }
    }
}

impl V8 {
    /// Sets lane `lane` to `v`.
    #[inline(always)]
    pub fn set(&mut self, lane: usize, v: Vec3) {
        self.x.0[lane] = v.x;
        self.y.0[lane] = v.y;
        self.z.0[lane] = v.z;
    }

    /// `v` in every lane.
    #[inline(always)]
    pub fn splat(v: Vec3) -> Self {
        V8 {
            x: F8::splat(v.x),
            y: F8::splat(v.y),
            z: F8::splat(v.z),
        }
    }

    /// Lane `lane`'s vector.
    #[inline(always)]
    pub fn get(&self, lane: usize) -> Vec3 {
        Vec3::new(self.x.0[lane], self.y.0[lane], self.z.0[lane])
    }

    /// glam's `Vec3::dot`: (x x' + y y') + z z'.
    #[inline(always)]
    pub fn dot(self, other: Self) -> F8 {
        self.x * other.x + self.y * other.y + self.z * other.z
    }

    /// Each component times `s`.
    #[inline(always)]
    pub fn scale(self, s: F8) -> Self {
        V8 {
            x: self.x * s,
            y: self.y * s,
            z: self.z * s,
        }
    }

    /// Component-wise product.
    #[inline(always)]
    pub fn mul(self, other: Self) -> Self {
        V8 {
            x: self.x * other.x,
            y: self.y * other.y,
            z: self.z * other.z,
        }
    }

    /// glam's `Vec3::is_finite`: every component finite.
    #[inline(always)]
    pub fn is_finite(self) -> M8 {
        self.x.is_finite() & self.y.is_finite() & self.z.is_finite()
    }

    /// glam's `== Vec3::ZERO`: every component zero (either sign).
    #[inline(always)]
    pub fn is_zero(self) -> M8 {
        let zero = F8::splat(0.0);
        self.x.eq(zero) & self.y.eq(zero) & self.z.eq(zero)
    }
}

/// `Frame` on lanes: the same operations in the same order.
pub struct LaneFrame {
    x: V8,
    y: V8,
    z: V8,
}

impl LaneFrame {
    /// `Frame::from_z` (Duff et al. 2017).
    #[inline(always)]
    pub fn from_z(n: V8) -> Self {
        let sign = F8::splat(1.0).copysign(n.z);
        let a = -1.0 / (sign + n.z);
        let b = n.x * n.y * a;
        Self {
            x: V8 {
                x: 1.0 + sign * n.x * n.x * a,
                y: sign * b,
                z: -sign * n.x,
            },
            y: V8 {
                x: b,
                y: sign + n.y * n.y * a,
                z: -n.y,
            },
            z: n,
        }
    }

    /// `Frame::to_local`.
    #[inline(always)]
    pub fn to_local(&self, v: V8) -> V8 {
        V8 {
            x: v.dot(self.x),
            y: v.dot(self.y),
            z: v.dot(self.z),
        }
    }

    /// `Frame::to_world`: x v.x + y v.y + z v.z.
    #[inline(always)]
    pub fn to_world(&self, v: V8) -> V8 {
        let (x, y, z) = (self.x, self.y, self.z);
        V8 {
            x: x.x * v.x + y.x * v.y + z.x * v.z,
            y: x.y * v.x + y.y * v.y + z.y * v.z,
            z: x.z * v.x + y.z * v.y + z.z * v.z,
        }
    }
}

/// glam's `try_normalize` (`unit_direction`) as a value and a mask.
#[inline(always)]
pub fn unit_direction(v: V8) -> (V8, M8) {
    let rcp = 1.0 / v.dot(v).sqrt();
    (v.scale(rcp), rcp.is_positive_finite())
}

/// `math::offset_ray_origin` per lane.
#[inline(always)]
pub fn offset_ray_origin(p: V8, geometric_normal: V8, w: V8) -> V8 {
    // glam's `max_element`: `if a > b { a } else { b }`, z and y first.
    let max = |a: F8, b: F8| a.gt(b).select(a, b);
    let largest = max(p.x.abs(), max(p.y.abs(), p.z.abs()));
    let scale = 1e-4 * (1.0 + largest);
    let offset = geometric_normal.scale(scale);
    let below = w.dot(geometric_normal).lt(F8::splat(0.0));
    below.select_v(
        V8 {
            x: p.x - offset.x,
            y: p.y - offset.y,
            z: p.z - offset.z,
        },
        V8 {
            x: p.x + offset.x,
            y: p.y + offset.y,
            z: p.z + offset.z,
        },
    )
}

/// `warp::power_heuristic(1, f_pdf, 1, g_pdf)` per lane.
#[inline(always)]
pub fn power_heuristic(f_pdf: F8, g_pdf: F8) -> F8 {
    let (f2, g2) = (f_pdf * f_pdf, g_pdf * g_pdf);
    let sum = f2 + g2;
    let zero = F8::splat(0.0);
    f_pdf
        .is_infinite()
        .select(F8::splat(1.0), sum.gt(zero).select(f2 / sum, zero))
}

/// `bsdf::canonical` per lane: a sample coordinate clamped to [0, 1), NaN to 0.
#[inline(always)]
pub fn canonical(x: F8) -> F8 {
    let zero = F8::splat(0.0);
    x.ge(zero).select(x.min(F8::splat(ONE_MINUS_EPSILON)), zero)
}

/// `warp::concentric_disk` per lane, for a canonical `u`: the disk point's x and y.
#[inline(always)]
pub fn concentric_disk(u: [F8; 2]) -> (F8, F8) {
    let zero = F8::splat(0.0);
    let (ox, oy) = (2.0 * u[0] - 1.0, 2.0 * u[1] - 1.0);
    let centre = ox.eq(zero) & oy.eq(zero);
    let wide = ox.abs().gt(oy.abs());
    let (sin, cos) = sin_cos_eighth_turn(FRAC_PI_4 * (wide.select(oy, ox) / wide.select(ox, oy)));
    let radius = wide.select(ox, oy);
    (
        centre.select(zero, radius * wide.select(cos, sin)),
        centre.select(zero, radius * wide.select(sin, cos)),
    )
}

/// A queued vertex's surface (its normals as `face_forward` left them), the direction towards
/// where the path came from, and the path's throughput: what every lane kernel starts from.
#[derive(Clone, Copy, Debug)]
pub struct QueuedSurface {
    pub position: Vec3,
    pub geometric_normal: Vec3,
    pub shading_normal: Vec3,
    pub wo: Vec3,
    pub throughput: Vec3,
}

/// [`QueuedSurface`]s, one lane each.
#[derive(Clone, Copy, Default)]
pub(super) struct SurfaceLanes {
    pub(super) position: V8,
    pub(super) geometric_normal: V8,
    pub(super) shading_normal: V8,
    pub(super) wo: V8,
    pub(super) throughput: V8,
}

impl SurfaceLanes {
    /// Writes `surface` into lane `lane`.
    #[inline(always)]
    pub(super) fn set(&mut self, lane: usize, surface: &QueuedSurface) {
        self.position.set(lane, surface.position);
        self.geometric_normal.set(lane, surface.geometric_normal);
        self.shading_normal.set(lane, surface.shading_normal);
        self.wo.set(lane, surface.wo);
        self.throughput.set(lane, surface.throughput);
    }
}
