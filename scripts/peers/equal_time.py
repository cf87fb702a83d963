#!/usr/bin/env python3
"""Equal-time tables: foton against Mitsuba 3 on the very same XML files (issue 7).

Run `bash scripts/peers/setup.sh` and `cargo build --release` once, then, from the repository root:

    .venv-peers/bin/python scripts/peers/equal_time.py                 # all six scenes
    .venv-peers/bin/python scripts/peers/equal_time.py --scenes furnace --spp 4,16 --repeat 1

For each scene, each renderer is measured against its own converged reference (foton's and
Mitsuba's, --reference-spp, cached under target/equal-time/ by scene, sample count and the scene
file's contents; --fresh-references renders foton's anew after a change to foton that alters the
expected image), so the numbers are each renderer's
noise, not the small differences between their materials. relMSE = mean((a - b)^2 / (b^2 + 0.01))
over pixels and channels, as `foton compare` computes it.

Seconds: foton's whole process (`foton render`: loading, building the BVH, rendering, writing the
EXR), Mitsuba's `mi.render` call alone after one render that compiles its kernels (llvm_ad_rgb),
back to back at each sample count (foton's runs first, after a pause that lets Mitsuba's threads
from the previous count go idle), median of --repeat runs (seeds 1..repeat; relMSE is their mean).

With --rounds N (default 3) each scene is measured N times over, the rounds one after another, so
that the machine's drifting speed (here, up to 0.3 in one ratio between runs minutes apart) shows
as a range: the tables give the median of the rounds' ratios and their range; a point's seconds
are the median of the rounds' medians and its relMSE the mean of their means.

From the points, per scene:
- equal spp: foton's relMSE / Mitsuba's at the largest sample count;
- equal time: foton's relMSE at Mitsuba's seconds for that count (interpolated in log-log between
  foton's points, extrapolated from the nearest two) / Mitsuba's relMSE;
- seconds to the same error: foton's seconds to reach Mitsuba's relMSE at that count / Mitsuba's.

Writes docs/equal-time.md (or --report), one CSV per scene (configuration, seconds, spp, relmse:
`foton chart` draws them) and the charts beside them in images/ beside the report.
"""

import argparse
import hashlib
import json
import math
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

os.environ.setdefault("DRJIT_LIBLLVM_PATH", "/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1")

import mitsuba as mi  # noqa: E402
import numpy as np  # noqa: E402

REPO = Path(__file__).resolve().parents[2]
PEERS = REPO / "scripts/peers"
SCENES = {
    "cornell": PEERS / "cornell.xml",
    "dof-sky": PEERS / "dof-sky.xml",
    "furnace": PEERS / "furnace.xml",
    "textured": PEERS / "textured.xml",
    "envmap": PEERS / "envmap.xml",
    "many-lights": PEERS / "many-lights.xml",
}
EPS = 1e-2
FOTON = REPO / "target/release/foton"


def sh(cmd):
    return subprocess.run(cmd, check=True, capture_output=True, text=True)


def foton_render(xml, spp, seed, out):
    start = time.perf_counter()
    sh([str(FOTON), "render", str(xml), "--spp", str(spp), "--seed", str(seed), "-o", str(out), "--quiet"])
    return time.perf_counter() - start


def foton_relmse(image, reference):
    result = json.loads(sh([str(FOTON), "compare", str(image), str(reference), "--json"]).stdout)
    return result["overall"]["rel_mse"]


def mitsuba_render(xml, spp, seed):
    scene = mi.load_file(str(xml), spp=str(spp))
    start = time.perf_counter()
    img = np.array(mi.render(scene, spp=spp, seed=seed)).astype(np.float64)[..., :3]
    return img, time.perf_counter() - start


def mitsuba_reference(xml, spp, chunk=256):
    total, done, k = 0.0, 0, 0
    while done < spp:
        n = min(chunk, spp - done)
        img, _ = mitsuba_render(xml, n, 1000 + k)
        total, done, k = total + img * n, done + n, k + 1
    return total / spp


