"""A source rig read from a glTF file (.glb, .gltf, .vrm) instead of a
source object: its rest shape and its morph targets, read with
``meshmorph.read_gltf`` and never imported into the scene.

The file's mesh is placed as Blender's glTF importer places it: by its
node's matrix in the file's scene, then glTF's Y up turned into Blender's Z
up, so that a marker file's positions and the target's world space agree
with what File > Import > glTF 2.0 would show. The copies of a vertex at
seams (glTF splits vertices at UV seams and between primitives) are welded
for the solve, as ``meshmorph transfer --source-ref`` welds them; a marker
file numbers the file's mesh as meshmorph reads it (every primitive's
vertices side by side, as ``meshmorph pick`` and ``meshmorph transfer``
number them)."""

import os

import numpy as np

from . import mesh_arrays
from .refusal import Refusal

# glTF's +Y up is Blender's +Z up: (x, y, z) becomes (x, -z, y).
Y_UP_TO_Z_UP = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]])


class FileSource:
    """The source of a transfer read from `path` (its mesh `mesh_name`, or
    the only one, or the largest): `name` (the path, for messages),
    `vertices` and `faces` (welded, in Blender's world space),
    `key_names` (its morph targets) and `poses(names)`."""

    def __init__(self, meshmorph, path, mesh_name=""):
        if not os.path.exists(path):
            raise Refusal("The source file {} does not exist: choose a .glb, .gltf or .vrm file".format(path))
        if not os.path.isfile(path):
            raise Refusal("The source file {} is not a regular file: choose a .glb, .gltf or .vrm file".format(path))
        self.name = path
        try:
            self.gltf = meshmorph.read_gltf(path, mesh_name.strip() or None)
        except (meshmorph.MeshmorphError, OSError, ValueError) as e:
            raise Refusal("The source file {} could not be read: {}".format(path, e)) from e
        m = self.gltf.transform
        self.matrix = Y_UP_TO_Z_UP @ m[:3, :3], Y_UP_TO_Z_UP @ m[:3, 3]
        vertices, self.faces, self.index = self.gltf.welded()
        if np.linalg.det(m[:3, :3]) < 0:
            self.faces = self.faces[:, ::-1].copy()  # mirrored by its node: turned over to face outwards
        if len(self.faces) == 0:
            raise Refusal("The mesh {} of {} has no triangles: choose another mesh".format(self.gltf.mesh_name, path))
        self.rest = vertices
        self.vertices = self.placed(vertices)
        self.file_vertices = self.placed(self.gltf.vertices)
        self.file_faces = self.gltf.faces
        # The first copy of each welded vertex.
        self.first = np.unique(self.index, return_index=True)[1]
        self.key_names = list(self.gltf.targets)

    def placed(self, positions):
        """The mesh's own positions `(n, 3)` in Blender's world space."""
        rotation, shift = self.matrix
        return positions @ rotation.T + shift

    def poses(self, names):
        """The morph targets `names` as positions of the welded mesh in
        Blender's world space, `(k, n, 3)`."""
        targets = self.gltf.targets
        return np.stack([self.placed(targets[n])[self.first] for n in names])

    def point(self, side, markers):
        """A marker's source side as a position in world space."""
        if "position" in side:
            return np.asarray(side["position"], dtype=np.float64)
        if "vertex" in side:
            v = side["vertex"]
            if not 0 <= v < len(self.file_vertices):
                raise Refusal(
                    "The marker file {} names vertex {} of the source, but the mesh {} of {} has {} vertices".format(
                        markers, v, self.gltf.mesh_name, self.name, len(self.file_vertices)
                    )
                )
            return self.file_vertices[v]
        t = side["triangle"]
        if not 0 <= t < len(self.file_faces):
            raise Refusal(
                "The marker file {} names triangle {} of the source, but the mesh {} of {} has {} triangles".format(
                    markers, t, self.gltf.mesh_name, self.name, len(self.file_faces)
                )
            )
        return np.asarray(side["barycentric"], dtype=np.float64) @ self.file_vertices[self.file_faces[t]]


def target_point(target, world, triangles, side, markers):
    """A marker's target side as a position in world space: `world` are the
    target's vertices there, `triangles` Blender's split of its polygons."""
    if "position" in side:
        return np.asarray(side["position"], dtype=np.float64)
    if "vertex" in side:
        v = side["vertex"]
        if not 0 <= v < len(world):
            raise Refusal("The marker file {} names vertex {} of {}, which has {}".format(markers, v, target.name, len(world)))
        return world[v]
    t = side["triangle"]
    if not 0 <= t < len(triangles):
        raise Refusal("The marker file {} names triangle {} of {}, which has {}".format(markers, t, target.name, len(triangles)))
    return np.asarray(side["barycentric"], dtype=np.float64) @ world[triangles[t]]


def markers(meshmorph, source, target, read, path):
    """The markers `read` from the marker file `path` between the file
    `source` and the object `target`, as positions in world space (so that
    they land on the welded mesh)."""
    world = mesh_arrays.to_world(target, mesh_arrays.rest(target))
    triangles = mesh_arrays.loop_triangles(target)
    pairs = read.pairs
    s = np.array([source.point(a, path) for a, _ in pairs])
    t = np.array([target_point(target, world, triangles, b, path) for _, b in pairs])
    try:
        return meshmorph.Markers.from_points(s, t, names=read.names)
    except (meshmorph.MeshmorphError, ValueError, TypeError) as e:
        raise Refusal("The markers of {} for {} and {} cannot be used: {}".format(path, source.name, target.name, e)) from e
