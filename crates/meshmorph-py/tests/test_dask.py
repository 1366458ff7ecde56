"""The Dask batch example: a batch of three targets on a local cluster of
two worker processes writes the same files as the same batch in one
process, and a target with a bad marker file is reported while the others
finish."""

import importlib.util
import json
from pathlib import Path

import numpy as np
import pytest

import meshmorph

from gltf_files import character, split
from test_meshmorph import bent, sheet

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "dask_batch.py"
spec = importlib.util.spec_from_file_location("dask_batch", EXAMPLE)
dask_batch = importlib.util.module_from_spec(spec)
spec.loader.exec_module(dask_batch)


def write_obj(path, v, f):
    with open(path, "w") as out:
        out.writelines("v {!r} {!r} {!r}\n".format(*p) for p in v.tolist())
        out.writelines("f {} {} {}\n".format(*(t + 1)) for t in f)


def make_batch(folder, bad=False):
    """A sheet bent three ways, and three sheets of other sizes to carry the
    bends to; with `bad`, the second target's marker file names a vertex it
    does not have."""
    vs, fs = sheet(10)
    write_obj(folder / "source.obj", vs, fs)
    for k, angle in enumerate((0.4, 0.8, 1.2)):
        write_obj(folder / "pose-{}.obj".format(k), bent(vs, angle), fs)
    targets = []
    for k, (n, scale) in enumerate(((12, 1.2), (15, 0.9), (9, 1.5))):
        vt, ft = sheet(n, scale=scale)
        write_obj(folder / "target-{}.obj".format(k), vt, ft)
        corners_s = [0, 10, 110, 120, 60]
        corners_t = [0, n, n * (n + 1), (n + 1) ** 2 - 1, (n + 1) ** 2 // 2]
        if bad and k == 1:
            corners_t[2] = 10**6
        (folder / "markers-{}.txt".format(k)).write_text(
            "".join("v {} v {}\n".format(a, b) for a, b in zip(corners_s, corners_t))
        )
        targets.append({"reference": "target-{}.obj".format(k), "markers": "markers-{}.txt".format(k), "output": "out-{}/".format(k)})
    batch = {"source": "source.obj", "poses": ["pose-{}.obj".format(k) for k in range(3)], "targets": targets}
    (folder / "batch.json").write_text(json.dumps(batch))
    return folder / "batch.json"


def outputs(folder):
    return {p.relative_to(folder).as_posix(): p.read_bytes() for p in sorted(folder.glob("out-*/*.obj"))}


@pytest.fixture(scope="module")
def client():
    distributed = pytest.importorskip("dask.distributed")
    cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None)
    with distributed.Client(cluster) as c:
        yield c
    cluster.close()


def test_a_batch_on_two_dask_workers_writes_what_one_process_writes(tmp_path, client):
    one, many = tmp_path / "one", tmp_path / "many"
    one.mkdir(), many.mkdir()
    reports = dask_batch.run_in_process(dask_batch.read_batch(str(make_batch(one))))
    assert all(r["ok"] for r in reports)
    reports = dask_batch.run_on_dask(dask_batch.read_batch(str(make_batch(many))), client)
    assert all(r["ok"] for r in reports), reports
    assert len({r["peak_memory_mb"] for r in reports}) >= 1 and all(r["seconds"] > 0 for r in reports)
    expected = outputs(one)
    assert len(expected) == 9 and outputs(many) == expected
    moved = meshmorph.read_mesh(one / "out-0" / "pose-2.obj").vertices
    rest = meshmorph.read_mesh(one / "target-0.obj").vertices
    assert np.abs(moved - rest).max() > 0.1


def test_a_target_with_a_bad_marker_file_is_named_and_the_others_finish(tmp_path, client):
    reports = dask_batch.run_on_dask(dask_batch.read_batch(str(make_batch(tmp_path, bad=True))), client)
    assert [r["ok"] for r in reports] == [True, False, True]
    assert "markers-1.txt" in reports[1]["error"] or "1000000" in reports[1]["error"], reports[1]["error"]
    assert len(list((tmp_path / "out-0").glob("*.obj"))) == 3 and len(list((tmp_path / "out-2").glob("*.obj"))) == 3
    assert not (tmp_path / "out-1").exists() or not list((tmp_path / "out-1").iterdir())


# ------------------------------------------------------------------ glTF and VRM characters

CORNERS = [[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0], [0, 0, 0], [0.5, -0.5, 0]]


def nearest(g, points):
    """The vertices of a glTF mesh `g` nearest to `points` (in its own space)."""
    return [int(np.argmin(np.linalg.norm(g.vertices - p, axis=1))) for p in points]


