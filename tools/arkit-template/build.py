#!/usr/bin/env python3
"""Builds meshmorph's ARKit expression template from an ICT-FaceKit checkout.

usage: tools/arkit-template/build.py FACEKIT_DIR OUT.glb

FACEKIT_DIR is a copy of the public repository ICT-VGL/ICT-FaceKit (MIT
licence): its FaceXModel/ folder holds the generic neutral head and one OBJ
per expression shape. Needs Python 3 and numpy. The output is the same bytes
on every run from the same input.

The GLB holds, in metres, one mesh per part, each with one triangle primitive
(the FaceKit's quads split along their first diagonal) and every expression
shape as a morph target, named in `mesh.extras.targetNames`:

- `head`: the face, the head and neck, the inside of the mouth and the eye
  sockets, one surface (the FaceKit's vertices 0 to 14061, in their order);
  `mesh.extras.regions` gives each region's first and last vertex, and
  `mesh.extras.landmarks` the 68 landmarks of the Multi-PIE / iBUG 300-W
  scheme (`{"name": "1".."68", "vertex": i}`);
- `eyeLeft`, `eyeRight` (eyeballs), `teethUpper`, `teethLower`,
  `gumsTongue`: the parts that move rigidly or nearly.

After its shapes the head has the FaceKit's identity model as targets too
(`identity000` to `identity099`, each one standard deviation of a principal
component of head shape, largest first), named in `mesh.extras.identityBases`:
meshmorph fits them to a user's head before the correspondence. Stored
densely (they move every vertex), each stretched to the 16-bit range: a
basis is its target times its entry in `mesh.extras.identityUnits` (metres),
in steps of about 1 µm.

Left and right are the head's own (as in ARKit's `eyeBlinkLeft`). The
FaceKit's eyelashes, lacrimal fluid and eye blend and occlusion meshes are
left out. Targets are sparse accessors of KHR_mesh_quantization: a vertex's
delta is stored as normalised 16-bit integers (1 m / 32767, about 31 µm, a
step of 0.007 % of the head's diagonal) and only where it is not zero:
deltas shorter than 0.1 mm (0.02 % of the diagonal), the noise of the
FaceKit's scans that moves every vertex a little in every shape, are zero.
"""

import json
import os
import struct
import sys

import numpy as np

# (mesh name, first face, last face, first vertex, last vertex): the
# FaceKit's README, "Geometry names" (inclusive ranges).
PARTS = [
    ("head", 0, 14033, 0, 14061),
    ("gumsTongue", 14034, 17005, 14062, 17038),
    ("teethUpper", 17006, 19249, 17039, 19246),
    ("teethLower", 19250, 21495, 19247, 21450),
    ("eyeLeft", 21496, 23093, 21451, 23020),
    ("eyeRight", 23094, 24691, 23021, 24590),
]

# The regions of the head (first and last vertex).
HEAD_REGIONS = [
    ("face", 0, 9408),
    ("headNeck", 9409, 11247),
    ("mouthSocket", 11248, 13293),
    ("eyeSocketLeft", 13294, 13677),
    ("eyeSocketRight", 13678, 14061),
]

# The FaceKit README's 68 Multi-PIE landmarks (0-based vertex indices), in
# the scheme's order 1 to 68.
LANDMARKS = [
    1225, 1888, 1052, 367, 1719, 1722, 2199, 1447, 966, 3661, 4390, 3927, 3924,
    2608, 3272, 4088, 3443, 268, 493, 1914, 2044, 1401, 3615, 4240, 4114, 2734,
    2509, 978, 4527, 4942, 4857, 1140, 2075, 1147, 4269, 3360, 1507, 1542, 1537,
    1528, 1518, 1511, 3742, 3751, 3756, 3721, 3725, 3732, 5708, 5695, 2081, 0,
    4275, 6200, 6213, 6346, 6461, 5518, 5957, 5841, 5702, 5711, 5533, 6216,
    6207, 6470, 5517, 5966,
]

