//! The scene description: plain data, as a loader reads it from a file, in no format's terms.
//!
//! Every loader (one per format, `scene::lxs`, …) produces a [`SceneDesc`]; `scene::build` turns it
//! into the bevy_ecs `World` the render schedule runs on. Nothing here knows about rendering.
//! The description holds physical quantities with neutral defaults: radiance and radiant
//! intensity (not a format's gain and power), microfacet roughness as GGX alpha, indices of
//! refraction, linear RGB colours. Each loader converts its format's conventions into these.
//! Geometry and lights are already in world space; images are decoded to linear RGB.

use std::f32::consts::PI;
use std::fmt;
use std::path::PathBuf;

use glam::{Affine3A, Mat4, Vec2, Vec3};

use crate::bsdf::lafortune::LafortuneFit;
use crate::camera::{CameraType, pinhole};
pub use crate::light::spot::SpotFalloff;
pub use crate::material::texels::Texels;
pub use crate::material::texture::Wrap;
use crate::settings::IntegratorKind;
pub use crate::texture::TextureGraph;

/// Where something came from: a file, a 1-based line and, where the format has them (XML),
/// a 1-based column. Displayed as `file:line` or `file:line:column`.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Location {
    pub file: PathBuf,
    pub line: usize,
    pub column: Option<usize>,
}

impl Location {
    /// A line in `file`, without a column.
    pub fn line(file: impl Into<PathBuf>, line: usize) -> Self {
        Self {
            file: file.into(),
            line,
            column: None,
        }
    }
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}", self.file.display(), self.line)?;
        match self.column {
            Some(column) => write!(f, ":{column}"),
            None => Ok(()),
        }
    }
}

/// A scene file could not be loaded: where, and why (with the offending text).
#[derive(Clone, Debug, PartialEq)]
pub struct SceneError {
    pub location: Location,
    pub message: String,
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: error: {}", self.location, self.message)
    }
}

impl std::error::Error for SceneError {}

/// Something the loader skipped or read in a way the format does not say; the render goes on.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneWarning {
    pub location: Location,
    pub message: String,
}

impl fmt::Display for SceneWarning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: warning: {}", self.location, self.message)
    }
}

/// Everything a scene file says.
#[derive(Clone, Debug)]
pub struct SceneDesc {
    pub camera: CameraDesc,
    pub film: FilmDesc,
    /// `Sampler "pixelsamples"`, if given.
    pub pixel_samples: Option<u32>,
    /// `SurfaceIntegrator "maxdepth"` or `"eyedepth"`, if given.
    pub max_depth: Option<u32>,
    /// The integrator the scene asks for, where foton has it (the command line overrides it).
    pub integrator: Option<IntegratorKind>,
    /// Emitters seen directly from the camera (also through null surfaces) render black
    /// (Mitsuba's `hide_emitters`).
    pub hide_emitters: bool,
    pub filter: FilterDesc,
    /// Decoded images, referred to by the texture graph's image nodes and by lights.
    pub textures: Vec<ImageTexture>,
    /// The scene's textures (procedural, composite, image lookups); a
    /// [`ColorParam::Texture`] names one of its nodes.
    pub texture_graph: TextureGraph,
    pub materials: Vec<MaterialDesc>,
    pub shapes: Vec<ShapeDesc>,
    /// Groups of shapes declared once (in the group's space) and placed by
    /// [`Geometry::Instance`] shapes (Mitsuba's `shapegroup`).
    pub shape_groups: Vec<Vec<ShapeDesc>>,
    pub lights: Vec<LightDesc>,
    /// Warnings met while loading, in file order.
    pub warnings: Vec<SceneWarning>,
    /// What the loader adapted within the format (printed with the warnings, as notes).
    pub notes: Vec<String>,
}

