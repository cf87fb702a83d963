"""Redo the tables of the original Java renderer's final report with foton.

The original (shared/seed/final-report.md) rendered a depth-of-field series on
metal2_scene/untitled.lxs at 960x540 and a fisheye series on scene_hard at 640x360, both with
4 hops and 1,600 samples per pixel (16 AA x 100). This script renders the same series with
foton, times each render (foton's own reported seconds), and writes:

- docs/images/report-tables.jpg: each foton image beside the original's, with a caption;
- docs/report-tables.md: the table, the settings and the exact command;
- the same table in Markdown on stdout.

scene_hard's geometry is missing upstream, so the fisheye series uses metal2_scene instead.
The defaults are the original's settings; --spp and --scale make a quicker run.
"""

from __future__ import annotations

import argparse
import os
import sys
from dataclasses import dataclass
from pathlib import Path

from foton_common import (
    REPO,
    display_command,
    foton_binary,
    render,
    require_file,
    shared_root,
)

from PIL import Image, ImageDraw, ImageFont

FULL_SPP = 1600
MAX_DEPTH = 4
SHEET_CELL = (480, 270)  # Each image is fitted into this box on the contact sheet.
SUBSTITUTE_NOTE = (
    "scene_hard's geometry is missing upstream, so foton renders the fisheye series on "
    "metal2_scene/untitled.lxs; the original's fisheye times are for scene_hard, so their "
    "speed-ups compare different scenes."
)


@dataclass(frozen=True)
class Shot:
    """One image of the original report: its name, camera settings and time."""

    name: str
    original_image: str
    width: int
    height: int
    settings: str
    camera_options: tuple[str, ...]
    original_seconds: float


def dof(index: int, focal: float, radius: float, seconds: float) -> Shot:
    """A depth-of-field shot: thin lens with focal distance `focal` and lens radius `radius`."""
    return Shot(
        name=f"dof{index}",
        original_image=f"dof-{index}.png",
        width=960,
        height=540,
        settings=f"thin lens, focal distance {focal:g}, lens radius {radius:g}",
        camera_options=(
            "--camera", "thin-lens",
            "--focal-distance", f"{focal:g}",
            "--lens-radius", f"{radius:g}",
        ),
        original_seconds=seconds,
    )


def fisheye(index: int, aperture: float, seconds: float) -> Shot:
    """A fisheye shot with an aperture of `aperture` degrees."""
    return Shot(
        name=f"fisheye{index}",
        original_image=f"fisheye-{index}.png",
        width=640,
        height=360,
        settings=f"fisheye, aperture {aperture:g} deg, on metal2_scene (original: scene_hard)",
        camera_options=("--camera", "fisheye", "--fisheye-fov", f"{aperture:g}"),
        original_seconds=seconds,
    )


SHOTS = (
    dof(1, 11, 1, 1115),
    dof(2, 11, 2, 1026),
    dof(3, 11, 3, 1093),
    dof(4, 7, 2, 1075),
    dof(5, 13, 2, 1077),
    fisheye(1, 45, 6538),
    fisheye(2, 120, 2286),
    fisheye(3, 240, 1750),
)


@dataclass(frozen=True)
class Result:
    """A shot rendered by foton: where the image is, its resolution and foton's time."""

    shot: Shot
    image: Path
    resolution: tuple[int, int]
    spp: int
    seconds: float

    @property
    def projected_seconds(self) -> float:
        """foton's time scaled to the original's work (time linear in pixels x spp)."""
        width, height = self.resolution
        work = width * height * self.spp
        return self.seconds * (self.shot.width * self.shot.height * FULL_SPP) / work

    @property
    def speedup(self) -> float:
        """The original's time over foton's time projected to the original's settings."""
        return self.shot.original_seconds / self.projected_seconds


def parse_args() -> argparse.Namespace:
    """The command-line options."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument(
        "--spp", type=int, default=FULL_SPP,
        help=f"samples per pixel (default: the original's {FULL_SPP})",
    )
    parser.add_argument(
        "--scale", type=float, default=1.0,
        help="resolution factor on the original's 960x540 / 640x360 (default: 1)",
    )
    parser.add_argument("--threads", type=int, help="foton's worker threads (default: all cores)")
    parser.add_argument(
        "--renders", type=Path, default=REPO / "out" / "report-tables",
        help="folder for foton's images (default: out/report-tables)",
    )
    parser.add_argument(
        "--docs", type=Path, default=REPO / "docs",
        help="folder for report-tables.md and images/report-tables.jpg (default: docs)",
    )
    args = parser.parse_args()
    if args.spp < 1:
        parser.error("--spp must be at least 1")
    if not 0 < args.scale <= 4:
        parser.error("--scale must be in (0, 4]")
    return args


def render_shot(shot: Shot, scene: Path, args: argparse.Namespace) -> Result:
    """Render one shot with foton at the requested spp and scale; return its result."""
    width = max(1, round(shot.width * args.scale))
    height = max(1, round(shot.height * args.scale))
    options = [
        "--spp", str(args.spp),
        "--max-depth", str(MAX_DEPTH),
        "--resolution", f"{width}x{height}",
        *shot.camera_options,
    ]
    if args.threads:
        options += ["--threads", str(args.threads)]
    image = args.renders / f"{shot.name}.png"
    print(f"rendering {shot.name} ({shot.settings}, {width}x{height}, {args.spp} spp)...",
          file=sys.stderr, flush=True)
    seconds = render(scene, image, options)
    return Result(shot=shot, image=image, resolution=(width, height), spp=args.spp,
                  seconds=seconds)


def is_full(args: argparse.Namespace) -> bool:
    """Whether the run uses the original's settings, so times compare directly."""
    return args.spp == FULL_SPP and args.scale == 1.0


