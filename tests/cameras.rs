//! The cameras against geometry whose image is known exactly.
//!
//! - Every camera, with and without a thin lens, under both integrators, on the test box and the
//!   project's scene files: no rejected (NaN, infinite, negative) sample, no panic, not black.
//! - A thin lens of radius 0 is bitwise the camera without one.
//! - The fisheye and the equirectangular panorama, seen from the centre of a box whose six faces
//!   emit six colours inwards: each pixel whose whole footprint looks at one face shows exactly
//!   that face's colour, pixels outside the fisheye's image circle are exactly black, and the
//!   image is not mirrored (image up is camera up, image right camera right).
//! - The orthographic camera: an emitting square covers the same pixels at any distance.
//! - Depth of field: the 10%-90% width of a defocused edge matches the thin lens's circle of
//!   confusion, and the edge in focus is sharp.

use std::f32::consts::{FRAC_1_SQRT_2, PI};
use std::path::Path;

use crate::common::*;
use foton::camera::equirectangular::equirectangular_direction;
use foton::camera::fisheye::{self, FisheyeFit, fisheye_direction};
use foton::camera::{CameraType, equirectangular, orthographic, pinhole, thin_lens};
use foton::scene::build::RenderOptions;
use foton::scene::desc::{CameraDesc, SceneDesc};
use foton::settings::IntegratorKind;
use glam::{Vec2, Vec3};

const INTEGRATORS: [IntegratorKind; 2] = [IntegratorKind::PathTracer, IntegratorKind::RayCaster];

/// The box's faces by outward axis, with the radiance each emits inwards.
const FACE_COLOURS: [(Vec3, Vec3); 6] = [
    (Vec3::X, Vec3::new(1.0, 0.0, 0.0)),
    (Vec3::NEG_X, Vec3::new(0.0, 1.0, 0.0)),
    (Vec3::Y, Vec3::new(0.0, 0.0, 1.0)),
    (Vec3::NEG_Y, Vec3::new(1.0, 1.0, 0.0)),
    (Vec3::Z, Vec3::new(1.0, 0.0, 1.0)),
    (Vec3::NEG_Z, Vec3::new(0.0, 1.0, 1.0)),
];

/// A camera emitted radiance reaches unchanged: the film's mean of identical samples (f64 sums)
/// is exact, so anything beyond rounding means a sample saw another face or nothing.
const EXACT: f32 = 1e-6;

/// Slack on top of a pixel's angular footprint for f32 rounding in the direction maps.
const ANGLE_SLACK: f32 = 0.25 * PI / 180.0;

/// A box camera that is not axis-aligned with the image: forward is world -x, so camera right is
/// world +y and camera up world +z.
fn box_camera() -> CameraDesc {
    look_at(Vec3::ZERO, Vec3::NEG_X, 90.0)
}

/// The camera-to-world rotation of `box_camera`, for directions.
fn box_camera_to_world(direction: Vec3) -> Vec3 {
    box_camera().camera_to_world.transform_vector3(direction)
}

fn face_colour(axis: Vec3) -> Vec3 {
    FACE_COLOURS
        .iter()
        .find(|(face, _)| *face == axis)
        .map(|(_, colour)| *colour)
        .expect("an axis of the box")
}

/// The cube [-1, 1]^3 of null-material quads, each emitting its colour inwards.
fn six_colour_box(camera: CameraDesc, width: u32, height: u32) -> SceneDesc {
    let mut scene = empty_scene(camera, width, height);
    let null = null_material(&mut scene);
    for (axis, colour) in FACE_COLOURS {
        let u = if axis.x == 0.0 { Vec3::X } else { Vec3::Y };
        // u x v = -axis: the right-hand rule turns the normal inwards.
        let v = u.cross(axis);
        quad(
            &mut scene,
            [axis - u - v, axis + u - v, axis + u + v, axis - u + v],
            null,
            Some(emitter(colour)),
        );
    }
    scene
}

