"""Helpers shared by the report scripts: locating foton and the course scenes, running a
render and reading its time, and reading foton's linear EXR output."""

from __future__ import annotations

import importlib.util
import os
import re
import subprocess
import sys
from pathlib import Path
from typing import NoReturn

for _package in ("numpy", "OpenEXR", "PIL", "matplotlib"):
    if importlib.util.find_spec(_package) is None:
        sys.exit(
            f"error: the Python package {_package} is missing: run "
            "`bash scripts/setup-python.sh` and run this script with `.venv/bin/python`"
        )

import numpy as np  # noqa: E402
import OpenEXR  # noqa: E402

REPO = Path(__file__).resolve().parent.parent
BINARY = REPO / "target" / "release" / "foton"

# foton's last stdout line: "out.png written: 2.24 s, 16 spp, 3.71 M paths/s, 11.68 M rays/s".
_TIME_LINE = re.compile(r"written: ([0-9.]+) s,")


def fail(message: str) -> NoReturn:
    """Print an error message and exit with status 1."""
    print(f"error: {message}", file=sys.stderr)
    sys.exit(1)


def foton_binary() -> Path:
    """The release binary of foton, or exit telling the user how to build it."""
    if not BINARY.is_file():
        fail(f"{BINARY} not found: run `cargo build --release` in {REPO} first")
    return BINARY


def shared_root() -> Path:
    """The shared folder that holds scenes/itba: $FOTON_SHARED, else <repo>/../shared, else
    /work/shared; exit if the course scenes are in none of them."""
    candidates = []
    if os.environ.get("FOTON_SHARED"):
        candidates.append(Path(os.environ["FOTON_SHARED"]))
    candidates += [REPO.parent / "shared", Path("/work/shared")]
    for candidate in candidates:
        if (candidate / "scenes" / "itba").is_dir():
            return candidate
    fail(
        "the course scenes are absent; looked for scenes/itba in "
        + ", ".join(str(c) for c in candidates)
        + " (set FOTON_SHARED to the folder that holds scenes/itba)"
    )


def shared_scenes() -> Path:
    """The course scenes folder, scenes/itba under the shared folder."""
    return shared_root() / "scenes" / "itba"


def require_file(path: Path, what: str) -> Path:
    """Return `path`, or exit saying that `what` is missing."""
    if not path.is_file():
        fail(f"{what} not found: {path}")
    return path


def render(scene: Path, output: Path, options: list[str]) -> float:
    """Render `scene` to `output` with foton and the given CLI options; return foton's own
    reported render time in seconds. Exits with foton's messages if the render fails."""
    output.parent.mkdir(parents=True, exist_ok=True)
    command = [str(foton_binary()), "render", str(scene), "-o", str(output), *options]
    result = subprocess.run(command, capture_output=True, text=True, check=False)
    if result.returncode != 0:
        fail(f"foton failed ({' '.join(command)}):\n{result.stderr.strip()}")
    lines = result.stdout.strip().splitlines()
    match = _TIME_LINE.search(lines[-1]) if lines else None
    if match is None:
        fail(f"could not read the render time from foton's output:\n{result.stdout}")
    return float(match.group(1))


def read_exr(path: Path) -> np.ndarray:
    """The linear RGB of an EXR file as a float64 numpy array of shape (height, width, 3)."""
    with OpenEXR.File(str(path)) as exr:
        channels = exr.channels()
        if "RGB" in channels:
            rgb = channels["RGB"].pixels[..., :3]
        else:
            rgb = np.stack([channels[c].pixels for c in ("R", "G", "B")], axis=-1)
    return np.asarray(rgb, dtype=np.float64)


def display_command(argv: list[str]) -> str:
    """The command line that ran this script, for the generated documents."""
    script = Path(argv[0]).resolve()
    try:
        script_text = str(script.relative_to(REPO))
    except ValueError:
        script_text = str(script)
    return " ".join([".venv/bin/python", script_text, *argv[1:]])
