//! From a scene description to the bevy_ecs world: one entity per camera, shape and light, and
//! the resources the schedules read. Only what the scene uses is inserted.

use std::f32::consts::PI;

use bevy_ecs::prelude::*;
use glam::{Affine3A, Mat3, Vec3};

use super::desc::{AreaLightDesc, Geometry, LightDesc, MaterialDesc, Projection, SceneDesc};
use crate::camera::equirectangular::Equirectangular;
use crate::camera::fisheye::{Fisheye, FisheyeFit};
use crate::camera::orthographic::Orthographic;
use crate::camera::pinhole::Pinhole;
use crate::camera::thin_lens::ThinLens;
use crate::camera::{CameraPose, default_screen_window};
use crate::film::luminance;
use crate::film::{Film, PixelFilter};
use crate::integrator::start_pass::CameraSampling;
use crate::light::distant::DistantLight;
use crate::light::infinite::InfiniteLight;
use crate::light::point::PointLight;
use crate::light::spot::SpotLight;
use crate::material::MaterialTable;
use crate::material::texture::TextureTable;
use crate::sampling::{PixelSampler, SamplerKind};
use crate::settings::{IntegratorKind, RenderSettings};
use crate::shape::geometry::GeometryNeeds;
use crate::shape::{AreaEmitter, Plane, Sphere, SurfaceMaterial, TriangleMesh};

/// Samples per pixel and bounces when neither the scene nor the command line says.
pub const DEFAULT_SAMPLES_PER_PIXEL: u32 = 16;
pub const DEFAULT_MAX_DEPTH: u32 = 8;

/// The camera the command line asks for instead of the scene's.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CameraKind {
    Pinhole,
    ThinLens,
    Fisheye,
    Orthographic,
    Equirectangular,
}

/// What the command line sets on top of the scene file.
#[derive(Clone, Debug)]
pub struct RenderOptions {
    pub samples_per_pixel: Option<u32>,
    pub max_depth: Option<u32>,
    pub resolution: Option<(u32, u32)>,
    pub seed: u64,
    pub sampler: SamplerKind,
    pub integrator: IntegratorKind,
    pub time_limit: Option<std::time::Duration>,
    pub camera: Option<CameraKind>,
    pub focal_distance: Option<f32>,
    pub lens_radius: Option<f32>,
    pub fisheye_fov: Option<f32>,
    pub fisheye_fit: FisheyeFit,
    /// Render only these pixels (see `RenderSettings::pixels`).
    pub pixels: Option<Vec<u32>>,
}