/// The face a direction points at, and the angle from the direction to the nearest face
/// boundary (the great circles |d_a| = |d_b|, which contain every cube edge).
fn face_towards(direction: Vec3) -> (Vec3, f32) {
    let d = direction.normalize();
    let a = d.abs();
    let dominant = a.max_position();
    let second = (0..3)
        .filter(|&i| i != dominant)
        .map(|i| a[i])
        .fold(0.0, f32::max);
    let mut axis = Vec3::ZERO;
    axis[dominant] = d[dominant].signum();
    (axis, ((a[dominant] - second) * FRAC_1_SQRT_2).asin())
}

fn overrides(camera: &'static CameraType, integrator: IntegratorKind, spp: u32) -> RenderOptions {
    RenderOptions {
        camera: Some(camera),
        integrator: Some(integrator),
        ..options(spp, 1)
    }
}

fn assert_exact(pixel: Vec3, expected: Vec3, what: &str) {
    assert!(
        (pixel - expected).abs().max_element() <= EXACT,
        "{what}: {pixel}, expected {expected}"
    );
}

fn scene_file(name: &str) -> SceneDesc {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes")
        .join(name);
    foton::scene::load(&path).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn every_camera_and_lens_renders_finite_non_black_images_with_both_integrators() {
    // Every camera in the registry.
    let cameras = foton::camera::CAMERAS;
    let scenes = [
        ("test box", test_box()),
        ("default.lxs", scene_file("default.lxs")),
        ("cornell.lxs", scene_file("cornell.lxs")),
    ];
    let (width, height, spp) = (32, 24, 2);
    for (name, scene) in &scenes {
        for camera in cameras {
            // No lens, and a lens on every projection (a fisheye through a thin lens included).
            for lens_radius in [None, Some(0.05)] {
                for integrator in INTEGRATORS {
                    let options = RenderOptions {
                        resolution: Some((width, height)),
                        lens_radius,
                        focal_distance: Some(3.5),
                        ..overrides(camera, integrator, spp)
                    };
                    let film = render_film(
                        scene.clone(),
                        &RenderOptions {
                            max_depth: Some(4),
                            ..options
                        },
                    );
                    let case = format!("{name}, {camera:?}, lens {lens_radius:?}, {integrator:?}");
                    assert_eq!(film.rejected_samples(), 0, "{case}: rejected samples");
                    assert_eq!(
                        film.samples_per_pixel_min(),
                        spp as u64,
                        "{case}: missing samples"
                    );
                    let image = film.mean();
                    assert!(
                        image
                            .iter()
                            .all(|p| p.is_finite() && p.min_element() >= 0.0),
                        "{case}: non-finite or negative pixel"
                    );
                    // Every camera here sees the lit inside of a box: at least 2.5% of the
                    // image for the panorama and the 180 degree fisheye (19 and 34 pixels
                    // measured), most of it for the others.
                    let lit = image.iter().filter(|p| p.max_element() > 0.0).count();
                    assert!(lit * 100 >= image.len() * 2, "{case}: {lit} lit pixels");
                }
            }
        }
    }
}

#[test]
fn lens_of_radius_zero_is_bitwise_the_camera_without_lens() {
    let zero_lens = |camera: &'static CameraType, lens_radius: Option<f32>| {
        let options = RenderOptions {
            lens_radius,
            focal_distance: Some(2.0),
            seed: 11,
            ..overrides(camera, IntegratorKind::PathTracer, 4)
        };
        render(
            test_box(),
            &RenderOptions {
                max_depth: Some(4),
                ..options
            },
        )
    };
    assert_eq!(
        zero_lens(&thin_lens::CAMERA, Some(0.0)),
        zero_lens(&pinhole::CAMERA, None)
    );
    assert_eq!(
        zero_lens(&fisheye::CAMERA, Some(0.0)),
        zero_lens(&fisheye::CAMERA, None)
    );
}

/// The equidistant fisheye written out here rather than taken from the camera: the angle from the
/// view axis is r * fov / 2, the azimuth is the film point's (x right, y up).
fn equidistant_direction(normalized: Vec2, fov_radians: f32) -> Vec3 {
    let theta = normalized.length() * fov_radians * 0.5;
    let azimuth = Vec2::from_angle(normalized.y.atan2(normalized.x));
    (azimuth * theta.sin()).extend(theta.cos())
}

