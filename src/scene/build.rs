//! From a scene description to the bevy_ecs world: one entity per camera, shape and light, and
//! the resources the schedules read. Only what the scene uses is inserted.

use std::collections::HashMap;
use std::sync::Arc;

use bevy_ecs::prelude::*;
use glam::{Affine3A, Mat3, Vec3};

use super::desc::{
    ColorParam, FilterKind, Geometry, GlossyCoatingDesc, ImageTexture, LightDesc, MaterialDesc,
    MicrofacetDistribution, Roughness, SceneDesc, ShapeDesc, ToneMap,
};
use crate::bsdf::microfacet::clamp_alpha;
use crate::bsdf::microfacet_distribution::{DistributionKind, Microfacet};
use crate::bsdf::phong_distribution::PhongDistribution;
use crate::bsdf::plastic::internal_reflectance;
use crate::bsdf::rough_plastic::CoatingTables;
use crate::bsdf::thin_film::ThinFilm;
use crate::camera::fisheye::FisheyeFit;
use crate::camera::thin_lens::ThinLens;
use crate::camera::{CameraPose, CameraSetup, CameraType, default_screen_window};
use crate::film::{self, Film, PixelFilter};
use crate::integrator::start_pass::CameraSampling;
use crate::light::distant::DistantLight;
use crate::light::infinite::InfiniteLight;
use crate::light::point::PointLight;
use crate::light::spot::SpotLight;
use crate::light::sun_disc::SunDiscLight;
use crate::material::bump::BumpMap;
use crate::material::texture::{self, TextureTable};
use crate::material::{Color, GlossyCoating, Material, MaterialTable, PaintLobe};
use crate::sampling::{PixelSampler, SamplerKind};
use crate::settings::{IntegratorKind, RenderSettings};
use crate::shape::geometry::GeometryNeeds;
use crate::shape::{
    AreaEmitter, Disk, InstancedMesh, Plane, Sphere, SurfaceMaterial, TriangleMesh,
};

/// Samples per pixel and bounces when neither the scene nor the command line says.
pub const DEFAULT_SAMPLES_PER_PIXEL: u32 = 16;
pub const DEFAULT_MAX_DEPTH: u32 = 8;

/// What the command line sets on top of the scene file.
#[derive(Clone, Debug)]
pub struct RenderOptions {
    pub samples_per_pixel: Option<u32>,
    pub max_depth: Option<u32>,
    pub resolution: Option<(u32, u32)>,
    pub seed: u64,
    pub sampler: SamplerKind,
    /// The integrator; the scene's (else the path tracer) when `None`.
    pub integrator: Option<IntegratorKind>,
    pub time_limit: Option<std::time::Duration>,
    /// The camera to use instead of the scene's.
    pub camera: Option<&'static CameraType>,
    pub focal_distance: Option<f32>,
    pub lens_radius: Option<f32>,
    pub fisheye_fov: Option<f32>,
    pub fisheye_fit: FisheyeFit,
    /// Render only these pixels (see `RenderSettings::pixels`).
    pub pixels: Option<Vec<u32>>,
    /// The largest component a sample may bring to the film (`Film::clamp_samples`).
    pub clamp: Option<f32>,
}

impl Default for RenderOptions {
    fn default() -> Self {
        Self {
            samples_per_pixel: None,
            max_depth: None,
            resolution: None,
            seed: 0,
            sampler: SamplerKind::Sobol,
            integrator: None,
            time_limit: None,
            camera: None,
            focal_distance: None,
            lens_radius: None,
            fisheye_fov: None,
            fisheye_fit: FisheyeFit::Ellipse,
            pixels: None,
            clamp: None,
        }
    }
}

