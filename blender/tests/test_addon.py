"""The add-on inside Blender, run in the background by tools/test:

    blender -b --factory-startup --python-exit-code 1 --python blender/tests/test_addon.py -- LEGACY_ZIP

or, for Blender 4.2 and later, with Blender as a Python module (pip's
`bpy==4.2.0` on CPython 3.11) and the extension zip:

    python blender/tests/test_addon.py -- target/blender/meshmorph-VERSION-linux-x64-extension.zip

It installs the add-on from its zip as a user would (into the user scripts
folder given by BLENDER_USER_SCRIPTS), then: shape keys carried from a quad
source to a target of other topology (with an n-gon) equal the Python
package's transfer of the same arrays; a key added later is carried with
the kept correspondence; a glTF rig's morph targets, read from a GLB file
(made by the Python package's tests' gltf_files.py), arrive as shape keys,
and a missing file, a file that is not glTF or a key it lacks are refused
naming it; a rigidly turned key gives rigid in-betweens and a
baked animation; the ARKit expressions put on a head from empties and from
a landmark file equal the Python package's; bad selections give their
sentence, not a traceback; the
target's polygons, UVs and materials are untouched; hostile scenes (NaN and
infinite positions and transforms, a damaged kept correspondence, bad
marker files, an error the add-on did not foresee) give one sentence naming
the object and leave the scene as it was."""

import http.client
import json
import math
import os
import sys
import time
import traceback

import bpy  # first: with Blender as a Python module (pip's bpy), it brings addon_utils
import addon_utils

ZIP = sys.argv[sys.argv.index("--") + 1]
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
CLI = os.environ.get("MESHMORPH_BIN", os.path.join(ROOT, "target", "release", "meshmorph"))

if ZIP.endswith("-extension.zip"):
    # Blender 4.2 and later: installed as an extension, its wheels by Blender.
    bpy.ops.extensions.package_install_files(filepath=ZIP, repo="user_default", enable_on_install=True)
    ADDON = "bl_ext.user_default.meshmorph"
else:
    bpy.ops.preferences.addon_install(filepath=ZIP, overwrite=True)
    addon_utils.enable("meshmorph_blender", default_set=True, handle_error=None)
    ADDON = "meshmorph_blender"
assert hasattr(bpy.ops.meshmorph, "transfer_shape_keys"), "the add-on did not register"
# Both put on the path by the add-on from its bundled wheels (Debian's
# Blender has no numpy of its own).
import meshmorph
import numpy as np


# ------------------------------------------------------------------ scene

def grid(name, n, m, size, bump, merge=False):
    """A bumpy n x m grid of quads (two of them merged into a hexagon when
    `merge`), as a mesh object with a UV map and a material."""
    xs, ys = np.linspace(-size, size, n + 1), np.linspace(-size * 0.8, size * 0.8, m + 1)
    verts = [(x, y, bump * (math.sin(1.7 * x) + math.cos(1.3 * y))) for y in ys for x in xs]
    at = lambda i, j: j * (n + 1) + i
    faces = [[at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)] for j in range(m) for i in range(n)]
    if merge:
        faces = faces[2:]
        faces.append([at(0, 0), at(1, 0), at(2, 0), at(2, 1), at(1, 1), at(0, 1)])
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(verts, [], faces)
    uv = mesh.uv_layers.new(name="UVMap")
    for loop in mesh.loops:
        x, y, _ = verts[loop.vertex_index]
        uv.data[loop.index].uv = (x / size, y / size)
    mesh.materials.append(bpy.data.materials.new(name + "-material"))
    obj = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(obj)
    return obj


def coordinates(items, n):
    flat = np.empty(3 * n, dtype=np.float32)
    items.foreach_get("co", flat)
    return flat.reshape(n, 3).astype(np.float64)


def world(obj, local):
    m = np.array(obj.matrix_world, dtype=np.float64)
    return local @ m[:3, :3].T + m[:3, 3]


def local(obj, positions):
    m = np.linalg.inv(np.array(obj.matrix_world, dtype=np.float64))
    return positions @ m[:3, :3].T + m[:3, 3]


def triangles(obj):
    """Blender's triangles, turned over for an object mirrored by its
    transform, so that they face outwards in world space."""
    obj.data.calc_loop_triangles()
    t = np.empty(3 * len(obj.data.loop_triangles), dtype=np.int64)
    obj.data.loop_triangles.foreach_get("vertices", t)
    t = t.reshape(-1, 3)
    return t[:, ::-1].copy() if np.linalg.det(np.array(obj.matrix_world)[:3, :3]) < 0 else t


def add_key(obj, name, positions):
    if obj.data.shape_keys is None:
        obj.shape_key_add(name="Basis", from_mix=False)
    k = obj.shape_key_add(name=name, from_mix=False)
    k.data.foreach_set("co", positions.astype(np.float32).ravel())


def key(obj, name):
    return coordinates(obj.data.shape_keys.key_blocks[name].data, len(obj.data.vertices))


def bend(v, angle):
    out = v.copy()
    a = angle * (v[:, 0] + 1.2) / 2.4
    out[:, 0] = np.cos(a) * v[:, 0] - np.sin(a) * v[:, 2]
    out[:, 2] = np.sin(a) * v[:, 0] + np.cos(a) * v[:, 2]
    return out


def twist(v, angle):
    out = v.copy()
    a = angle * v[:, 0] / 1.2
    out[:, 1] = np.cos(a) * v[:, 1] - np.sin(a) * v[:, 2]
    out[:, 2] = np.sin(a) * v[:, 1] + np.cos(a) * v[:, 2]
    return out


def select(*objects, active=None):
    for o in bpy.context.view_layer.objects:
        o.select_set(o in objects)
    bpy.context.view_layer.objects.active = active


MARKED = {"c0": (0, 0), "c1": (1, 0), "c2": (1, 1), "c3": (0, 1), "mid": (0.5, 0.5), "q": (0.25, 0.75)}


def mark(obj, n, m):
    for name, (u, w) in MARKED.items():
        g = obj.vertex_groups.new(name="marker." + name)
        g.add([round(w * m) * (n + 1) + round(u * n)], 1.0, "REPLACE")