/// Renders the six-colour box with the fisheye and checks every pixel against the face its
/// footprint looks at. Returns how many pixels were checked inside the image circle.
fn check_fisheye_box(fov_degrees: f32, fit: FisheyeFit, width: u32, height: u32) -> usize {
    let fov = fov_degrees.to_radians();
    let size = Vec2::new(width as f32, height as f32);
    let half_extent = match fit {
        FisheyeFit::Ellipse => size * 0.5,
        FisheyeFit::Circle => Vec2::splat(size.min_element() * 0.5),
    };
    // Samples jitter over the whole pixel: its footprint reaches this far, in normalised film
    // units, from its centre.
    let footprint_radius = (Vec2::splat(0.5) / half_extent).length();
    // The equidistant map stretches normalised distances by at most fov / 2 (radially exactly,
    // tangentially sin(theta) / r <= fov / 2): the footprint's angular radius.
    let footprint_angle = footprint_radius * fov * 0.5;
    let mut checked_inside = 0;
    for integrator in INTEGRATORS {
        let options = RenderOptions {
            fisheye_fov: Some(fov_degrees),
            fisheye_fit: fit,
            ..overrides(&fisheye::CAMERA, integrator, 4)
        };
        let image = render(six_colour_box(box_camera(), width, height), &options);
        checked_inside = 0;
        let mut faces_seen = Vec::new();
        for y in 0..height {
            for x in 0..width {
                let pixel = image[(y * width + x) as usize];
                let centred = (Vec2::new(x as f32, y as f32) + 0.5 - size * 0.5) / half_extent;
                let normalized = Vec2::new(centred.x, -centred.y);
                let case = format!(
                    "{fov_degrees} degrees {fit:?} {width}x{height} {integrator:?} pixel ({x}, {y})"
                );
                let r = normalized.length();
                if r - footprint_radius > 1.0 {
                    assert_eq!(pixel, Vec3::ZERO, "{case} is outside the image circle");
                    continue;
                }
                if r + footprint_radius > 1.0 {
                    continue; // Straddles the rim.
                }
                let direction = equidistant_direction(normalized, fov);
                let from_camera = fisheye_direction(normalized, fov).expect("inside the circle");
                assert!(
                    from_camera.abs_diff_eq(direction, 1e-5),
                    "{case}: {from_camera}"
                );
                let (face, margin) = face_towards(box_camera_to_world(direction));
                if margin > footprint_angle + ANGLE_SLACK {
                    assert_exact(pixel, face_colour(face), &case);
                    checked_inside += 1;
                    if !faces_seen.contains(&face) {
                        faces_seen.push(face);
                    }
                }
            }
        }
        // A hemisphere sees five faces whole or in part, the sphere all six.
        let expected_faces = if fov_degrees > 270.0 { 6 } else { 5 };
        assert_eq!(
            faces_seen.len(),
            expected_faces,
            "faces seen {faces_seen:?}"
        );
    }
    checked_inside
}

#[test]
fn fisheye_pixels_show_the_face_their_direction_points_at() {
    let cases = [
        (180.0, FisheyeFit::Circle, 64, 64, 32.0 * 32.0),
        (180.0, FisheyeFit::Ellipse, 96, 64, 48.0 * 32.0),
        (180.0, FisheyeFit::Circle, 96, 64, 32.0 * 32.0),
        (360.0, FisheyeFit::Circle, 64, 64, 32.0 * 32.0),
    ];
    for (fov_degrees, fit, width, height, semi_axes_product) in cases {
        let checked = check_fisheye_box(fov_degrees, fit, width, height);
        // Only pixels near a face boundary or the rim are skipped: 82% to 88% of the image
        // circle's area is checked (2788, 4260, 2788 and 2624 pixels).
        let circle_area = PI * semi_axes_product;
        assert!(
            checked as f32 > 0.75 * circle_area,
            "{fov_degrees} degrees {fit:?} {width}x{height}: {checked} of {circle_area} checked"
        );
    }
}