/// Builds the world; returns it with notes on what was adapted (for the user, as warnings).
pub fn build_world(desc: SceneDesc, options: &RenderOptions) -> (World, Vec<String>) {
    let mut notes = Vec::new();
    let mut world = World::new();
    let (width, height) = options
        .resolution
        .unwrap_or((desc.film.x_resolution, desc.film.y_resolution));
    let (width, height) = (width.max(1), height.max(1));
    let settings = RenderSettings {
        width,
        height,
        samples_per_pixel: options
            .samples_per_pixel
            .or(desc.pixel_samples)
            .unwrap_or(DEFAULT_SAMPLES_PER_PIXEL)
            .max(1),
        max_depth: options
            .max_depth
            .or(desc.max_depth)
            .unwrap_or(DEFAULT_MAX_DEPTH),
        hide_emitters: desc.hide_emitters,
        seed: options.seed,
        sampler: options.sampler,
        integrator: options
            .integrator
            .or(desc.integrator)
            .unwrap_or(IntegratorKind::PathTracer),
        time_limit: options.time_limit,
        pixels: options.pixels.clone(),
    };

    spawn_camera(&mut world, &desc, options, width, height, &mut notes);

    let mut materials: Vec<Material> = desc.materials.iter().map(material).collect();
    let default_material = materials.len();
    materials.push(Material::Lambertian {
        reflectance: Color::Constant(Vec3::splat(0.5)),
    });
    let material_table = MaterialTable::new(materials);
    let uses_textures = material_table.uses_textures();
    let needs_uvs = material_table.needs_uvs();

    // Instances place their groups' meshes by reference; any other member (a sphere, a plane)
    // is placed as a shape of its own.
    let placed_members: Vec<ShapeDesc> = (desc.shapes.iter())
        .filter_map(|shape| match shape.geometry {
            Geometry::Instance { group } => Some((shape, desc.shape_groups.get(group)?)),
            _ => None,
        })
        .flat_map(|(instance, members)| {
            (members.iter())
                .filter(|m| !matches!(m.geometry, Geometry::TriangleMesh { .. }))
                .map(|member| ShapeDesc {
                    object_to_world: instance.object_to_world * member.object_to_world,
                    ..member.clone()
                })
        })
        .collect();
    let mut shared_meshes = HashMap::new();
    for shape in desc.shapes.iter().chain(&placed_members) {
        let material = SurfaceMaterial(shape.material.unwrap_or(default_material) as u32);
        let to_world = Affine3A::from_mat4(shape.object_to_world);
        let mut spawned = match &shape.geometry {
            Geometry::Instance { group } => {
                let members = desc.shape_groups.get(*group).map_or(&[][..], Vec::as_slice);
                for (k, member) in members.iter().enumerate() {
                    let shared = shared_meshes
                        .entry((*group, k))
                        .or_insert_with(|| shared_mesh(member, needs_uvs));
                    let Some(mesh) = shared else { continue };
                    let material = member.material.unwrap_or(default_material) as u32;
                    world.spawn((
                        InstancedMesh {
                            object_to_world: to_world,
                            ..mesh.clone()
                        },
                        SurfaceMaterial(material),
                    ));
                }
                continue;
            }
            Geometry::TriangleMesh {
                positions,
                normals,
                uvs,
                indices,
            } => {
                let normal_matrix = to_world.matrix3.inverse().transpose();
                let mesh = TriangleMesh {
                    positions: positions
                        .iter()
                        .map(|p| to_world.transform_point3(*p))
                        .collect(),
                    normals: normals.as_ref().map(|ns| {
                        ns.iter()
                            .map(|n| Vec3::from(normal_matrix * glam::Vec3A::from(*n)))
                            .collect()
                    }),
                    uvs: uvs.clone().filter(|_| needs_uvs),
                    indices: indices.clone(),
                };
                world.spawn((mesh, material))
            }
            Geometry::Sphere { radius } => world.spawn((
                Sphere {
                    object_to_world: to_world,
                    radius: *radius,
                },
                material,
            )),
            Geometry::Disk => world.spawn((
                Disk {
                    object_to_world: to_world,
                },
                material,
            )),
            Geometry::Plane { normal } => {
                let normal_matrix = to_world.matrix3.inverse().transpose();
                let plane = Plane {
                    point: to_world.translation.into(),
                    normal: Vec3::from(normal_matrix * glam::Vec3A::from(*normal))
                        .normalize_or(Vec3::Z),
                };
                world.spawn((plane, material))
            }
        };
        if let Some(light) = &shape.area_light {
            let area = shape.surface_area();
            if area.is_finite() && area > 0.0 {
                spawned.insert(AreaEmitter {
                    radiance: light.radiance,
                });
            } else {
                notes.push(format!(
                    "{}: an area light on a shape without finite area is ignored",
                    shape.location
                ));
            }
        }
    }

    let mut environments = 0;
    for light in &desc.lights {
        match light {
            LightDesc::Point {
                position,
                intensity,
            } => {
                world.spawn(PointLight {
                    position: *position,
                    intensity: *intensity,
                });
            }
            LightDesc::Spot {
                position,
                direction,
                intensity,
                cone_angle,
                cone_delta_angle,
                falloff,
            } => {
                world.spawn(SpotLight::new(
                    *position,
                    *direction,
                    *intensity,
                    (*cone_angle, *cone_delta_angle),
                    *falloff,
                ));
            }
            LightDesc::Distant {
                direction_to_light,
                radiance,
            } => {
                world.spawn(DistantLight {
                    direction_to_light: direction_to_light.normalize_or(Vec3::Z),
                    radiance: *radiance,
                });
            }
            LightDesc::SunDisc {
                direction_to_light,
                radiance,
                sin_theta_max,
            } => {
                world.spawn(SunDiscLight::new(
                    *direction_to_light,
                    *radiance,
                    *sin_theta_max,
                ));
            }
            LightDesc::Infinite {
                radiance,
                map,
                light_to_world,
            } => {
                environments += 1;
                if environments > 1 {
                    notes.push("more than one infinite light: only the first is used".into());
                    continue;
                }
                world.spawn(InfiniteLight {
                    radiance: *radiance,
                    map: map
                        .and_then(|id| desc.textures.get(id))
                        .map(|image| image_texture(image, image.texels.to_linear())),
                    light_to_world: Mat3::from_mat4(*light_to_world),
                });
            }
        }
    }

    if uses_textures {
        world.insert_resource(TextureTable {
            textures: desc
                .textures
                .iter()
                .map(|image| image_texture(image, image.texels.clone()))
                .collect(),
            graph: desc.texture_graph.clone(),
        });
    }
    world.insert_resource(GeometryNeeds { uvs: needs_uvs });
    world.insert_resource(material_table);
    world.insert_resource(CameraSampling {
        sampler: PixelSampler::new(settings.sampler, settings.samples_per_pixel, settings.seed),
        filter: PixelFilter::new(
            match desc.filter.kind {
                FilterKind::Box => film::FilterKind::Box,
                FilterKind::Gaussian { alpha } => film::FilterKind::Gaussian { alpha },
                FilterKind::BlackmanHarris => film::FilterKind::BlackmanHarris,
                FilterKind::Mitchell { b, c } => film::FilterKind::Mitchell { b, c },
                FilterKind::Triangle => film::FilterKind::Triangle,
                FilterKind::Sinc { tau } => film::FilterKind::Sinc { tau },
            },
            desc.filter.radius,
        ),
    });
    let mut film = Film::new(width, height);
    film.clamp_samples(options.clamp);
    world.insert_resource(film);
    world.insert_resource(settings);
    (world, notes)
}

