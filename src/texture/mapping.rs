//! Texture mappings: from a shading point to the texture's own coordinates, as LuxRender 1.x
//! defines them (`core/texture.cpp`: `TextureMapping2D::Create`, `UVMapping2D`,
//! `SphericalMapping2D`, `CylindricalMapping2D`, `PlanarMapping2D`,
//! `TextureMapping3D::Apply3DTextureMappingOptions`, `GlobalMapping3D`, `UVMapping3D`).

use std::f32::consts::{FRAC_1_PI, PI};

use glam::{Affine3A, EulerRot, Quat, Vec2, Vec3};

use super::ShadingPoint;

/// 2D mappings (LuxRender's `"string mapping"`), each giving (s, t).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Mapping2D {
    /// s = uscale u + udelta, t = vscale v + vdelta.
    Uv { scale: Vec2, delta: Vec2 },
    /// The direction of the point from the texture space's origin: s = phi / 2pi, t = theta / pi
    /// (theta from +z, phi from +x towards +y), then scaled and offset like `Uv`.
    Spherical {
        world_to_texture: Affine3A,
        scale: Vec2,
        delta: Vec2,
    },
    /// s = phi uscale / 2pi + udelta around the texture space's z axis; t = (1 - z) / 2.
    Cylindrical {
        world_to_texture: Affine3A,
        uscale: f32,
        udelta: f32,
    },
    /// s = p . v1 + udelta, t = p . v2 + vdelta, with p in world space.
    Planar { v1: Vec3, v2: Vec3, delta: Vec2 },
}

impl Default for Mapping2D {
    /// LuxRender's default: `uv` with unit scale and no offset.
    fn default() -> Self {
        Mapping2D::Uv {
            scale: Vec2::ONE,
            delta: Vec2::ZERO,
        }
    }
}

/// (theta, phi) of a direction: theta in [0, pi] from +z, phi in [0, 2pi) from +x towards +y
/// (pbrt's `SphericalTheta`, `SphericalPhi`).
fn spherical_angles(d: Vec3) -> (f32, f32) {
    let theta = d.z.clamp(-1.0, 1.0).acos();
    let phi = d.y.atan2(d.x);
    (theta, if phi < 0.0 { phi + 2.0 * PI } else { phi })
}

impl Mapping2D {
    pub fn map(&self, sp: &ShadingPoint) -> Vec2 {
        match *self {
            Mapping2D::Uv { scale, delta } => sp.uv * scale + delta,
            Mapping2D::Spherical {
                world_to_texture,
                scale,
                delta,
            } => {
                let d = world_to_texture
                    .transform_point3(sp.p)
                    .normalize_or(Vec3::Z);
                let (theta, phi) = spherical_angles(d);
                Vec2::new(phi * 0.5 * FRAC_1_PI, theta * FRAC_1_PI) * scale + delta
            }
            Mapping2D::Cylindrical {
                world_to_texture,
                uscale,
                udelta,
            } => {
                let p = world_to_texture.transform_point3(sp.p);
                let (_, phi) = spherical_angles(Vec3::new(p.x, p.y, 0.0).normalize_or(Vec3::X));
                Vec2::new(phi * 0.5 * FRAC_1_PI * uscale + udelta, 0.5 - 0.5 * p.z)
            }
            Mapping2D::Planar { v1, v2, delta } => Vec2::new(sp.p.dot(v1), sp.p.dot(v2)) + delta,
        }
    }
}

/// 3D mappings (LuxRender's `"string coordinates"`), giving a point in texture space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Mapping3D {
    /// The world-space point in the texture's space.
    Global { world_to_texture: Affine3A },
    /// The point (u, v, 0) in the texture's space.
    Uv { world_to_texture: Affine3A },
}

impl Mapping3D {
    /// The world-to-texture transform of LuxRender's 3D mappings: the transform current at the
    /// `Texture` directive, *not* inverted (LuxRender 1.x's `Context::Texture` passes
    /// `curTransform` as `tex2world`, and `TextureMapping3D(const Transform &x)` stores it as
    /// `WorldToTexture` unchanged, as pbrt-v1 did; only the 2D spherical and cylindrical
    /// mappings invert it), then `Apply3DTextureMappingOptions` (`core/texture.cpp`): times
    /// Scale(1 / `scale`), RotateX, RotateY, RotateZ (`rotate`, degrees) and
    /// Translate(-`translate`), each composed on the right, so a point is translated first and
    /// the CTM applies last. A zero scale component is replaced by 1.
    pub fn world_to_texture(
        ctm: Affine3A,
        scale: Vec3,
        rotate_degrees: Vec3,
        translate: Vec3,
    ) -> Affine3A {
        let safe = |s: f32| if s != 0.0 && s.is_finite() { s } else { 1.0 };
        let inv_scale = Vec3::new(
            1.0 / safe(scale.x),
            1.0 / safe(scale.y),
            1.0 / safe(scale.z),
        );
        let r = rotate_degrees * (PI / 180.0);
        let rotation = Quat::from_euler(EulerRot::XYZ, r.x, r.y, r.z);
        ctm * Affine3A::from_scale(inv_scale)
            * Affine3A::from_quat(rotation)
            * Affine3A::from_translation(-translate)
    }