#[test]
fn fisheye_360_sees_forward_at_the_centre_and_backward_at_the_rim() {
    let options = RenderOptions {
        fisheye_fov: Some(360.0),
        ..overrides(&fisheye::CAMERA, IntegratorKind::RayCaster, 4)
    };
    let image = render(six_colour_box(box_camera(), 64, 64), &options);
    let forward = face_colour(Vec3::NEG_X);
    let backward = face_colour(Vec3::X);
    // The centre 4x4 pixels are within 12 degrees of the view axis.
    for (x, y) in [(30, 30), (33, 33), (31, 32)] {
        assert_exact(image[y * 64 + x], forward, "centre");
    }
    // 3 pixels in from the rim (r ~ 0.9): 160 to 163 degrees from the view axis, all around.
    for (x, y) in [(32, 3), (32, 60), (3, 32), (60, 32), (11, 11), (52, 52)] {
        assert_exact(image[y * 64 + x], backward, &format!("rim ({x}, {y})"));
    }
}

/// The value shared by the pixels [x0, x1) x [y0, y1), asserting they all agree exactly.
fn uniform_region(image: &[Vec3], width: u32, xs: (u32, u32), ys: (u32, u32), what: &str) -> Vec3 {
    let first = image[(ys.0 * width + xs.0) as usize];
    for y in ys.0..ys.1 {
        for x in xs.0..xs.1 {
            assert_exact(image[(y * width + x) as usize], first, what);
        }
    }
    first
}

#[test]
fn fisheye_image_up_is_camera_up_and_right_is_camera_right() {
    // Independent of `fisheye_direction`: regions near the middle of each border and the centre,
    // named by the world axis `box_camera` puts there.
    let (forward, right, up) = (Vec3::NEG_X, Vec3::Y, Vec3::Z);
    for (width, height) in [(64, 64), (96, 64)] {
        let options = RenderOptions {
            fisheye_fov: Some(180.0),
            ..overrides(&fisheye::CAMERA, IntegratorKind::PathTracer, 4)
        };
        let image = render(six_colour_box(box_camera(), width, height), &options);
        let (cx, cy) = (width / 2, height / 2);
        // From 1/32 to 1/8 of the size in from a border: 68 to 80 degrees off axis, within
        // 4 degrees of the border's mid-line, well inside the side face.
        let (ix, iy) = (width / 16, height / 16);
        let regions = [
            ("top", (cx - 2, cx + 2), (iy / 2 + 1, iy * 2), up),
            (
                "bottom",
                (cx - 2, cx + 2),
                (height - iy * 2, height - iy / 2 - 1),
                -up,
            ),
            (
                "right",
                (width - ix * 2, width - ix / 2 - 1),
                (cy - 2, cy + 2),
                right,
            ),
            ("left", (ix / 2 + 1, ix * 2), (cy - 2, cy + 2), -right),
            ("centre", (cx - 4, cx + 4), (cy - 4, cy + 4), forward),
        ];
        for (name, xs, ys, axis) in regions {
            let seen = uniform_region(&image, width, xs, ys, name);
            assert_exact(seen, face_colour(axis), &format!("{width}x{height} {name}"));
        }
    }
}

