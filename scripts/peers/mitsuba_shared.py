#!/usr/bin/env python3
"""Renders the seven shared public Mitsuba scenes (../shared/scenes/mitsuba, SOURCES.md there) with
foton and with Mitsuba 3 at their own resolution and the same sample count, and writes
docs/images/mitsuba-NAME.png (foton | Mitsuba | absolute difference, one exposure) and a Markdown
table of the agreement to stdout. Run `bash scripts/peers/setup.sh` and `cargo build --release`
first, then from the repository root:

    .venv-peers/bin/python scripts/peers/mitsuba_shared.py [--spp 32] [--scenes tut-cbox,ppg-torus]
"""

import argparse
import os
import subprocess
import time
from pathlib import Path

os.environ.setdefault("DRJIT_LIBLLVM_PATH", "/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1")

import numpy as np  # noqa: E402
import mitsuba as mi  # noqa: E402

REPO = Path(__file__).resolve().parents[2]
SHARED = Path(os.environ.get("FOTON_SHARED", REPO.parent / "shared")) / "scenes/mitsuba"
SCENES = {
    "mdata-cbox": "mdata-cbox/cbox.xml",
    "mdata-matpreview": "mdata-matpreview/matpreview.xml",
    "mdata-hello": "mdata-hello/scenes/hello.xml",
    "mdata-roughconductor-copper": "mdata-roughconductor-copper/docs/scenes/bsdf_roughconductor_copper.xml",
    "tut-cbox": "tut-cbox/scenes/cbox.xml",
    "bitterli-cornell-box": "bitterli-cornell-box/scene_v0.6.xml",
    "ppg-torus": "ppg-torus/scene.xml",
}
# Mitsuba takes only parameters a scene declares; the torus's default integrator is its
# repository's own plugin, rendered with path (foton falls back to path with a warning too).
PARAMS = {"ppg-torus": {"integrator": "path"}}
WIDTH = 240  # of each panel in the picture


def load_mitsuba(path, name, spp):
    params = dict(PARAMS.get(name, {}))
    try:
        return mi.load_file(str(path), spp=str(spp), **params)
    except Exception:
        return mi.load_file(str(path), **params)


def panel(img, scale):
    img = np.clip(img / scale, 0, 1) ** (1 / 2.2)
    step = max(1, img.shape[1] // WIDTH)
    return (img[::step, ::step] * 255).astype(np.uint8)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--spp", type=int, default=32)
    ap.add_argument("--scenes", default="", help="comma-separated names (default: all)")
    args = ap.parse_args()
    mi.set_variant("llvm_ad_rgb" if os.path.exists(os.environ["DRJIT_LIBLLVM_PATH"]) else "scalar_rgb")
    out = REPO / "docs/images"
    tmp = REPO / "out/mitsuba-shared"
    tmp.mkdir(parents=True, exist_ok=True)
    print("| scene | resolution | mean foton / Mitsuba (R, G, B) | relative MSE | foton s | Mitsuba s |")
    print("|---|---|---|---|---|---|")
    chosen = [n for n in args.scenes.split(",") if n] or list(SCENES)
    for name, rel in ((n, SCENES[n]) for n in chosen):
        path = SHARED / rel
        t = time.time()
        scene = load_mitsuba(path, name, args.spp)
        # A scene without an integrator renders with Mitsuba's default, path.
        integrator = None if scene.integrator() else mi.load_dict({"type": "path"})
        m = np.array(mi.render(scene, spp=args.spp, seed=0, integrator=integrator))[..., :3]
        tm = time.time() - t
        exr = tmp / f"{name}.exr"
        t = time.time()
        subprocess.run([str(REPO / "target/release/foton"), "render", str(path), "--spp", str(args.spp), "-o", str(exr)],
                       check=True, capture_output=True)
        tf = time.time() - t
        f = np.array(mi.Bitmap(str(exr)))[..., :3]
        ratio = f.mean(axis=(0, 1)) / np.maximum(m.mean(axis=(0, 1)), 1e-9)
        rel_mse = np.mean((f - m) ** 2 / (m ** 2 + 1e-2))
        scale = np.percentile(m, 99.5) + 1e-6
        diff = np.abs(f - m).mean(-1, keepdims=True).repeat(3, -1)
        gap = np.zeros((panel(m, scale).shape[0], 4, 3), np.uint8)
        picture = np.concatenate([panel(f, scale), gap, panel(m, scale), gap, panel(diff, 0.25 * scale)], 1)
        mi.util.write_bitmap(str(out / f"mitsuba-{name}.png"), mi.Bitmap(picture))
        print(f"| {name} | {m.shape[1]}x{m.shape[0]} | {ratio[0]:.3f}, {ratio[1]:.3f}, {ratio[2]:.3f} "
              f"| {rel_mse:.4f} | {tf:.1f} | {tm:.1f} |", flush=True)


if __name__ == "__main__":
    main()