def make_rig_batch(folder, target=None, name="batch.json", **batch):
    """A rig (the sheet of gltf_files, its targets `Up`, `Bend` and `Lift`)
    and a VRM character (the same sheet, its halves two primitives, with a
    target `Up` of its own), a marker file between them, and a batch file
    carrying the rig's shapes into a copy of the character; `target` and
    `batch` change the target's and the file's keys; `name` is the batch
    file's."""
    character(folder / "plain.glb")
    plain = meshmorph.read_gltf(folder / "plain.glb")
    v = plain.vertices
    meshmorph.write_gltf(
        folder / "rig.glb", plain, {"Bend": bent(v, 0.8), "Lift": v + [0, 0, 0.1] * (1 + v[:, :1])}
    )
    character(folder / "char.vrm", vrm=True, split=True)
    char = meshmorph.read_gltf(folder / "char.vrm")
    rig = meshmorph.read_gltf(folder / "rig.glb")
    (folder / "rig-char.txt").write_text(
        "".join("v {} v {}\n".format(a, b) for a, b in zip(nearest(rig, CORNERS), nearest(char, CORNERS)))
    )
    t = {"reference": "char.vrm", "mesh": "Face", "markers": "rig-char.txt", "gltf": "out/char-shapes.vrm", "vrm_expressions": True}
    t.update(target or {})
    t = {k: v for k, v in t.items() if v is not None}
    b = {"source": "rig.glb", "source_mesh": "FaceNode", "shapes": ["Bend", "Lift"], "targets": [t]}
    b.update(batch)
    b = {k: v for k, v in b.items() if v is not None}
    (folder / name).write_text(json.dumps(b))
    return folder / name


def test_a_rigs_chosen_morph_targets_go_into_a_copy_of_the_characters_own_file(tmp_path, client):
    one, many = tmp_path / "one", tmp_path / "many"
    one.mkdir(), many.mkdir()
    reports = dask_batch.run_in_process(dask_batch.read_batch(str(make_rig_batch(one))))
    assert [r["ok"] for r in reports] == [True], reports
    assert reports[0]["poses"] == 2 and reports[0]["output"].endswith("char-shapes.vrm")
    reports = dask_batch.run_on_dask(dask_batch.read_batch(str(make_rig_batch(many))), client)
    assert [r["ok"] for r in reports] == [True], reports
    written = (one / "out" / "char-shapes.vrm").read_bytes()
    assert (many / "out" / "char-shapes.vrm").read_bytes() == written
    back = meshmorph.read_gltf(one / "out" / "char-shapes.vrm")
    rig = meshmorph.read_gltf(one / "rig.glb")
    assert list(back.targets) == ["Up", "Bend", "Lift"]
    # The same sheet: each shape comes back as the rig has it, the seam
    # between the two primitives closed.
    for name in ["Bend", "Lift"]:
        moved = back.targets[name] - back.vertices
        given = rig.targets[name][nearest(rig, back.vertices)] - back.vertices
        assert np.abs(moved - given).max() < 0.1 * np.abs(given).max(), name
    wv, _, index = back.welded()
    for name in ["Bend", "Lift"]:
        assert np.allclose(back.targets[name], back.targets[name][np.unique(index, return_index=True)[1]][index])
    doc, _ = split(written)
    assert set(doc["extensions"]["VRMC_vrm"]["expressions"]["custom"]) == {"Bend", "Lift"}
    assert doc["asset"]["copyright"] == "the test's own" and doc["materials"][0]["name"] == "Skin"
    # The character's own file is as it was.
    _, _, _, data = character(tmp_path / "again.vrm", vrm=True, split=True)
    assert (one / "char.vrm").read_bytes() == data


def test_every_morph_target_by_default_and_one_of_the_same_name_replaced_only_when_asked(tmp_path):
    batch = make_rig_batch(tmp_path, target={"vrm_expressions": None}, shapes=None, source_mesh=None)
    reports = dask_batch.run_in_process(dask_batch.read_batch(str(batch)))
    assert not reports[0]["ok"] and reports[0]["poses"] == 3
    assert "`Up`" in reports[0]["error"] and "replace_shapes = true" in reports[0]["error"], reports[0]["error"]
    assert not (tmp_path / "out" / "char-shapes.vrm").exists()
    batch = make_rig_batch(tmp_path, target={"vrm_expressions": None, "replace_shapes": True}, shapes=None)
    reports = dask_batch.run_in_process(dask_batch.read_batch(str(batch)))
    assert reports[0]["ok"], reports
    back = meshmorph.read_gltf(tmp_path / "out" / "char-shapes.vrm")
    assert list(back.targets) == ["Up", "Bend", "Lift"]
    # The character's Up is now the rig's, carried: the same lift.
    rig = meshmorph.read_gltf(tmp_path / "rig.glb")
    given = rig.targets["Up"][nearest(rig, back.vertices)] - back.vertices
    assert np.abs(back.targets["Up"] - back.vertices - given).max() < 0.1 * np.abs(given).max()