/// A shape group's member as a mesh to share between instances: its triangles, normals and
/// (where the scene samples textures) uvs per triangle in the group's space; `None` for a
/// member that is not a mesh. It is placed at the identity; each instance sets its own map.
fn shared_mesh(member: &ShapeDesc, needs_uvs: bool) -> Option<InstancedMesh> {
    let Geometry::TriangleMesh {
        positions,
        normals,
        uvs,
        indices,
    } = &member.geometry
    else {
        return None;
    };
    let to_group = Affine3A::from_mat4(member.object_to_world);
    let normal_matrix = to_group.matrix3.inverse().transpose();
    let p = |i: u32| to_group.transform_point3(positions[i as usize]);
    Some(InstancedMesh {
        triangles: Arc::new(indices.iter().map(|t| t.map(p)).collect()),
        normals: normals.as_ref().map(|ns| {
            let n = |i: u32| Vec3::from(normal_matrix * glam::Vec3A::from(ns[i as usize]));
            Arc::new(indices.iter().map(|t| t.map(n)).collect())
        }),
        uvs: (uvs.as_ref().filter(|_| needs_uvs))
            .map(|uvs| Arc::new(indices.iter().map(|t| t.map(|i| uvs[i as usize])).collect())),
        object_to_world: Affine3A::IDENTITY,
    })
}

