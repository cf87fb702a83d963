#!/usr/bin/env python3
"""foton against Mitsuba 3 (llvm_ad_rgb) on the very same Mitsuba XML files, back to back.

Run from the repository root (after `bash scripts/peers/setup.sh` and `cargo build --release`):

    .venv-peers/bin/python scripts/peers/throughput.py [--spp 64] [--repeat 3] [--rounds 3]
        [--foton BIN] [--baseline OLD_BIN] [--process]

For each of scripts/peers/{furnace,dof-sky,cornell}.xml, Mitsuba 3's render call compiles its
kernels once, then --rounds rounds alternate, seconds apart: `foton bench FILE --spp N
--repeat R` (its median paths per second over the whole render), the --baseline binary's
bench where given, and the median of R timed Mitsuba renders at the same spp. This machine's
speed drifts by up to 30 % within minutes, so each round's ratio is taken between neighbours
and the table gives the median of the rounds' ratios (with their range) beside the medians of
the speeds. Prints a Markdown table with the load average before and after. About 1 minute a
round.

With --process, foton's speed is that of its whole process instead, as issue 6's target reads
it: the median wall time of R runs of `foton render FILE --spp N -o TMP.exr`, each a fresh
process that starts, loads the scene, builds the BVH, renders and writes the image.
"""

import argparse
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

os.environ.setdefault("DRJIT_LIBLLVM_PATH", "/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1")

import mitsuba as mi  # noqa: E402

REPO = Path(__file__).resolve().parents[2]
SCENES = ["furnace", "dof-sky", "cornell"]


def load_average():
    return " ".join(Path("/proc/loadavg").read_text().split()[:3])


def foton_paths_per_second(foton, scene, spp, repeat):
    out = subprocess.run(
        [str(foton), "bench", str(scene), "--spp", str(spp), "--repeat", str(repeat)],
        check=True,
        capture_output=True,
        text=True,
    ).stdout
    match = re.search(r"median ([0-9.]+) M paths/s", out)
    if not match:
        sys.exit(f"error: no median in foton bench's output for {scene}:\n{out}")
    return float(match.group(1)) * 1e6


def foton_process_samples_per_second(foton, scene, spp, repeat, samples):
    with tempfile.TemporaryDirectory() as directory:
        output = Path(directory) / "image.exr"
        command = [str(foton), "render", str(scene), "--spp", str(spp), "-o", str(output)]
        seconds = []
        for _ in range(repeat):
            start = time.perf_counter()
            subprocess.run(command, check=True, capture_output=True)
            seconds.append(time.perf_counter() - start)
    return samples / statistics.median(seconds)


def foton_speed(foton, scene, args, samples):
    """foton's samples per second on `scene`: its whole process's with --process, else its
    bench's; `samples` is the render's count (width x height x spp)."""
    if args.process:
        return foton_process_samples_per_second(foton, scene, args.spp, args.repeat, samples)
    return foton_paths_per_second(foton, scene, args.spp, args.repeat)


class Mitsuba:
    """One scene loaded in Mitsuba 3, its kernels compiled by a first render."""

    def __init__(self, scene, spp):
        self.spp = spp
        self.scene = mi.load_file(str(scene), spp=str(spp))
        film = self.scene.sensors()[0].film().crop_size()
        self.samples = int(film[0]) * int(film[1]) * spp
        self.render_seconds()

    def render_seconds(self):
        import drjit as dr

        start = time.perf_counter()
        # The same seed keeps later renders from recompiling the kernels.
        image = mi.render(self.scene, spp=self.spp, seed=0)
        dr.eval(image)
        dr.sync_thread()
        return time.perf_counter() - start

    def samples_per_second(self, repeat):
        return self.samples / statistics.median(self.render_seconds() for _ in range(repeat))


def mega(values):
    return f"{statistics.median(values) / 1e6:.2f}"


def ratio_cell(ratios):
    return f"{statistics.median(ratios):.2f}x ({min(ratios):.2f}-{max(ratios):.2f})"


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--spp", type=int, default=64)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--foton", type=Path, default=REPO / "target/release/foton")
    parser.add_argument("--baseline", type=Path, help="another foton binary, alternated with --foton")
    parser.add_argument(
        "--process", action="store_true", help="time foton's whole process (`render`), not its `bench`"
    )
    args = parser.parse_args()
    for binary in filter(None, [args.foton, args.baseline]):
        if not binary.exists():
            sys.exit(f"error: {binary} not found: run `cargo build --release` first")
    mi.set_variant("llvm_ad_rgb")
    before = load_average()
    rows = []
    for name in SCENES:
        scene = REPO / "scripts/peers" / f"{name}.xml"
        mitsuba = Mitsuba(scene, args.spp)
        fotons, baselines, mitsubas = [], [], []
        for round in range(args.rounds):
            # Mitsuba's threads stay busy for some hundred milliseconds after a render call
            # (see equal_time.py): foton's bench starts after a pause.
            time.sleep(1.0)
            fotons.append(foton_speed(args.foton, scene, args, mitsuba.samples))
            if args.baseline:
                baselines.append(foton_speed(args.baseline, scene, args, mitsuba.samples))
            mitsubas.append(mitsuba.samples_per_second(args.repeat))
            line = f"{name} round {round + 1}: foton {fotons[-1] / 1e6:.2f} M/s"
            if args.baseline:
                line += f", baseline {baselines[-1] / 1e6:.2f} M/s"
            print(f"{line}, Mitsuba {mitsubas[-1] / 1e6:.2f} M/s", file=sys.stderr)
        rows.append((name, fotons, baselines, mitsubas))
    measured = "whole processes" if args.process else "renders (foton bench)"
    print(
        f"{args.spp} spp; {args.rounds} alternating rounds, each the median of {args.repeat} {measured}; "
        f"load average before {before}, after {load_average()}\n"
    )
    header = "| scene | foton M samples/s | Mitsuba 3 llvm_ad_rgb M samples/s | foton / Mitsuba |"
    rule = "|---|---|---|---|"
    if args.baseline:
        header += " baseline M samples/s | baseline / Mitsuba | foton / baseline |"
        rule += "---|---|---|"
    print(header)
    print(rule)
    for name, fotons, baselines, mitsubas in rows:
        row = f"| {name}.xml | {mega(fotons)} | {mega(mitsubas)} | "
        row += ratio_cell([f / m for f, m in zip(fotons, mitsubas)]) + " |"
        if args.baseline:
            row += f" {mega(baselines)} | " + ratio_cell([b / m for b, m in zip(baselines, mitsubas)])
            row += " | " + ratio_cell([f / b for f, b in zip(fotons, baselines)]) + " |"
        print(row)


if __name__ == "__main__":
    main()