# The shapes besides the neutral head: the 53 of vertex_indices.json, then
# the four the FaceKit ships beside them.
EXTRA_SHAPES = ["cheekRaiser_L", "cheekRaiser_R", "PupilDilate_L", "PupilDilate_R"]

# The FaceKit's eyeLook shapes move the lids and the skin around the eyes,
# not the eyeballs (a rig turns those by bones). Here each eyeball also
# turns about its centre (the centre of the sphere that best fits it) in
# its own side's eyeLook shapes, by EYE_TURN degrees at full weight, its
# front (+z) towards the look: up is +y, the head's left +x, so looking in
# (to the nose) is -x for the left eye and +x for the right.
EYE_TURN = 30.0
EYE_LOOKS = {  # shape: (eyeball, direction of the look, before the turn)
    "eyeLookUp_L": ("eyeLeft", (0, 1)), "eyeLookDown_L": ("eyeLeft", (0, -1)),
    "eyeLookIn_L": ("eyeLeft", (-1, 0)), "eyeLookOut_L": ("eyeLeft", (1, 0)),
    "eyeLookUp_R": ("eyeRight", (0, 1)), "eyeLookDown_R": ("eyeRight", (0, -1)),
    "eyeLookIn_R": ("eyeRight", (1, 0)), "eyeLookOut_R": ("eyeRight", (-1, 0)),
}

# The FaceKit's identity model: its 100 principal components of head shape.
IDENTITY_BASES = 100

METRES_PER_UNIT = 0.01  # the FaceKit models in centimetres
STEPS = 32767.0
NOISE = 0.01  # 0.1 mm, in the FaceKit's centimetres  # normalised 16-bit: 1 m per 32767 steps

GENERATOR = "meshmorph tools/arkit-template/build.py"
COPYRIGHT = (
    "ICT-FaceKit, Copyright (c) 2020 USC Institute for Creative Technologies, "
    "MIT licence (LICENSE-ICT-FaceKit beside this file)"
)


def read_obj(path, faces=False):
    """Vertex positions (float64, n x 3) and, if asked, the polygons
    (0-based vertex indices) of an OBJ file."""
    verts = []
    polys = []
    with open(path, "r", encoding="utf-8") as f:
        for line in f:
            if line.startswith("v "):
                p = line.split()
                verts.append((float(p[1]), float(p[2]), float(p[3])))
            elif faces and line.startswith("f "):
                polys.append([int(c.split("/")[0]) - 1 for c in line.split()[1:]])
    return np.array(verts, dtype=np.float64), polys


def triangles_of(polys):
    tris = []
    for p in polys:
        for k in range(1, len(p) - 1):
            tris.append((p[0], p[k], p[k + 1]))
    return np.array(tris, dtype=np.int64)


class Glb:
    """A GLB's JSON and binary chunk, built in order."""

    def __init__(self):
        self.bin = bytearray()
        self.views = []
        self.accessors = []

    def view(self, data, target=None):
        while len(self.bin) % 4:
            self.bin.append(0)
        v = {"buffer": 0, "byteOffset": len(self.bin), "byteLength": len(data)}
        if target is not None:
            v["target"] = target
        self.bin.extend(data)
        self.views.append(v)
        return len(self.views) - 1

    def accessor(self, a):
        self.accessors.append(a)
        return len(self.accessors) - 1


def positions_accessor(glb, pos):
    p = pos.astype("<f4")
    view = glb.view(p.tobytes(), target=34962)
    return glb.accessor({
        "bufferView": view,
        "componentType": 5126,
        "count": len(p),
        "type": "VEC3",
        "min": [float(x) for x in p.min(axis=0)],
        "max": [float(x) for x in p.max(axis=0)],
    })


def indices_accessor(glb, tris, num_vertices):
    if num_vertices < 65536:
        data, ctype = tris.astype("<u2").tobytes(), 5123
    else:
        data, ctype = tris.astype("<u4").tobytes(), 5125
    view = glb.view(data, target=34963)
    return glb.accessor({
        "bufferView": view,
        "componentType": ctype,
        "count": int(tris.size),
        "type": "SCALAR",
    })