fn spawn_camera(
    world: &mut World,
    desc: &SceneDesc,
    options: &RenderOptions,
    width: u32,
    height: u32,
    notes: &mut Vec<String>,
) {
    let camera = &desc.camera;
    let pose = CameraPose(Affine3A::from_mat4(camera.camera_to_world));
    let mut window = camera
        .screen_window
        .unwrap_or_else(|| default_screen_window(width, height));
    // A resolution of another shape than the window's: keep the window's width, fit its height.
    let window_aspect = (window[1] - window[0]) / (window[3] - window[2]);
    let image_aspect = width as f32 / height as f32;
    if (window_aspect / image_aspect - 1.0).abs() > 1e-3 {
        let centre = 0.5 * (window[2] + window[3]);
        let half = 0.5 * (window[1] - window[0]) / image_aspect;
        window[2] = centre - half;
        window[3] = centre + half;
    }
    let kind = options.camera.unwrap_or(camera.kind);
    let setup = CameraSetup {
        scene: camera,
        scene_names_it: *kind == *camera.kind,
        options,
        screen_window: window,
    };
    let mut entity = world.spawn(pose);
    (kind.build)(&setup, &mut entity, notes);
    ThinLens::compose(&setup, &mut entity);
}

/// The material table's entry for a described material.
fn material(desc: &MaterialDesc) -> Material {
    let color = |c: &ColorParam| match *c {
        ColorParam::Constant(rgb) => Color::Constant(rgb),
        ColorParam::Texture(id) => Color::Texture(id),
    };
    match desc {
        MaterialDesc::Diffuse { reflectance } => Material::Lambertian {
            reflectance: color(reflectance),
        },
        MaterialDesc::RoughDiffuse {
            reflectance,
            sigma_degrees,
        } => Material::OrenNayar {
            reflectance: color(reflectance),
            sigma_degrees: color(sigma_degrees),
        },
        MaterialDesc::CoatedDiffuse {
            diffuse,
            specular,
            absorption,
            depth,
            roughness,
            anisotropy,
        } => Material::CoatedGlossy {
            diffuse: color(diffuse),
            specular: color(specular),
            absorption: color(absorption),
            depth: *depth,
            roughness: *roughness,
            anisotropy: *anisotropy,
        },
        MaterialDesc::Mirror { reflectance } => Material::SpecularReflection {
            reflectance: color(reflectance),
        },
        MaterialDesc::Dielectric {
            reflectance,
            transmittance,
            ior,
        } => Material::Dielectric {
            reflectance: color(reflectance),
            transmittance: color(transmittance),
            eta: *ior,
        },
        MaterialDesc::RoughConductor {
            specular,
            alpha_u,
            alpha_v,
        } => Material::Conductor {
            f0: color(specular),
            alpha_x: *alpha_u,
            alpha_y: *alpha_v,
        },
        MaterialDesc::GlossyTranslucent {
            diffuse,
            transmittance,
            front,
            back,
        } => {
            let coating = |c: &GlossyCoatingDesc| GlossyCoating {
                specular: color(&c.specular),
                absorption: color(&c.absorption),
                depth: c.depth,
                roughness: c.roughness,
                anisotropy: c.anisotropy,
                multibounce: c.multibounce,
            };
            Material::GlossyTranslucent {
                diffuse: color(diffuse),
                transmittance: color(transmittance),
                front: coating(front),
                back: coating(back),
            }
        }
        MaterialDesc::DiffuseTranslucent {
            reflectance,
            transmittance,
            sigma_degrees,
        } => Material::DiffuseTranslucent {
            reflectance: color(reflectance),
            transmittance: color(transmittance),
            sigma_degrees: color(sigma_degrees),
        },
        MaterialDesc::Conductor {
            reflectance,
            eta,
            k,
            roughness,
        } => Material::ComplexConductor {
            reflectance: color(reflectance),
            eta: *eta,
            k: *k,
            distribution: roughness.as_ref().map(microfacet),
        },
        MaterialDesc::RoughDielectric {
            reflectance,
            transmittance,
            ior,
            roughness,
        } => Material::RoughDielectric {
            reflectance: color(reflectance),
            transmittance: color(transmittance),
            eta: *ior,
            distribution: microfacet(roughness),
        },
        MaterialDesc::ThinDielectric {
            reflectance,
            transmittance,
            ior,
        } => Material::ThinDielectric {
            reflectance: color(reflectance),
            transmittance: color(transmittance),
            eta: *ior,
        },
        MaterialDesc::Plastic {
            diffuse,
            specular,
            ior,
            alpha: None,
            nonlinear,
        } => Material::Plastic {
            diffuse: color(diffuse),
            specular: color(specular),
            eta: *ior,
            internal_reflectance: internal_reflectance(*ior),
            nonlinear: *nonlinear,
        },
        MaterialDesc::Plastic {
            diffuse,
            specular,
            ior,
            alpha: Some(alpha),
            nonlinear,
        } => Material::RoughPlastic {
            diffuse: color(diffuse),
            specular: color(specular),
            eta: *ior,
            alpha: *alpha,
            nonlinear: *nonlinear,
            tables: CoatingTables::of(clamp_alpha(*alpha), *ior),
        },
        MaterialDesc::FittedConductor {
            glossy,
            mirror,
            roughness,
            anisotropy,
            film,
        } => Material::FittedConductor {
            glossy: color(glossy),
            mirror: color(mirror),
            roughness: *roughness,
            anisotropy: *anisotropy,
            film: film.map(|(thickness, index)| ThinFilm { thickness, index }),
        },
        MaterialDesc::Velvet {
            reflectance,
            legendre,
            thickness,
        } => Material::Velvet {
            reflectance: color(reflectance),
            legendre: *legendre,
            thickness: *thickness,
        },
        MaterialDesc::CarPaint {
            diffuse,
            absorption,
            depth,
            lobes,
        } => Material::CarPaint {
            diffuse: color(diffuse),
            absorption: color(absorption),
            depth: *depth,
            lobes: [0, 1, 2].map(|i| PaintLobe {
                specular: color(&lobes[i].specular),
                f0: lobes[i].f0,
                roughness: lobes[i].roughness,
            }),
        },
        MaterialDesc::BlinnPlastic {
            diffuse,
            specular,
            exponent,
        } => Material::BlinnPlastic {
            diffuse: color(diffuse),
            specular: color(specular),
            distribution: PhongDistribution {
                ex: *exponent,
                ey: *exponent,
            },
        },
        MaterialDesc::FresnelBlend {
            diffuse,
            specular,
            exponents: (ex, ey),
        } => Material::FresnelBlend {
            diffuse: color(diffuse),
            specular: color(specular),
            distribution: PhongDistribution { ex: *ex, ey: *ey },
        },
        MaterialDesc::Lafortune(fit) => Material::Lafortune(fit),
        MaterialDesc::Null => Material::Null,
        MaterialDesc::OneSided { material } => Material::OneSided {
            material: *material,
        },
        MaterialDesc::Mix {
            first,
            second,
            amount,
        } => Material::Mix {
            first: *first,
            second: *second,
            amount: color(amount),
        },
        MaterialDesc::Bump {
            material,
            height,
            sample_distance,
        } => Material::Bump {
            material: *material,
            bump: BumpMap {
                height: *height,
                sample_distance: *sample_distance,
            },
        },
    }
}

