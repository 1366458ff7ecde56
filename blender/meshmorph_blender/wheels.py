"""The bundled wheels made importable.

Blender 4.2 and later install an extension's wheels themselves (the
manifest lists them). The legacy add-on for older versions carries the same
wheels in ``wheels/`` beside this file; the first time meshmorph is
needed they are unpacked into ``site-packages/`` beside it (a wheel is a
zip, and a compiled module cannot be imported from a zip) and that folder
is put at the end of ``sys.path``.
"""

import os
import sys
import zipfile

HERE = os.path.dirname(os.path.abspath(__file__))
WHEELS = os.path.join(HERE, "wheels")
SITE = os.path.join(HERE, "site-packages")


def bundled():
    """The wheel files carried beside the add-on, sorted."""
    if not os.path.isdir(WHEELS):
        return []
    return sorted(f for f in os.listdir(WHEELS) if f.endswith(".whl"))


def _unpack(names):
    """Unpacks `names` into a fresh folder of its own, then puts it in place,
    so that a failure leaves no half-unpacked site-packages behind; when
    another Blender started at the same time got there first, its folder
    serves."""
    import tempfile

    partial = tempfile.mkdtemp(prefix="site-packages.", dir=HERE)
    try:
        for name in names:
            with zipfile.ZipFile(os.path.join(WHEELS, name)) as wheel:
                wheel.extractall(partial)
        with open(os.path.join(partial, "UNPACKED"), "w") as marker:
            marker.write("\n".join(names) + "\n")
        if os.path.isdir(SITE) and _unpacked() != names:
            _remove(SITE)
        if not os.path.isdir(SITE):
            os.replace(partial, SITE)
    except OSError:
        if _unpacked() != names:
            raise
    finally:
        if os.path.isdir(partial):
            _remove(partial)


def _remove(folder):
    import shutil

    shutil.rmtree(folder, ignore_errors=True)


def _unpacked():
    try:
        with open(os.path.join(SITE, "UNPACKED")) as marker:
            return marker.read().split()
    except OSError:
        return None


def load():
    """Imports and returns the meshmorph package, unpacking the bundled
    wheels first when they are not importable yet. Raises ImportError with
    a sentence for the user when that fails."""
    try:
        import meshmorph  # installed: by Blender from the extension's wheels, or by pip

        return meshmorph
    except ImportError:
        pass
    names = bundled()
    if names and _unpacked() != names:
        try:
            _unpack(names)
        except (OSError, zipfile.BadZipFile) as e:
            raise ImportError(
                "the wheels bundled with the add-on could not be unpacked beside it ({}); "
                "reinstall the add-on from its release zip".format(e)
            ) from e
    if names and SITE not in sys.path:
        # After Blender's own folders: a numpy that Blender ships is kept,
        # the bundled one serves where there is none.
        sys.path.append(SITE)
    try:
        import meshmorph
    except ImportError as e:
        raise ImportError(
            "meshmorph's Python package could not be loaded ({}); install the add-on "
            "from its release zip, which carries the package for this Blender".format(e)
        ) from e
    return meshmorph
