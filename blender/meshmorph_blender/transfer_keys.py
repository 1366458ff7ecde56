"""Shape keys carried from a source character to a target of any topology
(deformation transfer, Sumner and Popović 2004): one correspondence, fitted
from markers or reused from the target, then one solve per key."""

import os

import numpy as np

from . import kept_correspondence, mesh_arrays
from .refusal import Refusal


def fit_report(c):
    """The fit in one line, as percentages of the target's diagonal and area."""
    if c.mean_distance is None:
        return "Fit figures are not kept in a loaded correspondence."
    return "Fit: mean distance {:.3f} %, 95 % within {:.3f} % of the target's diagonal; {:.2f} % of its area uncovered.".format(
        100 * c.mean_distance, 100 * c.distance_95, 100 * (c.uncovered_area or 0.0)
    )


def chosen_keys(source, wanted):
    """The source's keys to carry: all (`wanted` empty) or the names in
    `wanted`, comma-separated, each checked."""
    names = mesh_arrays.key_names(source)
    if not names:
        raise Refusal("{} has no shape keys besides its basis: select a source with shape keys".format(source.name))
    if not wanted.strip():
        return names
    chosen = [w.strip() for w in wanted.split(",") if w.strip()]
    for w in chosen:
        if w not in names:
            raise Refusal("{} has no shape key \"{}\"; it has: {}".format(source.name, w, ", ".join(names)))
    return chosen


def transfer(meshmorph, source, target, names, markers, refit=False, progress=None):
    """Adds to `target` one shape key per name of `source`'s `names`, with
    the same names. `markers()` gives the markers when a fit is needed.
    Returns (the fit report, whether a kept correspondence was reused)."""
    fs, ft = mesh_arrays.triangles(source), mesh_arrays.triangles(target)
    if len(fs) == 0 or len(ft) == 0:
        empty = source if len(fs) == 0 else target
        raise Refusal("{} has no faces: select meshes with faces".format(empty.name))
    vs = mesh_arrays.to_world(source, mesh_arrays.rest(source))
    vt = mesh_arrays.to_world(target, mesh_arrays.rest(target))
    print_ = kept_correspondence.fingerprint(fs, len(vs), ft, len(vt))
    found = None if refit else kept_correspondence.kept(meshmorph, target, source.name, print_)
    step = (lambda d, t: progress("fit", d, t)) if progress else None
    try:
        if found is None:
            correspondence = meshmorph.correspond(vs, fs, vt, ft, markers(), progress=step)
            report = fit_report(correspondence)
            kept_correspondence.keep(target, source.name, print_, correspondence, report)
        else:
            correspondence, report = found
        poses = np.stack([mesh_arrays.to_world(source, mesh_arrays.key_positions(source, n)) for n in names])
        transfer = meshmorph.Transfer(vs, fs, vt, ft, correspondence)
        # In batches of one pose a core (each batch in parallel), so that
        # progress is shown from Blender's main thread between them: the
        # package calls a progress callback from its worker threads, where
        # Blender's API must not be touched.
        batch = max(2, os.cpu_count() or 2)
        moved = np.empty((len(names), len(vt), 3))
        for start in range(0, len(names), batch):
            transfer.apply_all(poses[start : start + batch], out=moved[start : start + batch])
            if progress:
                progress("keys", min(start + batch, len(names)), len(names))
    except meshmorph.MeshmorphError as e:
        raise Refusal(str(e)) from e
    for name, world in zip(names, moved):
        block = mesh_arrays.store_key(target, name, mesh_arrays.to_object(target, world))
        given = source.data.shape_keys.key_blocks[name]
        block.slider_min, block.slider_max = given.slider_min, given.slider_max
    return report, found is not None
