"""Which pixel sampler converges fastest on a depth-of-field scene.

Renders metal2_scene/untitled.lxs through a thin lens (the lens blur dominates the image) as a
high-spp multi-jittered reference with its own seed, then with each sampler (independent,
stratified, multi-jittered) at 1, 2, 4, ... spp for a few seeds, and measures against the
reference the RMSE of the linear radiance (foton's .exr output) and the median relative squared
error (robust to fireflies), and foton's render time. Writes:

- docs/images/sampler-convergence.png: the errors against spp and against time, log-log;
- docs/sampler-convergence.md: the numbers, the ranking and the exact command;
- the same table in Markdown on stdout.
"""

from __future__ import annotations

import argparse
import math
import os
import sys
from dataclasses import dataclass
from pathlib import Path

from foton_common import (
    REPO,
    display_command,
    foton_binary,
    read_exr,
    render,
    require_file,
    shared_scenes,
)

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

SAMPLERS = ("independent", "stratified", "multi-jittered")
REFERENCE_SEED = 1000  # Differs from every test seed (0, 1, 2, ...).


@dataclass(frozen=True)
class Point:
    """One sampler at one spp: the errors and the time, each averaged over the seeds (the RMSE
    from the mean MSE)."""

    sampler: str
    spp: int
    rmse: float
    median_rel_se: float
    seconds: float


# The two error measures: (attribute of Point, label, short label, format in the table).
METRICS = (
    ("rmse", "RMSE of linear radiance", "RMSE", "{:.4f}"),
    ("median_rel_se", "median relative squared error", "median rel. SE", "{:.2e}"),
)
RELATIVE_EPSILON = 0.01  # Keeps dark pixels from dominating the relative error.


