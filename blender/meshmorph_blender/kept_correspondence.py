"""The correspondence kept in the .blend, on the target object, so that
shape keys added to the source later transfer without a new fit.

It is stored as the target's custom property ``meshmorph_correspondence``:
the source's name, a fingerprint of both meshes at rest (vertex positions
in their own space, and triangles) and one of the markers it was fitted
from, the fit report, and meshmorph's correspondence file,
base64-encoded (saved and reloaded with the .blend). A kept fit serves
while both meshes are unchanged and the markers are either unchanged or
not given at all; a changed mesh or changed markers fit anew.
"""

import base64
import hashlib
import os
import tempfile

PROPERTY = "meshmorph_correspondence"


def meshes_print(source_rest, fs, target_rest, ft):
    """Names both meshes at rest: positions (as Blender stores them) and triangles."""
    h = hashlib.sha256()
    for rest, tris in ((source_rest, fs), (target_rest, ft)):
        h.update(rest.astype("<f4").tobytes())
        h.update(tris.astype("<i8").tobytes())
    return h.hexdigest()[:32]


def markers_print(markers):
    """Names a set of markers (their file as meshmorph writes it)."""
    with tempfile.TemporaryDirectory() as folder:
        path = os.path.join(folder, "markers.txt")
        markers.save(path)
        with open(path, "rb") as f:
            return hashlib.sha256(f.read()).hexdigest()[:32]


def keep(target, source_name, meshes, markers, correspondence, report):
    """Stores `correspondence` (with its report and fingerprints) on `target`."""
    with tempfile.TemporaryDirectory() as folder:
        path = os.path.join(folder, "kept.corr")
        correspondence.save(path)
        with open(path, "rb") as f:
            data = base64.b64encode(f.read()).decode("ascii")
    target[PROPERTY] = {
        "source": source_name,
        "meshes": meshes,
        "markers": markers,
        "report": report,
        "data": data,
    }


def kept(meshmorph, target, source_name, meshes, markers):
    """The correspondence kept on `target` that serves `source_name` with
    these meshes and markers (None: no markers given), and its report; None
    when there is none that serves."""
    stored = target.get(PROPERTY)
    if stored is None or stored.get("source") != source_name or stored.get("meshes") != meshes:
        return None
    if markers is not None and stored.get("markers") != markers:
        return None
    with tempfile.TemporaryDirectory() as folder:
        path = os.path.join(folder, "kept.corr")
        with open(path, "wb") as f:
            f.write(base64.b64decode(stored["data"]))
        try:
            return meshmorph.Correspondence.load(path), stored.get("report", "")
        except meshmorph.MeshmorphError:
            return None


def describe(target):
    """One line on what `target` keeps, or None."""
    stored = target.get(PROPERTY)
    if stored is None:
        return None
    return "Kept: the fit from {}. {}".format(stored.get("source"), stored.get("report", ""))
