"""For scale: trimesh's Sumner fitting step (`trimesh.registration.nricp_sumner`,
the only deformation-transfer piece on PyPI) on horse -> camel with the 107
markers, against meshmorph's whole correspondence from Python. Needs trimesh,
scipy and rtree besides meshmorph.

    python crates/meshmorph-py/bench/trimesh_nricp.py
"""

import re
import time
from pathlib import Path

import numpy as np
import trimesh

import meshmorph

D = Path(__file__).resolve().parents[4] / "shared" / "data" / "dt" / "horse-camel"
horse = trimesh.load(D / "horse-poses/horse-reference.obj", process=False)
camel = trimesh.load(D / "camel-poses/camel-reference.obj", process=False)
lines = [re.split(r"[ ,]+", line.strip()) for line in open(D / "markers/horse-camel-107.cons")][1:]
pairs = np.array([[int(a), int(b)] for a, b in lines])

begin = time.perf_counter()
trimesh.registration.nricp_sumner(horse, camel, source_landmarks=pairs[:, 0], target_positions=camel.vertices[pairs[:, 1]])
print(f"trimesh nricp_sumner (the fitting step): {time.perf_counter() - begin:.2f} s")
begin = time.perf_counter()
meshmorph.correspond(horse.vertices, horse.faces, camel.vertices, camel.faces, pairs)
print(f"meshmorph.correspond (fitting, matching, fit report): {time.perf_counter() - begin:.2f} s")