def parse_args() -> argparse.Namespace:
    """The command-line options."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--resolution", default="240x135", help="image size (default: 240x135)")
    parser.add_argument(
        "--max-depths", type=int, nargs="+", default=[4, 1],
        help="maximum bounces, one study each (default: 4 1; depth 1 has no caustic paths, so "
             "the film and lens sampling dominate its noise)",
    )
    parser.add_argument("--focal-distance", type=float, default=11.0,
                        help="thin lens focal distance (default: 11)")
    parser.add_argument("--lens-radius", type=float, default=2.0,
                        help="thin lens radius (default: 2)")
    parser.add_argument("--reference-spp", type=int, default=4096,
                        help="spp of the multi-jittered reference (default: 4096)")
    parser.add_argument("--max-spp", type=int, default=256,
                        help="highest spp measured, a power of two (default: 256)")
    parser.add_argument("--seeds", type=int, default=3,
                        help="seeds averaged per point (default: 3)")
    parser.add_argument("--threads", type=int, help="foton's worker threads (default: all cores)")
    parser.add_argument(
        "--renders", type=Path, default=REPO / "out" / "sampler-convergence",
        help="folder for foton's .exr images (default: out/sampler-convergence)",
    )
    parser.add_argument(
        "--docs", type=Path, default=REPO / "docs",
        help="folder for sampler-convergence.md and images/sampler-convergence.png "
             "(default: docs)",
    )
    args = parser.parse_args()
    if args.max_spp < 1 or args.max_spp & (args.max_spp - 1):
        parser.error("--max-spp must be a power of two")
    if args.reference_spp < 4 * args.max_spp:
        parser.error("--reference-spp must be at least 4 times --max-spp")
    if args.seeds < 1:
        parser.error("--seeds must be at least 1")
    return args


def spp_levels(max_spp: int) -> list[int]:
    """1, 2, 4, ..., max_spp."""
    return [2**k for k in range(int(math.log2(max_spp)) + 1)]


def common_options(args: argparse.Namespace, depth: int) -> list[str]:
    """The foton options that every render of a study shares: the lens, size and depth."""
    options = [
        "--resolution", args.resolution,
        "--max-depth", str(depth),
        "--camera", "thin-lens",
        "--focal-distance", f"{args.focal_distance:g}",
        "--lens-radius", f"{args.lens_radius:g}",
    ]
    if args.threads:
        options += ["--threads", str(args.threads)]
    return options


def study(scene: Path, args: argparse.Namespace, depth: int) -> list[Point]:
    """Render the reference, then every (sampler, spp, seed), all at maximum depth `depth`;
    return one Point per (sampler, spp)."""
    folder = args.renders / f"depth{depth}"
    print(f"depth {depth}: rendering the reference ({args.reference_spp} spp)...",
          file=sys.stderr, flush=True)
    render(scene, folder / "reference.exr", [
        *common_options(args, depth), "--sampler", "multi-jittered",
        "--spp", str(args.reference_spp), "--seed", str(REFERENCE_SEED),
    ])
    reference = read_exr(folder / "reference.exr")
    points = []
    for sampler in SAMPLERS:
        for spp in spp_levels(args.max_spp):
            squared, relative, times = [], [], []
            for seed in range(args.seeds):
                output = folder / f"{sampler}-{spp}spp-seed{seed}.exr"
                times.append(render(scene, output, [
                    *common_options(args, depth), "--sampler", sampler, "--spp", str(spp),
                    "--seed", str(seed),
                ]))
                error = (read_exr(output) - reference) ** 2
                squared.append(float(np.mean(error)))
                relative.append(median_relative_squared_error(error, reference))
            point = Point(sampler, spp, math.sqrt(np.mean(squared)), float(np.mean(relative)),
                          float(np.mean(times)))
            print(f"depth {depth} {sampler:>14} {spp:>4} spp: RMSE {point.rmse:.4f}, median "
                  f"relative squared error {point.median_rel_se:.6f}, {point.seconds:.2f} s",
                  file=sys.stderr, flush=True)
            points.append(point)
    return points


def median_relative_squared_error(error: np.ndarray, reference: np.ndarray) -> float:
    """The median over pixels of (x - ref)^2 / (ref^2 + epsilon), averaged over channels:
    the typical pixel's error, which the rare very bright paths (fireflies) that dominate
    any mean over pixels do not decide."""
    return float(np.median(np.mean(error / (reference**2 + RELATIVE_EPSILON), axis=2)))


def slope(points: list[Point], metric: str) -> float:
    """The least-squares slope of log `metric` against log spp, from 4 spp up (Monte Carlo's
    1/N is -0.5 for the RMSE and -1 for a squared error; steeper is better)."""
    fitted = [p for p in points if p.spp >= 4]
    values = [getattr(p, metric) for p in fitted]
    return float(np.polyfit(np.log([p.spp for p in fitted]), np.log(values), 1)[0])


def by_sampler(points: list[Point]) -> dict[str, list[Point]]:
    """The points grouped by sampler, each group in increasing spp."""
    return {s: sorted((p for p in points if p.sampler == s), key=lambda p: p.spp)
            for s in SAMPLERS}


def chart(studies: dict[int, list[Point]], title: str, output: Path) -> None:
    """Plot each error measure against spp and against render time, log-log, one line per
    sampler and one row per maximum depth, with Monte Carlo's rate as a dotted guide."""
    figure, grid = plt.subplots(len(studies), 2 * len(METRICS),
                                figsize=(5 * 2 * len(METRICS), 4.2 * len(studies)),
                                squeeze=False)
    for (depth, points), row in zip(studies.items(), grid):
        groups = by_sampler(points)
        for index, (metric, label, _, _) in enumerate(METRICS):
            by_spp, by_time = row[2 * index], row[2 * index + 1]
            for sampler, series in groups.items():
                values = [getattr(p, metric) for p in series]
                by_spp.loglog([p.spp for p in series], values, "o-",
                              label=f"{sampler} (slope {slope(series, metric):.2f})")
                by_time.loglog([p.seconds for p in series], values, "o-", label=sampler)
            first = groups["independent"]
            power = 0.5 if metric == "rmse" else 1.0
            start = getattr(first[0], metric)
            by_spp.loglog([p.spp for p in first], [start / p.spp**power for p in first], "k:",
                          label="1/sqrt(spp)" if metric == "rmse" else "1/spp")
            by_spp.set(xlabel="samples per pixel", ylabel=label,
                       title=f"depth {depth}: {label}\nagainst spp")
            by_time.set(xlabel="foton render time (s)", ylabel=label,
                        title=f"depth {depth}: {label}\nagainst render time")
            for axes in (by_spp, by_time):
                axes.grid(True, which="both", alpha=0.3)
                axes.legend(fontsize="small")
    figure.suptitle(title)
    figure.tight_layout()
    output.parent.mkdir(parents=True, exist_ok=True)
    figure.savefig(output, dpi=80)
    plt.close(figure)


