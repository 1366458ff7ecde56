"""The correspondence kept in the .blend, on the target object, so that
shape keys added to the source later transfer without a new fit.

It is stored as the target's custom property ``meshmorph_correspondence``:
the source's name, a fingerprint of both meshes' vertex counts and
triangles (a changed mesh needs a new fit), the fit report, and meshmorph's
correspondence file, base64-encoded (saved and reloaded with the .blend).
"""

import base64
import hashlib
import os
import tempfile

PROPERTY = "meshmorph_correspondence"


def fingerprint(fs, nvs, ft, nvt):
    """Names both meshes' topology: vertex counts and triangles."""
    h = hashlib.sha256()
    for part in (fs, ft):
        h.update(part.astype("<i8").tobytes())
    return "{} {} {}".format(nvs, nvt, h.hexdigest()[:32])


def keep(target, source_name, print_, correspondence, report):
    """Stores `correspondence` (with its report) on `target`."""
    with tempfile.TemporaryDirectory() as folder:
        path = os.path.join(folder, "kept.corr")
        correspondence.save(path)
        with open(path, "rb") as f:
            data = base64.b64encode(f.read()).decode("ascii")
    target[PROPERTY] = {"source": source_name, "fingerprint": print_, "report": report, "data": data}


def kept(meshmorph, target, source_name, print_):
    """The correspondence kept on `target` for `source_name` with this
    fingerprint, and its report; None when there is none that fits."""
    stored = target.get(PROPERTY)
    if stored is None or stored.get("source") != source_name or stored.get("fingerprint") != print_:
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