def characters():
    source = grid("Source", 8, 6, 1.2, 0.1)
    source.location, source.rotation_euler, source.scale = (0.5, -2, 0.3), (0.3, 0.1, 0.7), (1.5, 1.5, 1.5)
    v = coordinates(source.data.vertices, len(source.data.vertices))
    add_key(source, "bend", bend(v, 1.2))
    add_key(source, "twist", twist(v, 0.9))
    add_key(source, "bulge", v + np.array([0, 0, 0.3]) * np.exp(-4 * (v[:, :1] ** 2 + v[:, 1:2] ** 2)))
    target = grid("Target", 13, 9, 1.5, 0.07, merge=True)
    target.location, target.rotation_euler, target.scale = (3, 1, 0), (0, 0, -0.4), (1.0, 0.8, 1.2)
    mark(source, 8, 6)
    mark(target, 13, 9)
    bpy.context.view_layer.update()
    return source, target


def expected(source, target, names):
    """The Python package's transfer of the same arrays, in the target's
    space, as Blender stores it (32-bit floats)."""
    vs = world(source, coordinates(source.data.vertices, len(source.data.vertices)))
    vt = world(target, coordinates(target.data.vertices, len(target.data.vertices)))
    fs, ft = triangles(source), triangles(target)

    def group_points(obj, v):
        out = []
        for name in MARKED:
            g = obj.vertex_groups["marker." + name].index
            out.append(next(v[x.index] for x in obj.data.vertices if any(e.group == g for e in x.groups)))
        return np.array(out)

    markers = meshmorph.Markers.from_points(group_points(source, vs), group_points(target, vt))
    c = meshmorph.correspond(vs, fs, vt, ft, markers)
    poses = np.stack([world(source, key(source, n)) for n in names])
    return local(target, meshmorph.Transfer(vs, fs, vt, ft, c).apply_all(poses)).astype(np.float32)


def diagonal(v):
    return float(np.linalg.norm(v.max(0) - v.min(0)))


def error_of(operator, **kw):
    """The error an operator reports (bpy.ops raises it as RuntimeError)."""
    try:
        operator(**kw)
    except RuntimeError as e:
        return str(e)
    return None


# ------------------------------------------------------------------ tests

def test_transfer_equals_the_python_packages_and_a_later_key_reuses_the_fit():
    source, target = characters()
    polygons = [tuple(p.vertices) for p in target.data.polygons]
    uvs = np.empty(2 * len(target.data.loops), dtype=np.float32)
    target.data.uv_layers[0].data.foreach_get("uv", uvs)
    s = bpy.context.scene.meshmorph
    s.marker_source, s.group_prefix = "GROUPS", "marker."
    select(source, target, active=target)
    assert bpy.ops.meshmorph.transfer_shape_keys() == {"FINISHED"}
    names = [k.name for k in target.data.shape_keys.key_blocks]
    assert names == ["Basis", "bend", "twist", "bulge"], names
    want = expected(source, target, ["bend", "twist", "bulge"])
    d = diagonal(coordinates(target.data.vertices, len(target.data.vertices)))
    worst = max(float(np.abs(key(target, n) - w).max()) for n, w in zip(["bend", "twist", "bulge"], want))
    print("  largest difference from the Python package: {:.3g} of the diagonal".format(worst / d))
    assert worst <= 1e-9 * d, worst / d
    moved = max(float(np.abs(key(target, n) - key(target, "Basis")).max()) for n in ["bend", "twist", "bulge"])
    assert moved > 0.05 * d, "the keys barely move the target"
    assert [tuple(p.vertices) for p in target.data.polygons] == polygons
    after = np.empty_like(uvs)
    target.data.uv_layers[0].data.foreach_get("uv", after)
    assert np.array_equal(after, uvs) and target.data.materials[0].name == "Target-material"
    assert "meshmorph_correspondence" in target

    v = coordinates(source.data.vertices, len(source.data.vertices))
    add_key(source, "later", bend(twist(v, -0.5), -0.8))
    for g in list(source.vertex_groups):
        source.vertex_groups.remove(g)  # no markers now: only the kept fit can serve
    s.keys = "later"
    assert bpy.ops.meshmorph.transfer_shape_keys() == {"FINISHED"}
    s.keys = ""
    mark(source, 8, 6)
    assert np.abs(key(target, "later") - expected(source, target, ["later"])[0]).max() <= 1e-9 * d
    assert [k.name for k in target.data.shape_keys.key_blocks][-1] == "later"


def vertex_of_group(obj, name):
    g = obj.vertex_groups["marker." + name].index
    return next(v.index for v in obj.data.vertices if any(e.group == g for e in v.groups))


def test_markers_from_empties_and_from_a_marker_file_give_the_same_keys():
    source, target = bpy.data.objects["Source"], bpy.data.objects["Target"]
    want = {n: key(target, n) for n in ("bend", "twist", "bulge")}
    d = diagonal(want["bend"])
    for obj, suffix in ((source, ""), (target, ".001")):
        vs = world(obj, coordinates(obj.data.vertices, len(obj.data.vertices)))
        for name in MARKED:
            empty = bpy.data.objects.new(name + suffix, None)
            bpy.context.scene.collection.objects.link(empty)
            empty.parent = obj
            empty.matrix_world.translation = vs[vertex_of_group(obj, name)].tolist()
    bpy.context.view_layer.update()
    s = bpy.context.scene.meshmorph
    s.marker_source, s.keys, s.refit = "EMPTIES", "bend,twist,bulge", True
    select(source, target, active=target)
    assert bpy.ops.meshmorph.transfer_shape_keys() == {"FINISHED"}
    for n, w in want.items():
        assert np.abs(key(target, n) - w).max() <= 1e-6 * d, n  # empties hold 32-bit positions
    for obj in (source, target):
        for child in list(obj.children):
            bpy.data.objects.remove(child)

    path = os.path.join(bpy.app.tempdir, "pairs.cons")
    with open(path, "w") as f:
        f.write("{}\n".format(len(MARKED)))
        f.writelines("{}, {}\n".format(vertex_of_group(source, n), vertex_of_group(target, n)) for n in MARKED)
    s.marker_source, s.marker_file = "FILE", path
    assert bpy.ops.meshmorph.transfer_shape_keys() == {"FINISHED"}
    for n, w in want.items():
        assert np.abs(key(target, n) - w).max() <= 1e-9 * d, n
    s.keys, s.refit = "", False