impl SceneDesc {
    /// A scene with nothing in it yet, and neutral defaults a loader overrides with its format's:
    /// a 90-degree perspective camera at the origin (its `location` where the loader would name
    /// the camera), a 640x480 film with gamma 2.2 and autolinear tone mapping, a one-pixel box
    /// filter.
    pub fn empty(camera_location: Location) -> Self {
        Self {
            camera: CameraDesc {
                kind: &pinhole::CAMERA,
                fov_degrees: DEFAULT_FOV_DEGREES,
                camera_to_world: Mat4::IDENTITY,
                screen_window: None,
                lens_radius: 0.0,
                focal_distance: 1e6,
                location: camera_location,
            },
            film: FilmDesc {
                x_resolution: 640,
                y_resolution: 480,
                gamma: 2.2,
                filename: None,
                tonemap: ToneMap::AutoLinear,
            },
            pixel_samples: None,
            max_depth: None,
            integrator: None,
            hide_emitters: false,
            filter: FilterDesc {
                kind: FilterKind::Box,
                radius: Vec2::splat(0.5),
            },
            textures: Vec::new(),
            texture_graph: TextureGraph::default(),
            materials: Vec::new(),
            shapes: Vec::new(),
            shape_groups: Vec::new(),
            lights: Vec::new(),
            warnings: Vec::new(),
            notes: Vec::new(),
        }
    }
}

/// The field of view when a scene gives none (and of cameras that take none, should the
/// command line switch to one that does).
pub const DEFAULT_FOV_DEGREES: f32 = 90.0;

#[derive(Clone, Debug, PartialEq)]
pub struct CameraDesc {
    /// The projection, from the camera registry.
    pub kind: &'static CameraType,
    /// The field of view in degrees, for the kinds that take one (see [`CameraType::fov`]).
    pub fov_degrees: f32,
    /// Camera space to world: camera space has x right, y up, z forward (the viewing direction).
    pub camera_to_world: Mat4,
    /// The screen window [xmin xmax ymin ymax]; `None`: the shorter image axis spans [-1, 1].
    pub screen_window: Option<[f32; 4]>,
    /// A thin lens in front of the projection: radius 0 is none.
    pub lens_radius: f32,
    pub focal_distance: f32,
    pub location: Location,
}

