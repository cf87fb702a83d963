#!/usr/bin/env python3
"""foton against Mitsuba 3 (llvm_ad_rgb) on the very same Mitsuba XML files, back to back.

Run from the repository root (after `bash scripts/peers/setup.sh` and `cargo build --release`):

    .venv-peers/bin/python scripts/peers/throughput.py [--spp 64] [--repeat 3]

For each of scripts/peers/{furnace,dof-sky,cornell}.xml: `foton bench FILE --spp N --repeat R`
(its median paths per second over the whole render), then Mitsuba 3's render call on the same
file with the same spp: one render first to compile the kernels, then the median of R timed
renders. Prints a Markdown table of samples per second and the ratio foton / Mitsuba, with the
load average before and after (ratios mean little on a loaded machine). About 3 minutes.
"""

import argparse
import os
import re
import statistics
import subprocess
import sys
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


def mitsuba_samples_per_second(scene, spp, repeat):
    import drjit as dr

    loaded = mi.load_file(str(scene), spp=str(spp))
    film = loaded.sensors()[0].film().crop_size()
    samples = int(film[0]) * int(film[1]) * spp
    times = []
    # The first render compiles the kernels; the same seed keeps the later ones from recompiling.
    for _ in range(repeat + 1):
        start = time.perf_counter()
        image = mi.render(loaded, spp=spp, seed=0)
        dr.eval(image)
        dr.sync_thread()
        times.append(time.perf_counter() - start)
    return samples / statistics.median(times[1:])


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--spp", type=int, default=64)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--foton", type=Path, default=REPO / "target/release/foton")
    args = parser.parse_args()
    if not args.foton.exists():
        sys.exit(f"error: {args.foton} not found: run `cargo build --release` first")
    mi.set_variant("llvm_ad_rgb")
    before = load_average()
    rows = []
    for name in SCENES:
        scene = REPO / "scripts/peers" / f"{name}.xml"
        # Mitsuba's threads stay busy for some hundred milliseconds after a render call (see
        # equal_time.py): foton's bench starts after a pause.
        time.sleep(1.0)
        foton = foton_paths_per_second(args.foton, scene, args.spp, args.repeat)
        mitsuba = mitsuba_samples_per_second(scene, args.spp, args.repeat)
        rows.append((name, foton, mitsuba))
        print(f"{name}: foton {foton / 1e6:.2f} M/s, Mitsuba {mitsuba / 1e6:.2f} M/s", file=sys.stderr)
    print(f"{args.spp} spp, medians of {args.repeat}; load average before {before}, after {load_average()}\n")
    print("| scene | foton M samples/s | Mitsuba 3 llvm_ad_rgb M samples/s | foton / Mitsuba |")
    print("|---|---|---|---|")
    for name, foton, mitsuba in rows:
        print(f"| {name}.xml | {foton / 1e6:.2f} | {mitsuba / 1e6:.2f} | {foton / mitsuba:.2f}x |")


if __name__ == "__main__":
    main()
