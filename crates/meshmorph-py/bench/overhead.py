"""Python against the Rust library on the same work (examples/same_work.rs
times the Rust side, run first by this script): horse -> camel's
correspondence, its ten poses with apply_all, 100 horse frames, 10 frames
of a 1M-triangle strip, and `at` on two triangles. Prints a markdown table;
the fastest of 3 (correspondence), 10 (strip) or 15 runs each side.

    python crates/meshmorph-py/bench/overhead.py   (with meshmorph installed)
"""

import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

import meshmorph

ROOT = Path(__file__).resolve().parents[3]
DT = ROOT.parent / "shared" / "data" / "dt"


def fastest(runs, f):
    best = float("inf")
    for _ in range(runs):
        t = time.perf_counter()
        f()
        best = min(best, time.perf_counter() - t)
    return best


def main():
    work = Path(tempfile.mkdtemp(prefix="meshmorph-overhead-"))
    rust = json.loads(
        subprocess.run(
            ["cargo", "run", "--quiet", "--release", "--locked", "-p", "meshmorph-py", "--example", "same_work", "--", str(DT), str(work)],
            cwd=ROOT, check=True, capture_output=True, text=True,
        ).stdout
    )
    d = DT / "horse-camel"
    horse = meshmorph.read_mesh(d / "horse-poses/horse-reference.obj")
    camel = meshmorph.read_mesh(d / "camel-poses/camel-reference.obj")
    markers = meshmorph.read_markers(d / "markers/horse-camel-107.cons")
    poses = np.stack([meshmorph.read_mesh(d / f"horse-poses/horse-{k:02}.obj").vertices for k in range(1, 11)])
    hv, hf, cv, cf = horse.vertices, horse.faces, camel.vertices, camel.faces
    found = {}
    py = {"correspond": fastest(3, lambda: found.setdefault("c", meshmorph.correspond(hv, hf, cv, cf, markers)))}
    transfer = meshmorph.Transfer(hv, hf, cv, cf, found["c"])
    py["apply_all"] = fastest(15, lambda: transfer.apply_all(poses))
    walk = meshmorph.Interpolator(hv, poses[4], hf)
    py["frames_100"] = fastest(15, lambda: walk.frames(np.linspace(0, 1, 100)))
    strip = meshmorph.read_mesh(work / "strip.obj")
    curl = meshmorph.read_mesh(work / "curl.obj")
    big = meshmorph.Interpolator(strip.vertices[:, :2], curl.vertices[:, :2], strip.faces)
    py["strip_frames"] = fastest(10, lambda: big.frames(np.linspace(0, 1, 10)))
    # Into a buffer the caller keeps, as the Rust side's repeated runs reuse
    # their freed memory (a new 80 MB array is new pages each time).
    buffer = np.empty((10,) + strip.vertices[:, :2].shape)
    py["strip_frames_out"] = fastest(10, lambda: big.frames(np.linspace(0, 1, 10), out=buffer))
    frames_out = np.empty((100,) + hv.shape)
    py["frames_100_out"] = fastest(15, lambda: walk.frames(np.linspace(0, 1, 100), out=frames_out))
    one = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    small = meshmorph.Interpolator(one, one @ np.array([[0.9, 0.3], [-0.3, 0.9]]), np.array([[0, 1, 2], [0, 2, 3]]))
    calls = 100_000
    py["small_at"] = fastest(3, lambda: [small.at(k / calls) for k in range(calls)]) / calls
    rows = [
        ("horse → camel correspondence (107 markers)", "correspond"),
        ("horse → camel, 10 poses (`apply_all`)", "apply_all"),
        ("horse, 100 frames (`frames`)", "frames_100"),
        (f"strip of {rust['strip_triangles']:,} triangles (planar), 10 frames (`frames`)", "strip_frames"),
    ]
    print("| work | Rust library | Python | Python overhead |")
    print("|---|---:|---:|---:|")
    for name, key in rows:
        r, p = rust[key], py[key]
        print(f"| {name} | {r * 1e3:.1f} ms | {p * 1e3:.1f} ms | {100 * (p / r - 1):+.1f} % |")
    for name, key, rkey in [
        ("horse, 100 frames, `frames(out=)`", "frames_100_out", "frames_100"),
        (f"strip, 10 frames, `frames(out=)`", "strip_frames_out", "strip_frames"),
        ("strip, 10 frames: Python's new array against Rust's first call (new memory both)", "strip_frames", "strip_first"),
    ]:
        r, p = rust[rkey], py[key]
        print(f"| {name} | {r * 1e3:.1f} ms | {p * 1e3:.1f} ms | {100 * (p / r - 1):+.1f} % |")
    r, p = rust["small_at"], py["small_at"]
    print(f"| `at` on two triangles, a call | {r * 1e6:.2f} µs | {p * 1e6:.2f} µs | {(p - r) * 1e6:+.2f} µs a call |")


if __name__ == "__main__":
    sys.exit(main())