def loglog(points, x):
    """y at x on the polyline through points (x, y), in log-log, extrapolated from the ends."""
    pts = sorted(points)
    if len(pts) == 1:
        return pts[0][1] * pts[0][0] / x  # one point: assume y proportional to 1 / x
    i = 1
    while i < len(pts) - 1 and pts[i][0] < x:
        i += 1
    (x0, y0), (x1, y1) = pts[i - 1], pts[i]
    t = (math.log(x) - math.log(x0)) / (math.log(x1) - math.log(x0))
    return math.exp(math.log(y0) + t * (math.log(y1) - math.log(y0)))


def measure(name, xml, args, cache):
    # Keyed by what the reference depends on besides the renderer: the sample count and the file.
    digest = hashlib.sha256(Path(xml).read_bytes()).hexdigest()[:12]
    key = f"{name}-{args.reference_spp}-{digest}"
    foton_ref = cache / f"{key}-foton-ref.exr"
    if args.fresh_references or not foton_ref.exists():
        print(f"{name}: foton reference at {args.reference_spp} spp", flush=True)
        foton_render(xml, args.reference_spp, 999, foton_ref)
    mitsuba_ref_path = cache / f"{key}-mitsuba-ref.npy"
    if mitsuba_ref_path.exists():
        mitsuba_ref = np.load(mitsuba_ref_path)
    else:
        print(f"{name}: Mitsuba reference at {args.reference_spp} spp", flush=True)
        mitsuba_ref = mitsuba_reference(xml, args.reference_spp)
        np.save(mitsuba_ref_path, mitsuba_ref)
    mitsuba_render(xml, 1, 12345)  # compiles the kernels
    rows = []
    out = cache / f"{name}-foton.exr"
    for spp in args.spp:
        f_times, f_errs, m_times, m_errs = [], [], [], []
        # foton's runs as one block, after a pause: for some hundred milliseconds after a render
        # call Mitsuba's threads still take CPU, which slowed a foton run started at once by
        # about 35 % (dof-sky, 64 spp: 0.489 s against 0.36 s alone; 0.38 s after 0.3 s).
        time.sleep(1.0)
        for seed in range(1, args.repeat + 1):
            f_times.append(foton_render(xml, spp, seed, out))
            f_errs.append(foton_relmse(out, foton_ref))
        for seed in range(1, args.repeat + 1):
            img, seconds = mitsuba_render(xml, spp, seed)
            m_times.append(seconds)
            m_errs.append(float(np.mean((img - mitsuba_ref) ** 2 / (mitsuba_ref**2 + EPS))))
        rows.append(("foton", statistics.median(f_times), spp, statistics.fmean(f_errs)))
        rows.append(("mitsuba", statistics.median(m_times), spp, statistics.fmean(m_errs)))
        print(f"{name} {spp:5d} spp: foton {rows[-2][1]:.3f} s {rows[-2][3]:.3e} | "
              f"Mitsuba {rows[-1][1]:.3f} s {rows[-1][3]:.3e}", flush=True)
    return rows


def summarise(rows):
    f = [(s, e) for c, s, _, e in rows if c == "foton"]
    m = [(s, e) for c, s, _, e in rows if c == "mitsuba"]
    top = max(spp for _, _, spp, _ in rows)
    (m_seconds, m_err), (f_seconds_top, f_err_top) = m[-1], f[-1]  # rows are in spp order
    equal_spp = f_err_top / m_err
    equal_time = loglog(f, m_seconds) / m_err
    # Seconds to Mitsuba's error: invert foton's (relMSE, seconds) polyline.
    to_error = loglog([(e, s) for s, e in f], m_err) / m_seconds
    return top, m_seconds, f_seconds_top, equal_spp, equal_time, to_error


def merge_rounds(rounds):
    """One row per (renderer, spp) over the rounds: median seconds, mean relMSE."""
    merged = []
    for i, (config, _, spp, _) in enumerate(rounds[0]):
        seconds = [r[i][1] for r in rounds]
        errors = [r[i][3] for r in rounds]
        merged.append((config, statistics.median(seconds), spp, statistics.fmean(errors)))
    return merged