def test_the_pick_button_runs_meshmorph_pick_and_reads_the_saved_markers_back():
    pick = __import__(ADDON + ".pick", fromlist=["pick"])

    if not os.path.exists(CLI):
        raise AssertionError("the meshmorph command is not built at {} (cargo build --release)".format(CLI))
    source, target = bpy.data.objects["Source"], bpy.data.objects["Target"]
    path = os.path.join(bpy.app.tempdir, "picked.txt")
    picking = pick.Picking(pick.executable(CLI), source, target, path, open_browser=False)
    try:
        for _ in range(300):
            address = picking.address()
            if address:
                break
            time.sleep(0.1)
        assert address, "pick printed no address"
        port, token = address[len("http://127.0.0.1:") :].rstrip("/").split("/")
        pairs = [{"name": n, "source": {"vertex": vertex_of_group(source, n)}, "target": {"vertex": vertex_of_group(target, n)}} for n in MARKED]

        def call(what, body):
            c = http.client.HTTPConnection("127.0.0.1", int(port), timeout=60)
            host = "127.0.0.1:" + port
            c.request("POST", "/{}/api/{}".format(token, what), json.dumps(body), {"Host": host, "Origin": "http://" + host, "Content-Type": "application/json"})
            r = c.getresponse()
            return r.status, r.read()

        assert not picking.newly_saved()
        assert call("save", {"pairs": pairs})[0] == 200
        assert picking.newly_saved() and not picking.newly_saved()
        assert call("done", {})[0] == 200
        for _ in range(300):
            ended = picking.finished()
            if ended is not None:
                break
            time.sleep(0.1)
        assert ended is not None and ended[0] == 0, ended
    finally:
        picking.stop()
    markers = meshmorph.read_markers(path)
    assert markers.names == list(MARKED)
    assert [(p[0]["vertex"], p[1]["vertex"]) for p in markers.pairs] == [(vertex_of_group(source, n), vertex_of_group(target, n)) for n in MARKED]


def transferred(keys):
    """Source and Target selected, their marker groups as markers, and
    `keys` transferred (with the kept fit where it serves)."""
    source, target = bpy.data.objects["Source"], bpy.data.objects["Target"]
    s = bpy.context.scene.meshmorph
    s.marker_source, s.keys, s.refit = "GROUPS", keys, False
    select(source, target, active=target)
    assert bpy.ops.meshmorph.transfer_shape_keys() == {"FINISHED"}
    return source, target, s


def test_a_changed_mesh_or_changed_markers_fit_anew_and_a_mirrored_target_works():
    source, target, s = transferred("bend")
    kept = dict(target["meshmorph_correspondence"])
    # The same markers and meshes: the kept fit serves.
    assert bpy.ops.meshmorph.transfer_shape_keys() == {"FINISHED"}
    assert dict(target["meshmorph_correspondence"]) == kept
    # Another marker: a new fit.
    g = source.vertex_groups.new(name="marker.extra")
    g.add([30], 1.0, "REPLACE")
    t = target.vertex_groups.new(name="marker.extra")
    t.add([60], 1.0, "REPLACE")
    assert bpy.ops.meshmorph.transfer_shape_keys() == {"FINISHED"}
    assert target["meshmorph_correspondence"]["markers"] != kept["markers"]
    source.vertex_groups.remove(g)
    target.vertex_groups.remove(t)
    # A re-sculpted target basis: a new fit.
    basis = target.data.shape_keys.reference_key
    basis.data[5].co.z += 0.05
    target.data.vertices[5].co.z += 0.05
    assert bpy.ops.meshmorph.transfer_shape_keys() == {"FINISHED"}
    assert target["meshmorph_correspondence"]["meshes"] != kept["meshes"]
    # A target mirrored by its transform: its triangles are turned over, and
    # the keys are the package's transfer onto the mirrored surface.
    target.scale = (-1.0, 0.8, 1.2)
    bpy.context.view_layer.update()
    assert bpy.ops.meshmorph.transfer_shape_keys() == {"FINISHED"}
    d = diagonal(key(target, "Basis"))
    assert np.abs(key(target, "bend") - expected(source, target, ["bend"])[0]).max() <= 1e-9 * d
    target.scale = (1.0, 0.8, 1.2)
    bpy.context.view_layer.update()
    s.keys = ""


def test_pick_never_saves_over_a_file():
    pick = __import__(ADDON + ".pick", fromlist=["pick"])
    folder = bpy.app.tempdir
    first = pick.unused_path(folder, "a-to-b.markers", ".txt")
    open(first, "w").close()
    second = pick.unused_path(folder, "a-to-b.markers", ".txt")
    assert second != first and second.endswith("a-to-b.markers-2.txt") and not os.path.exists(second)


def rigid_residual(a, b):
    """How far `b` is from a rigid motion of `a` (largest distance after the
    best rotation and translation), and the rotation's angle."""
    ca, cb = a - a.mean(0), b - b.mean(0)
    u, _, vt = np.linalg.svd(ca.T @ cb)
    r = (u @ vt).T
    if np.linalg.det(r) < 0:
        vt[-1] *= -1
        r = (u @ vt).T
    residual = float(np.linalg.norm(ca @ r.T - cb, axis=1).max())
    return residual, math.degrees(math.acos(max(-1.0, min(1.0, (np.trace(r) - 1) / 2))))


