"""Blender objects as the arrays meshmorph takes, and results written back.

The solve runs on the mesh's own vertices (shape keys are stored on them),
triangulated as Blender triangulates quads and n-gons for drawing
(``loop_triangles``); the object's polygons, UVs and materials are never
touched. Positions are taken to world space with the object's transform,
so that two characters are compared as the scene shows them and a scaled
object stays rigid where it looks rigid, and results are brought back into
the object's own space before they are stored.
"""

import numpy as np

from .refusal import Refusal


def triangles(obj):
    """The mesh's triangles `(m, 3)` int64, as Blender splits its polygons,
    wound as they face in world space: an object mirrored by its transform
    (a negative scale) has them turned over, so that their normals still
    point outwards there."""
    mesh = obj.data
    mesh.calc_loop_triangles()
    tris = np.empty(len(mesh.loop_triangles) * 3, dtype=np.int64)
    mesh.loop_triangles.foreach_get("vertices", tris)
    tris = tris.reshape(-1, 3)
    if np.linalg.det(matrix(obj)[:3, :3]) < 0:
        tris = tris[:, ::-1].copy()
    return tris


def matrix(obj):
    """The object's world transform, a 4x4 float64 array; refused when it
    flattens the object (a scale of 0), which no result could undo."""
    m = np.array(obj.matrix_world, dtype=np.float64)
    scales = np.linalg.svd(m[:3, :3], compute_uv=False)
    if not scales[-1] > 1e-9 * scales[0]:
        raise Refusal("{} is scaled to nothing along an axis: give it a scale other than 0".format(obj.name))
    return m


def to_world(obj, local):
    """Object-space positions `(..., n, 3)` taken to world space."""
    m = matrix(obj)
    return local @ m[:3, :3].T + m[:3, 3]


def to_object(obj, world):
    """World-space positions `(..., n, 3)` taken to the object's space."""
    inverse = np.linalg.inv(matrix(obj))
    return world @ inverse[:3, :3].T + inverse[:3, 3]


def _coordinates(items, n):
    flat = np.empty(n * 3, dtype=np.float32)
    items.foreach_get("co", flat)
    return flat.reshape(n, 3).astype(np.float64)


def rest(obj):
    """The object's rest shape in object space: its shape keys' reference
    key (the basis), or its vertices when it has no shape keys."""
    mesh = obj.data
    keys = mesh.shape_keys
    if keys is not None and keys.reference_key is not None:
        return _coordinates(keys.reference_key.data, len(mesh.vertices))
    return _coordinates(mesh.vertices, len(mesh.vertices))


def key_names(obj):
    """The names of the object's shape keys other than the basis, in order."""
    keys = obj.data.shape_keys
    if keys is None:
        return []
    return [k.name for k in keys.key_blocks if k != keys.reference_key]


def key_positions(obj, name):
    """The positions of the shape key `name` in object space `(n, 3)`."""
    block = obj.data.shape_keys.key_blocks[name]
    return _coordinates(block.data, len(obj.data.vertices))


def store_key(obj, name, local):
    """Stores object-space positions `(n, 3)` as the shape key `name`: a new
    key, or the existing key of that name given new positions. The object
    gets a basis first if it has no shape keys. Returns the key."""
    if obj.data.shape_keys is None:
        obj.shape_key_add(name="Basis", from_mix=False)
    block = obj.data.shape_keys.key_blocks.get(name)
    if block is None:
        block = obj.shape_key_add(name=name, from_mix=False)
    block.data.foreach_set("co", np.ascontiguousarray(local, dtype=np.float32).ravel())
    obj.data.update()
    return block


def diagonal(points):
    """The length of the bounding box's diagonal of `points` `(n, 3)`."""
    return float(np.linalg.norm(points.max(axis=0) - points.min(axis=0)))
