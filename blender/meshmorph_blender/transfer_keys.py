"""Shape keys carried from a source character to a target of any topology
(deformation transfer, Sumner and Popović 2004): one correspondence, fitted
from markers or reused from the target, then one solve per key."""

import os

import numpy as np

from . import kept_correspondence, mesh_arrays
from .file_source import FileSource
from .refusal import Missing, Refusal


def fit_report(c):
    """The fit in one line, as percentages of the target's diagonal and area."""
    if c.mean_distance is None:
        return "Fit figures are not kept in a loaded correspondence."
    return "Fit: mean distance {:.3f} %, 95 % within {:.3f} % of the target's diagonal; {:.2f} % of its area uncovered.".format(
        100 * c.mean_distance, 100 * c.distance_95, 100 * (c.uncovered_area or 0.0)
    )


def chosen_keys(source, target, wanted):
    """The source's keys to carry (a source object's shape keys, a source
    file's morph targets): all (`wanted` empty), or the key named `wanted`,
    or the names in `wanted`, comma-separated; each checked, and none named
    like the target's basis (which would move its rest shape)."""
    if isinstance(source, FileSource):
        names = source.key_names
        if not names:
            raise Refusal(
                "The mesh {} of {} has no morph targets: choose a rig with shape keys".format(source.gltf.mesh_name, source.name)
            )
    else:
        names = mesh_arrays.key_names(source)
    if not names:
        raise Refusal("{} has no shape keys besides its basis: select a source with shape keys".format(source.name))
    if not wanted.strip():
        chosen = names
    elif wanted.strip() in names:
        chosen = [wanted.strip()]
    else:
        chosen = [w.strip() for w in wanted.split(",") if w.strip()]
        for w in chosen:
            if w not in names:
                kind = "morph target" if isinstance(source, FileSource) else "shape key"
                raise Refusal("{} has no {} \"{}\"; it has: {}".format(source.name, kind, w, ", ".join(names)))
    keys = target.data.shape_keys
    basis = keys.reference_key.name if keys is not None else "Basis"
    if basis in chosen:
        raise Refusal(
            "{}'s key \"{}\" has the name of {}'s basis: rename one of them".format(source.name, basis, target.name)
        )
    return chosen


class Work:
    """A transfer's arrays, gathered from Blender on its main thread; `run`
    (which touches no Blender data, so it may run on another thread) does
    the fit and the solves; `store` writes the keys back, on the main
    thread again. The source is an object or a `FileSource`."""

    def __init__(self, meshmorph, source, target, names, markers, refit):
        self.meshmorph = meshmorph
        self.source, self.target, self.names = source, target, names
        from_file = isinstance(source, FileSource)
        self.fs = source.faces if from_file else mesh_arrays.triangles(source)
        self.ft = mesh_arrays.triangles(target)
        if len(self.fs) == 0 or len(self.ft) == 0:
            empty = source if len(self.fs) == 0 else target
            raise Refusal("{} has no faces: select meshes with faces".format(empty.name))
        target_rest = mesh_arrays.rest(target)
        self.vt = mesh_arrays.to_world(target, target_rest)
        if from_file:
            source_rest, self.vs, self.poses = source.rest, source.vertices, source.poses(names)
        else:
            source_rest = mesh_arrays.rest(source)
            self.vs = mesh_arrays.to_world(source, source_rest)
            self.poses = np.stack([mesh_arrays.to_world(source, mesh_arrays.key_positions(source, n)) for n in names])
        self.meshes = kept_correspondence.meshes_print(source_rest, self.fs, target_rest, self.ft)
        # Markers where there are some; a kept fit serves without them.
        try:
            self.markers = markers()
            self.markers_print = kept_correspondence.markers_print(self.markers)
        except Missing as missing:
            self.markers, self.markers_print, self.missing = None, None, missing
        # Read (and so checked) even for a new fit, which would replace it.
        found = kept_correspondence.kept(meshmorph, target, source.name, self.meshes, self.markers_print)
        if refit:
            found = None
        if found is None and self.markers is None:
            raise self.missing
        self.correspondence, self.report = found if found is not None else (None, None)
        self.reused = found is not None
        self.moved = None

    def run(self, progress=None):
        """The fit (unless a kept one serves) and every key's solve."""
        meshmorph = self.meshmorph
        try:
            if self.correspondence is None:
                step = (lambda d, t: progress("fit", d, t)) if progress else None
                self.correspondence = meshmorph.correspond(self.vs, self.fs, self.vt, self.ft, self.markers, progress=step)
                self.report = fit_report(self.correspondence)
            transfer = meshmorph.Transfer(self.vs, self.fs, self.vt, self.ft, self.correspondence)
            # In batches of one pose a core (each batch in parallel), with
            # progress between them.
            batch = max(2, os.cpu_count() or 2)
            n = len(self.names)
            self.moved = np.empty((n, len(self.vt), 3))
            for start in range(0, n, batch):
                transfer.apply_all(self.poses[start : start + batch], out=self.moved[start : start + batch])
                if progress:
                    progress("keys", min(start + batch, n), n)
        except meshmorph.MeshmorphError as e:
            raise Refusal("{} to {}: {}".format(self.source.name, self.target.name, e)) from e

    def store(self):
        """The keys written to the target, the fit kept; returns (the fit
        report, whether a kept correspondence served). Every key is checked
        before the first is written."""
        local = [mesh_arrays.storable(self.target, name, world) for name, world in zip(self.names, self.moved)]
        if not self.reused:
            kept_correspondence.keep(
                self.target, self.source.name, self.meshes, self.markers_print, self.correspondence, self.report
            )
        if isinstance(self.source, FileSource):
            # A glTF file's morph targets have no ranges and no relative keys.
            for name, positions in zip(self.names, local):
                mesh_arrays.store_key(self.target, name, positions)
            return self.report, self.reused
        given = self.source.data.shape_keys.key_blocks
        for name, positions in zip(self.names, local):
            block = mesh_arrays.store_key(self.target, name, positions)
            block.slider_min, block.slider_max = given[name].slider_min, given[name].slider_max
        # A key relative to another key stays relative to that key's copy.
        blocks = self.target.data.shape_keys.key_blocks
        for name in self.names:
            relative = given[name].relative_key.name
            if relative != self.source.data.shape_keys.reference_key.name and relative in blocks:
                blocks[name].relative_key = blocks[relative]
        return self.report, self.reused
