"""The ARKit expressions (the 52 blendshapes face trackers drive, those the
built-in template has) put on a head as shape keys, from 12 or more named
landmarks: a landmark file, vertex groups or empties parented to the head,
each named by its landmark (iBUG 300-W number 1 to 68, or an alias such as
noseTip, eyeOuterLeft, mouthCornerRight, chin; left and right the head's
own). The head's separate pieces (eyes, teeth, tongue in the same object)
move rigidly with the template's."""

from . import marker_sources, mesh_arrays
from .refusal import Missing, Refusal


def landmarks(meshmorph, obj, source, path, prefix):
    """The landmarks on `obj` in world space, `[(name, position)]`, from
    `source`: "FILE" (the file at `path`: positions in world space, vertex
    and triangle numbers the object's own), "GROUPS" (vertex groups named
    `prefix` + a landmark) or "EMPTIES" (empties parented to `obj`)."""
    if source == "FILE":
        if not path:
            raise Missing("Choose a landmark file for {} in the meshmorph panel".format(obj.name))
        world = mesh_arrays.to_world(obj, mesh_arrays.rest(obj))
        try:
            return meshmorph.read_landmarks(path, world, mesh_arrays.triangles(obj))
        except (meshmorph.MeshmorphError, OSError, ValueError) as e:
            raise Refusal("The landmarks of {} could not be read: {}".format(obj.name, e)) from e
    if source == "GROUPS":
        found = marker_sources.group_centres(obj, prefix)
        what = "vertex groups named \"{}…\" (with vertices in them)".format(prefix)
    else:
        found = marker_sources.empties(obj)
        what = "empties parented to it"
    if not found:
        raise Missing("No landmarks on {}: give it {}, each named by its landmark (chin, noseTip, 31, ...)".format(obj.name, what))
    return [(name, tuple(p)) for name, p in found.items()]


def add(meshmorph, obj, points, replace=False):
    """Adds the expressions to `obj` as shape keys (value 0); returns their
    names and the ARKit names the template lacks. A key of the same name
    is refused unless `replace`."""
    existing = set(mesh_arrays.key_names(obj))
    world = mesh_arrays.to_world(obj, mesh_arrays.rest(obj))
    faces = mesh_arrays.triangles(obj)
    if len(faces) == 0:
        raise Refusal("{} has no faces: select a head with faces".format(obj.name))
    try:
        out = meshmorph.expressions(world, faces, points)
    except meshmorph.MeshmorphError as e:
        raise Refusal("{}: {}".format(obj.name, e)) from e
    clash = [n for n in out["names"] if n in existing]
    if clash and not replace:
        raise Refusal(
            "{} already has shape keys named {}: rename or delete them, or tick Replace Keys".format(
                obj.name, ", ".join(clash[:5]) + (", ..." if len(clash) > 5 else "")
            )
        )
    mesh_arrays.room_for(obj, len(out["names"]))
    local = [
        mesh_arrays.storable(obj, name, world + delta) for name, delta in zip(out["names"], out["deltas"])
    ]
    for name, positions in zip(out["names"], local):
        mesh_arrays.store_key(obj, name, positions).value = 0.0
    return out["names"], out["missing"], out["warnings"]
