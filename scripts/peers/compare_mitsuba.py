#!/usr/bin/env python3
"""Compares foton with Mitsuba 3 on the same scene: accuracy (images) and speed (samples per second).

Run `bash scripts/peers/setup.sh` once, then, from the repository root:

    .venv-peers/bin/python scripts/peers/compare_mitsuba.py            # diffuse scene, 1024 spp
    .venv-peers/bin/python scripts/peers/compare_mitsuba.py --scene full --spp 256 --no-speed

Scenes: `diffuse` is scenes/cornell-diffuse.lxs and its twin scripts/peers/cornell-diffuse.xml
(matched exactly); `full` is scenes/cornell.lxs (rendered from a copy with a box filter) and
scripts/peers/cornell.xml (glass matched, metal approximated: see that file).

Accuracy: both render at the same resolution, depth (foton --max-depth N is Mitsuba max_depth
N + 1) and box filter, each as two halves of spp/2 with different seeds. The full images are the
halves' means. The difference between halves measures each renderer's own noise, so the script
gives the relative RMSE between the renderers and the RMSE that noise alone would give: if the
renderers agree, they are equal (ratio near 1); a bias shows as a ratio above 1.

Speed: foton bench (median of --repeat), Mitsuba llvm_ad_rgb (median of --repeat renders after
one render that compiles the kernels) and scalar_rgb (median of 3), back to back in one run.

Prints a Markdown summary, writes docs/peers.md (or --report) and docs/images/peer-*.png.
"""

import argparse
import os
import re
import shlex
import statistics
import subprocess
import sys
import time
from pathlib import Path

os.environ.setdefault("DRJIT_LIBLLVM_PATH", "/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1")

import numpy as np  # noqa: E402
import mitsuba as mi  # noqa: E402

REPO = Path(__file__).resolve().parents[2]
SCENES = {
    "diffuse": (REPO / "scenes/cornell-diffuse.lxs", REPO / "scripts/peers/cornell-diffuse.xml"),
    "full": (REPO / "scenes/cornell.lxs", REPO / "scripts/peers/cornell.xml"),
    # cornell.lxs with the metal sphere made white matte: the glass alone, matched exactly.
    "glass": (REPO / "scenes/cornell.lxs", REPO / "scripts/peers/cornell.xml"),
}
EPS = 1e-2  # the relative error's floor, in units of radiance, for dark pixels


def sh(cmd, **kw):
    return subprocess.run(cmd, check=True, capture_output=True, text=True, **kw)


def uptime():
    return sh(["uptime"]).stdout.strip()


def box_filter_copy(lxs: Path, out_dir: Path) -> Path:
    """The scene with its PixelFilter replaced by a one-pixel box, beside... in out_dir.

    Relative paths in the scene would break; cornell.lxs has none."""
    text = lxs.read_text()
    text = re.sub(r'PixelFilter\s+"[^"]*"[^\n]*', 'PixelFilter "box" "float xwidth" [0.5] "float ywidth" [0.5]', text)
    path = out_dir / (lxs.stem + "-box.lxs")
    path.write_text(text)
    return path


# Image files go through Mitsuba's Bitmap in a child process: in this process, an EXR read or write
# after an llvm_ad_rgb render hangs for good (a futex wait, seen with Mitsuba 3.9.1 here).
_IO = """
import sys, numpy as np, mitsuba as mi
mi.set_variant("scalar_rgb")
src, dst = sys.argv[1], sys.argv[2]
if src.endswith(".npy"):
    mi.util.write_bitmap(dst, mi.Bitmap(np.ascontiguousarray(np.load(src), dtype=np.float32)))
else:
    np.save(dst, np.array(mi.Bitmap(src)))
"""


def _convert(src, dst):
    sh([sys.executable, "-c", _IO, str(src), str(dst)])


def read_exr(path: Path) -> np.ndarray:
    npy = path.with_suffix(".npy")
    _convert(path, npy)
    img = np.load(npy).astype(np.float64)[..., :3]
    npy.unlink()
    return img


def write_image(img, path: Path):
    """EXR: linear float; PNG: sRGB, clamped at 1."""
    npy = path.parent / (path.name + ".npy")
    np.save(npy, np.asarray(img, dtype=np.float32))
    _convert(npy, path)
    npy.unlink()