def delta_accessor(glb, q):
    """A normalised-short accessor of the quantised deltas `q` (n x 3
    int16): sparse (only the rows that are not zero) unless that is larger
    than all of them."""
    moved = np.nonzero(np.any(q != 0, axis=1))[0]
    if len(moved) * 8 >= len(q) * 6:
        return glb.accessor({
            "bufferView": glb.view(q.astype("<i2").tobytes()),
            "componentType": 5122,
            "normalized": True,
            "count": len(q),
            "type": "VEC3",
            "min": [int(x) for x in q.min(axis=0)],
            "max": [int(x) for x in q.max(axis=0)],
        })
    a = {
        "componentType": 5122,
        "normalized": True,
        "count": len(q),
        "type": "VEC3",
        "min": [int(x) for x in np.minimum(q.min(axis=0), 0)],
        "max": [int(x) for x in np.maximum(q.max(axis=0), 0)],
    }
    if len(moved):
        if len(q) < 65536:
            idx, itype = moved.astype("<u2").tobytes(), 5123
        else:
            idx, itype = moved.astype("<u4").tobytes(), 5125
        a["sparse"] = {
            "count": int(len(moved)),
            "indices": {"bufferView": glb.view(idx), "componentType": itype},
            "values": {"bufferView": glb.view(q[moved].astype("<i2").tobytes())},
        }
    return glb.accessor(a)


def sphere_centre(points):
    """The centre of the sphere that best fits `points` (least squares on
    |p|^2 = 2 c.p + (r^2 - |c|^2))."""
    a = np.hstack([2 * points, np.ones((len(points), 1))])
    b = (points ** 2).sum(axis=1)
    solution = np.linalg.lstsq(a, b, rcond=None)[0]
    return solution[:3]


