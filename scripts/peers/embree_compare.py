#!/usr/bin/env python3
"""Closest-hit rays per second on the same 1M-triangle mesh and the same incoherent rays:
foton's BVH (one thread, criterion) against Embree (PyPI embreex, one thread: the binding
traces a batch with one rtcIntersect1 per ray), in one run.

    bash scripts/peers/setup.sh
    .venv-peers/bin/python scripts/peers/embree_compare.py

`cargo bench --bench bvh` writes the mesh and rays to target/bvh-peer/ (raw f32: 9 per
triangle, 6 per ray) and measures foton; this script then loads the same files into Embree.
Prints each side's rays per second: criterion's median wall time for foton and the median
of 5 passes for Embree, and, since this machine is shared, both per CPU second of the tracing
thread (foton's bench reads /proc/thread-self/schedstat, Python's time.thread_time), which
counts only the time the thread ran. The ratios of both.
"""
import re
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
from embreex import rtcore_scene as rtcs
from embreex.mesh_construction import TriangleMesh

ROOT = Path(__file__).resolve().parents[2]
PEER = ROOT / "target" / "bvh-peer"


def foton_rays_per_second():
    """Runs the criterion bench for one-thread closest hits; returns its median rays/s (wall)
    and its rays per CPU second."""
    out = subprocess.run(
        ["cargo", "bench", "--bench", "bvh", "--", "--noplot", "closest_hit_1_thread|build_torus_1m"],
        cwd=ROOT, capture_output=True, text=True, check=True).stdout
    print(out)
    unit = {"": 1.0, "K": 1e3, "M": 1e6, "G": 1e9}
    thrpt = re.findall(r"closest_hit_1_thread.*?thrpt:\s+\[\S+ \S+ (\S+) (\w?)elem/s", out, re.S)
    value, prefix = thrpt[0]
    cpu = re.search(r"closest hit, one thread: (\S+) M rays per CPU second", out)
    return float(value) * unit[prefix], float(cpu.group(1)) * 1e6


def embree_rays_per_second(passes=5):
    mesh = np.fromfile(PEER / "mesh.f32", dtype="<f4").reshape(-1, 3, 3)
    rays = np.fromfile(PEER / "rays.f32", dtype="<f4").reshape(-1, 2, 3)
    origins = np.ascontiguousarray(rays[:, 0])
    dirs = np.ascontiguousarray(rays[:, 1])
    scene = rtcs.EmbreeScene()
    start = time.perf_counter()
    TriangleMesh(scene, mesh)
    scene.run(origins[:1], dirs[:1])  # the first query commits (builds) the scene
    build = time.perf_counter() - start
    times, cpu_times = [], []
    for _ in range(passes):
        start, cpu = time.perf_counter(), time.thread_time()
        result = scene.run(origins, dirs, output=1)
        times.append(time.perf_counter() - start)
        cpu_times.append(time.thread_time() - cpu)
    hits = int((result["geomID"] != -1).sum()) if isinstance(result, dict) else -1
    print(f"embree: {len(mesh)} triangles, build + first ray {build:.3f} s, "
          f"{hits}/{len(origins)} rays hit")
    median = lambda xs: sorted(xs)[len(xs) // 2]
    return len(origins) / median(times), len(origins) / median(cpu_times)


def main():
    foton, foton_cpu = foton_rays_per_second()
    embree, embree_cpu = embree_rays_per_second()
    print(f"closest hit, 1 thread, wall: foton {foton / 1e6:.3f} M rays/s, "
          f"embree {embree / 1e6:.3f} M rays/s, foton/embree {foton / embree:.2f}")
    print(f"closest hit, 1 thread, per CPU second: foton {foton_cpu / 1e6:.3f} M rays/s, "
          f"embree {embree_cpu / 1e6:.3f} M rays/s, foton/embree {foton_cpu / embree_cpu:.2f}")


if __name__ == "__main__":
    sys.exit(main())
