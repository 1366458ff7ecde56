"""What an operator may change, recorded before it runs and put back when
it stops on an error: the scene is as it was, whatever failed and when.

Each operator writes only to the selected meshes: their shape keys (points,
values, ranges, relative keys), the shape keys' animation (F-curves and the
action holding them) and the kept correspondence (a custom property). A
snapshot holds those and nothing else; it needs neither numpy nor meshmorph,
so it is taken before either is loaded.
"""

from array import array

import bpy

from .kept_correspondence import PROPERTY

_BLOCK_FIELDS = ("value", "mute", "interpolation", "vertex_group")
_POINT_FIELDS = ("co", "handle_left", "handle_right")
_POINT_ENUMS = ("interpolation", "handle_left_type", "handle_right_type", "easing", "type")


def fcurves(obj):
    """The F-curves of the object's shape key animation (Blender 5's layered
    actions keep them in a channel bag), or None without an animation."""
    keys = obj.data.shape_keys
    data = keys.animation_data if keys is not None else None
    action = data.action if data is not None else None
    if action is None:
        return None
    if hasattr(action, "fcurves"):
        return action.fcurves
    try:
        from bpy_extras import anim_utils

        bag = anim_utils.action_get_channelbag_for_slot(action, data.action_slot)
        return bag.fcurves if bag is not None else None
    except (ImportError, AttributeError):
        return None


def _copy(value):
    """A custom property's value as plain Python (dicts, lists)."""
    if hasattr(value, "to_dict"):
        return value.to_dict()
    if hasattr(value, "to_list"):
        return value.to_list()
    return value


def _points(curve):
    return [
        tuple(tuple(getattr(p, f)) for f in _POINT_FIELDS) + tuple(getattr(p, f) for f in _POINT_ENUMS)
        for p in curve.keyframe_points
    ]


def _block(block):
    co = array("f", bytes(4 * 3 * len(block.data)))
    block.data.foreach_get("co", co)
    state = {f: getattr(block, f) for f in _BLOCK_FIELDS}
    state.update(
        name=block.name,
        co=co,
        slider_min=block.slider_min,
        slider_max=block.slider_max,
        relative_key=block.relative_key.name,
    )
    return state


class _ObjectState:
    def __init__(self, obj):
        self.obj = obj
        self.has_property = PROPERTY in obj
        self.property = _copy(obj[PROPERTY]) if self.has_property else None
        keys = obj.data.shape_keys
        self.blocks = None if keys is None else [_block(b) for b in keys.key_blocks]
        data = keys.animation_data if keys is not None else None
        self.has_animation = data is not None
        self.action = data.action if data is not None else None
        curves = fcurves(obj)
        self.curves = None if curves is None else {(c.data_path, c.array_index): _points(c) for c in curves}

    def restore(self):
        obj = self.obj
        if self.has_property:
            if PROPERTY not in obj or _copy(obj[PROPERTY]) != self.property:
                obj[PROPERTY] = self.property
        elif PROPERTY in obj:
            del obj[PROPERTY]
        if self.blocks is None:
            if obj.data.shape_keys is not None:
                obj.shape_key_clear()
            return
        if obj.data.shape_keys is None:
            obj.shape_key_add(name=self.blocks[0]["name"], from_mix=False)
        blocks = obj.data.shape_keys.key_blocks
        names = {b["name"] for b in self.blocks}
        for block in [b for b in blocks if b.name not in names]:
            obj.shape_key_remove(block)
        for state in self.blocks:
            block = blocks.get(state["name"]) or obj.shape_key_add(name=state["name"], from_mix=False)
            block.data.foreach_set("co", state["co"])
            for f in _BLOCK_FIELDS:
                if getattr(block, f) != state[f]:
                    setattr(block, f, state[f])
            block.slider_min, block.slider_max = -10.0, 10.0  # each is kept on its side of the other
            block.slider_min, block.slider_max = state["slider_min"], state["slider_max"]
        for state in self.blocks:
            if blocks[state["name"]].relative_key.name != state["relative_key"] and state["relative_key"] in blocks:
                blocks[state["name"]].relative_key = blocks[state["relative_key"]]
        self._restore_animation()
        obj.data.update()

    def _restore_animation(self):
        keys = self.obj.data.shape_keys
        if not self.has_animation:
            if keys.animation_data is not None:
                keys.animation_data_clear()
            return
        data = keys.animation_data or keys.animation_data_create()
        if data.action != self.action:
            data.action = self.action
        curves = fcurves(self.obj)
        if curves is None or self.curves is None:
            return
        for curve in [c for c in curves if (c.data_path, c.array_index) not in self.curves]:
            curves.remove(curve)
        for (path, index), points in self.curves.items():
            curve = curves.find(path, index=index) or curves.new(path, index=index)
            if _points(curve) == points:
                continue
            while len(curve.keyframe_points):
                curve.keyframe_points.remove(curve.keyframe_points[-1], fast=True)
            curve.keyframe_points.add(len(points))
            for point, state in zip(curve.keyframe_points, points):
                for f, v in zip(_POINT_FIELDS + _POINT_ENUMS, state):
                    setattr(point, f, v)
            curve.update()


class Snapshot:
    """The state of `objects` (meshes; others are skipped) that operators change."""

    def __init__(self, objects):
        seen = []
        for obj in objects:
            if obj is not None and obj.type == "MESH" and obj.data is not None and obj not in seen:
                seen.append(obj)
        self.objects = [_ObjectState(obj) for obj in seen]
        self.actions = set(bpy.data.actions)

    def restore(self):
        """Puts every object back as it was; actions made since (and used by
        nothing now) are removed."""
        for state in self.objects:
            try:
                state.restore()
            except ReferenceError:
                pass  # the object itself is gone
        for action in [a for a in bpy.data.actions if a not in self.actions and a.users == 0]:
            bpy.data.actions.remove(action)
