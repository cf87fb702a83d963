"""Renders the six-colour box (tests/cameras.rs) through an equidistant fisheye with Blender Cycles
and with foton, and reports the per-pixel difference away from face edges and the image rim.

Cycles' FISHEYE_EQUIDISTANT maps the pixel centre (u, v) in [0, 1]^2 to r = hypot(2u-1, 2v-1),
theta = r * fov / 2, azimuth atan2(2v-1, 2u-1), black for r > 1: foton's `Ellipse` fit.

Usage (from the repository root, after `cargo build --release`):
    python3 -m venv /work/venv-bpy && /work/venv-bpy/bin/pip install bpy==5.0.1 numpy
    /work/venv-bpy/bin/python scripts/cycles_fisheye.py [--fov 180] [--size 96x64] [--spp 16]
"""

import argparse
import math
import subprocess
import tempfile
from pathlib import Path

import bpy
import numpy as np
from mathutils import Matrix

# Outward axis of each face and the radiance it emits inwards, as in tests/cameras.rs.
FACES = [
    ((1, 0, 0), (1, 0, 0)),
    ((-1, 0, 0), (0, 1, 0)),
    ((0, 1, 0), (0, 0, 1)),
    ((0, -1, 0), (1, 1, 0)),
    ((0, 0, 1), (1, 0, 1)),
    ((0, 0, -1), (0, 1, 1)),
]
# The camera at the box's centre looks along world -x; camera right is world +y, up world +z.
CAMERA_TO_WORLD = np.array([[0, 0, -1], [1, 0, 0], [0, 1, 0]], dtype=float)  # columns x, y, z


def face_corners(axis):
    axis = np.array(axis, dtype=float)
    u = np.array([1.0, 0, 0]) if axis[0] == 0 else np.array([0, 1.0, 0])
    v = np.cross(u, axis)  # u x v = -axis: the normal faces inwards
    return [axis - u - v, axis + u - v, axis + u + v, axis - u + v]


def write_lxs(path, fov, width, height):
    lines = [
        "LookAt 0 0 0  -1 0 0  0 0 1",
        f'Camera "fisheye" "float fov" [{fov}]',
        f'Film "fleximage" "integer xresolution" [{width}] "integer yresolution" [{height}]',
        'PixelFilter "box" "float xwidth" [0.5] "float ywidth" [0.5]',
        "WorldBegin",
        'MakeNamedMaterial "null" "string type" ["null"]',
    ]
    for axis, colour in FACES:
        points = " ".join(f"{c:g}" for corner in face_corners(axis) for c in corner)
        lines += [
            "AttributeBegin",
            'NamedMaterial "null"',
            'AreaLightSource "area" "color L" [{} {} {}]'.format(*colour),
            f'Shape "trianglemesh" "integer indices" [0 1 2 0 2 3] "point P" [{points}]',
            "AttributeEnd",
        ]
    lines.append("WorldEnd")
    path.write_text("\n".join(lines) + "\n")


def render_foton(folder, fov, width, height, spp):
    scene = folder / "six_colour_box.lxs"
    write_lxs(scene, fov, width, height)
    output = folder / "foton.exr"
    root = Path(__file__).resolve().parent.parent
    subprocess.run(
        [str(root / "target/release/foton"), "render", str(scene), "--output", str(output),
         "--spp", str(spp), "--max-depth", "1", "--fisheye-fit", "ellipse"],
        check=True,
    )
    return load_exr(output, width, height)


