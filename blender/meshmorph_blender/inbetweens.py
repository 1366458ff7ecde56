"""As-rigid-as-possible in-betweens (Alexa, Cohen-Or and Levin 2000, with
rotations made consistent, Baxter, Barla and Anjyo 2008) as shape keys:
keys between two of an object's keys, or an animation through a list of
keys baked to one key a frame with keyframed values (which glTF exports as
morph targets). Blender's own mix of keys is linear, so a part that turns
shrinks on its way; these keep it rigid."""

import numpy as np

from . import mesh_arrays
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
        raise Refusal("Ask for at least one in-between")
    if start == end:
        raise Refusal("Choose two different keys to go between")
    a, b = _world_key(obj, start), _world_key(obj, end)
    ts = [(i + 1) / (count + 1) for i in range(count)]
    try:
        frames = meshmorph.Interpolator(a, b, _faces(obj)).frames(ts)
    except meshmorph.MeshmorphError as e:
        raise Refusal(str(e)) from e
    base = end if start == obj.data.shape_keys.reference_key.name else "{} to {}".format(start, end)
    names = []
    for t, world in zip(ts, frames):
        name = "{} {:g} %".format(base, round(100 * t, 2))
        block = mesh_arrays.store_key(obj, name, mesh_arrays.to_object(obj, world))
        block.value = 0.0
        names.append(name)
    return names


def bake(meshmorph, obj, keys, frames_per_key, first_frame, prefix="ARAP"):
    """Bakes the animation through `keys` (names, in order; the basis may be
    one) with `frames_per_key` frames from one key to the next, starting at
    `first_frame`: one shape key a frame, its value keyframed 1 on its frame
    and 0 on the frames either side. Returns the keys' names."""
    if len(keys) < 2:
        raise Refusal("List at least two keys to animate through, comma-separated")
    if frames_per_key < 1:
        raise Refusal("Give at least one frame from one key to the next")
    keys_of = obj.data.shape_keys
    if keys_of is not None and any(k.startswith(prefix + " ") for k in keys):
        raise Refusal("Bake through your own keys, not the baked \"{} ....\" ones".format(prefix))
    stack = np.stack([_world_key(obj, k) for k in keys])
    ss = np.linspace(0, len(keys) - 1, (len(keys) - 1) * frames_per_key + 1)
    try:
        frames = meshmorph.Sequence(stack, _faces(obj)).frames(ss)
    except meshmorph.MeshmorphError as e:
        raise Refusal(str(e)) from e
    _forget_bake(obj, prefix)
    names = []
    for i, world in enumerate(frames):
        name = "{} {:04d}".format(prefix, i)
        block = mesh_arrays.store_key(obj, name, mesh_arrays.to_object(obj, world))
        frame = first_frame + i
        for f, v in ((frame - 1, 0.0), (frame, 1.0), (frame + 1, 0.0)):
            block.value = v
            block.keyframe_insert("value", frame=f)
        names.append(name)
    for curve in _curves(obj):
        if _baked_name(curve.data_path, prefix):
            for point in curve.keyframe_points:
                point.interpolation = "LINEAR"
    return names


def _baked_name(data_path, prefix):
    """Whether an F-curve's path is the value of a baked key."""
    return data_path.startswith('key_blocks["{} '.format(prefix)) and data_path.endswith('"].value')


def _curves(obj):
    """The F-curves of the object's shape key animation (none without one;
    Blender 5's layered actions keep them in a channel bag)."""
    data = obj.data.shape_keys.animation_data
    action = data.action if data is not None else None
    if action is None:
        return []
    if hasattr(action, "fcurves"):
        return list(action.fcurves)
    try:
        from bpy_extras import anim_utils

        bag = anim_utils.action_get_channelbag_for_slot(action, data.action_slot)
        return list(bag.fcurves) if bag is not None else []
    except (ImportError, AttributeError):
        return []


def _forget_bake(obj, prefix):
    """Removes an earlier bake: its keys and their curves."""
    data = obj.data.shape_keys.animation_data
    action = data.action if data is not None else None
    if action is not None and hasattr(action, "fcurves"):
        for curve in [c for c in action.fcurves if _baked_name(c.data_path, prefix)]:
            action.fcurves.remove(curve)
    blocks = obj.data.shape_keys.key_blocks
    for name in [b.name for b in blocks if b.name.startswith(prefix + " ") and b.name[len(prefix) + 1 :].isdigit()]:
        obj.shape_key_remove(blocks[name])
