"""As-rigid-as-possible in-betweens (Alexa, Cohen-Or and Levin 2000, with
rotations made consistent, Baxter, Barla and Anjyo 2008) as shape keys:
keys between two of an object's keys, or an animation through a list of
keys baked to one key a frame with keyframed values (which glTF exports as
morph targets). Blender's own mix of keys is linear, so a part that turns
shrinks on its way; these keep it rigid."""

import numpy as np

from . import mesh_arrays
from .scene_snapshot import fcurves
from .refusal import Refusal

BASIS = "Basis"


def _world_key(obj, name):
    keys = obj.data.shape_keys
    if keys is None:
        raise Refusal("{} has no shape keys: select an object with shape keys".format(obj.name))
    if name == keys.reference_key.name:
        local = mesh_arrays.rest(obj)
    elif name in keys.key_blocks:
        local = mesh_arrays.key_positions(obj, name)
    else:
        names = [k.name for k in keys.key_blocks]
        raise Refusal("{} has no shape key \"{}\"; it has: {}".format(obj.name, name, ", ".join(names)))
    return mesh_arrays.to_world(obj, local)


def _faces(obj):
    f = mesh_arrays.triangles(obj)
    if len(f) == 0:
        raise Refusal("{} has no faces: select a mesh with faces".format(obj.name))
    return f


def add(meshmorph, obj, start, end, count):
    """Adds `count` in-between keys from key `start` to key `end` (either may
    be the basis), evenly in time; returns their names."""
    if count < 1:
        raise Refusal("Ask for at least one in-between on {}".format(obj.name))
    if start == end:
        raise Refusal("Choose two different keys of {} to go between".format(obj.name))
    mesh_arrays.room_for(obj, count)
    a, b = _world_key(obj, start), _world_key(obj, end)
    ts = [(i + 1) / (count + 1) for i in range(count)]
    try:
        frames = meshmorph.Interpolator(a, b, _faces(obj)).frames(ts)
    except meshmorph.MeshmorphError as e:
        raise Refusal("{}: {}".format(obj.name, e)) from e
    base = end if start == obj.data.shape_keys.reference_key.name else "{} to {}".format(start, end)
    names = ["{} {:g} %".format(base, round(100 * t, 2)) for t in ts]
    local = [mesh_arrays.storable(obj, name, world) for name, world in zip(names, frames)]
    for name, positions in zip(names, local):
        mesh_arrays.store_key(obj, name, positions).value = 0.0
    return names


def bake(meshmorph, obj, keys, frames_per_key, first_frame, prefix="ARAP"):
    """Bakes the animation through `keys` (names, in order; the basis may be
    one) with `frames_per_key` frames from one key to the next, starting at
    `first_frame`: one shape key a frame, its value keyframed 1 on its frame
    and 0 on the frames either side. Returns the keys' names."""
    if len(keys) < 2:
        raise Refusal("List at least two of {}'s keys to animate through, comma-separated".format(obj.name))
    if frames_per_key < 1:
        raise Refusal("Give {}'s bake at least one frame from one key to the next".format(obj.name))
    keys_of = obj.data.shape_keys
    if keys_of is not None and any(k.startswith(prefix + " ") for k in keys):
        raise Refusal("Bake through {}'s own keys, not the baked \"{} ....\" ones".format(obj.name, prefix))
    mesh_arrays.room_for(obj, (len(keys) - 1) * frames_per_key + 1)
    stack = np.stack([_world_key(obj, k) for k in keys])
    ss = np.linspace(0, len(keys) - 1, (len(keys) - 1) * frames_per_key + 1)
    try:
        frames = meshmorph.Sequence(stack, _faces(obj)).frames(ss)
    except meshmorph.MeshmorphError as e:
        raise Refusal("{}: {}".format(obj.name, e)) from e
    names = ["{} {:04d}".format(prefix, i) for i in range(len(frames))]
    local = [mesh_arrays.storable(obj, name, world) for name, world in zip(names, frames)]
    # An earlier bake's keys are given the new positions (so that they keep
    # their place among the object's keys) and its curves made anew; its
    # keys beyond the new bake's are removed last.
    _forget_curves(obj, prefix)
    for i, (name, positions) in enumerate(zip(names, local)):
        block = mesh_arrays.store_key(obj, name, positions)
        frame = first_frame + i
        for f, v in ((frame - 1, 0.0), (frame, 1.0), (frame + 1, 0.0)):
            block.value = v
            block.keyframe_insert("value", frame=f)
    for curve in fcurves(obj) or []:
        if _baked_name(curve.data_path, prefix):
            for point in curve.keyframe_points:
                point.interpolation = "LINEAR"
    blocks = obj.data.shape_keys.key_blocks
    for name in [b.name for b in blocks if _baked_key(b.name, prefix) and b.name not in names]:
        obj.shape_key_remove(blocks[name])
    return names


def _baked_name(data_path, prefix):
    """Whether an F-curve's path is the value of a baked key."""
    return data_path.startswith('key_blocks["{} '.format(prefix)) and data_path.endswith('"].value')


def _baked_key(name, prefix):
    """Whether a key's name is that of a baked key ("ARAP 0012")."""
    return name.startswith(prefix + " ") and name[len(prefix) + 1 :].isdigit()


def _forget_curves(obj, prefix):
    """Removes an earlier bake's curves."""
    curves = fcurves(obj)
    if curves is not None:
        for curve in [c for c in curves if _baked_name(c.data_path, prefix)]:
            curves.remove(curve)