#[test]
fn equirectangular_pixels_show_the_face_their_direction_points_at() {
    let (width, height) = (128, 64);
    // A pixel spans 2 pi / width in longitude and pi / height in latitude; its footprint lies
    // within half its diagonal (in angle) of its centre's direction.
    let footprint_angle = Vec2::new(PI / width as f32, PI / (2.0 * height as f32)).length();
    let mut checked = 0;
    for integrator in INTEGRATORS {
        let options = overrides(&equirectangular::CAMERA, integrator, 4);
        let image = render(six_colour_box(box_camera(), width, height), &options);
        checked = 0;
        for y in 0..height {
            for x in 0..width {
                let longitude = ((x as f32 + 0.5) / width as f32 - 0.5) * 2.0 * PI;
                let latitude = (0.5 - (y as f32 + 0.5) / height as f32) * PI;
                let direction = Vec3::new(
                    latitude.cos() * longitude.sin(),
                    latitude.sin(),
                    latitude.cos() * longitude.cos(),
                );
                let from_camera = equirectangular_direction(longitude, latitude);
                assert!(
                    from_camera.abs_diff_eq(direction, 1e-5),
                    "{from_camera} vs {direction}"
                );
                let (face, margin) = face_towards(box_camera_to_world(direction));
                if margin > footprint_angle + ANGLE_SLACK {
                    let case = format!("{integrator:?} pixel ({x}, {y})");
                    assert_exact(image[(y * width + x) as usize], face_colour(face), &case);
                    checked += 1;
                }
            }
        }
        // Independent of `equirectangular_direction`: the centre looks forward, a quarter turn
        // right shows camera right, the top row up, the bottom row down, the left border back.
        let at = |x: u32, y: u32| image[(y * width + x) as usize];
        let (cx, cy) = (width / 2, height / 2);
        let landmarks = [
            ("centre", at(cx, cy), Vec3::NEG_X),
            ("quarter right", at(cx + width / 4, cy), Vec3::Y),
            ("quarter left", at(cx - width / 4, cy), Vec3::NEG_Y),
            ("top", at(cx, 0), Vec3::Z),
            ("bottom", at(cx, height - 1), Vec3::NEG_Z),
            ("left border", at(0, cy), Vec3::X),
        ];
        for (name, pixel, axis) in landmarks {
            assert_exact(pixel, face_colour(axis), &format!("{integrator:?} {name}"));
        }
    }
    // Only pixels near a face boundary are skipped: 7552 of 8192 checked.
    assert!(checked > 6000, "{checked} of 8192 pixels checked");
}

#[test]
fn orthographic_square_covers_the_same_pixels_at_any_distance() {
    let size = 32;
    let radiance = Vec3::new(0.25, 0.5, 1.0);
    // The unit square is [-0.5, 0.5]^2 in camera x and y; with window [xmin, xmax] the pixel
    // edges fall on its edges, so each pixel is wholly on or off it: columns and rows [lo, hi).
    let windows = [
        ([-1.0, 1.0, -1.0, 1.0], (8, 24), (8, 24)),
        ([0.0, 2.0, -1.0, 1.0], (0, 8), (8, 24)),
        ([-1.0, 1.0, -0.5, 1.5], (8, 24), (16, 32)),
    ];
    for (window, columns, rows) in windows {
        for distance in [0.5, 3.0, 40.0] {
            let mut camera = look_at(Vec3::ZERO, Vec3::Y, 90.0);
            camera.kind = &orthographic::CAMERA;
            camera.screen_window = Some(window);
            let mut scene = empty_scene(camera, size, size);
            let black = matte(&mut scene, Vec3::ZERO);
            // Camera x is world x, camera y world z; the normal faces the camera (-y).
            let corner = |x: f32, z: f32| Vec3::new(x, distance, z);
            quad(
                &mut scene,
                [
                    corner(-0.5, -0.5),
                    corner(0.5, -0.5),
                    corner(0.5, 0.5),
                    corner(-0.5, 0.5),
                ],
                black,
                Some(emitter(radiance)),
            );
            let image = render(scene, &options(4, 1));
            for y in 0..size {
                for x in 0..size {
                    let on_square =
                        (columns.0..columns.1).contains(&x) && (rows.0..rows.1).contains(&y);
                    let expected = if on_square { radiance } else { Vec3::ZERO };
                    let case = format!("window {window:?}, distance {distance}, pixel ({x}, {y})");
                    assert_exact(image[(y * size + x) as usize], expected, &case);
                }
            }
        }
    }
}

/// The fraction of a uniform disk left of the vertical line at `t` radii from its centre: the
/// edge spread function of a defocused straight edge.
fn disk_fraction_left_of(t: f32) -> f32 {
    let t = t.clamp(-1.0, 1.0);
    0.5 + (t * (1.0 - t * t).sqrt() + t.asin()) / PI
}

/// The 10%-90% rise distance, in pixels, of a profile going from 0 to 1, interpolating
/// linearly between pixel centres.
fn rise_width(profile: &[f32]) -> f32 {
    let crossing = |level: f32| {
        let i = profile
            .iter()
            .position(|&v| v >= level)
            .filter(|&i| i > 0)
            .unwrap_or_else(|| panic!("profile never rises through {level}: {profile:?}"));
        let (below, above) = (profile[i - 1], profile[i]);
        // Pixel i - 1's centre is at i - 0.5.
        i as f32 - 0.5 + (level - below) / (above - below)
    };
    crossing(0.9) - crossing(0.1)
}