#[derive(Clone, Debug, PartialEq)]
pub struct FilmDesc {
    pub x_resolution: u32,
    pub y_resolution: u32,
    /// Display gamma for 8-bit output (LuxRender's `gamma`, default 2.2).
    pub gamma: f32,
    /// `filename` without extension, if given.
    pub filename: Option<String>,
    pub tonemap: ToneMap,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ToneMap {
    /// LuxRender's `autolinear`: exposure from the image's mean luminance.
    AutoLinear,
    /// `linear` (or any other kernel): a fixed scale.
    Linear { scale: f32 },
    /// LuxRender's `reinhard`: Reinhard et al. 2002's global operator.
    Reinhard {
        prescale: f32,
        postscale: f32,
        burn: f32,
    },
    /// LuxRender 0.x's `reinhard`: the curve on absolute luminance (`film::ToneMapOp`).
    ReinhardAbsolute {
        prescale: f32,
        postscale: f32,
        burn: f32,
    },
    /// LuxRender's `contrast`: Ward 1994, `ywa` the display adaptation luminance.
    Contrast { ywa: f32 },
    /// LuxRender's `maxwhite`: the brightest pixel to white.
    MaxWhite,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FilterDesc {
    pub kind: FilterKind,
    /// Half-widths in pixels (LuxRender's `xwidth`, `ywidth`).
    pub radius: Vec2,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FilterKind {
    Box,
    /// `alpha`: the falloff, as in pbrt: exp(-alpha x^2) - exp(-alpha r^2).
    Gaussian {
        alpha: f32,
    },
    BlackmanHarris,
    /// Mitchell and Netravali 1988 cubic with parameters B and C (LuxRender's defaults 1/3, 1/3).
    Mitchell {
        b: f32,
        c: f32,
    },
    /// A tent reaching 0 at the radius.
    Triangle,
    /// Lanczos-windowed sinc with `tau` lobes (LuxRender's `sinc`, default 3).
    Sinc {
        tau: f32,
    },
}

/// A decoded image, rows from the top.
#[derive(Clone, Debug)]
pub struct ImageTexture {
    pub name: String,
    pub path: PathBuf,
    pub width: u32,
    pub height: u32,
    /// `width * height` texels, linear RGB (already multiplied by `gain`, `gamma` undone) or
    /// 8-bit codes decoded to those values at lookup.
    pub texels: Texels,
    /// uv mapping: (u, v) -> (u * scale.x + delta.x, v * scale.y + delta.y), then wrapped.
    pub scale: Vec2,
    pub delta: Vec2,
    pub wrap: Wrap,
}

pub type TextureId = usize;
pub type MaterialId = usize;

/// A colour parameter: a constant or a node of the scene's texture graph.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ColorParam {
    Constant(Vec3),
    Texture(TextureId),
}

/// A float parameter: a constant or a texture node, read as the mean of its channels (the
/// texture graph's rule; a constant holds the value in all three).
pub type FloatParam = ColorParam;

/// A surface's scattering, as a physical model.
#[derive(Clone, Debug, PartialEq)]
pub enum MaterialDesc {
    /// Lambertian reflection.
    Diffuse { reflectance: ColorParam },
    /// Oren-Nayar rough diffuse reflection; `sigma_degrees`: the standard deviation of the
    /// facet slope angle.
    RoughDiffuse {
        reflectance: ColorParam,
        sigma_degrees: FloatParam,
    },
    /// A diffuse base under a glossy dielectric coating (Schlick's coated model):
    /// `specular` the coating's reflectance at normal incidence, `absorption` and `depth` its
    /// absorption coefficient and thickness, `roughness` Schlick's r (GGX alpha^2),
    /// `anisotropy` Schlick's (0 isotropic, positive: wider along the surface's v).
    CoatedDiffuse {
        diffuse: ColorParam,
        specular: ColorParam,
        absorption: ColorParam,
        depth: f32,
        roughness: f32,
        anisotropy: f32,
    },
    /// A perfect mirror: `reflectance` at every angle, no Fresnel falloff.
    Mirror { reflectance: ColorParam },
    /// A smooth dielectric interface: `ior` inside over outside (the normal points outside);
    /// `reflectance` and `transmittance` scale the Fresnel-weighted lobes.
    Dielectric {
        reflectance: ColorParam,
        transmittance: ColorParam,
        ior: f32,
    },
    /// A GGX microfacet conductor, its Fresnel term Schlick's approximation from `specular`, the
    /// reflectance at normal incidence; `alpha_u`, `alpha_v` are the roughness along the surface's
    /// u and v directions.
    RoughConductor {
        specular: ColorParam,
        alpha_u: f32,
        alpha_v: f32,
    },
    /// Diffuse reflection of `reflectance` and diffuse transmission of `transmittance`
    /// (LuxRender's `mattetranslucent`), both Oren-Nayar of slope deviation `sigma_degrees`
    /// (0: Lambertian).
    DiffuseTranslucent {
        reflectance: ColorParam,
        transmittance: ColorParam,
        sigma_degrees: FloatParam,
    },
    /// A conductor of complex index `eta` + i `k` (relative to the outside) with the exact
    /// Fresnel term, its lobe scaled by `reflectance`: smooth (a mirror) for `roughness` None.
    Conductor {
        reflectance: ColorParam,
        eta: Vec3,
        k: Vec3,
        roughness: Option<Roughness>,
    },
    /// A microfacet dielectric interface (Walter et al. 2007): `ior` inside over outside.
    RoughDielectric {
        reflectance: ColorParam,
        transmittance: ColorParam,
        ior: f32,
        roughness: Roughness,
    },
    /// A thin dielectric sheet of index `ior` (relative to its surroundings): mirror reflection
    /// and straight transmission, interreflections summed.
    ThinDielectric {
        reflectance: ColorParam,
        transmittance: ColorParam,
        ior: f32,
    },
    /// A diffuse base under a dielectric coating of index `ior` (relative to outside), smooth
    /// for `alpha` None, else GGX of that alpha; `nonlinear`: the base's interreflections
    /// tint it (Kd / (1 - Fdr Kd)) rather than only brighten it (Kd / (1 - Fdr)).
    Plastic {
        diffuse: ColorParam,
        specular: ColorParam,
        ior: f32,
        alpha: Option<f32>,
        nonlinear: bool,
    },
    /// A mirror plus a glossy Schlick microfacet lobe of roughness r = `roughness`, each with a
    /// conductor Fresnel term whose complex index is fitted to a reflectance (`mirror`,
    /// `glossy`; pbrt-v1's `FresnelApproxEta`/`FresnelApproxK`): LuxRender's `shinymetal`.
    /// `anisotropy` is Schlick's (0 isotropic, positive: wider along the surface's v);
    /// `film` a thin film's thickness (nm) and index on the mirror.
    FittedConductor {
        glossy: ColorParam,
        mirror: ColorParam,
        roughness: f32,
        anisotropy: f32,
        film: Option<(f32, f32)>,
    },
    /// Asperity scattering of a thin layer (Koenderink and Pont 2002): `legendre` the phase
    /// function's coefficients A1..A3, `thickness` the layer's optical thickness.
    Velvet {
        reflectance: ColorParam,
        legendre: [f32; 3],
        thickness: f32,
    },
    /// Car paint (Günther et al. 2005): three Schlick microfacet lobes over a diffuse base of
    /// `diffuse` under a clear coat of absorption `absorption` and thickness `depth`.
    CarPaint {
        diffuse: ColorParam,
        absorption: ColorParam,
        depth: f32,
        lobes: [CarPaintLobeDesc; 3],
    },
    /// A thin translucent sheet (LuxRender's `glossytranslucent`): on each side a glossy
    /// coating over the diffuse base `diffuse`, and diffuse transmission of `transmittance`
    /// through both coatings. `front` is on the side the normal points to.
    GlossyTranslucent {
        diffuse: ColorParam,
        transmittance: ColorParam,
        front: GlossyCoatingDesc,
        back: GlossyCoatingDesc,
    },
    /// A Lambertian base plus a Blinn microfacet lobe of `exponent` (LuxRender 0.x's `plastic`).
    BlinnPlastic {
        diffuse: ColorParam,
        specular: ColorParam,
        exponent: f32,
    },
    /// Ashikhmin and Shirley's diffuse and anisotropic Phong lobe, exponents along dp/du and
    /// across (LuxRender 0.x's `substrate`).
    FresnelBlend {
        diffuse: ColorParam,
        specular: ColorParam,
        exponents: (f32, f32),
    },
    /// A measured BRDF of generalized cosine lobes (LuxRender 0.x's `primer`, `clay`, ...).
    Lafortune(&'static LafortuneFit),
    /// Invisible: rays pass through (for light emitters).
    Null,
    /// `amount` of `second`, `1 - amount` of `first`.
    Mix {
        first: MaterialId,
        second: MaterialId,
        amount: FloatParam,
    },
    /// `material` with its shading normal bent by the displacement `height` (a float texture,
    /// world units), differentiated over steps of `sample_distance`.
    Bump {
        material: MaterialId,
        height: TextureId,
        sample_distance: f32,
    },
    /// `material` seen from the side its surface's normal faces, black from the back (Mitsuba's
    /// reflecting BSDFs outside `twosided`). Any other material scatters from both sides.
    OneSided { material: MaterialId },
}

/// One side's coating of [`MaterialDesc::GlossyTranslucent`], as in
/// [`MaterialDesc::CoatedDiffuse`]; `multibounce` adds Schlick's interreflection in the
/// coating's creases.
#[derive(Clone, Debug, PartialEq)]
pub struct GlossyCoatingDesc {
    pub specular: ColorParam,
    pub absorption: ColorParam,
    pub depth: f32,
    pub roughness: f32,
    /// Schlick's anisotropy (see [`MaterialDesc::CoatedDiffuse`]).
    pub anisotropy: f32,
    pub multibounce: bool,
}

/// One specular lobe of [`MaterialDesc::CarPaint`]: its colour, its Fresnel reflectance at
/// normal incidence, its roughness (Schlick's r is its square).
#[derive(Clone, Debug, PartialEq)]
pub struct CarPaintLobeDesc {
    pub specular: ColorParam,
    pub f0: f32,
    pub roughness: f32,
}

/// A microfacet distribution of normals.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MicrofacetDistribution {
    Beckmann,
    Ggx,
}

/// Microfacet roughness: the distribution and its alpha (RMS slope for Beckmann) along the
/// surface's u and v directions.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Roughness {
    pub distribution: MicrofacetDistribution,
    pub alpha_u: f32,
    pub alpha_v: f32,
}

#[derive(Clone, Debug, PartialEq)]
pub enum Geometry {
    /// A sphere of `radius` around the object-space origin.
    Sphere { radius: f32 },
    /// Triangles in object space.
    TriangleMesh {
        positions: Vec<Vec3>,
        /// Per-vertex shading normals, if given.
        normals: Option<Vec<Vec3>>,
        /// Per-vertex uv, if given.
        uvs: Option<Vec<Vec2>>,
        indices: Vec<[u32; 3]>,
    },
    /// The course's infinite plane through the object-space origin.
    Plane { normal: Vec3 },
    /// The unit disk in the object-space plane z = 0, normal +z (Mitsuba's `disk`).
    Disk,
    /// A placed copy of `SceneDesc::shape_groups[group]`, each member with its own material; its
    /// meshes are shared (built once, placed by a second BVH level), not copied.
    Instance { group: usize },
}

#[derive(Clone, Debug, PartialEq)]
pub struct ShapeDesc {
    pub geometry: Geometry,
    pub object_to_world: Mat4,
    /// `None`: no material was set; the builder uses a grey diffuse.
    pub material: Option<MaterialId>,
    pub area_light: Option<AreaLightDesc>,
    pub location: Location,
}

impl ShapeDesc {
    /// The surface area in world space; infinite for a plane. A sphere under a non-uniform scale
    /// counts as one of the geometric-mean radius (exact for a uniform scale).
    pub fn surface_area(&self) -> f32 {
        let to_world = Affine3A::from_mat4(self.object_to_world);
        match &self.geometry {
            Geometry::TriangleMesh {
                positions, indices, ..
            } => {
                let p = |i: u32| to_world.transform_point3(positions[i as usize]);
                indices
                    .iter()
                    .map(|&[a, b, c]| 0.5 * (p(b) - p(a)).cross(p(c) - p(a)).length())
                    .sum()
            }
            Geometry::Sphere { radius } => {
                let m = to_world.matrix3;
                let scale = (m.x_axis.length() * m.y_axis.length() * m.z_axis.length()).cbrt();
                4.0 * PI * (radius * scale).powi(2)
            }
            Geometry::Disk => {
                let m = to_world.matrix3;
                PI * m.x_axis.cross(m.y_axis).length()
            }
            Geometry::Plane { .. } | Geometry::Instance { .. } => f32::INFINITY,
        }
    }
}

/// A shape that emits: one-sided, from the side its normals face.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AreaLightDesc {
    /// Emitted radiance (W m^-2 sr^-1 per RGB channel), uniform over the surface.
    pub radiance: Vec3,
}