impl Default for RenderOptions {
    fn default() -> Self {
        Self {
            samples_per_pixel: None,
            max_depth: None,
            resolution: None,
            seed: 0,
            sampler: SamplerKind::MultiJittered,
            integrator: IntegratorKind::PathTracer,
            time_limit: None,
            camera: None,
            focal_distance: None,
            lens_radius: None,
            fisheye_fov: None,
            fisheye_fit: FisheyeFit::Ellipse,
            pixels: None,
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
        seed: options.seed,
        sampler: options.sampler,
        integrator: options.integrator,
        time_limit: options.time_limit,
        pixels: options.pixels.clone(),
    };

    spawn_camera(&mut world, &desc, options, width, height, &mut notes);

    let mut materials = desc.materials.clone();
    let default_material = materials.len();
    materials.push(MaterialDesc::Matte {
        kd: super::desc::ColorParam::Constant(Vec3::splat(0.5)),
    });
    let material_table = MaterialTable { materials };
    let uses_textures = material_table.uses_textures();

    for shape in &desc.shapes {
        let material = SurfaceMaterial(shape.material.unwrap_or(default_material) as u32);
        let to_world = Affine3A::from_mat4(shape.object_to_world);
        let (mut spawned, area) = match &shape.geometry {
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
                    uvs: uvs.clone().filter(|_| uses_textures),
                    indices: indices.clone(),
                };
                let area = mesh_area(&mesh);
                let entity = world.spawn((mesh, material));
                (entity, area)
            }
            Geometry::Sphere { radius } => {
                let m = to_world.matrix3;
                let scale = (m.x_axis.length() * m.y_axis.length() * m.z_axis.length()).cbrt();
                let area = 4.0 * PI * (radius * scale).powi(2);
                let entity = world.spawn((
                    Sphere {
                        object_to_world: to_world,
                        radius: *radius,
                    },
                    material,
                ));
                (entity, area)
            }
            Geometry::Plane { normal } => {
                let normal_matrix = to_world.matrix3.inverse().transpose();
                let plane = Plane {
                    point: to_world.translation.into(),
                    normal: Vec3::from(normal_matrix * glam::Vec3A::from(*normal))
                        .normalize_or(Vec3::Z),
                };
                (world.spawn((plane, material)), f32::INFINITY)
            }
        };
        if let Some(light) = &shape.area_light {
            if area.is_finite() && area > 0.0 {
                spawned.insert(AreaEmitter {
                    radiance: area_radiance(light, area),
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
            } => {
                world.spawn(SpotLight::new(
                    *position,
                    *direction,
                    *intensity,
                    *cone_angle,
                    *cone_delta_angle,
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
                    map: map.and_then(|id| desc.textures.get(id).cloned()),
                    light_to_world: Mat3::from_mat4(*light_to_world),
                });
            }
        }
    }

    if uses_textures {
        world.insert_resource(TextureTable {
            textures: desc.textures.clone(),
        });
    }
    world.insert_resource(GeometryNeeds { uvs: uses_textures });
    world.insert_resource(material_table);
    world.insert_resource(CameraSampling {
        sampler: PixelSampler::new(settings.sampler, settings.samples_per_pixel, settings.seed),
        filter: PixelFilter::new(&desc.filter),
    });
    world.insert_resource(Film::new(width, height));
    world.insert_resource(settings);
    (world, notes)
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
    let scene_fov = match camera.projection {
        Projection::Perspective { fov_degrees } | Projection::Fisheye { fov_degrees } => {
            fov_degrees
        }
        _ => 90.0,
    };
    let kind = options.camera.unwrap_or(match camera.projection {
        Projection::Fisheye { .. } => CameraKind::Fisheye,
        Projection::Orthographic => CameraKind::Orthographic,
        Projection::Equirectangular => CameraKind::Equirectangular,
        _ if camera.lens_radius > 0.0 => CameraKind::ThinLens,
        _ => CameraKind::Pinhole,
    });
    let lens = ThinLens {
        lens_radius: options.lens_radius.unwrap_or(camera.lens_radius).max(0.0),
        focal_distance: options
            .focal_distance
            .unwrap_or(camera.focal_distance)
            .max(1e-4),
    };
    let mut entity = world.spawn(pose);
    match kind {
        CameraKind::Pinhole | CameraKind::ThinLens => {
            let fov_degrees = match camera.projection {
                Projection::Perspective { fov_degrees } => fov_degrees,
                _ => scene_fov,
            };
            entity.insert(Pinhole {
                fov_degrees,
                screen_window: window,
            });
        }
        CameraKind::Orthographic => {
            entity.insert(Orthographic {
                screen_window: window,
            });
        }
        CameraKind::Equirectangular => {
            entity.insert(Equirectangular);
        }
        CameraKind::Fisheye => {
            entity.insert(Fisheye {
                fov_degrees: options.fisheye_fov.unwrap_or(match camera.projection {
                    Projection::Fisheye { fov_degrees } => fov_degrees,
                    _ => 180.0,
                }),
                fit: options.fisheye_fit,
            });
        }
    }
    // The lens composes with any projection; radius 0 is exactly the pinhole, so no stage.
    let wants_lens = kind == CameraKind::ThinLens || options.lens_radius.is_some();
    if wants_lens && lens.lens_radius > 0.0 {
        entity.insert(lens);
    } else if kind == CameraKind::ThinLens {
        notes.push("thin-lens camera with lens radius 0: rendered as a pinhole".into());
    }
}

/// LuxRender's area light: L * gain, and with power and efficacy both set, scaled so the
/// emitter's luminous flux is power * efficacy (flux = pi * area * L for a one-sided
/// Lambertian emitter).
fn area_radiance(light: &AreaLightDesc, area: f32) -> Vec3 {
    let mut gain = light.gain;
    let y = luminance(light.l);
    if light.power > 0.0 && light.efficacy > 0.0 && y > 0.0 {
        gain *= light.power * light.efficacy / (PI * area * y);
    }
    light.l * gain
}

fn mesh_area(mesh: &TriangleMesh) -> f32 {
    mesh.indices
        .iter()
        .map(|[a, b, c]| {
            let p = |i: &u32| mesh.positions[*i as usize];
            0.5 * (p(b) - p(a)).cross(p(c) - p(a)).length()
        })
        .sum()
}