    pub fn map(&self, sp: &ShadingPoint) -> Vec3 {
        match *self {
            Mapping3D::Global { world_to_texture } => world_to_texture.transform_point3(sp.p),
            Mapping3D::Uv { world_to_texture } => {
                world_to_texture.transform_point3(Vec3::new(sp.uv.x, sp.uv.y, 0.0))
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(p: Vec3, uv: Vec2) -> ShadingPoint {
        ShadingPoint {
            p,
            uv,
            n: Vec3::Z,
            object: 0,
        }
    }

    #[test]
    fn uv_and_planar() {
        let m = Mapping2D::Uv {
            scale: Vec2::new(8.0, -1.0),
            delta: Vec2::new(0.5, 1.0),
        };
        assert_eq!(
            m.map(&at(Vec3::ZERO, Vec2::new(0.25, 0.25))),
            Vec2::new(2.5, 0.75)
        );
        let m = Mapping2D::Planar {
            v1: Vec3::X,
            v2: Vec3::new(0.0, 0.0, 2.0),
            delta: Vec2::new(0.1, 0.2),
        };
        let st = m.map(&at(Vec3::new(3.0, 5.0, 7.0), Vec2::ZERO));
        assert!((st - Vec2::new(3.1, 14.2)).length() < 1e-5, "{st}");
    }

    #[test]
    fn spherical_and_cylindrical() {
        let translate = Affine3A::from_translation(Vec3::new(0.0, 0.0, -10.0));
        let sph = Mapping2D::Spherical {
            world_to_texture: translate,
            scale: Vec2::ONE,
            delta: Vec2::ZERO,
        };
        // +z of the texture space (world z = 12): theta = 0; -y: phi = 3pi/2, theta = pi/2.
        let top = sph.map(&at(Vec3::new(0.0, 0.0, 12.0), Vec2::ZERO));
        assert!(top.y.abs() < 1e-6, "{top}");
        let side = sph.map(&at(Vec3::new(0.0, -3.0, 10.0), Vec2::ZERO));
        assert!((side - Vec2::new(0.75, 0.5)).length() < 1e-6, "{side}");
        let cyl = Mapping2D::Cylindrical {
            world_to_texture: Affine3A::IDENTITY,
            uscale: 2.0,
            udelta: 0.1,
        };
        let st = cyl.map(&at(Vec3::new(-4.0, 0.0, 0.5), Vec2::ZERO));
        assert!((st - Vec2::new(1.1, 0.25)).length() < 1e-6, "{st}");
    }

    #[test]
    fn mapping_3d_options() {
        // A texture declared under Translate 1 0 0, with scale 0.5 and translate (0, 2, 0):
        // LuxRender's W2T = CTM * Scale(1/s) * Translate(-t), applied right to left, maps
        // q to 2 (q - (0, 2, 0)) + (1, 0, 0): the CTM is not inverted.
        let ctm = Affine3A::from_translation(Vec3::X);
        let w2t = Mapping3D::world_to_texture(
            ctm,
            Vec3::splat(0.5),
            Vec3::ZERO,
            Vec3::new(0.0, 2.0, 0.0),
        );
        let m = Mapping3D::Global {
            world_to_texture: w2t,
        };
        let q = Vec3::new(3.0, 4.0, 5.0);
        let expected = ((q - Vec3::new(0.0, 2.0, 0.0)) * 2.0) + Vec3::X;
        assert!((m.map(&at(q, Vec2::ZERO)) - expected).length() < 1e-5);
        // A 90 degree rotation about z turns x into y.
        let rot = Mapping3D::world_to_texture(
            Affine3A::IDENTITY,
            Vec3::ONE,
            Vec3::new(0.0, 0.0, 90.0),
            Vec3::ZERO,
        );
        assert!((rot.transform_point3(Vec3::X) - Vec3::Y).length() < 1e-6);
        // RotateX(90) * RotateZ(90): z first (x to y), then x (y to z); the other order would
        // leave x on y.
        let rot = Mapping3D::world_to_texture(
            Affine3A::IDENTITY,
            Vec3::ONE,
            Vec3::new(90.0, 0.0, 90.0),
            Vec3::ZERO,
        );
        assert!((rot.transform_point3(Vec3::X) - Vec3::Z).length() < 1e-6);
        let uv = Mapping3D::Uv {
            world_to_texture: Affine3A::IDENTITY,
        };
        assert_eq!(
            uv.map(&at(Vec3::ONE, Vec2::new(0.2, 0.3))),
            Vec3::new(0.2, 0.3, 0.0)
        );
    }
}