def render_cycles(folder, fov, width, height, spp):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = spp
    scene.cycles.use_denoising = False
    scene.cycles.max_bounces = 0
    scene.cycles.filter_width = 1.0  # a 1-pixel box: samples jitter over the whole pixel
    scene.render.resolution_x, scene.render.resolution_y = width, height
    scene.render.resolution_percentage = 100
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.image_settings.color_depth = "32"
    scene.world = bpy.data.worlds.new("black")
    scene.world.color = (0, 0, 0)
    for axis, colour in FACES:
        mesh = bpy.data.meshes.new(f"face{axis}")
        mesh.from_pydata([tuple(c) for c in face_corners(axis)], [], [(0, 1, 2, 3)])
        material = bpy.data.materials.new(f"emit{axis}")
        material.use_nodes = True
        nodes = material.node_tree.nodes
        nodes.clear()
        emission = nodes.new("ShaderNodeEmission")
        emission.inputs["Color"].default_value = (*colour, 1.0)
        emission.inputs["Strength"].default_value = 1.0
        out = nodes.new("ShaderNodeOutputMaterial")
        material.node_tree.links.new(emission.outputs["Emission"], out.inputs["Surface"])
        mesh.materials.append(material)
        scene.collection.objects.link(bpy.data.objects.new(mesh.name, mesh))
    camera = bpy.data.cameras.new("fisheye")
    camera.type = "PANO"
    camera.panorama_type = "FISHEYE_EQUIDISTANT"
    camera.fisheye_fov = math.radians(fov)
    camera.clip_start = 0.01
    camera_object = bpy.data.objects.new("camera", camera)
    # Blender cameras look along local -z with local +y up.
    rotation = np.column_stack([CAMERA_TO_WORLD[:, 0], CAMERA_TO_WORLD[:, 1], -CAMERA_TO_WORLD[:, 2]])
    camera_object.matrix_world = Matrix([list(row) + [0] for row in rotation] + [[0, 0, 0, 1]])
    scene.collection.objects.link(camera_object)
    scene.camera = camera_object
    output = folder / "cycles.exr"
    scene.render.filepath = str(output)
    bpy.ops.render.render(write_still=True)
    return load_exr(output, width, height)


def load_exr(path, width, height):
    """Linear RGB, rows from the top."""
    image = bpy.data.images.load(str(path))
    pixels = np.array(image.pixels[:], dtype=np.float32).reshape(height, width, image.channels)
    return pixels[::-1, :, :3]


def checkable_pixels(fov, width, height):
    """Pixels whose whole footprint lies inside the image ellipse and looks at one face."""
    fov = math.radians(fov)
    half = np.array([width / 2, height / 2])
    footprint_radius = np.linalg.norm(0.5 / half)
    footprint_angle = footprint_radius * fov / 2 + math.radians(0.25)
    mask = np.zeros((height, width), dtype=bool)
    for y in range(height):
        for x in range(width):
            n = (np.array([x + 0.5, y + 0.5]) - half) / half
            n[1] = -n[1]
            r = np.linalg.norm(n)
            if r + footprint_radius > 1:
                continue
            theta, azimuth = r * fov / 2, math.atan2(n[1], n[0])
            d = CAMERA_TO_WORLD @ np.array(
                [math.sin(theta) * math.cos(azimuth), math.sin(theta) * math.sin(azimuth), math.cos(theta)]
            )
            a = np.sort(np.abs(d))
            mask[y, x] = math.asin((a[2] - a[1]) / math.sqrt(2)) > footprint_angle
    return mask


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--fov", type=float, default=180.0)
    parser.add_argument("--size", default="96x64")
    parser.add_argument("--spp", type=int, default=16)
    args = parser.parse_args()
    width, height = map(int, args.size.split("x"))
    with tempfile.TemporaryDirectory() as folder:
        folder = Path(folder)
        foton = render_foton(folder, args.fov, width, height, args.spp)
        cycles = render_cycles(folder, args.fov, width, height, args.spp)
    mask = checkable_pixels(args.fov, width, height)
    difference = np.abs(foton - cycles).max(axis=2)
    away = difference[mask]
    print(f"{args.fov} degree fisheye, {width}x{height}, {args.spp} spp")
    print(f"away from edges and rim: {mask.sum()} pixels, max |foton - cycles| {away.max():.3g}, "
          f"mean {away.mean():.3g}, differing by > 1e-3: {(away > 1e-3).sum()}")
    print(f"all pixels: mean |foton - cycles| {difference.mean():.3g}, "
          f"differing by > 0.05: {(difference > 0.05).sum()} of {width * height}")


if __name__ == "__main__":
    main()
