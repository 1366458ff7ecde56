"""glTF files through the Python package: read_gltf gives one mesh of a
user's file as arrays, write_gltf writes a copy of the file with new shapes
added as morph targets and everything else kept; every refusal names its
argument, the file and the mesh. The files are made by hand, as a glTF
exporter writes them (gltf_files.py)."""

import numpy as np
import pytest

import meshmorph

from gltf_files import character, split


def test_read_gltf_gives_the_mesh_its_targets_and_notes_the_other_mesh(tmp_path):
    v, f, up, _ = character(tmp_path / "face.glb")
    g = meshmorph.read_gltf(tmp_path / "face.glb")
    assert g.mesh_name == "Face"
    assert np.allclose(g.vertices, v) and g.vertices.dtype == np.float64
    assert np.array_equal(g.faces, f) and g.faces.dtype == np.int64
    assert list(g.targets) == ["Up"]
    assert np.allclose(g.targets["Up"], v + up, atol=1e-6)
    assert not g.skinned
    # The node's translation places it (for markers, never the deltas).
    assert np.allclose(g.transform[:3, 3], [0, 1, 0]) and np.allclose(g.transform[:3, :3], np.eye(3))
    assert any("Eye" in n for n in g.notes), g.notes
    assert "Face" in repr(g) and g.path.name == "face.glb"
    # Chosen by the node's name too.
    eye = meshmorph.read_gltf(tmp_path / "face.glb", mesh="EyeNode")
    assert eye.mesh_name == "Eye" and eye.vertices.shape == (3, 3) and eye.targets == {}
    # Welded: a sheet has no copies, so the index is every vertex.
    wv, wf, index = g.welded()
    assert np.allclose(wv[index], g.vertices) and wf.shape == g.faces.shape


def test_write_gltf_adds_shapes_and_keeps_the_rest_of_the_file(tmp_path):
    v, f, up, data = character(tmp_path / "face.glb")
    g = meshmorph.read_gltf(tmp_path / "face.glb")
    bent = g.vertices.copy()
    bent[:, 2] += 0.1 * bent[:, 0] ** 2
    meshmorph.write_gltf(tmp_path / "out.glb", g, {"Bent": bent, "Still": g.vertices})
    back = meshmorph.read_gltf(tmp_path / "out.glb")
    assert list(back.targets) == ["Up", "Bent", "Still"]
    assert np.allclose(back.targets["Bent"], bent, atol=1e-6)
    assert np.allclose(back.targets["Up"], v + up, atol=1e-6)
    assert np.array_equal(back.targets["Still"], back.vertices)
    before, before_bin = split(data)
    after, after_bin = split((tmp_path / "out.glb").read_bytes())
    for key in ["asset", "scene", "scenes", "nodes", "materials", "extras"]:
        assert after[key] == before[key], key
    assert after["meshes"][1] == before["meshes"][1]
    assert after["meshes"][0]["weights"] == [0.0, 0.0, 0.0]
    assert after_bin[: len(before_bin)] == before_bin
    # The input is untouched.
    assert (tmp_path / "face.glb").read_bytes() == data


def test_a_shape_whose_name_the_mesh_has_replaces_it_only_when_asked(tmp_path):
    character(tmp_path / "face.glb")
    g = meshmorph.read_gltf(tmp_path / "face.glb")
    flat = g.vertices.copy()
    with pytest.raises(meshmorph.MeshmorphError, match=r"face\.glb.*Face.*`Up`: pass replace=True"):
        meshmorph.write_gltf(tmp_path / "out.glb", g, {"Up": flat})
    assert not (tmp_path / "out.glb").exists()
    meshmorph.write_gltf(tmp_path / "out.glb", g, {"Up": flat}, replace=True)
    back = meshmorph.read_gltf(tmp_path / "out.glb")
    assert list(back.targets) == ["Up"] and np.array_equal(back.targets["Up"], back.vertices)


def test_a_vrm_gains_custom_expressions_of_the_new_shapes(tmp_path):
    character(tmp_path / "face.vrm", vrm=True)
    g = meshmorph.read_gltf(tmp_path / "face.vrm")
    meshmorph.write_gltf(tmp_path / "out.vrm", g, {"jawOpen": g.vertices + [0, 0, 0.01]}, vrm_expressions=True)
    doc, _ = split((tmp_path / "out.vrm").read_bytes())
    custom = doc["extensions"]["VRMC_vrm"]["expressions"]["custom"]
    assert custom["jawOpen"]["morphTargetBinds"][0]["index"] == 1
    # Not a VRM: refused, naming the file.
    character(tmp_path / "face.glb")
    plain = meshmorph.read_gltf(tmp_path / "face.glb")
    with pytest.raises(meshmorph.MeshmorphError, match=r"face\.glb.*vrm_expressions=True needs a VRM"):
        meshmorph.write_gltf(tmp_path / "out.glb", plain, {"jawOpen": plain.vertices}, vrm_expressions=True)
    assert not (tmp_path / "out.glb").exists()