def ratio(r):
    """A ratio with two decimals, or two significant digits below 0.1 (0.0031x, not 0.00x)."""
    return f"{r:.2f}x" if r >= 0.1 else f"{r:.2g}x"


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scenes", default=",".join(SCENES))
    ap.add_argument("--spp", default="4,16,64")
    ap.add_argument("--reference-spp", type=int, default=1024)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--rounds", type=int, default=3, help="measure each scene this many times over")
    ap.add_argument("--report", type=Path, default=REPO / "docs/equal-time.md")
    ap.add_argument(
        "--fresh-references",
        action="store_true",
        help="render foton's references anew (after a change that alters the expected image)",
    )
    args = ap.parse_args()
    args.spp = [int(s) for s in args.spp.split(",")]
    if not FOTON.exists():
        sys.exit(f"{FOTON} missing: run cargo build --release first")
    mi.set_variant("llvm_ad_rgb")
    cache = REPO / "target/equal-time"
    cache.mkdir(parents=True, exist_ok=True)
    images = args.report.parent / "images"  # beside the report: a trial run leaves docs/ alone
    images.mkdir(parents=True, exist_ok=True)
    load_before = os.getloadavg()
    table = []
    for name in args.scenes.split(","):
        rounds = [measure(name, SCENES[name], args, cache) for _ in range(args.rounds)]
        rows = merge_rounds(rounds)
        csv = images / f"equal-time-{name}.csv"
        csv.write_text("configuration,seconds,spp,relmse\n"
                       + "".join(f"{c},{s:.6f},{spp},{e:.6e}\n" for c, s, spp, e in rows))
        subprocess.run([str(FOTON), "chart", str(csv), "-o", str(csv.with_suffix(".svg"))], check=False)
        table.append((name, rows, [summarise(r) for r in rounds]))
    load_after = os.getloadavg()

    lines = [
        "# Error per second: foton against Mitsuba 3 at equal time",
        "",
        "Generated by `.venv-peers/bin/python scripts/peers/equal_time.py "
        f"--spp {','.join(map(str, args.spp))} --reference-spp {args.reference_spp} --repeat {args.repeat} --rounds {args.rounds}` "
        f"(load average {load_before[0]:.2f} before, {load_after[0]:.2f} after; "
        f"{os.cpu_count()} cores). Each renderer against its own {args.reference_spp}-spp reference; "
        "foton's seconds are its whole process, Mitsuba's (`llvm_ad_rgb`) its render call. "
        f"Ratios below 1 favour foton: the median of the {args.rounds} rounds' ratios, their range in brackets; "
        "seconds are medians over the rounds.",
        "",
        "| scene | spp | Mitsuba s | foton s | relMSE foton / Mitsuba, equal spp | equal time | "
        "seconds to Mitsuba's error, foton / Mitsuba |",
        "|---|---|---|---|---|---|---|",
    ]

    def spread(values):
        return f"{ratio(statistics.median(values))} ({ratio(min(values))}-{ratio(max(values))})"

    for name, _, summaries in table:
        top = summaries[0][0]
        m_s, f_s, e_spp, e_time, to_err = ([s[k] for s in summaries] for k in range(1, 6))
        lines.append(f"| {name} | {top} | {statistics.median(m_s):.3f} | {statistics.median(f_s):.3f} | "
                     f"{spread(e_spp)} | {spread(e_time)} | {spread(to_err)} |")
    lines += ["", "Points (median seconds, mean relMSE over the seeds and rounds):", ""]
    lines += ["| scene | renderer | spp | seconds | relMSE |", "|---|---|---|---|---|"]
    for name, rows, _ in table:
        lines += [f"| {name} | {c} | {spp} | {s:.3f} | {e:.3e} |" for c, s, spp, e in rows]
    lines += ["", "Charts (relMSE against seconds, log-log): "
              + ", ".join(f"[{n}](images/equal-time-{n}.svg)" for n, _, _ in table) + "."]
    args.report.write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