def test_a_rigidly_turned_key_gives_rigid_inbetweens_and_a_rigid_baked_animation():
    obj = grid("Turning", 10, 10, 1.0, 0.15)
    obj.location, obj.scale = (0, 4, 0), (2.0, 2.0, 2.0)
    v = coordinates(obj.data.vertices, len(obj.data.vertices))
    c, s = math.cos(math.radians(120)), math.sin(math.radians(120))
    add_key(obj, "turned", v @ np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]]).T + [0.3, 0, 0.1])
    bpy.context.view_layer.update()
    select(obj, active=obj)
    settings = bpy.context.scene.meshmorph
    settings.inbetween_from, settings.inbetween_to, settings.inbetween_count = "", "turned", 3
    assert bpy.ops.meshmorph.add_inbetweens() == {"FINISHED"}
    d = diagonal(v)
    for t in (0.25, 0.5, 0.75):
        name = "turned {:g} %".format(100 * t)
        residual, angle = rigid_residual(v, key(obj, name))
        print("  in-between at {:.2f}: {:.3g} of the diagonal from rigid, turned {:.4f} deg".format(t, residual / d, angle))
        assert residual < 1e-6 * d and abs(angle - 120 * t) < 1e-3, (residual, angle)
        linear = v + t * (key(obj, "turned") - v)
        assert rigid_residual(v, linear)[0] > 0.1 * d  # what Blender's own mix does

    bpy.context.scene.frame_set(10)
    settings.bake_keys, settings.frames_per_key = "Basis, turned", 4
    assert bpy.ops.meshmorph.bake_animation() == {"FINISHED"}
    baked = ["ARAP {:04d}".format(i) for i in range(5)]
    blocks = obj.data.shape_keys.key_blocks
    assert all(b in blocks for b in baked)
    for i, b in enumerate(baked):
        residual, angle = rigid_residual(v, key(obj, b))
        assert residual < 1e-6 * d and abs(angle - 30 * i) < 1e-3, (b, residual, angle)
        curve = obj.data.shape_keys.animation_data.action.fcurves.find('key_blocks["{}"].value'.format(b))
        assert curve.evaluate(10 + i) == 1.0 and curve.evaluate(11 + i) == 0.0 and curve.evaluate(9 + i) == 0.0
    # Baked again, with fewer frames: the earlier bake is replaced, not added to.
    settings.frames_per_key = 2
    assert bpy.ops.meshmorph.bake_animation() == {"FINISHED"}
    assert sorted(b.name for b in obj.data.shape_keys.key_blocks if b.name.startswith("ARAP ")) == ["ARAP 0000", "ARAP 0001", "ARAP 0002"]
    curves = [c.data_path for c in obj.data.shape_keys.animation_data.action.fcurves]
    assert len(curves) == 3, curves
    settings.frames_per_key = 4
    assert bpy.ops.meshmorph.bake_animation() == {"FINISHED"}

    # glTF exports the baked keys as morph targets with animated weights.
    addon_utils.enable("io_scene_gltf2", default_set=True)
    path = os.path.join(bpy.app.tempdir, "baked.glb")
    select(obj, active=obj)
    bpy.ops.export_scene.gltf(filepath=path, use_selection=True, export_morph=True, export_animations=True)
    with open(path, "rb") as f:
        glb = f.read()
    length = int.from_bytes(glb[12:16], "little")
    document = json.loads(glb[20 : 20 + length])
    mesh = document["meshes"][0]
    assert all(b in mesh["extras"]["targetNames"] for b in baked), mesh.get("extras")
    assert len(mesh["primitives"][0]["targets"]) == len(mesh["extras"]["targetNames"])
    channels = [c["target"]["path"] for a in document["animations"] for c in a["channels"]]
    assert "weights" in channels, channels


def test_bad_selections_give_a_sentence_not_a_traceback():
    source, target = bpy.data.objects["Source"], bpy.data.objects["Target"]
    plain = bpy.data.objects.new("Plain", bpy.data.meshes.new("Plain"))
    bpy.context.scene.collection.objects.link(plain)
    cases = [
        (bpy.ops.meshmorph.transfer_shape_keys, (), None, "Select two meshes: first the source"),
        (bpy.ops.meshmorph.transfer_shape_keys, (target,), target, "Select two meshes: first the source"),
        (bpy.ops.meshmorph.transfer_shape_keys, (plain, target), target, "Plain has no shape keys besides its basis"),
        (bpy.ops.meshmorph.add_inbetweens, (plain,), plain, "Select a mesh with shape keys"),
        (bpy.ops.meshmorph.bake_animation, (plain,), plain, "Select a mesh with shape keys"),
    ]
    for operator, chosen, active, sentence in cases:
        select(*chosen, active=active)
        said = error_of(operator)
        assert said is not None and sentence in said and "Traceback" not in said, said
    twin = bpy.data.objects.new("Twin", source.data)
    bpy.context.scene.collection.objects.link(twin)
    select(source, twin, active=twin)
    assert "Source and Twin share one mesh" in error_of(bpy.ops.meshmorph.transfer_shape_keys)
    settings = bpy.context.scene.meshmorph
    select(source, plain, active=plain)
    plain.data.from_pydata([(0, 0, 0), (1, 0, 0), (0, 1, 0)], [], [(0, 1, 2)])
    source.data.shape_keys.key_blocks["bulge"].name = "Basis.001"
    settings.keys = "Basis.001"
    plain.shape_key_add(name="Basis.001")
    said = error_of(bpy.ops.meshmorph.transfer_shape_keys)
    assert "has the name of Plain's basis" in said, said
    source.data.shape_keys.key_blocks["Basis.001"].name = "bulge"
    select(source, target, active=target)
    settings.keys, settings.refit = "smile", False
    assert "Source has no shape key \"smile\"" in error_of(bpy.ops.meshmorph.transfer_shape_keys)
    settings.keys, settings.refit, settings.marker_source, settings.marker_file = "", True, "FILE", "/nonexistent/markers.txt"
    said = error_of(bpy.ops.meshmorph.transfer_shape_keys)
    assert "/nonexistent/markers.txt" in said and "Traceback" not in said, said
    settings.marker_source = "EMPTIES"
    said = error_of(bpy.ops.meshmorph.transfer_shape_keys)
    assert "No markers: give Source and Target empties parented to each object" in said, said
    select(bpy.data.objects["Turning"], active=bpy.data.objects["Turning"])
    settings.inbetween_to = "nothing"
    assert "Turning has no shape key \"nothing\"" in error_of(bpy.ops.meshmorph.add_inbetweens)
    settings.inbetween_to = "turned"
    bpy.ops.object.mode_set(mode="EDIT")
    assert "Go back to Object Mode on Turning first" in error_of(bpy.ops.meshmorph.add_inbetweens)
    bpy.ops.object.mode_set(mode="OBJECT")
    select(source, target, active=target)
    settings.marker_source, settings.refit = "GROUPS", False
    scale = target.scale.copy()
    target.scale = (1, 0, 1)
    bpy.context.view_layer.update()
    assert "Target is scaled to nothing along an axis" in error_of(bpy.ops.meshmorph.transfer_shape_keys)
    target.scale = scale


