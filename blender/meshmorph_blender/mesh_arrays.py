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
    tris = loop_triangles(obj)
    if np.linalg.det(matrix(obj)[:3, :3]) < 0:
        tris = tris[:, ::-1].copy()
    return tris


def loop_triangles(obj):
    """The mesh's triangles `(m, 3)` int64, as Blender splits its polygons
    and winds them (a marker file's triangle numbers and barycentric
    coordinates refer to these)."""
    mesh = obj.data
    mesh.calc_loop_triangles()
    tris = np.empty(len(mesh.loop_triangles) * 3, dtype=np.int64)
    mesh.loop_triangles.foreach_get("vertices", tris)
    return tris.reshape(-1, 3)


def matrix(obj):
    """The object's world transform, a 4x4 float64 array; refused when it
    is not finite, is not affine, or flattens the object (a scale of 0),
    which no result could undo."""
    m = np.array(obj.matrix_world, dtype=np.float64)
    if not np.isfinite(m).all():
        raise Refusal(
            "{}'s transform is not a finite number (NaN or infinite in its location, rotation or scale, "
            "or a parent's or constraint's): give it finite values".format(obj.name)
        )
    if not np.array_equal(m[3], [0.0, 0.0, 0.0, 1.0]):
        raise Refusal("{}'s transform has a perspective part: give it an ordinary location, rotation and scale".format(obj.name))
    scales = np.linalg.svd(m[:3, :3], compute_uv=False)
    if not scales[-1] > 1e-9 * scales[0]:
        raise Refusal("{} is scaled to nothing along an axis: give it a scale other than 0".format(obj.name))
    return m


def location(obj):
    """Where `obj` (an empty, say) is in world space, a float64 3-vector;
    refused when it is not finite."""
    p = np.array(obj.matrix_world.translation, dtype=np.float64)
    if not np.isfinite(p).all():
        where = " (parented to {})".format(obj.parent.name) if obj.parent is not None else ""
        raise Refusal("{}{} is not at a finite location (NaN or infinite): give it finite values".format(obj.name, where))
    return p


def to_world(obj, local):
    """Object-space positions `(..., n, 3)` taken to world space."""
    m = matrix(obj)
    return local @ m[:3, :3].T + m[:3, 3]


def to_object(obj, world):
    """World-space positions `(..., n, 3)` taken to the object's space."""
    inverse = np.linalg.inv(matrix(obj))
    return world @ inverse[:3, :3].T + inverse[:3, 3]


def _coordinates(obj, items, what):
    """The `co` of `items` (the mesh's vertices or a key's points) as an
    `(n, 3)` float64 array; refused when one is not finite."""
    n = len(obj.data.vertices)
    if len(items) != n:
        raise Refusal("{}'s {} has {} points for {} vertices: the mesh is damaged".format(obj.name, what, len(items), n))
    flat = np.empty(n * 3, dtype=np.float32)
    items.foreach_get("co", flat)
    co = flat.reshape(n, 3).astype(np.float64)
    bad = ~np.isfinite(co).all(axis=1)
    if bad.any():
        raise Refusal(
            "{}'s {} has a position that is not a finite number (NaN or infinite) at vertex {}: fix or remove it".format(
                obj.name, what, int(np.argmax(bad))
            )
        )
    return co


def rest(obj):
    """The object's rest shape in object space: its shape keys' reference
    key (the basis), or its vertices when it has no shape keys."""
    mesh = obj.data
    keys = mesh.shape_keys
    if keys is not None and keys.reference_key is not None:
        return _coordinates(obj, keys.reference_key.data, 'basis "{}"'.format(keys.reference_key.name))
    return _coordinates(obj, mesh.vertices, "mesh")


def key_names(obj):
    """The names of the object's shape keys other than the basis, in order."""
    keys = obj.data.shape_keys
    if keys is None:
        return []
    return [k.name for k in keys.key_blocks if k != keys.reference_key]


def key_positions(obj, name):
    """The positions of the shape key `name` in object space `(n, 3)`."""
    block = obj.data.shape_keys.key_blocks[name]
    return _coordinates(obj, block.data, 'shape key "{}"'.format(name))


MAX_NEW_KEYS = 10000
MAX_NEW_BYTES = 2 << 30


def room_for(obj, count):
    """Refuses `count` new keys on `obj` when that is more keys, or more
    memory for their positions (computed in float64 and stored in float32),
    than is reasonable: a count from a .blend made elsewhere may be
    anything."""
    needed = count * len(obj.data.vertices) * 3 * (8 + 4)
    if count > MAX_NEW_KEYS or needed > MAX_NEW_BYTES:
        raise Refusal(
            "{} would get {} new shape keys ({:.1f} GB of positions): ask for fewer, at most {} or 2 GB".format(
                obj.name, count, needed / 1e9, MAX_NEW_KEYS
            )
        )


def storable(obj, name, world):
    """World-space positions `(n, 3)` for the key `name` of `obj`, in the
    object's space as Blender stores them (float32); refused, before
    anything is written, when one would not be finite there."""
    local = to_object(obj, world).astype(np.float32)
    bad = ~np.isfinite(local).all(axis=1)
    if bad.any():
        raise Refusal(
            "{}'s shape key \"{}\" would not be a finite number at vertex {} (the result or the object's "
            "transform is too large): nothing was changed".format(obj.name, name, int(np.argmax(bad)))
        )
    return local


def store_key(obj, name, local):
    """Stores object-space positions `(n, 3)` float32 (from `storable`) as
    the shape key `name`: a new key, or the existing key of that name given
    new positions. The object gets a basis first if it has no shape keys.
    Returns the key."""
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