#[derive(Clone, Debug, PartialEq)]
pub enum LightDesc {
    /// Radiant intensity `intensity` (W sr^-1) from `position`, the same in every direction.
    Point { position: Vec3, intensity: Vec3 },
    Spot {
        position: Vec3,
        /// Unit vector the spot points along.
        direction: Vec3,
        intensity: Vec3,
        /// Full cone half-angle (`coneangle`) and the width of its falloff (`conedeltaangle`), degrees.
        cone_angle: f32,
        cone_delta_angle: f32,
        /// The curve across the falloff band (LuxRender's and Mitsuba's differ).
        falloff: SpotFalloff,
    },
    /// Light arriving from `direction_to_light` (unit, world space) with radiance `radiance`.
    Distant {
        direction_to_light: Vec3,
        radiance: Vec3,
    },
    /// A distant disc (the sun): `radiance` from every direction within the cone around
    /// `direction_to_light` (unit, world space) whose half-angle has sine `sin_theta_max`.
    SunDisc {
        direction_to_light: Vec3,
        radiance: Vec3,
        sin_theta_max: f32,
    },
    /// Environment light: constant `radiance`, times the lat-long map if given.
    Infinite {
        radiance: Vec3,
        map: Option<TextureId>,
        light_to_world: Mat4,
    },
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn locations_show_the_column_where_there_is_one() {
        let mut at = Location::line("scene.xml", 12);
        assert_eq!(at.to_string(), "scene.xml:12");
        at.column = Some(7);
        assert_eq!(at.to_string(), "scene.xml:12:7");
    }
}