# ------------------------------------------------------------------ hostile scenes

def addon_module(name):
    return __import__(ADDON + "." + name, fromlist=[name])


def scene_state(*objects):
    """What the operators could change on `objects`: shape keys (names,
    points, values, ranges, relative keys), their F-curves, the kept
    correspondence, the mesh's vertices."""
    out = []
    for o in objects:
        keys = o.data.shape_keys
        blocks = None
        curves = None
        if keys is not None:
            blocks = [
                (b.name, key(o, b.name).tobytes(), b.value, b.slider_min, b.slider_max, b.relative_key.name, b.mute)
                for b in keys.key_blocks
            ]
            action = keys.animation_data.action if keys.animation_data is not None else None
            if action is not None:
                curves = sorted(
                    (c.data_path, c.array_index, tuple((tuple(p.co), p.interpolation) for p in c.keyframe_points))
                    for c in action.fcurves
                )
        kept = o.get("meshmorph_correspondence")
        kept = kept.to_dict() if hasattr(kept, "to_dict") else kept.to_list() if hasattr(kept, "to_list") else kept
        vertices = coordinates(o.data.vertices, len(o.data.vertices)).tobytes()
        out.append((o.name, blocks, curves, kept, vertices))
    return out, len(bpy.data.actions)


def refused(operator, watched, *words):
    """Runs `operator` and checks that it refuses in one sentence (no
    traceback, one line) containing `words` (the object's name among them),
    and that `watched` objects are as they were."""
    before = scene_state(*watched)
    said = error_of(operator)
    assert said is not None, "no refusal: wanted {}".format(words)
    text = said.strip()
    if text.startswith("Error: "):
        text = text[len("Error: ") :]
    assert "Traceback" not in said and "\n" not in text and text, said
    for w in words:
        assert w in text, (w, said)
    assert scene_state(*watched) == before, "the scene changed: " + said
    return text


def set_points(items, positions):
    items.foreach_set("co", np.asarray(positions, dtype=np.float32).ravel())


def test_non_finite_positions_and_transforms_are_refused_naming_the_object():
    source, target = bpy.data.objects["Source"], bpy.data.objects["Target"]
    s = bpy.context.scene.meshmorph
    s.marker_source, s.group_prefix, s.keys, s.refit = "GROUPS", "marker.", "", True
    select(source, target, active=target)
    both = (source, target)
    nan, inf = float("nan"), float("inf")

    # NaN at a marker vertex group's vertex (in the basis and the mesh).
    i = vertex_of_group(source, "mid")
    basis = source.data.shape_keys.reference_key
    rest = key(source, basis.name)
    bad = rest.copy()
    bad[i] = (nan, 0.0, 0.0)
    set_points(basis.data, bad)
    refused(bpy.ops.meshmorph.transfer_shape_keys, both, "Source", "not a finite number", "vertex {}".format(i))
    set_points(basis.data, rest)
    # NaN and infinite in a source key, and in the target's basis.
    bent = key(source, "bend")
    bad = bent.copy()
    bad[3, 2] = inf
    set_points(source.data.shape_keys.key_blocks["bend"].data, bad)
    refused(bpy.ops.meshmorph.transfer_shape_keys, both, "Source", 'shape key "bend"', "vertex 3")
    set_points(source.data.shape_keys.key_blocks["bend"].data, bent)
    target_rest = key(target, "Basis")
    bad = target_rest.copy()
    bad[vertex_of_group(target, "c2"), 1] = nan
    set_points(target.data.shape_keys.reference_key.data, bad)
    refused(bpy.ops.meshmorph.transfer_shape_keys, both, "Target", 'basis "Basis"', "not a finite number")
    set_points(target.data.shape_keys.reference_key.data, target_rest)
    # A mesh without shape keys: its vertices are read.
    bare = grid("Bare", 3, 3, 1.0, 0.0)
    bare.data.vertices[1].co = (0.0, nan, 0.0)
    select(source, bare, active=bare)
    refused(bpy.ops.meshmorph.transfer_shape_keys, (source, bare), "Bare's mesh", "vertex 1")
    bpy.data.objects.remove(bare)

    # A scale, location or rotation of NaN or infinity, on the object or a parent.
    select(source, target, active=target)
    for obj in both:
        for attribute, value, words in (
            ("scale", (nan, 1.0, 1.0), (obj.name + "'s transform is not a finite number",)),
            ("location", (0.0, nan, 0.0), (obj.name + "'s transform is not a finite number",)),
            ("rotation_euler", (0.0, 0.0, nan), (obj.name + "'s transform is not a finite number",)),
            ("location", (0.0, inf, 0.0), (obj.name,)),  # Blender keeps it as the largest float32
        ):
            kept = tuple(getattr(obj, attribute))
            setattr(obj, attribute, value)
            bpy.context.view_layer.update()
            refused(bpy.ops.meshmorph.transfer_shape_keys, both, *words)
            setattr(obj, attribute, kept)
            bpy.context.view_layer.update()
    holder = bpy.data.objects.new("Holder", None)
    bpy.context.scene.collection.objects.link(holder)
    placed = [tuple(getattr(target, a)) for a in ("location", "rotation_euler", "scale")]
    target.parent = holder
    holder.scale = (1.0, nan, 1.0)
    bpy.context.view_layer.update()
    refused(bpy.ops.meshmorph.transfer_shape_keys, both, "Target's transform is not a finite number")
    target.parent = None
    target.location, target.rotation_euler, target.scale = placed
    bpy.data.objects.remove(holder)
    bpy.context.view_layer.update()

    # In-betweens and a bake: a NaN scale, and an infinite key.
    turning = bpy.data.objects["Turning"]
    select(turning, active=turning)
    s.inbetween_from, s.inbetween_to, s.inbetween_count, s.bake_keys = "", "turned", 3, "Basis, turned"
    turning.scale = (2.0, 2.0, nan)
    bpy.context.view_layer.update()
    for operator in (bpy.ops.meshmorph.add_inbetweens, bpy.ops.meshmorph.bake_animation):
        refused(operator, (turning,), "Turning's transform is not a finite number")
    turning.scale = (2.0, 2.0, 2.0)
    bpy.context.view_layer.update()
    turned = key(turning, "turned")
    bad = turned.copy()
    bad[7, 0] = -inf
    set_points(turning.data.shape_keys.key_blocks["turned"].data, bad)
    for operator in (bpy.ops.meshmorph.add_inbetweens, bpy.ops.meshmorph.bake_animation):
        refused(operator, (turning,), "Turning", 'shape key "turned"', "vertex 7")
    set_points(turning.data.shape_keys.key_blocks["turned"].data, turned)

    # Empties at a NaN location.
    select(source, target, active=target)
    for obj, suffix in ((source, ""), (target, ".001")):
        for name in MARKED:
            empty = bpy.data.objects.new(name + suffix, None)
            bpy.context.scene.collection.objects.link(empty)
            empty.parent = obj
    source.children[0].location = (nan, 0.0, 0.0)
    bpy.context.view_layer.update()
    s.marker_source = "EMPTIES"
    said = refused(bpy.ops.meshmorph.transfer_shape_keys, both, "parented to Source", "not at a finite location")
    assert source.children[0].name in said, said
    # Not even a kept fit serves when the markers given are damaged.
    s.refit = False
    refused(bpy.ops.meshmorph.transfer_shape_keys, both, "parented to Source", "not at a finite location")
    for obj in both:
        for child in list(obj.children):
            bpy.data.objects.remove(child)

    # A result that Blender's 32-bit floats cannot hold is refused before it is written.
    mesh_arrays = addon_module("mesh_arrays")
    try:
        mesh_arrays.storable(target, "huge", np.full((len(target.data.vertices), 3), 1e300))
        raise AssertionError("a result beyond float32 was not refused")
    except addon_module("refusal").Refusal as e:
        assert "Target's shape key \"huge\" would not be a finite number" in str(e), e
    transferred("")  # all put back: it works again


