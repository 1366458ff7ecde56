"""glTF files made by hand, as a glTF exporter writes them, for the tests
of the Python package (test_gltf.py, test_dask.py) and of the Blender add-on
(blender/tests/test_addon.py, inside Blender, where there is no pytest):
numpy only."""

import json
import struct

import numpy as np


def sheet(n=6):
    """A square sheet of n quads a side, split in two."""
    xs = np.linspace(-1.0, 1.0, n + 1)
    x, y = np.meshgrid(xs, xs)
    v = np.stack([x.ravel(), y.ravel(), np.zeros(x.size)], axis=1)
    f = []
    for j in range(n):
        for i in range(n):
            a, b = j * (n + 1) + i, j * (n + 1) + i + 1
            c, d = (j + 1) * (n + 1) + i + 1, (j + 1) * (n + 1) + i
            f += [[a, b, c], [a, c, d]]
    return v, np.array(f, dtype=np.int64)


def glb(json_doc, bin_chunk):
    """The bytes of a GLB of `json_doc` and `bin_chunk`."""
    text = json.dumps(json_doc).encode()
    text += b" " * (-len(text) % 4)
    bin_chunk += b"\0" * (-len(bin_chunk) % 4)
    out = struct.pack("<4sII", b"glTF", 2, 12 + 8 + len(text) + 8 + len(bin_chunk))
    out += struct.pack("<I4s", len(text), b"JSON") + text
    out += struct.pack("<I4s", len(bin_chunk), b"BIN\0") + bin_chunk
    return out


def split(data):
    """The JSON and the binary chunk of a GLB's bytes."""
    (length,) = struct.unpack_from("<I", data, 12)
    doc = json.loads(data[20 : 20 + length])
    return doc, data[28 + length :]


def character(path, vrm=False, split=False):
    """A GLB of a sheet (mesh `Face`, a morph target `Up` lifting its
    middle) and a triangle (mesh `Eye`), with a material and the asset's
    copyright; with `vrm`, a VRM 1.0's `VRMC_vrm` data; with `split`, the
    sheet's left and right halves are two primitives, each with its own
    vertices (the middle column in both)."""
    v, f = sheet()
    up = np.zeros_like(v)
    up[:, 2] = 0.2 * np.exp(-4 * (v[:, 0] ** 2 + v[:, 1] ** 2))
    eye = np.array([[0, 0, 0.1], [0.1, 0, 0.1], [0, 0.1, 0.1]], dtype=np.float32)
    chunks, views, accessors = [], [], []

    def add(array, kind, target=None):
        data = np.ascontiguousarray(array).tobytes()
        offset = sum(len(c) for c in chunks)
        chunks.append(data + b"\0" * (-len(data) % 4))
        view = {"buffer": 0, "byteOffset": offset, "byteLength": len(data)}
        if target:
            view["target"] = target
        views.append(view)
        accessor = {"bufferView": len(views) - 1, "count": len(array)}
        if kind == "VEC3":
            accessor.update(componentType=5126, type="VEC3",
                            min=array.min(0).tolist(), max=array.max(0).tolist())
        else:
            accessor.update(componentType=5125, type="SCALAR")
        accessors.append(accessor)
        return len(accessors) - 1

    primitives = []
    halves = [f[v[f].mean(1)[:, 0] < 0], f[v[f].mean(1)[:, 0] > 0]] if split else [f]
    for half in halves:
        used = np.unique(half)
        local = np.searchsorted(used, half)
        primitives.append({
            "attributes": {"POSITION": add(v[used].astype(np.float32), "VEC3", 34962)},
            "indices": add(local.astype(np.uint32).ravel(), "SCALAR", 34963),
            "material": 0,
            "targets": [{"POSITION": add(up[used].astype(np.float32), "VEC3", 34962)}],
        })
    eye_position = add(eye, "VEC3", 34962)
    doc = {
        "asset": {"version": "2.0", "copyright": "the test's own", "generator": "test_gltf.py"},
        "scene": 0,
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [{"name": "FaceNode", "mesh": 0, "translation": [0, 1, 0]}, {"name": "EyeNode", "mesh": 1}],
        "materials": [{"name": "Skin", "pbrMetallicRoughness": {"baseColorFactor": [1, 0.8, 0.7, 1]}}],
        "meshes": [
            {"name": "Face", "weights": [0.0], "extras": {"targetNames": ["Up"]},
             "primitives": primitives},
            {"name": "Eye", "primitives": [{"attributes": {"POSITION": eye_position}}]},
        ],
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [{"byteLength": sum(len(c) for c in chunks)}],
        "extras": {"kept": True},
    }
    if vrm:
        doc["extensionsUsed"] = ["VRMC_vrm"]
        doc["extensions"] = {"VRMC_vrm": {"specVersion": "1.0", "meta": {"name": "sheet", "authors": ["test"], "licenseUrl": "https://vrm.dev/licenses/1.0/"},
                                          "humanoid": {"humanBones": {}}, "expressions": {"preset": {}, "custom": {}}}}
    data = glb(doc, b"".join(chunks))
    path.write_bytes(data)
    return v, f, up, data
