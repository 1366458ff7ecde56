"""The ARKit expressions put on a head: the built-in template's own head,
turned, scaled and moved, with its 17 recommended landmarks."""

import numpy as np
import pytest

import meshmorph

RECOMMENDED = ["1", "9", "17", "18", "22", "23", "27", "28", "31", "37", "40", "43", "46", "49", "52", "55", "58"]


def moved_head():
    t = meshmorph.arkit_template()
    c, s = np.cos(0.4), np.sin(0.4)
    turn = np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])
    vertices = 1.5 * t["vertices"] @ turn.T + np.array([0.1, -0.3, 2.0])
    landmarks = {n: vertices[t["landmarks"][n]] for n in RECOMMENDED}
    return t, vertices, landmarks, turn


def test_the_template_head_gets_its_arkit_shapes():
    t, vertices, landmarks, turn = moved_head()
    assert len(t["landmarks"]) == 68
    out = meshmorph.expressions(vertices, t["faces"], landmarks)
    names = out["names"]
    assert len(names) == 51 and "jawOpen" in names and "eyeBlinkLeft" in names
    assert out["missing"] == ["tongueOut"]
    deltas = out["deltas"]
    assert deltas.shape == (51, len(vertices), 3) and deltas.dtype == np.float64
    # jawOpen moves the chin down (the head's own down, turned with it).
    chin = t["landmarks"]["9"]
    jaw = deltas[names.index("jawOpen")][chin]
    down = turn @ np.array([0.0, -1.0, 0.0])
    assert jaw @ down > 0.01
    # eyeBlinkLeft leaves the chin exactly still.
    assert np.all(deltas[names.index("eyeBlinkLeft")][chin] == 0.0)
    report = {r["name"]: r for r in out["report"]}
    assert report["jawOpen"]["moved"] > 100 and report["jawOpen"]["largest"] > 0.0


def test_landmarks_as_pairs_with_aliases_and_transfer():
    t, vertices, landmarks, _ = moved_head()
    aliases = {"9": "chin", "31": "noseTip", "37": "eyeOuterRight"}
    pairs = [(aliases.get(n, n), tuple(p)) for n, p in landmarks.items()]
    out = meshmorph.expressions(vertices, t["faces"], pairs, method="transfer", all_shapes=True)
    assert len(out["names"]) > 51
    assert out["deltas"].shape[0] == len(out["names"])


@pytest.mark.parametrize(
    "landmarks, message",
    [
        ({"1": (0.0, 0.0, 0.0)}, "12"),
        ("noseTip", "landmarks"),
        ([("chin", (0.0, 0.0))], "3 coordinates"),
        ([("chin", (0.0, float("nan"), 0.0))], "landmarks"),
        ({"earlobe": (0.0, 0.0, 0.0), **{n: (0.0, 0.0, float(k)) for k, n in enumerate(RECOMMENDED)}}, "earlobe"),
    ],
)
def test_bad_landmarks_are_refused_naming_them(landmarks, message):
    t = meshmorph.arkit_template()
    with pytest.raises(meshmorph.MeshmorphError, match=message):
        meshmorph.expressions(t["vertices"], t["faces"], landmarks)


def test_bad_method_and_template_are_refused(tmp_path):
    t, vertices, landmarks, _ = moved_head()
    with pytest.raises(meshmorph.MeshmorphError, match="method"):
        meshmorph.expressions(vertices, t["faces"], landmarks, method="copy")
    bad = tmp_path / "rig.glb"
    bad.write_bytes(b"not a glb")
    with pytest.raises(meshmorph.MeshmorphError, match="rig.glb"):
        meshmorph.expressions(vertices, t["faces"], landmarks, template=bad)


def test_a_landmark_file_by_position_and_by_vertex(tmp_path):
    t, vertices, landmarks, _ = moved_head()
    lines = ["# landmarks"]
    for k, (n, p) in enumerate(landmarks.items()):
        # In lines of text a number alone reads as a coordinate: ibug9, not 9.
        if k % 2:
            lines.append("ibug{} {} {} {}".format(n, *p))
        else:
            lines.append("ibug{} {}".format(n, t["landmarks"][n]))
    path = tmp_path / "head.txt"
    path.write_text("\n".join(lines) + "\n")
    read = meshmorph.read_landmarks(path, vertices, t["faces"])
    assert [n for n, _ in read] == ["ibug" + n for n in landmarks]
    for (n, p) in read:
        assert np.allclose(p, landmarks[n[len("ibug"):]])
    a = meshmorph.expressions(vertices, t["faces"], read)["deltas"]
    b = meshmorph.expressions(vertices, t["faces"], landmarks)["deltas"]
    assert np.allclose(a, b)
    path.write_text("chin 99999999\n")
    with pytest.raises(meshmorph.MeshmorphError, match="head.txt"):
        meshmorph.read_landmarks(path, vertices, t["faces"])
