"""Marker pairs from what an artist has in the scene: a marker file, vertex
groups of the same name on both objects, or empties parented to each
object and paired by name.

Vertex groups and empties become positions in world space, put on the
surfaces by the correspondence (a group of one vertex lands on that vertex;
a larger group on its weighted centre). A marker file's vertex and triangle
numbers are the objects' own (triangles as Blender splits the polygons,
which is how ``meshmorph pick`` from the panel numbers them) and its
positions are in world space.
"""

import os
import re

import numpy as np

from . import mesh_arrays
from .refusal import Missing, Refusal

DUPLICATE = re.compile(r"\.\d{3}$")


def from_file(meshmorph, source, target, path, target_path=""):
    """Markers for `source` and `target` read from `path` (meshmorph's
    marker file, or with `target_path` the source's and the target's point
    files)."""
    if not path:
        raise Missing("Choose a marker file in the meshmorph panel")
    for given in (path, target_path):
        if given and os.path.exists(given) and not os.path.isfile(given):
            raise Refusal("The marker file {} for {} and {} is not a regular file: choose a file".format(given, source.name, target.name))
    try:
        return meshmorph.read_markers(path, target_path or None)
    except (meshmorph.MeshmorphError, OSError, ValueError) as e:
        raise Refusal("The markers for {} and {} could not be read: {}".format(source.name, target.name, e)) from e


def group_centres(obj, prefix):
    """{name without prefix: world position} of the object's vertex groups
    whose names start with `prefix` (each its vertices' weighted centre)."""
    groups = {g.index: g.name[len(prefix):] for g in obj.vertex_groups if g.name.startswith(prefix)}
    if not groups:
        return {}
    world = mesh_arrays.to_world(obj, mesh_arrays.rest(obj))
    sums = {i: np.zeros(3) for i in groups}
    weights = {i: 0.0 for i in groups}
    for v in obj.data.vertices:
        for g in v.groups:
            if g.group in groups and g.weight > 0:
                sums[g.group] += g.weight * world[v.index]
                weights[g.group] += g.weight
    return {groups[i]: sums[i] / weights[i] for i in groups if weights[i] > 0}


def from_vertex_groups(meshmorph, source, target, prefix):
    """Markers from the vertex groups named `prefix` + a name on both
    objects, paired by that name."""
    s = group_centres(source, prefix)
    t = group_centres(target, prefix)
    return _paired(meshmorph, s, t, "vertex groups named \"{}…\" (with vertices in them)".format(prefix), source, target)


def empties(obj):
    """{name without Blender's .001 suffix: world position} of the empties
    parented to `obj`."""
    return {DUPLICATE.sub("", child.name): mesh_arrays.location(child) for child in obj.children if child.type == "EMPTY"}


def from_empties(meshmorph, source, target):
    """Markers from empties parented to each object, paired by name (the
    target's copy of "nose" may be "nose.001")."""
    return _paired(meshmorph, empties(source), empties(target), "empties parented to each object", source, target)


def _paired(meshmorph, s, t, what, source, target):
    names = [n for n in s if n in t]
    if not names:
        raise Missing("No markers: give {} and {} {} with the same names".format(source.name, target.name, what))
    try:
        return meshmorph.Markers.from_points(
            np.array([s[n] for n in names]), np.array([t[n] for n in names]), names=names
        )
    except (meshmorph.MeshmorphError, ValueError, TypeError) as e:
        raise Refusal("The markers on {} and {} ({}) cannot be used: {}".format(source.name, target.name, what, e)) from e