def test_a_damaged_kept_correspondence_is_refused_naming_the_object():
    source, target, s = transferred("bend")
    good = target["meshmorph_correspondence"].to_dict()
    import base64

    damaged = [
        "a string from another tool",
        42,
        2.5,
        [1, 2, 3],
        b"bytes",
        {"unrelated": 1},
        dict(good, source=5),
        dict(good, meshes=[1, 2]),
        dict(good, report={"a": 1}),
        dict(good, data="!!! not base64 !!!"),
        dict(good, data=""),
        dict(good, data=base64.b64encode(b"not a correspondence file").decode("ascii")),
        dict(good, data=good["data"][: len(good["data"]) // 2 // 4 * 4]),
        dict(good, data=base64.b64encode(b"\x00" * 64).decode("ascii")),
    ]
    describe = addon_module("kept_correspondence").describe
    for value in damaged:
        target["meshmorph_correspondence"] = value
        for refit in (False, True):
            s.refit = refit
            refused(bpy.ops.meshmorph.transfer_shape_keys, (source, target), "Target's custom property meshmorph_correspondence", "Forget")
        assert describe(target).startswith("Kept: "), value  # the panel draws, whatever is kept
    # Forgetting it lets the transfer run again.
    select(source, target, active=target)
    assert bpy.ops.meshmorph.forget_correspondence() == {"FINISHED"}
    assert "meshmorph_correspondence" not in target and describe(target) is None
    s.refit = False
    assert bpy.ops.meshmorph.transfer_shape_keys() == {"FINISHED"}
    assert target["meshmorph_correspondence"].to_dict()["source"] == "Source"
    s.keys = ""


def test_bad_marker_files_are_refused_in_a_sentence():
    source, target = bpy.data.objects["Source"], bpy.data.objects["Target"]
    s = bpy.context.scene.meshmorph
    select(source, target, active=target)
    s.marker_source, s.refit, s.target_points_file = "FILE", True, ""
    folder = bpy.app.tempdir
    n = len(target.data.vertices)
    contents = {
        "garbage.txt": "\x00\xff this is not a marker file\n",
        "out-of-range.cons": "1\n0, {}\n".format(n + 5),
        "negative.cons": "1\n-3, 0\n",
        "nan.txt": "# meshmorph markers\nnose source 0 nan 0 0 target 0 nan 0 0\n",
    }
    for name, text in contents.items():
        path = os.path.join(folder, name)
        with open(path, "w", encoding="latin-1") as f:
            f.write(text)
        s.marker_file = path
        refused(bpy.ops.meshmorph.transfer_shape_keys, (source, target), "Target")
    s.marker_file = folder  # a folder, not a file
    refused(bpy.ops.meshmorph.transfer_shape_keys, (source, target), "is not a regular file", "Source and Target")
    s.marker_source, s.marker_file, s.refit = "GROUPS", "", False


def test_settings_from_elsewhere_are_refused_naming_the_object():
    turning = bpy.data.objects["Turning"]
    select(turning, active=turning)
    s = bpy.context.scene.meshmorph
    s.inbetween_from, s.inbetween_to, s.bake_keys = "", "turned", "Basis, turned"
    stored = bpy.context.scene["meshmorph"]
    # Blender keeps what a .blend holds, below the settings' minimum too.
    for field, value, operator, words in (
        ("inbetween_count", -5, bpy.ops.meshmorph.add_inbetweens, ("at least one in-between on Turning",)),
        ("inbetween_count", 2**31 - 1, bpy.ops.meshmorph.add_inbetweens, ("Turning would get 2147483647 new shape keys",)),
        ("frames_per_key", 0, bpy.ops.meshmorph.bake_animation, ("Turning's bake at least one frame",)),
        ("frames_per_key", 2**31 - 1, bpy.ops.meshmorph.bake_animation, ("Turning would get", "new shape keys")),
    ):
        kept = stored[field]
        stored[field] = value
        refused(operator, (turning,), *words)
        stored[field] = kept
    # A settings property of another type altogether reads as the defaults.
    saved = stored.to_dict()
    bpy.context.scene["meshmorph"] = "from another add-on"
    assert bpy.context.scene.meshmorph.inbetween_count == 3
    refused(bpy.ops.meshmorph.add_inbetweens, (turning,), "Choose the key of Turning to go to")
    bpy.context.scene["meshmorph"] = saved
    assert bpy.context.scene.meshmorph.inbetween_to == "turned"


def test_an_unexpected_error_is_one_sentence_and_the_scene_is_put_back():
    source, target = bpy.data.objects["Source"], bpy.data.objects["Target"]
    turning = bpy.data.objects["Turning"]
    mesh_arrays = addon_module("mesh_arrays")
    store_key = mesh_arrays.store_key
    calls = []

    def failing(obj, name, local):
        calls.append(name)
        if len(calls) == 2:
            raise ZeroDivisionError("a fault in the middle of writing")
        return store_key(obj, name, local)

    s = bpy.context.scene.meshmorph
    s.marker_source, s.keys, s.refit = "GROUPS", "", True  # a new fit: the kept one is replaced, then put back
    v = coordinates(source.data.vertices, len(source.data.vertices))
    add_key(source, "fresh", twist(v, 0.4))  # new on the target: removed again
    target["meshmorph_correspondence"] = dict(target["meshmorph_correspondence"].to_dict(), report="as kept")
    mesh_arrays.store_key = failing
    try:
        select(source, target, active=target)
        refused(
            bpy.ops.meshmorph.transfer_shape_keys,
            (source, target),
            "Transfer Shape Keys on Target stopped on an unexpected error (ZeroDivisionError",
            "nothing was changed",
        )
        # A bake over an earlier bake: keys, values and curves come back.
        calls.clear()
        select(turning, active=turning)
        s.bake_keys, s.frames_per_key = "Basis, turned", 3
        refused(bpy.ops.meshmorph.bake_animation, (turning,), "Bake ARAP Animation on Turning stopped on an unexpected error")
        calls.clear()
        s.inbetween_from, s.inbetween_to, s.inbetween_count = "", "turned", 2
        refused(bpy.ops.meshmorph.add_inbetweens, (turning,), "Add In-betweens on Turning stopped on an unexpected error")
        # On a mesh without shape keys, none are left behind.
        plain = grid("Keyless", 3, 3, 1.0, 0.0)
        mark(plain, 3, 3)
        calls.clear()
        select(source, plain, active=plain)
        s.refit = False
        refused(bpy.ops.meshmorph.transfer_shape_keys, (source, plain), "on Keyless stopped on an unexpected error")
        assert plain.data.shape_keys is None and "meshmorph_correspondence" not in plain
    finally:
        mesh_arrays.store_key = store_key
    source.shape_key_remove(source.data.shape_keys.key_blocks["fresh"])
    s.frames_per_key, s.refit = 4, False



RECOMMENDED = ("1", "9", "17", "18", "22", "23", "27", "28", "31", "37", "40", "43", "46", "49", "52", "55", "58")


def test_arkit_expressions_from_empties_and_from_a_landmark_file_equal_the_python_packages():
    import tempfile

    t = meshmorph.arkit_template()
    mesh = bpy.data.meshes.new("Head")
    mesh.from_pydata(t["vertices"].tolist(), [], t["faces"].tolist())
    head = bpy.data.objects.new("Head", mesh)
    bpy.context.scene.collection.objects.link(head)
    head.location, head.rotation_euler, head.scale = (1.0, -0.5, 0.2), (0.2, 0.0, 0.4), (10.0, 10.0, 10.0)
    bpy.context.view_layer.update()
    v = world(head, coordinates(head.data.vertices, len(head.data.vertices)))
    points = {n: v[t["landmarks"][n]] for n in RECOMMENDED}
    for n, p in points.items():
        empty = bpy.data.objects.new("chin" if n == "9" else n, None)
        bpy.context.scene.collection.objects.link(empty)
        empty.parent = head
        empty.matrix_world.translation = p
    bpy.context.view_layer.update()
    s = bpy.context.scene.meshmorph
    s.landmark_source, s.replace_keys = "EMPTIES", False
    select(head, active=head)
    assert bpy.ops.meshmorph.arkit_expressions() == {"FINISHED"}
    made = meshmorph.expressions(v, triangles(head), points)
    names = made["names"]
    assert [k.name for k in head.data.shape_keys.key_blocks][1:] == names
    want = local(head, v + made["deltas"][names.index("jawOpen")]).astype(np.float32)
    got = key(head, "jawOpen")
    assert np.abs(got - want).max() <= 1e-6 * diagonal(want) + 1e-6, np.abs(got - want).max()
    chin = t["landmarks"]["9"]
    assert np.linalg.norm(world(head, got)[chin] - v[chin]) > 0.01 * diagonal(v)
    # Again: the keys are there, refused naming them, the head as it was.
    refused(bpy.ops.meshmorph.arkit_expressions, (head,), "Head", "eyeBlinkLeft", "Replace Keys")
    # From a landmark file, by vertex, replacing the keys: the same keys.
    with tempfile.TemporaryDirectory() as d:
        path = os.path.join(d, "head.txt")
        with open(path, "w") as f:
            f.writelines("ibug{} {}\n".format(n, t["landmarks"][n]) for n in RECOMMENDED)
        s.landmark_source, s.landmark_file, s.replace_keys = "FILE", path, True
        assert bpy.ops.meshmorph.arkit_expressions() == {"FINISHED"}
        assert np.abs(key(head, "jawOpen") - want).max() <= 1e-6 * diagonal(want) + 1e-6
        # Too few landmarks: one sentence naming the head, nothing changed.
        with open(path, "w") as f:
            f.writelines("ibug{} {}\n".format(n, t["landmarks"][n]) for n in RECOMMENDED[:5])
        refused(bpy.ops.meshmorph.arkit_expressions, (head,), "Head", "12")
    s.landmark_source, s.landmark_file, s.replace_keys = "EMPTIES", "", False
    for child in list(head.children):
        bpy.data.objects.remove(child)
    bpy.data.objects.remove(head)

# ------------------------------------------------------------------ a source rig from a glTF file

sys.path.insert(0, os.path.join(ROOT, "crates", "meshmorph-py", "tests"))
from gltf_files import character  # noqa: E402  (the Python package's tests' hand-made GLB)


def plane_target(name, n):
    """A plane of n x n quads where Blender's glTF importer puts the sheet
    of gltf_files' character: x from -1 to 1, y = 0, z from 0 to 2 (its
    node lifts it by 1 along glTF's Y, which is Blender's Z)."""
    xs = np.linspace(-1.0, 1.0, n + 1)
    verts = [(x, 0.0, 1.0 + z) for z in xs for x in xs]
    faces = [[j * (n + 1) + i, j * (n + 1) + i + 1, (j + 1) * (n + 1) + i + 1, (j + 1) * (n + 1) + i] for j in range(n) for i in range(n)]
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(verts, [], faces)
    obj = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(obj)
    return obj


def test_keys_from_a_source_file_arrive_on_the_target_and_bad_files_are_refused_naming_them():
    import pathlib
    import tempfile

    with tempfile.TemporaryDirectory() as d:
        character(pathlib.Path(d) / "plain.glb")
        plain = meshmorph.read_gltf(os.path.join(d, "plain.glb"))
        rig = os.path.join(d, "rig.glb")
        meshmorph.write_gltf(rig, plain, {"Bend": bend(plain.vertices, 0.8)})
        target = plane_target("Plane", 12)
        vt = coordinates(target.data.vertices, len(target.data.vertices))
        # The markers: the sheet's corners, middle and one more point, by
        # vertex number in the file's mesh and in the target.
        corners = np.array([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0], [0, 0, 0], [0.5, -0.5, 0]], dtype=float)
        in_blender = np.stack([corners[:, 0], -corners[:, 2], corners[:, 1] + 1], axis=1)
        nearest = lambda points, at: [int(np.argmin(np.linalg.norm(points - p, axis=1))) for p in at]
        pairs = zip(nearest(plain.vertices, corners), nearest(vt, in_blender))
        markers = os.path.join(d, "rig-plane.txt")
        with open(markers, "w") as f:
            f.writelines("v {} v {}\n".format(a, b) for a, b in pairs)
        s = bpy.context.scene.meshmorph
        s.source_file, s.source_mesh, s.marker_source, s.marker_file = rig, "FaceNode", "FILE", markers
        s.target_points_file, s.keys, s.refit = "", "Up, Bend", True
        select(target, active=target)
        assert bpy.ops.meshmorph.transfer_shape_keys() == {"FINISHED"}
        assert [k.name for k in target.data.shape_keys.key_blocks] == ["Basis", "Up", "Bend"]
        # Up lifts the sheet's middle along glTF's +Z, which is Blender's -Y.
        x, z = vt[:, 0], vt[:, 2] - 1
        lift = 0.2 * np.exp(-4 * (x ** 2 + z ** 2))
        moved = key(target, "Up") - vt
        # Where a vertex of the target is one of the file's sheet (every
        # other row and column), the lift is the file's; between them the
        # file's triangles are flat, so it is lower.
        shared = np.array([j % 2 == 0 and i % 2 == 0 for j in range(13) for i in range(13)])
        off = np.abs(moved[:, 1] + lift)
        print("  Up from the file: largest difference {:.3g} of its lift at the file's vertices, {:.3g} between".format(
            off[shared].max() / lift.max(), off.max() / lift.max()))
        assert off[shared].max() < 0.15 * lift.max() and off.max() < 0.25 * lift.max()
        assert np.abs(moved[:, [0, 2]]).max() < 0.1 * lift.max()
        # And exactly the Python package's transfer of the file's welded
        # mesh, placed as Blender's importer places it.
        g = meshmorph.read_gltf(rig)
        wv, wf, index = g.welded()
        first = np.unique(index, return_index=True)[1]
        y_up = np.array([[1.0, 0, 0], [0, 0, -1.0], [0, 1.0, 0]])
        m = g.transform
        place = lambda p: (p @ m[:3, :3].T + m[:3, 3]) @ y_up.T
        points = meshmorph.Markers.from_points(
            place(plain.vertices[nearest(plain.vertices, corners)]), vt[nearest(vt, in_blender)]
        )
        ft = triangles(target)
        c = meshmorph.correspond(place(wv), wf, vt, ft, points)
        want = meshmorph.Transfer(place(wv), wf, vt, ft, c).apply_all(np.stack([place(g.targets[n])[first] for n in ("Up", "Bend")]))
        for n, w in zip(("Up", "Bend"), want.astype(np.float32)):
            assert np.abs(key(target, n) - w).max() <= 1e-6 * diagonal(vt), n
        assert np.abs(key(target, "Bend") - vt).max() > 0.1
        assert target["meshmorph_correspondence"].to_dict()["source"] == rig

        # Refusals naming the file: missing, not glTF, a key it does not have;
        # and markers given other than by a marker file.
        text = os.path.join(d, "text.glb")
        with open(text, "wb") as f:
            f.write(b"not a glTF file")
        s.keys = ""
        for path, words in (
            (os.path.join(d, "missing.glb"), ("missing.glb", "does not exist")),
            (text, ("text.glb", "could not be read")),
        ):
            s.source_file = path
            refused(bpy.ops.meshmorph.transfer_shape_keys, (target,), *words)
        s.source_file, s.keys = rig, "Smile"
        refused(bpy.ops.meshmorph.transfer_shape_keys, (target,), "rig.glb", "has no morph target \"Smile\"", "Up, Bend")
        s.keys, s.source_mesh = "Up", "Nose"
        refused(bpy.ops.meshmorph.transfer_shape_keys, (target,), "rig.glb", "Nose")
        s.source_mesh, s.marker_source = "", "GROUPS"
        refused(bpy.ops.meshmorph.transfer_shape_keys, (target,), "Source File", "marker file", "Plane")
        s.marker_source = "FILE"
        with open(markers, "w") as f:
            f.write("v 1000000 v 0\n")
        refused(bpy.ops.meshmorph.transfer_shape_keys, (target,), "rig-plane.txt", "1000000", "rig.glb")
        source = bpy.data.objects["Source"]
        select(source, target, active=target)
        refused(bpy.ops.meshmorph.transfer_shape_keys, (source, target), "Source File", "Source is selected too")
    s.source_file, s.source_mesh, s.marker_file, s.keys, s.refit = "", "", "", "", False
    bpy.data.objects.remove(target)


failed = 0
for name, test in list(globals().items()):
    if name.startswith("test_") and callable(test):
        try:
            test()
            print("blender add-on: {} ... ok".format(name))
        except Exception:
            failed += 1
            traceback.print_exc()
            print("blender add-on: {} ... FAILED".format(name))
print("blender add-on: {} failed".format(failed) if failed else "blender add-on: all passed")
sys.exit(1 if failed else 0)