/// The BSDF's distribution of the description's kind and alphas.
fn microfacet(roughness: &Roughness) -> Microfacet {
    let kind = match roughness.distribution {
        MicrofacetDistribution::Beckmann => DistributionKind::Beckmann,
        MicrofacetDistribution::Ggx => DistributionKind::TrowbridgeReitz,
    };
    Microfacet::new(kind, roughness.alpha_u, roughness.alpha_v)
}

/// The described image, reading its texels from `texels` (the environment light reads them
/// as linear RGB, textures as they were decoded).
fn image_texture<T>(image: &ImageTexture, texels: T) -> texture::ImageTexture<T> {
    texture::ImageTexture {
        width: image.width,
        height: image.height,
        texels,
        scale: image.scale,
        delta: image.delta,
        wrap: image.wrap,
    }
}

/// The film's tone map for the described one.
pub fn tone_map(desc: ToneMap) -> film::ToneMap {
    match desc {
        ToneMap::AutoLinear => film::ToneMap::AutoLinear,
        ToneMap::Linear { scale } => film::ToneMap::Linear { scale },
        ToneMap::Reinhard {
            prescale,
            postscale,
            burn,
        } => film::ToneMap::Reinhard {
            prescale,
            postscale,
            burn,
        },
        ToneMap::ReinhardAbsolute {
            prescale,
            postscale,
            burn,
        } => film::ToneMap::ReinhardAbsolute {
            prescale,
            postscale,
            burn,
        },
        ToneMap::Contrast { ywa } => film::ToneMap::Contrast { ywa },
        ToneMap::MaxWhite => film::ToneMap::MaxWhite,
    }
}