def eye_turn(points, look):
    """The deltas of an eyeball's `points` turned about its centre by
    EYE_TURN degrees, its front (+z) towards `look` (x, y)."""
    centre = sphere_centre(points)
    angle = np.radians(EYE_TURN)
    axis = np.cross([0.0, 0.0, 1.0], [look[0], look[1], 0.0])
    axis /= np.linalg.norm(axis)
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    turn = np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * (k @ k)
    return (points - centre) @ turn.T + centre - points


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__.split("\n\n")[1])
    root, out = sys.argv[1], sys.argv[2]
    model = os.path.join(root, "FaceXModel")
    neutral_path = os.path.join(model, "generic_neutral_mesh.obj")
    if not os.path.isfile(neutral_path):
        sys.exit(f"{root}: no FaceXModel/generic_neutral_mesh.obj (is it an ICT-FaceKit checkout?)")
    with open(os.path.join(model, "vertex_indices.json"), encoding="utf-8") as f:
        shapes = json.load(f)["expressions"] + EXTRA_SHAPES

    neutral, polys = read_obj(neutral_path, faces=True)
    deltas = []
    for name in shapes:
        v, _ = read_obj(os.path.join(model, name + ".obj"))
        if v.shape != neutral.shape:
            sys.exit(f"{name}.obj: {len(v)} vertices, the neutral head has {len(neutral)}")
        d = v - neutral
        if name in EYE_LOOKS:
            eye, look = EYE_LOOKS[name]
            _, _, _, e0, e1 = next(p for p in PARTS if p[0] == eye)
            d[e0:e1 + 1] = eye_turn(neutral[e0:e1 + 1], look)
        # The FaceKit's shapes move every vertex a little (its scans'
        # noise: up to 0.08 mm on the far side of the face in eyeBlink_L);
        # what moves less than NOISE stays exactly still.
        d[np.linalg.norm(d, axis=1) < NOISE] = 0.0
        d = np.rint(d * METRES_PER_UNIT * STEPS)
        if np.abs(d).max() > STEPS:
            sys.exit(f"{name}.obj: a delta of more than 1 m")
        deltas.append(d.astype(np.int16))

    # The identity model on the head's vertices.
    head_end = PARTS[0][4] + 1
    identity_names = [f"identity{i:03d}" for i in range(IDENTITY_BASES)]
    identity, identity_units = [], []
    for name in identity_names:
        v, _ = read_obj(os.path.join(model, name + ".obj"))
        if v.shape != neutral.shape:
            sys.exit(f"{name}.obj: {len(v)} vertices, the neutral head has {len(neutral)}")
        d = (v - neutral)[:head_end] * METRES_PER_UNIT
        # Each basis stretched to the 16-bit range, its scale beside it:
        # 1 µm steps where the shapes' 31 µm would add up over 100 bases
        # to a tenth of a millimetre.
        unit = float(np.abs(d).max())
        identity.append(np.rint(d / unit * STEPS).astype(np.int16))
        identity_units.append(unit)

    glb = Glb()
    meshes, nodes = [], []
    for name, f0, f1, v0, v1 in PARTS:
        tris = triangles_of(polys[f0:f1 + 1])
        if tris.min() < v0 or tris.max() > v1:
            sys.exit(f"{name}: faces {f0}-{f1} reach outside vertices {v0}-{v1}")
        pos = neutral[v0:v1 + 1] * METRES_PER_UNIT
        n = len(pos)
        prim = {
            "attributes": {"POSITION": positions_accessor(glb, pos)},
            "indices": indices_accessor(glb, tris - v0, n),
            "mode": 4,
            "targets": [{"POSITION": delta_accessor(glb, d[v0:v1 + 1])} for d in deltas],
        }
        extras = {"targetNames": shapes}
        if name == "head":
            prim["targets"] += [{"POSITION": delta_accessor(glb, d)} for d in identity]
            extras = {
                "targetNames": shapes + identity_names,
                "identityBases": identity_names,
                "identityUnits": identity_units,
            }
            extras["regions"] = {r: [a, b] for r, a, b in HEAD_REGIONS}
            extras["landmarks"] = [
                {"name": str(k + 1), "vertex": v} for k, v in enumerate(LANDMARKS)
            ]
        meshes.append({"name": name, "primitives": [prim], "extras": extras})
        nodes.append({"name": name, "mesh": len(meshes) - 1})

    while len(glb.bin) % 4:
        glb.bin.append(0)
    doc = {
        "asset": {"version": "2.0", "generator": GENERATOR, "copyright": COPYRIGHT},
        "extensionsUsed": ["KHR_mesh_quantization"],
        "extensionsRequired": ["KHR_mesh_quantization"],
        "scene": 0,
        "scenes": [{"name": "ICT-FaceKit", "nodes": list(range(len(nodes)))}],
        "nodes": nodes,
        "meshes": meshes,
        "accessors": glb.accessors,
        "bufferViews": glb.views,
        "buffers": [{"byteLength": len(glb.bin)}],
    }
    js = json.dumps(doc, separators=(",", ":"), ensure_ascii=True).encode("ascii")
    js += b" " * (-len(js) % 4)
    total = 12 + 8 + len(js) + 8 + len(glb.bin)
    blob = (
        struct.pack("<4sII", b"glTF", 2, total)
        + struct.pack("<I4s", len(js), b"JSON") + js
        + struct.pack("<I4s", len(glb.bin), b"BIN\0") + bytes(glb.bin)
    )
    tmp = out + ".partial"
    with open(tmp, "wb") as f:
        f.write(blob)
    os.replace(tmp, out)
    moved = [int(np.count_nonzero(np.any(d[:11248] != 0, axis=1))) for d in deltas]
    print(f"{out}: {len(blob)} bytes, {len(shapes)} shapes, head vertices moved per shape "
          f"{min(moved)} to {max(moved)}")


if __name__ == "__main__":
    main()
