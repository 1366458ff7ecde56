"""Shape keys a second inside Blender: the horse's ten poses carried to the
camel by the add-on, against the command line on the same files.

    tools/blender-package
    blender -b --factory-startup --python blender/bench/horse_camel.py -- target/blender/meshmorph-*-legacy.zip

(run from the repository, with ../shared/data beside it and the command
line built: cargo build --release). Prints a table for BENCHMARKS.md."""

import os
import subprocess
import sys
import tempfile
import time

import addon_utils
import bpy

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
D = os.path.join(ROOT, "..", "shared", "data", "dt", "horse-camel")
CLI = os.path.join(ROOT, "target", "release", "meshmorph")
POSES = [os.path.join(D, "horse-poses", "horse-{:02d}.obj".format(i)) for i in range(1, 11)]
MARKERS = os.path.join(D, "markers", "horse-camel-107.cons")
SOURCE = os.path.join(D, "horse-poses", "horse-reference.obj")
TARGET = os.path.join(D, "camel-poses", "camel-reference.obj")

with tempfile.TemporaryDirectory() as user:
    os.environ["BLENDER_USER_SCRIPTS"] = user
    bpy.ops.preferences.addon_install(filepath=sys.argv[sys.argv.index("--") + 1], overwrite=True)
    addon_utils.enable("meshmorph_blender", default_set=True)
    import meshmorph

    def character(name, path):
        m = meshmorph.read_mesh(path)
        mesh = bpy.data.meshes.new(name)
        mesh.from_pydata(m.vertices.tolist(), [], m.faces.tolist())
        obj = bpy.data.objects.new(name, mesh)
        bpy.context.scene.collection.objects.link(obj)
        return obj

    horse, camel = character("horse", SOURCE), character("camel", TARGET)
    horse.shape_key_add(name="Basis")
    for p in POSES:
        key = horse.shape_key_add(name=os.path.basename(p)[:-4])
        key.data.foreach_set("co", meshmorph.read_mesh(p).vertices.astype("float32").ravel())
    for o in bpy.context.view_layer.objects:
        o.select_set(o in (horse, camel))
    bpy.context.view_layer.objects.active = camel
    s = bpy.context.scene.meshmorph
    s.marker_source, s.marker_file = "FILE", MARKERS

    def timed(run, repeat=3):
        best = float("inf")
        for _ in range(repeat):
            start = time.perf_counter()
            run()
            best = min(best, time.perf_counter() - start)
        return best

    def fit_and_transfer():
        s.refit = True
        assert bpy.ops.meshmorph.transfer_shape_keys() == {"FINISHED"}

    def transfer_only():
        s.refit = False
        assert bpy.ops.meshmorph.transfer_shape_keys() == {"FINISHED"}

    blender_fit = timed(fit_and_transfer)
    blender_keys = timed(transfer_only)

    # The same work on arrays, the package alone: factoring and 10 poses.
    h, c = meshmorph.read_mesh(SOURCE), meshmorph.read_mesh(TARGET)
    poses = [meshmorph.read_mesh(p).vertices for p in POSES]
    import numpy as np

    poses = np.stack(poses)
    kept = meshmorph.correspond(h.vertices, h.faces, c.vertices, c.faces, meshmorph.read_markers(MARKERS))
    package_keys = timed(lambda: meshmorph.Transfer(h.vertices, h.faces, c.vertices, c.faces, kept).apply_all(poses))

    with tempfile.TemporaryDirectory() as out:
        corr = os.path.join(out, "horse-camel.corr")
        common = [CLI, "transfer", "--source-ref", SOURCE, "--target-ref", TARGET]
        n = [0]

        def cli(extra):
            n[0] += 1
            subprocess.run(common + extra + ["-o", os.path.join(out, str(n[0]))] + POSES, check=True, capture_output=True)

        cli_fit = timed(lambda: cli(["--markers", MARKERS]))
        subprocess.run([CLI, "correspond", "--source-ref", SOURCE, "--target-ref", TARGET, "--markers", MARKERS, "-o", corr], check=True, capture_output=True)
        cli_keys = timed(lambda: cli(["--correspondence", corr]))

print()
print("| horse -> camel, 10 poses (best of 3) | Blender add-on | command line |")
print("|---|---|---|")
print("| markers -> fit -> 10 shape keys | {:.2f} s | {:.2f} s |".format(blender_fit, cli_fit))
print("| kept correspondence -> 10 shape keys | {:.2f} s ({:.1f} keys/s) | {:.2f} s ({:.1f} poses/s) |".format(
    blender_keys, 10 / blender_keys, cli_keys, 10 / cli_keys))
print("| the Python package alone: factoring + 10 poses on arrays | {:.2f} s | |".format(package_keys))
