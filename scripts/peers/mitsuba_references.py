#!/usr/bin/env python3
"""Renders the converged Mitsuba 3 references of the small scenes in scenes/mitsuba/ (NAME.xml ->
NAME.exr beside it, linear RGB) and records how in scenes/mitsuba/references.json; writes the
environment map sky.exr that envmap.xml uses first. Run `bash scripts/peers/setup.sh` once, then
from the repository root:

    .venv-peers/bin/python scripts/peers/mitsuba_references.py [--spp 4096] [--scenes cbox,lights]

Mitsuba renders with `llvm_ad_rgb` where LLVM 19 is installed (setup.sh does it), else
`scalar_rgb`; seed 0. tests/mitsuba_references.rs compares foton with these images.
"""

import argparse
import json
import os
from pathlib import Path

LLVM = "/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1"
os.environ.setdefault("DRJIT_LIBLLVM_PATH", LLVM)

import numpy as np  # noqa: E402
import mitsuba as mi  # noqa: E402

REPO = Path(__file__).resolve().parents[2]
FOLDER = REPO / "scenes/mitsuba"


def write_sky(path: Path):
    """A 64x32 latitude-longitude map: a bright warm sun patch, a blue sky brightening toward the
    horizon, a dark brown ground; asymmetric in azimuth so that a wrong rotation shows."""
    h, w = 32, 64
    v = (np.arange(h) + 0.5) / h
    u = (np.arange(w) + 0.5) / w
    theta = v[:, None] * np.pi  # 0 at the top row
    sky = np.stack([0.25 + 0.5 * np.sin(theta), 0.4 + 0.5 * np.sin(theta), np.full_like(theta, 1.0)], -1)
    ground = np.array([0.15, 0.1, 0.05])
    img = np.where((v[:, None] < 0.5)[..., None], sky, ground) * np.ones((h, w, 1))
    img[..., 0] *= 1.0 + 0.5 * np.cos(2 * np.pi * u)[None, :]  # redder toward u = 0
    img[6:9, 40:43] = [40.0, 32.0, 20.0]  # the sun
    mi.Bitmap(img.astype(np.float32)).write(str(path))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--spp", type=int, default=4096)
    ap.add_argument("--scenes", default="")
    args = ap.parse_args()
    variant = "llvm_ad_rgb" if os.path.exists(LLVM) else "scalar_rgb"
    mi.set_variant(variant)
    write_sky(FOLDER / "sky.exr")
    names = [n for n in args.scenes.split(",") if n] or sorted(p.stem for p in FOLDER.glob("*.xml"))
    index_path = FOLDER / "references.json"
    index = json.loads(index_path.read_text()) if index_path.exists() else {}
    for name in names:
        scene = mi.load_file(str(FOLDER / f"{name}.xml"), spp=str(args.spp))
        img = mi.render(scene, spp=args.spp, seed=0)
        mi.util.write_bitmap(str(FOLDER / f"{name}.exr"), img)
        index[name] = {"spp": args.spp, "variant": variant, "mitsuba": mi.__version__, "seed": 0}
        print(f"{name}: {np.array(img).shape}, mean {np.array(img).mean():.5f}", flush=True)
    index_path.write_text(json.dumps(index, indent=2, sort_keys=True) + "\n")


if __name__ == "__main__":
    main()
