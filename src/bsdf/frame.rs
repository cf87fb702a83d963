//! An orthonormal shading frame built around a normal.

use glam::Vec3;

/// Orthonormal basis (`x`, `y`, `z`); `z` is the shading normal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    pub x: Vec3,
    pub y: Vec3,
    pub z: Vec3,
}

impl Frame {
    /// A frame around the unit vector `n`, without branches on a threshold or
    /// normalisation: Duff et al. 2017, "Building an Orthonormal Basis,
    /// Revisited" (JCGT 6(1)), Listing 3. `copysign` makes it continuous
    /// everywhere except across the plane n.z = 0, and exact at n = -z.
    pub fn from_z(n: Vec3) -> Self {
        let sign = 1.0f32.copysign(n.z);
        let a = -1.0 / (sign + n.z);
        let b = n.x * n.y * a;
        Self {
            x: Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x),
            y: Vec3::new(b, sign + n.y * n.y * a, -n.y),
            z: n,
        }
    }

    /// A frame around the unit normal `n` whose x axis is `tangent` made orthogonal to `n`
    /// (Gram-Schmidt), as Mitsuba 3 orients anisotropic BSDFs along dp/du
    /// (`SurfaceInteraction::initialize_sh_frame`); `from_z` where the tangent is parallel to
    /// `n` (to 1e-6 of its length) or not finite.
    pub fn from_z_and_tangent(n: Vec3, tangent: Vec3) -> Self {
        let x = tangent - n * n.dot(tangent);
        if x.length_squared() > 1e-12 * tangent.length_squared()
            && let Some(x) = x.try_normalize()
        {
            Self {
                x,
                y: n.cross(x),
                z: n,
            }
        } else {
            Self::from_z(n)
        }
    }

    /// World to local: the coordinates of `v` along `x`, `y`, `z`.
    pub fn to_local(&self, v: Vec3) -> Vec3 {
        Vec3::new(v.dot(self.x), v.dot(self.y), v.dot(self.z))
    }

    /// Local to world.
    pub fn to_world(&self, v: Vec3) -> Vec3 {
        self.x * v.x + self.y * v.y + self.z * v.z
    }
}