def test_bad_input_is_refused_naming_the_argument_file_and_mesh(tmp_path):
    _, _, _, data = character(tmp_path / "face.glb")
    g = meshmorph.read_gltf(tmp_path / "face.glb")
    out = tmp_path / "out.glb"
    cases = [
        (lambda: meshmorph.read_gltf(tmp_path / "missing.glb"), r"missing\.glb"),
        (lambda: meshmorph.read_gltf(tmp_path / "face.glb", mesh="Nose"), r"face\.glb.*`Nose`"),
        (lambda: meshmorph.read_gltf(tmp_path / "face.glb", mesh=3), r"mesh: expected a mesh's or node's name"),
        (lambda: meshmorph.read_gltf(3), r"path: expected a path"),
        (lambda: meshmorph.write_gltf(out, "gltf", {}), r"gltf: expected a Gltf"),
        (lambda: meshmorph.write_gltf(out, g, [g.vertices]), r"shapes: expected a dict"),
        (lambda: meshmorph.write_gltf(out, g, {1: g.vertices}), r"shapes: a key is"),
        (lambda: meshmorph.write_gltf(out, g, {"Short": g.vertices[:-1]}), r"shapes\[\"Short\"\]: 48 vertices, mesh `Face` has 49"),
        (lambda: meshmorph.write_gltf(out, g, {"Nan": g.vertices * np.nan}), r"shapes\[\"Nan\"\]"),
        (lambda: meshmorph.write_gltf(tmp_path / "face.glb", g, {"New": g.vertices}), r"path: .*the file the mesh was read from"),
        (lambda: meshmorph.write_gltf(tmp_path / "no" / "such" / "out.glb", g, {"New": g.vertices}), r"path: "),
    ]
    for call, message in cases:
        with pytest.raises(meshmorph.MeshmorphError, match=message):
            call()
    assert not out.exists()
    assert (tmp_path / "face.glb").read_bytes() == data
    # Not a glTF file at all, and a GLB cut short: refused naming the file.
    (tmp_path / "text.glb").write_bytes(b"not a glTF file")
    (tmp_path / "cut.glb").write_bytes(data[: len(data) // 2])
    for name in ["text.glb", "cut.glb"]:
        with pytest.raises(meshmorph.MeshmorphError, match=name.replace(".", r"\.")):
            meshmorph.read_gltf(tmp_path / name)


def test_the_readmes_flow_carries_a_rigs_targets_into_a_copy_of_the_character(tmp_path):
    _, _, up, _ = character(tmp_path / "rig.glb")
    character(tmp_path / "char.vrm", vrm=True)
    rig, char = meshmorph.read_gltf(tmp_path / "rig.glb"), meshmorph.read_gltf(tmp_path / "char.vrm", mesh="Face")
    (sv, sf, si), (tv, tf, ti) = rig.welded(), char.welded()
    corners = [[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0], [0, 0, 0]]
    markers = meshmorph.Markers.from_points(np.array(corners, float), np.array(corners, float))
    c = meshmorph.correspond(sv, sf, tv, tf, markers)
    transfer = meshmorph.Transfer(sv, sf, tv, tf, c)
    shapes = {
        name + "_copy": transfer.apply(p[np.unique(si, return_index=True)[1]])[ti]
        for name, p in rig.targets.items()
    }
    meshmorph.write_gltf(tmp_path / "char-shapes.vrm", char, shapes, vrm_expressions=True)
    back = meshmorph.read_gltf(tmp_path / "char-shapes.vrm")
    assert list(back.targets) == ["Up", "Up_copy"]
    # The same sheet: the shape comes back as it was, to a small fraction of its lift.
    moved = back.targets["Up_copy"] - back.vertices
    assert np.abs(moved - up).max() < 0.1 * np.abs(up).max()


def test_two_primitives_are_one_surface_welded_where_their_vertices_coincide(tmp_path):
    v, f, up, _ = character(tmp_path / "split.glb", split=True)
    g = meshmorph.read_gltf(tmp_path / "split.glb")
    # The middle column (7 vertices) is in both primitives.
    assert g.vertices.shape == (49 + 7, 3) and g.faces.shape == f.shape
    wv, wf, index = g.welded()
    assert wv.shape == (49, 3) and wf.shape == f.shape
    assert np.allclose(wv[index], g.vertices)
    assert sorted(set(index.tolist())) == list(range(49))
    # A shape given on the welded vertices, expanded by the index, goes into both primitives.
    lifted = wv + [0, 0, 0.05]
    meshmorph.write_gltf(tmp_path / "out.glb", g, {"Lift": lifted[index]})
    back = meshmorph.read_gltf(tmp_path / "out.glb")
    assert list(back.targets) == ["Up", "Lift"]
    assert np.allclose(back.targets["Lift"] - back.vertices, [0, 0, 0.05], atol=1e-6)
    doc, _ = split((tmp_path / "out.glb").read_bytes())
    assert [len(p["targets"]) for p in doc["meshes"][0]["primitives"]] == [2, 2]
