"""Mitsuba 3's points for `foton converge --peer`: relMSE against a reference at growing spp.

    bash scripts/peers/setup.sh
    .venv-peers/bin/python scripts/peers/mitsuba_converge.py scripts/peers/dof-sky.xml \
        --reference-spp 2048 --spp 1,2,4,8,16,32,64 -o mitsuba-dof.csv

Writes a CSV with foton converge's columns (configuration, seconds, spp, relmse), relMSE =
mean((a - b)^2 / (b^2 + 0.01)) over pixels and channels, as `foton compare` computes it. The
reference is Mitsuba's own render at --reference-spp (saved as NAME-reference.npy beside the CSV
and reused), or --reference REF.npy. Seconds are wall time of mi.render after one warm-up render
(the first render of a variant compiles its kernels). Extra XML parameters: --param name=value.
Images stay numpy arrays: in this process, reading or writing an EXR after an llvm_ad_rgb
render hangs (Mitsuba 3.9.1 here), see compare_mitsuba.py.
"""
import argparse
import os
import time
from pathlib import Path

os.environ.setdefault("DRJIT_LIBLLVM_PATH", "/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1")

import mitsuba as mi  # noqa: E402
import numpy as np  # noqa: E402

EPS = 1e-2


def render(xml, spp, seed, params):
    scene = mi.load_file(str(xml), spp=str(spp), **params)
    start = time.perf_counter()
    img = np.array(mi.render(scene, spp=spp, seed=seed)).astype(np.float64)[..., :3]
    return img, time.perf_counter() - start


def render_chunked(xml, spp, seed, params, chunk=256):
    total, done, k = 0.0, 0, 0
    while done < spp:
        n = min(chunk, spp - done)
        img, _ = render(xml, n, seed * 1000 + k, params)
        total = total + img * n
        done, k = done + n, k + 1
    return total / spp


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("xml", type=Path)
    ap.add_argument("--spp", default="1,2,4,8,16,32,64")
    ap.add_argument("--reference", type=Path, help="a .npy reference (else rendered)")
    ap.add_argument("--reference-spp", type=int, default=2048)
    ap.add_argument("--variant", default="llvm_ad_rgb")
    ap.add_argument("--label", default="mitsuba")
    ap.add_argument("--param", action="append", default=[], help="XML parameter name=value")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("-o", "--output", type=Path, required=True)
    args = ap.parse_args()
    mi.set_variant(args.variant)
    params = dict(p.split("=", 1) for p in args.param)
    ref_path = args.reference or args.output.with_name(args.output.stem + "-reference.npy")
    if ref_path.exists():
        reference = np.load(ref_path)
    else:
        reference = render_chunked(args.xml, args.reference_spp, 999, params)
        np.save(ref_path, reference)
    spps = [int(s) for s in args.spp.split(",")]
    render(args.xml, spps[0], 12345, params)  # warm-up: kernel compilation
    lines = ["configuration,seconds,spp,relmse"]
    for spp in spps:
        img, seconds = render(args.xml, spp, args.seed, params)
        rel = float(np.mean((img - reference) ** 2 / (reference ** 2 + EPS)))
        lines.append(f"{args.label},{seconds:.6f},{spp},{rel:.6e}")
        print(lines[-1], flush=True)
    args.output.write_text("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