def test_batch_keys_that_do_not_go_together_or_an_output_over_an_input_are_refused_naming_the_file_and_key(tmp_path):
    make_batch(tmp_path)  # the mesh files: source.obj, pose-0.obj, target-0.obj
    cases = [
        (make_rig_batch(tmp_path, name="case-0.json", fps=12), "does not handle fps"),
        (make_rig_batch(tmp_path, name="case-1.json", target={"gltf_dense": True}), "target 0 .*does not handle gltf_dense"),
        (make_rig_batch(tmp_path, name="case-2.json", source="source.obj", shapes=None), "lists no poses .*source.obj` is not one"),
        (make_rig_batch(tmp_path, name="case-3.json", poses=["pose-0.obj"]), "`shapes` chooses morph targets of a glTF source"),
        (make_rig_batch(tmp_path, name="case-4.json", source="source.obj", poses=["pose-0.obj"], shapes=None), "`source_mesh` chooses the mesh of a glTF"),
        (make_rig_batch(tmp_path, name="case-5.json", target={"output": "folder/"}), "`output` is a folder for the poses listed"),
        (make_rig_batch(tmp_path, name="case-6.json", target={"reference": "target-0.obj", "mesh": None, "vrm_expressions": None}), "copy of a glTF or VRM `reference`"),
        (make_rig_batch(tmp_path, name="case-7.json", target={"reference": "target-0.obj", "gltf": None, "output": "o/", "vrm_expressions": None}, source="source.obj",
                        poses=["pose-0.obj"], shapes=None, source_mesh=None), "`mesh` chooses the mesh of a glTF or VRM `reference`"),
        (make_rig_batch(tmp_path, name="case-8.json", target={"gltf": None}), "give `output`"),
        (make_rig_batch(tmp_path, name="case-9.json", target={"vrm_expressions": "yes"}), "`vrm_expressions` is true or false"),
        (make_rig_batch(tmp_path, name="case-10.json", targets=[]), "lists no targets"),
        (make_rig_batch(tmp_path, name="case-11.json", target={"gltf": "rig.glb"}), "output .*rig.glb would overwrite the input"),
        (make_rig_batch(tmp_path, name="case-12.json", target={"reference": "target-0.obj", "gltf": None, "mesh": None, "vrm_expressions": None, "output": "."},
                        source="source.obj", poses=["pose-0.obj"], shapes=None, source_mesh=None), "output .*pose-0.obj would overwrite the input"),
    ]
    for batch, message in cases:
        with pytest.raises(ValueError, match=message):
            dask_batch.read_batch(str(batch))
        assert str(batch) in str(pytest.raises(ValueError, dask_batch.read_batch, str(batch)).value)


def test_a_missing_shape_a_missing_rig_or_a_file_that_is_not_gltf_fails_its_target_naming_it(tmp_path):
    reports = dask_batch.run_in_process(dask_batch.read_batch(str(make_rig_batch(tmp_path, shapes=["Bend", "Smile"]))))
    error = reports[0]["error"]
    assert not reports[0]["ok"] and "rig.glb" in error and "`Smile`" in error and "Up, Bend, Lift" in error, error
    for source, contents in [("missing.glb", None), ("text.glb", b"not a glTF file")]:
        if contents:
            (tmp_path / source).write_bytes(contents)
        reports = dask_batch.run_in_process(dask_batch.read_batch(str(make_rig_batch(tmp_path, source=source))))
        assert not reports[0]["ok"] and source in reports[0]["error"], reports[0]["error"]
    # A marker naming a vertex the character does not have: named with the marker file.
    batch = make_rig_batch(tmp_path)
    (tmp_path / "rig-char.txt").write_text("v 0 v 1000000\n")
    reports = dask_batch.run_in_process(dask_batch.read_batch(str(batch)))
    assert "rig-char.txt" in reports[0]["error"] and "1000000" in reports[0]["error"], reports[0]["error"]
    assert not (tmp_path / "out" / "char-shapes.vrm").exists()