def markdown_table(results: list[Result], full: bool) -> str:
    """The results as a Markdown table."""
    header = ["Image", "Settings", "foton resolution, spp", "foton (s)"]
    if not full:
        header.append("foton projected to 1,600 spp, original size (s)")
    header += ["Original (s)", "Speed-up"]
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    for result in results:
        shot = result.shot
        width, height = result.resolution
        row = [shot.name, shot.settings, f"{width}x{height}, {result.spp}",
               f"{result.seconds:.2f}"]
        if not full:
            row.append(f"{result.projected_seconds:.0f}")
        row += [f"{shot.original_seconds:,.0f}", f"{result.speedup:.1f}x"]
        lines.append("| " + " | ".join(row) + " |")
    return "\n".join(lines)


def fit(image: Image.Image, box: tuple[int, int]) -> Image.Image:
    """`image` scaled to fit in `box`, keeping its aspect ratio."""
    scale = min(box[0] / image.width, box[1] / image.height)
    size = (max(1, round(image.width * scale)), max(1, round(image.height * scale)))
    return image.convert("RGB").resize(size, Image.LANCZOS)


def contact_sheet(results: list[Result], originals: Path, title: str, full: bool,
                  output: Path) -> None:
    """Write a JPEG with each foton image beside the original's, each pair captioned."""
    font = ImageFont.load_default(size=15)
    small = ImageFont.load_default(size=13)
    margin, gap, caption_height, title_height = 12, 8, 44, 52
    cell_w, cell_h = SHEET_CELL
    row_h = cell_h + caption_height + gap
    width = 2 * cell_w + gap + 2 * margin
    height = title_height + len(results) * row_h + margin
    sheet = Image.new("RGB", (width, height), "white")
    draw = ImageDraw.Draw(sheet)
    draw.text((margin, 8), title, fill="black", font=font)
    draw.text((margin, 28), "left: foton    right: original Java renderer", fill="dimgray",
              font=small)
    for row, result in enumerate(results):
        shot = result.shot
        top = title_height + row * row_h
        for column, path in enumerate((result.image, originals / shot.original_image)):
            with Image.open(path) as image:
                tile = fit(image, SHEET_CELL)
            left = margin + column * (cell_w + gap)
            offset = ((cell_w - tile.width) // 2, (cell_h - tile.height) // 2)
            sheet.paste(tile, (left + offset[0], top + offset[1]))
        width_px, height_px = result.resolution
        draw.text((margin, top + cell_h + 4),
                  f"{shot.name}: {shot.settings}; foton {width_px}x{height_px}, "
                  f"{result.spp} spp, depth {MAX_DEPTH}",
                  fill="black", font=small)
        projected = "" if full else (
            f" (projected to the original's settings: {result.projected_seconds:.0f} s)")
        draw.text((margin, top + cell_h + 22),
                  f"foton {result.seconds:.2f} s{projected}, original "
                  f"{shot.original_seconds:,.0f} s, speed-up {result.speedup:.1f}x",
                  fill="black", font=small)
    output.parent.mkdir(parents=True, exist_ok=True)
    sheet.save(output, quality=85, optimize=True)


def write_markdown(path: Path, table: str, args: argparse.Namespace, full: bool,
                   command: str, load: float) -> None:
    """Write docs/report-tables.md: the settings, the command, the table and the notes."""
    if full:
        settings = f"the original's settings: {FULL_SPP} spp at the original resolution"
        projection = ""
    else:
        settings = (f"reduced settings: {args.spp} spp (original: {FULL_SPP}) at {args.scale:g} "
                    "times the original resolution")
        projection = ("\n- The projected column scales foton's time to the original's work, "
                      "assuming time linear in pixels x spp; the speed-up uses it.")
    text = f"""# The original report's tables, redone with foton

- Rendered with {settings}, maximum depth {MAX_DEPTH}.
- Machine: {os.cpu_count()} cores, foton threads: {args.threads or "all"}, load average {load:.1f}
  when the run started. Times are foton's own reported render seconds.
- The original's times are from its final report (Java, on the authors' unknown machine), so the
  speed-ups are indicative only.{projection}
- {SUBSTITUTE_NOTE}

Command:

```
{command}
```

{table}

![foton (left) beside the original (right)](images/report-tables.jpg)
"""
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text)


def main() -> None:
    """Render the series, write the contact sheet and the Markdown, print the table."""
    args = parse_args()
    foton_binary()
    shared = shared_root()
    scene = require_file(shared / "scenes" / "itba" / "metal2_scene" / "untitled.lxs",
                         "the metal2 scene")
    originals = shared / "seed" / "final-images"
    for shot in SHOTS:
        require_file(originals / shot.original_image, "the original's image")
    load = os.getloadavg()[0]
    results = [render_shot(shot, scene, args) for shot in SHOTS]
    full = is_full(args)
    table = markdown_table(results, full)
    label = "original settings" if full else f"{args.spp} spp, scale {args.scale:g}"
    contact_sheet(results, originals, f"The original report's series, redone with foton ({label})",
                  full, args.docs / "images" / "report-tables.jpg")
    write_markdown(args.docs / "report-tables.md", table, args, full, display_command(sys.argv),
                   load)
    print(table)
    print()
    print(SUBSTITUTE_NOTE)


if __name__ == "__main__":
    main()
