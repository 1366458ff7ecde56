"""``meshmorph pick`` started on the two selected objects: both written as
triangle OBJ files in world space (vertices in Blender's order, triangles
as Blender splits the polygons, so the saved markers number them as the
add-on does), the page opened in the browser, and the marker file read back
each time the page saves it."""

import os
import shutil
import subprocess
import tempfile

from . import mesh_arrays
from .refusal import Refusal


def executable(configured):
    """The meshmorph command: the configured path, or `meshmorph` on PATH."""
    found = shutil.which(configured or "meshmorph")
    if found is None:
        raise Refusal(
            "Picking needs the meshmorph command: install it (cargo install --path "
            "crates/meshmorph-cli) or set its path in the add-on's preferences"
        )
    return found


def write_obj(obj, path):
    """`obj`'s rest shape in world space with its triangles, as OBJ."""
    v = mesh_arrays.to_world(obj, mesh_arrays.rest(obj))
    f = mesh_arrays.triangles(obj) + 1
    with open(path, "w") as out:
        out.write("# {} as meshmorph's Blender add-on hands it to meshmorph pick\n".format(obj.name))
        out.writelines("v {!r} {!r} {!r}\n".format(*p) for p in v.tolist())
        out.writelines("f {} {} {}\n".format(*t) for t in f.tolist())


def unused_path(folder, stem, extension):
    """`folder/stem.extension`, or with -2, -3, ... the first that does not
    exist: the markers are never saved over a file."""
    path = os.path.join(folder, stem + extension)
    k = 2
    while os.path.exists(path):
        path = os.path.join(folder, "{}-{}{}".format(stem, k, extension))
        k += 1
    return path


class Picking:
    """One running `meshmorph pick`: its process, its files, the markers."""

    def __init__(self, command, source, target, markers_path, start=(), open_browser=True):
        self.folder = tempfile.mkdtemp(prefix="meshmorph-pick-")
        try:
            self.markers_path = markers_path
            src = os.path.join(self.folder, "source.obj")
            tgt = os.path.join(self.folder, "target.obj")
            write_obj(source, src)
            write_obj(target, tgt)
            args = [command, "pick", src, tgt, "--output", markers_path] + (["--open"] if open_browser else [])
            for given in start:
                # The markers to start from (one file of pairs, or the two point
                # files), as they are: pick only reads them.
                args += ["--markers", given]
            self.saved = self._stamp()
            self.log = os.path.join(self.folder, "pick.log")
            with open(self.log, "w") as log:
                self.process = subprocess.Popen(args, stdout=log, stderr=subprocess.STDOUT)
        except BaseException:
            shutil.rmtree(self.folder, ignore_errors=True)
            raise

    def address(self):
        """The page's address once pick has printed it, else None."""
        try:
            with open(self.log) as log:
                for line in log:
                    if "http://127.0.0.1:" in line:
                        return line[line.index("http://") :].split()[0]
        except OSError:
            pass
        return None

    def _stamp(self):
        try:
            s = os.stat(self.markers_path)
            return (s.st_mtime_ns, s.st_size)
        except OSError:
            return None

    def newly_saved(self):
        """Whether the page saved the markers since the last call."""
        stamp = self._stamp()
        changed = stamp is not None and stamp != self.saved
        self.saved = stamp
        return changed

    def finished(self):
        """None while running; else the exit status and what it printed."""
        status = self.process.poll()
        if status is None:
            return None
        try:
            with open(self.log) as log:
                said = log.read().strip()
        except OSError:
            said = ""
        shutil.rmtree(self.folder, ignore_errors=True)
        return status, said

    def stop(self):
        if self.process.poll() is None:
            self.process.terminate()
            self.process.wait(timeout=10)
        shutil.rmtree(self.folder, ignore_errors=True)
