"""The correspondence kept in the .blend, on the target object, so that
shape keys added to the source later transfer without a new fit.

It is stored as the target's custom property ``meshmorph_correspondence``:
the source's name, a fingerprint of both meshes at rest (vertex positions
in their own space, and triangles) and one of the markers it was fitted
from, the fit report, and meshmorph's correspondence file,
base64-encoded (saved and reloaded with the .blend). A kept fit serves
while both meshes are unchanged and the markers are either unchanged or
not given at all; a changed mesh or changed markers fit anew.

The property is read here and nowhere else, and checked whole: one that is
not what the add-on keeps (another type, a field missing or of another
type, data that is not base64 or not a correspondence: a .blend from
elsewhere, or edited by hand) is refused with a sentence naming the object,
whether or not it would serve; Forget Kept Correspondence removes it.
"""

import base64
import binascii
import hashlib
import os
import tempfile

from .refusal import Refusal

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


def _damaged(target, what):
    return Refusal(
        "{}'s custom property {} is not a correspondence the add-on can read ({}): remove it with "
        "Forget Kept Correspondence in the meshmorph panel, then transfer again".format(target.name, PROPERTY, what)
    )


_FIELDS = {"source": True, "meshes": True, "markers": False, "report": False, "data": True}


def read(target):
    """What `target` keeps, as a dict of strings with the data decoded to
    bytes; None when it keeps nothing."""
    stored = target.get(PROPERTY)
    if stored is None:
        return None
    if not hasattr(stored, "to_dict"):
        raise _damaged(target, "it is of type {}, not a group of fields".format(type(stored).__name__))
    fields = stored.to_dict()
    for name, needed in _FIELDS.items():
        if name not in fields:
            if needed:
                raise _damaged(target, "it has no field \"{}\"".format(name))
        elif not isinstance(fields[name], str):
            raise _damaged(target, "its field \"{}\" is of type {}, not text".format(name, type(fields[name]).__name__))
    try:
        data = base64.b64decode(fields["data"].encode("ascii"), validate=True)
    except (binascii.Error, ValueError, UnicodeEncodeError):
        raise _damaged(target, "its field \"data\" is not base64") from None
    if not data:
        raise _damaged(target, "its field \"data\" is empty")
    return dict(fields, data=data)


def kept(meshmorph, target, source_name, meshes, markers):
    """The correspondence kept on `target` that serves `source_name` with
    these meshes and markers (None: no markers given), and its report; None
    when there is none that serves."""
    stored = read(target)
    if stored is None or stored["source"] != source_name or stored["meshes"] != meshes:
        return None
    if markers is not None and stored.get("markers") != markers:
        return None
    with tempfile.TemporaryDirectory() as folder:
        path = os.path.join(folder, "kept.corr")
        with open(path, "wb") as f:
            f.write(stored["data"])
        try:
            return meshmorph.Correspondence.load(path), stored.get("report", "")
        except (meshmorph.MeshmorphError, OSError, ValueError) as e:
            said = str(e).replace("`{}`, ".format(path), "").replace("`{}`".format(path), "the data").replace(path, "the data")
            raise _damaged(target, "its data is not a correspondence: {}".format(said)) from e


def describe(target):
    """One line on what `target` keeps, or None."""
    try:
        stored = read(target)
    except Refusal:
        return "Kept: something the add-on cannot read (meshmorph_correspondence). Forget it to transfer again"
    if stored is None:
        return None
    return "Kept: the fit from {}. {}".format(stored["source"], stored.get("report", ""))