#[test]
fn depth_of_field_blurs_an_edge_by_the_circle_of_confusion() {
    let (width, height, fov_degrees) = (96, 32, 30.0_f32);
    let edge_distance = 2.0;
    // Screen coordinates are tangents: the image height spans 2 tan(fov / 2).
    let pixels_per_tangent = height as f32 / (2.0 * (fov_degrees.to_radians() * 0.5).tan());
    let edge_column = width as f32 * 0.5;
    let mut scene = empty_scene(look_at(Vec3::ZERO, Vec3::Y, fov_degrees), width, height);
    let black = matte(&mut scene, Vec3::ZERO);
    // A white emitter filling the right half of the view, its left edge on the view axis.
    let corner = |x: f32, z: f32| Vec3::new(x, edge_distance, z);
    quad(
        &mut scene,
        [
            corner(0.0, -10.0),
            corner(10.0, -10.0),
            corner(10.0, 10.0),
            corner(0.0, 10.0),
        ],
        black,
        Some(emitter(Vec3::ONE)),
    );
    let measured_width = |lens_radius: f32, focal_distance: f32| {
        let options = RenderOptions {
            lens_radius: Some(lens_radius),
            focal_distance: Some(focal_distance),
            ..overrides(&thin_lens::CAMERA, IntegratorKind::RayCaster, 64)
        };
        let image = render(scene.clone(), &options);
        let profile: Vec<f32> = (0..width)
            .map(|x| {
                (0..height)
                    .map(|y| image[(y * width + x) as usize].x)
                    .sum::<f32>()
                    / height as f32
            })
            .collect();
        rise_width(&profile)
    };
    // The thin lens images a point at depth d, focused at f, as a disk of diameter
    // 2 R |1/f - 1/d| in tangent units. The model profile is that disk's edge spread averaged
    // over each pixel (the box filter's footprint).
    let expected_width = |lens_radius: f32, focal_distance: f32| {
        let blur_radius =
            lens_radius * (1.0 / focal_distance - 1.0 / edge_distance).abs() * pixels_per_tangent;
        let profile: Vec<f32> = (0..width)
            .map(|x| {
                let steps = 64;
                (0..steps)
                    .map(|s| {
                        let u = x as f32 + (s as f32 + 0.5) / steps as f32;
                        disk_fraction_left_of((u - edge_column) / blur_radius.max(1e-6))
                    })
                    .sum::<f32>()
                    / steps as f32
            })
            .collect();
        rise_width(&profile)
    };

    // In focus: the step falls within one pixel column, a width of 0.8 by interpolation.
    let in_focus = measured_width(0.2, edge_distance);
    assert!(in_focus <= 1.0, "edge in focus is {in_focus} pixels wide");

    // Focused in front of the edge (|1/f - 1/d| = 0.5) with growing lenses, then behind it
    // (0.25). Blur radii 1.5 to 6 pixels. The model matches within 1% (measured 2.45, 4.26,
    // 8.31 and 4.26 against 2.43, 4.26, 8.27 and 4.26); 5% allows for the Monte Carlo noise of
    // 2048 samples a column, and is far below the 100% a wrong factor of 2 would give.
    let mut previous = in_focus;
    for (lens_radius, focal_distance) in [(0.05, 1.0), (0.1, 1.0), (0.2, 1.0)] {
        let measured = measured_width(lens_radius, focal_distance);
        let expected = expected_width(lens_radius, focal_distance);
        assert!(measured > previous, "width {measured} after {previous}");
        assert!(
            (measured - expected).abs() <= 0.05 * expected,
            "R {lens_radius}: {measured} vs {expected}"
        );
        previous = measured;
    }
    let behind = measured_width(0.2, 4.0);
    let expected = expected_width(0.2, 4.0);
    assert!(
        (behind - expected).abs() <= 0.05 * expected,
        "focus behind: {behind} vs {expected}"
    );
}