def markdown_table(points: list[Point]) -> str:
    """Each error measure and the time for each spp (rows) and sampler (columns), in Markdown,
    with the fitted slopes in the last row."""
    groups = by_sampler(points)
    header = ["spp"]
    for _, _, short, _ in METRICS:
        header += [f"{s} {short}" for s in SAMPLERS]
    header += [f"{s} s" for s in SAMPLERS]
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    for row in zip(*groups.values()):
        cells = [str(row[0].spp)]
        for metric, _, _, form in METRICS:
            cells += [form.format(getattr(p, metric)) for p in row]
        cells += [f"{p.seconds:.2f}" for p in row]
        lines.append("| " + " | ".join(cells) + " |")
    slopes = ["slope from 4 spp"]
    for metric, _, _, _ in METRICS:
        slopes += [f"{slope(g, metric):.2f}" for g in groups.values()]
    slopes += [""] * len(SAMPLERS)
    lines.append("| " + " | ".join(slopes) + " |")
    return "\n".join(lines)


def conclusion(points: list[Point]) -> str:
    """Sentences naming the fastest-converging sampler at the highest spp for each error
    measure, with the ratios to the others."""
    top = max(p.spp for p in points)
    sentences = []
    for metric, label, _, _ in METRICS:
        final = sorted((p for p in points if p.spp == top), key=lambda p: getattr(p, metric))
        best = final[0]
        ratios = " and ".join(
            f"{getattr(best, metric) / getattr(p, metric):.2f}x {p.sampler}'s" for p in final[1:])
        sentences.append(f"By {label}, at {top} spp {best.sampler} converges fastest: its "
                         f"{label} is {ratios}.")
    return " ".join(sentences)


def write_markdown(path: Path, sections: list[str], description: str, command: str) -> None:
    """Write docs/sampler-convergence.md: the setup, the command, one section per depth."""
    body = "\n\n".join(sections)
    text = f"""# Sampler convergence on a depth-of-field scene

{description}

Command:

```
{command}
```

{body}

The RMSE is over all pixels and channels of the linear radiance, with the mean squared error
averaged over the seeds before the square root. At depth 4 it is dominated by rare very bright
paths (fireflies: the floor lit through the mirror spheres by the small light), which no pixel
sampler removes, since the samplers only place the film and lens samples; at every depth the
bright reflections of the light in the spheres weigh heavily in it. The median relative squared
error, the median over pixels of (x - ref)^2 / (ref^2 + 0.01) averaged over channels (then over
the seeds), is the typical pixel's error, so it shows the film and lens sampling better; at
depth 4 even the typical pixel converges slower than 1/spp, since the rare bright paths make
its estimate skewed. Depth 1 (direct light only) has no such paths: there the film and lens
sampling dominate the noise. The stratified sampler uses the squarest m x n grid with
m x n >= spp, so at spp that are not squares (2, 8, 32, 128) some strata stay empty and its
error steps up; multi-jittered has no such steps. Times are foton's own reported render seconds, averaged over the
seeds; the machine's load makes them noisy. The reference's own noise puts a small floor under
the error at the highest spp.

![The errors against spp and against time](images/sampler-convergence.png)
"""
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text)


def main() -> None:
    """Run the study at each depth, then write the chart, the Markdown and the tables."""
    args = parse_args()
    foton_binary()
    scene = require_file(shared_scenes() / "metal2_scene" / "untitled.lxs", "the metal2 scene")
    description = (
        f"Scene: metal2_scene/untitled.lxs through a thin lens (focal distance "
        f"{args.focal_distance:g}, lens radius {args.lens_radius:g}), {args.resolution}. "
        f"Reference: multi-jittered, {args.reference_spp} spp, seed {REFERENCE_SEED}. Each "
        f"point: {args.seeds} seed(s). Machine: {os.cpu_count()} cores, foton threads: "
        f"{args.threads or 'all'}, load average {os.getloadavg()[0]:.1f} when the run started."
    )
    studies = {depth: study(scene, args, depth) for depth in args.max_depths}
    sections = [f"## Maximum depth {depth}\n\n{conclusion(points)}\n\n{markdown_table(points)}"
                for depth, points in studies.items()]
    chart(studies, f"metal2_scene, thin lens fd {args.focal_distance:g} lr "
                   f"{args.lens_radius:g}, {args.resolution}; reference {args.reference_spp} spp",
          args.docs / "images" / "sampler-convergence.png")
    write_markdown(args.docs / "sampler-convergence.md", sections, description,
                   display_command(sys.argv))
    print("\n\n".join(sections))


if __name__ == "__main__":
    main()