def foton_render(foton, lxs, out, spp, res, depth, seed):
    cmd = [str(foton), "render", str(lxs), "-o", str(out), "--spp", str(spp),
           "--resolution", f"{res}x{res}", "--max-depth", str(depth), "--seed", str(seed)]
    t = time.perf_counter()
    sh(cmd)
    return time.perf_counter() - t, cmd


def mitsuba_render(xml, spp, res, depth, seed, chunk=256):
    """Renders spp samples as chunks of at most `chunk` spp (bounded memory), averaged."""
    total, done, k = None, 0, 0
    while done < spp:
        n = min(chunk, spp - done)
        scene = mi.load_file(str(xml), spp=str(n), res=str(res), max_depth=str(depth + 1))
        img = np.array(mi.render(scene, spp=n, seed=seed * 1000 + k)).astype(np.float64)[..., :3]
        total = img * n if total is None else total + img * n
        done += n
        k += 1
    return total / spp


def rel_mse(a, b, denom):
    return float(np.mean((a - b) ** 2 / denom))


def block_means(img, blocks):
    h, w, _ = img.shape
    return img.reshape(blocks, h // blocks, blocks, w // blocks, 3).mean(axis=(1, 3))


def error_image(f, m, block):
    """Signed relative difference (f - m) / mean(f, m) of luminance, averaged over block x block
    pixels (to see bias through the noise): blue where foton is darker, red where brighter, white
    at zero; full saturation at +-10 %. Linear values (write_bitmap applies sRGB)."""
    lum = np.array([0.2126, 0.7152, 0.0722])
    lf, lm = f @ lum, m @ lum
    h, w = lf.shape
    bf = lf.reshape(h // block, block, w // block, block).mean(axis=(1, 3))
    bm = lm.reshape(h // block, block, w // block, block).mean(axis=(1, 3))
    d = np.clip((bf - bm) / np.maximum(0.5 * (bf + bm), EPS) / 0.10, -1, 1)
    d = np.kron(d, np.ones((block, block)))
    out = np.ones((h, w, 3))
    pos, neg = np.clip(d, 0, 1), np.clip(-d, 0, 1)
    out[..., 1] -= pos + neg
    out[..., 2] -= pos
    out[..., 0] -= neg
    return np.clip(out, 0, 1) ** 2.2  # sRGB-ish back to linear, so the PNG shows the colours above


def accuracy(args, foton, name, lxs, xml, out_dir, depth):
    half = args.spp // 2
    f_halves, m_halves, f_cmds = [], [], []
    t_f = t_m = 0.0
    for seed in (1, 2):
        exr = out_dir / f"foton-{name}-{seed}.exr"
        dt, cmd = foton_render(foton, lxs, exr, half, args.res, depth, seed)
        t_f += dt
        f_cmds.append(" ".join(shlex.quote(str(c)) for c in cmd).replace(str(REPO) + "/", ""))
        f_halves.append(read_exr(exr))
        t = time.perf_counter()
        m_halves.append(mitsuba_render(xml, half, args.res, depth, seed))
        t_m += time.perf_counter() - t
        write_image(m_halves[-1], out_dir / f"mitsuba-{name}-{seed}.exr")
    f = 0.5 * (f_halves[0] + f_halves[1])
    m = 0.5 * (m_halves[0] + m_halves[1])
    denom = (0.5 * (f + m)) ** 2 + EPS ** 2
    measured = rel_mse(f, m, denom)
    # Noise only: each full image's variance is a quarter of its halves' squared difference.
    expected = 0.25 * rel_mse(*f_halves, denom) + 0.25 * rel_mse(*m_halves, denom)
    blocks = 8
    bf, bm = block_means(f, blocks), block_means(m, blocks)
    block_ratio = bf.mean(axis=2) / bm.mean(axis=2)
    worst = np.unravel_index(np.argmax(np.abs(block_ratio - 1)), block_ratio.shape)
    tag = name
    write_image(f, REPO / f"docs/images/peer-{tag}-foton.png")
    write_image(m, REPO / f"docs/images/peer-{tag}-mitsuba.png")
    write_image(error_image(f, m, 8), REPO / f"docs/images/peer-{tag}-error.png")
    return {
        "foton_mean": f.mean(axis=(0, 1)), "mitsuba_mean": m.mean(axis=(0, 1)),
        "ratio": f.mean() / m.mean(), "ratio_rgb": f.mean(axis=(0, 1)) / m.mean(axis=(0, 1)),
        "rel_rmse": measured ** 0.5, "rel_rmse_noise": expected ** 0.5,
        "rmse_over_mean": float(np.sqrt(np.mean((f - m) ** 2)) / m.mean()),
        "block_ratio": block_ratio, "worst_block": worst, "blocks": blocks,
        "time_foton": t_f, "time_mitsuba": t_m, "foton_cmds": f_cmds,
        "f": f, "m": m, "f_halves": f_halves, "m_halves": m_halves,
    }


def region_report(acc, regions):
    """Mean-luminance ratio foton / Mitsuba over named pixel boxes (x0, y0, x1, y1), and the difference in
    standard errors (z), each pixel's variance estimated from its two halves, pixels independent."""
    lum = np.array([0.2126, 0.7152, 0.0722])
    lines = []
    for name, (x0, y0, x1, y1) in regions.items():
        box = np.s_[y0:y1, x0:x1]
        a, b = acc["f"][box] @ lum, acc["m"][box] @ lum
        var = sum(((h1[box] - h2[box]) @ lum) ** 2 / 4 for h1, h2 in (acc["f_halves"], acc["m_halves"]))
        z = (a.mean() - b.mean()) / (np.sqrt(var.sum()) / a.size)
        lines.append(f"| {name} | {x0}..{x1} x {y0}..{y1} | {a.mean():.4f} | {b.mean():.4f} | "
                     f"{a.mean() / b.mean():.4f} | {z:+.1f} |")
    return lines


def foton_bench(foton, lxs, args):
    cmd = [str(foton), "bench", str(lxs), "--spp", str(args.bench_spp), "--resolution",
           f"{args.res}x{args.res}", "--max-depth", str(args.max_depth), "--repeat", str(args.repeat)]
    out = sh(cmd)
    text = (out.stdout + out.stderr).strip().splitlines()
    last = [l for l in text if l.strip()][-1]
    # "median 0.641 M paths/s over 5 runs (min ..., max ...)"
    m = re.search(r"median\s+([0-9.]+)\s*M paths/s", last)
    if not m:
        sys.exit(f"cannot read foton bench's last line: {last!r}")
    rate = float(m.group(1)) * 1e6
    seconds = args.res * args.res * args.bench_spp / rate
    return seconds, last, " ".join(shlex.quote(str(c)) for c in cmd).replace(str(REPO) + "/", "")


def mitsuba_times(variant, xml, args, runs, warmup):
    import drjit as dr
    mi.set_variant(variant)
    scene = mi.load_file(str(xml), spp=str(args.bench_spp), res=str(args.res), max_depth=str(args.max_depth + 1))
    times = []
    for i in range(warmup + runs):
        t = time.perf_counter()
        img = mi.render(scene, spp=args.bench_spp, seed=0)
        dr.eval(img)
        dr.sync_thread()
        _ = np.array(img)
        dt = time.perf_counter() - t
        if i >= warmup:
            times.append(dt)
    return statistics.median(times), times


def scene_files(name, out_dir):
    """The scene pair to render: the files themselves, or copies in out_dir changed as `name` says."""
    lxs, xml = SCENES[name]
    if name in ("full", "glass"):
        lxs = box_filter_copy(lxs, out_dir)
    if name == "glass":
        text = lxs.read_text()
        text, count = re.subn(r'^NamedMaterial "metal"', 'NamedMaterial "white"', text, flags=re.M)
        assert count == 1
        lxs = out_dir / "cornell-glass.lxs"
        lxs.write_text(text)
        text = xml.read_text()
        assert text.count('<ref id="metal"/>') == 1
        xml = out_dir / "cornell-glass.xml"
        xml.write_text(text.replace('<ref id="metal"/>', '<ref id="white"/>'))
    return lxs, xml


def rel(q):
    return str(q).replace(str(REPO) + "/", "")


DEPTH_NOTE = (
    "How depth is counted: foton's `--max-depth` counts scattering events; a ray passing through a `null` "
    "surface (here the light's quad) does not count. Mitsuba's `max_depth` counts every surface "
    "interaction, its `null` BSDF's included. At a finite depth, a path that crosses the light's quad "
    "therefore gets one more bounce in foton than in Mitsuba, and foton comes out a little brighter; the "
    "more energy a scene keeps past the cut (glass absorbs nothing), the larger the gap. Rendered with a "
    "depth where the cut hardly matters (a `NAME@DEPTH` row), the gap should vanish.")

NOTES = {
    "diffuse": "Matched exactly: the same geometry, camera, two-sided Lambertian materials, one-sided light "
               "(L x gain), light shape transparent to rays (foton `null`, Mitsuba `null` BSDF).",
    "glass": "`scenes/cornell.lxs` with the metal sphere white matte (copies made in `out/peers/`: "
             "`cornell-glass.lxs` with the box filter, `cornell-glass.xml`): everything matched exactly, "
             "the glass included (smooth dielectric, IOR 1.5 in vacuum).",
    "full": "Glass matched (smooth dielectric, IOR 1.5 in vacuum). The metal is approximated: foton's `metal2` "
            "is GGX (alpha 0.08), height-correlated Smith, Schlick Fresnel with F0 = Kr; Mitsuba's `principled` "
            "with metallic 1 has the same GGX and Schlick Fresnel on `base_color` but the separable Smith term. "
            "foton renders a copy of the scene (`out/peers/cornell-box.lxs`) with the box filter in place of "
            "its Blackman-Harris, which Mitsuba lacks. Expect agreement except, slightly, on the metal sphere "
            "and what it reflects.",
}

REGIONS = {  # pixel boxes (x0, y0, x1, y1) at 256x256, scaled to the resolution
    "back wall": (96, 40, 160, 110), "left (red) wall": (4, 60, 40, 200),
    "right (green) wall": (216, 60, 252, 200), "ceiling": (50, 2, 206, 14),
    "floor, front": (20, 235, 236, 255), "back sphere": (62, 158, 112, 205),
    "front sphere": (145, 165, 200, 215), "light": (104, 24, 150, 32),
}


def accuracy_section(args, foton, spec, out_dir):
    """spec: a scene name, or NAME@DEPTH to render it with another --max-depth."""
    base, _, d = spec.partition("@")
    depth = int(d) if d else args.max_depth
    name = spec.replace("@", "-depth")
    lxs, xml = scene_files(base, out_dir)
    mi.set_variant("llvm_ad_rgb")
    load0 = uptime()
    acc = accuracy(args, foton, name, lxs, xml, out_dir, depth)
    fm, mm = acc["foton_mean"], acc["mitsuba_mean"]
    r, c = acc["worst_block"]
    n = acc["blocks"]
    bsz = args.res // n
    ok = abs(acc["ratio"] - 1) < 0.01 and acc["rel_rmse"] / acc["rel_rmse_noise"] < 1.05
    verdict = ("**Verdict: agree** (means within 1 %, per-pixel differences at the noise level)." if ok else
               "**Verdict: differ** (means apart by 1 % or more, or per-pixel differences above the noise): "
               "see the regions below.")
    md = [f"## Accuracy: `{rel(SCENES[base][0])}` and `{rel(xml)}` ({name})", "", NOTES.get(base, ""), ""]
    if d:
        md += [f"foton `--max-depth {depth}`, Mitsuba `max_depth` {depth + 1}: paths long enough that the cut "
               "hardly matters.", ""]
    md += [
          f"{args.spp} spp each (two halves of {args.spp // 2} spp, seeds 1 and 2), Mitsuba `llvm_ad_rgb`. "
          f"foton took {acc['time_foton']:.1f} s, Mitsuba {acc['time_mitsuba']:.1f} s (with kernel compilation). "
          f"Load before: `{load0}`.", "",
          "| | foton | Mitsuba | foton / Mitsuba |", "|---|---|---|---|",
          f"| mean radiance R, G, B | {fm[0]:.5f}, {fm[1]:.5f}, {fm[2]:.5f} | {mm[0]:.5f}, {mm[1]:.5f}, {mm[2]:.5f} "
          f"| {acc['ratio_rgb'][0]:.4f}, {acc['ratio_rgb'][1]:.4f}, {acc['ratio_rgb'][2]:.4f} |",
          f"| mean radiance (all channels) | {fm.mean():.5f} | {mm.mean():.5f} | **{acc['ratio']:.4f}** |",
          "",
          f"- Per-pixel relative RMSE between the two images, sqrt(mean((f - m)^2 / (((f + m)/2)^2 + {EPS}^2))) "
          f"over pixels and channels: **{acc['rel_rmse']:.4f}**.",
          f"- What noise alone would give (from each renderer's two halves): {acc['rel_rmse_noise']:.4f}; "
          f"measured / noise = **{acc['rel_rmse'] / acc['rel_rmse_noise']:.3f}** (1 when the two agree "
          "up to noise; a bias raises it).",
          f"- RMSE / mean radiance: {acc['rmse_over_mean']:.4f}.", "", verdict, "",
          f"- Mean ratio over {n}x{n} blocks of {bsz}x{bsz} pixels: from {acc['block_ratio'].min():.4f} to "
          f"{acc['block_ratio'].max():.4f}; the furthest from 1 is block row {r}, column {c} "
          f"(pixels x {c * bsz}..{(c + 1) * bsz}, y {r * bsz}..{(r + 1) * bsz}).",
          "",
          "| region | pixels (x, y) | foton luminance | Mitsuba luminance | ratio | z (standard errors) |",
          "|---|---|---|---|---|---|"]
    s = args.res / 256
    md += region_report(acc, {k: tuple(int(v * s) for v in b) for k, b in REGIONS.items()})
    md += ["", f"Images: `docs/images/peer-{name}-foton.png`, `peer-{name}-mitsuba.png`, "
           f"and `peer-{name}-error.png` (relative luminance difference over 8x8-pixel blocks: "
           "red where foton is brighter, blue where darker, saturated at 10 %). "
           "The PNGs are sRGB, clamped at 1, without tone mapping.",
           "", f"![foton](images/peer-{name}-foton.png) ![Mitsuba](images/peer-{name}-mitsuba.png) "
           f"![difference](images/peer-{name}-error.png)", "",
           "foton's commands (the EXRs go to `out/peers/`, Mitsuba's too):", ""]
    md += [f"    {c}" for c in acc["foton_cmds"]]
    row = (f"| {name} | {acc['ratio']:.4f} | {acc['rel_rmse']:.4f} | {acc['rel_rmse_noise']:.4f} | "
           f"{acc['rel_rmse'] / acc['rel_rmse_noise']:.3f} | {'agree' if ok else 'differ'} |")
    return md + [""], row


def speed_section(args, foton, name, out_dir):
    lxs, xml = scene_files(name, out_dir)
    pixels = args.res * args.res
    paths = pixels * args.bench_spp
    load0 = uptime()
    f_median, f_line, f_cmd = foton_bench(foton, lxs, args)
    ll_median, ll_times = mitsuba_times("llvm_ad_rgb", xml, args, args.repeat, warmup=1)
    sc_median, sc_times = mitsuba_times("scalar_rgb", xml, args, 3, warmup=0)
    load1 = uptime()
    f_rate, ll_rate, sc_rate = paths / f_median, paths / ll_median, paths / sc_median
    summary = (f"Speed (`{name}`, {args.bench_spp} spp): foton {f_rate / 1e6:.2f} M samples/s, Mitsuba "
               f"`llvm_ad_rgb` {ll_rate / 1e6:.2f} M/s, `scalar_rgb` {sc_rate / 1e6:.2f} M/s: foton is "
               f"{f_rate / ll_rate:.2f}x the first and {f_rate / sc_rate:.2f}x the second (load average at the "
               f"start: {load0.split('load average:')[-1].strip()}; other work was running).")
    return summary, ["## Speed", "",
            f"`{rel(SCENES[name][0])}`, {args.res}x{args.res}, {args.bench_spp} spp ({paths:,} camera paths "
            "per render), depth as above; the three measured back to back in one run.", "",
            f"- Load before: `{load0}`", f"- Load after: `{load1}`", "",
            "| renderer | median time (s) | runs (s) | samples/s | foton / it |", "|---|---|---|---|---|",
            f"| foton `bench` (median of {args.repeat}) | {f_median:.3f} | last line: `{f_line.strip()}` | "
            f"{f_rate / 1e6:.3f} M | 1 |",
            f"| Mitsuba `llvm_ad_rgb` (median of {args.repeat}, after one compiling render) | {ll_median:.3f} | "
            f"{', '.join(f'{t:.2f}' for t in ll_times)} | {ll_rate / 1e6:.3f} M | {f_rate / ll_rate:.3f} |",
            f"| Mitsuba `scalar_rgb` (median of 3) | {sc_median:.3f} | {', '.join(f'{t:.2f}' for t in sc_times)} | "
            f"{sc_rate / 1e6:.3f} M | {f_rate / sc_rate:.3f} |",
            "", f"foton's command: `{f_cmd}`", ""]


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--scenes", default="diffuse", help="comma-separated: " + ", ".join(sorted(SCENES)) +
                   "; NAME@DEPTH renders NAME with --max-depth DEPTH")
    p.add_argument("--speed-scene", choices=sorted(SCENES), default="diffuse")
    p.add_argument("--spp", type=int, default=1024, help="accuracy samples per pixel (two halves)")
    p.add_argument("--bench-spp", type=int, default=64)
    p.add_argument("--res", type=int, default=256)
    p.add_argument("--max-depth", type=int, default=8, help="foton's bounces (Mitsuba: + 1)")
    p.add_argument("--repeat", type=int, default=5)
    p.add_argument("--no-accuracy", action="store_true")
    p.add_argument("--no-speed", action="store_true")
    p.add_argument("--foton", default=str(REPO / "target/release/foton"))
    p.add_argument("--out", default=str(REPO / "out/peers"))
    p.add_argument("--report", default=str(REPO / "docs/peers.md"))
    args = p.parse_args()

    out_dir = Path(args.out)
    out_dir.mkdir(parents=True, exist_ok=True)
    (REPO / "docs/images").mkdir(parents=True, exist_ok=True)
    foton = Path(args.foton)
    if not foton.exists():
        sys.exit(f"{foton} missing: run cargo build --release")
    commit = sh(["git", "-C", str(REPO), "rev-parse", "--short", "HEAD"]).stdout.strip()
    cpu = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name")), "?")
    scenes = args.scenes.split(",")
    argv = " ".join(shlex.quote(a) for a in sys.argv[1:])

    md = ["# foton and Mitsuba 3, on this machine", ""]
    md += [f"foton at commit {commit}; Mitsuba {mi.__version__} (PyPI); {os.cpu_count()} cores ({cpu}).",
           f"{args.res}x{args.res} pixels, foton `--max-depth {args.max_depth}` = Mitsuba `max_depth` "
           f"{args.max_depth + 1} (both: {args.max_depth} bounces; 1 would be direct light only), "
           "box filter one pixel wide, foton's default sampler (correlated multi-jittered), Mitsuba's `independent`. "
           "Russian roulette differs (foton after 2 bounces, Mitsuba after 5): it changes the noise, not the mean.",
           "", "Reproduce: `bash scripts/peers/setup.sh && cargo build --release && "
           f".venv-peers/bin/python scripts/peers/compare_mitsuba.py {argv}`", ""]
    head, body = [], []
    if not args.no_accuracy:
        head += [f"| scene | mean foton / Mitsuba | relative RMSE ({args.spp} spp) | noise alone | "
                 "RMSE / noise | verdict |", "|---|---|---|---|---|---|"]
        for name in scenes:
            section, row = accuracy_section(args, foton, name, out_dir)
            body += section
            head.append(row)
        head.append("")
    if not args.no_speed:
        summary, section = speed_section(args, foton, args.speed_scene, out_dir)
        body += section
        head += [summary, ""]
    md += ["## Summary", ""] + head + [DEPTH_NOTE, ""] + body

    text = "\n".join(md) + "\n"
    print(text)
    report = Path(args.report)
    report.write_text(text)
    print(f"wrote {report}", file=sys.stderr)


if __name__ == "__main__":
    main()
