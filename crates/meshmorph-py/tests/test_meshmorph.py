"""The Python package against the library (through the command line's
outputs, written with every digit), on procedural meshes and on the shared
pairs; every accepted dtype, every refusal naming its argument; no memory growth
over many calls (the GIL released: test_hostile.py; the time two threads
take: bench/threads.py)."""

import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

import meshmorph

ROOT = Path(__file__).resolve().parents[3]
SHARED = ROOT.parent / "shared" / "data" / "dt"
BINARY = Path(os.environ.get("MESHMORPH_BIN", ROOT / "target" / "release" / "meshmorph"))
IN_CI = bool(os.environ.get("CI"))


def needs(path: Path, what: str):
    """Skips (fails in CI) when `path` is missing."""
    if not path.exists():
        if IN_CI:
            pytest.fail(f"{what} not found at {path}; CI must run this check")
        pytest.skip(f"{what} not found at {path}")


def sheet(n=12, scale=1.0, bump=0.1):
    """A bumpy square sheet, n quads a side split in two."""
    xs = np.linspace(-scale, scale, n + 1)
    x, y = np.meshgrid(xs, xs)
    z = bump * scale * (np.sin(1.7 * x / scale) + np.cos(1.3 * y / scale))
    v = np.stack([x.ravel(), y.ravel(), z.ravel()], axis=1)
    f = []
    for j in range(n):
        for i in range(n):
            a, b, c, d = j * (n + 1) + i, j * (n + 1) + i + 1, (j + 1) * (n + 1) + i + 1, (j + 1) * (n + 1) + i
            f += [[a, b, c], [a, c, d]]
    return v, np.array(f, dtype=np.int64)


def bent(v, angle):
    """The sheet bent about the y axis, more towards +x."""
    out = v.copy()
    a = angle * (v[:, 0] + 1) / 2
    out[:, 0] = np.cos(a) * v[:, 0] - np.sin(a) * v[:, 2]
    out[:, 2] = np.sin(a) * v[:, 0] + np.cos(a) * v[:, 2]
    return out


def diagonal(v):
    return np.linalg.norm(v.max(0) - v.min(0))


# ---------------------------------------------------------------- interpolation

def test_interpolation_passes_through_its_keys_in_the_plane_and_in_space():
    v, f = sheet()
    for v0, v1 in [(v, bent(v, 1.2)), (v[:, :2], v[:, :2] * [1.5, 0.7])]:
        i = meshmorph.Interpolator(v0, v1, f)
        assert np.abs(i.at(0.0) - v0).max() < 1e-9
        assert np.abs(i.at(1.0) - v1).max() < 1e-9
        frames = i.frames([0.0, 0.5, 1.0])
        assert frames.shape == (3,) + v0.shape
        assert np.array_equal(frames[1], i.at(0.5))
        out = np.zeros_like(v0)
        assert i.at(0.5, out=out) is out and np.array_equal(out, frames[1])
        many = np.zeros((3,) + v0.shape)
        assert i.frames([0.0, 0.5, 1.0], out=many) is many and np.array_equal(many, frames)
        with pytest.raises(meshmorph.MeshmorphError, match="out:"):
            i.frames([0.0, 0.5], out=many)
        with pytest.raises(meshmorph.MeshmorphError, match="out:"):
            i.frames([0.0, 0.5, 1.0], out=np.asfortranarray(many))


def test_a_rigid_turn_stays_rigid():
    v, f = sheet()
    c, s = np.cos(2.0), np.sin(2.0)
    turned = v @ np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]]).T
    mid = meshmorph.Interpolator(v, turned, f).at(0.5)
    edges = f[:, [0, 1]]
    rest = np.linalg.norm(v[edges[:, 0]] - v[edges[:, 1]], axis=1)
    now = np.linalg.norm(mid[edges[:, 0]] - mid[edges[:, 1]], axis=1)
    assert np.abs(now - rest).max() < 1e-9


def test_sequence_and_blend():
    v, f = sheet()
    keys = np.stack([v, bent(v, 0.8), bent(v, 1.6)])
    s = meshmorph.Sequence(keys, f)
    for k in range(3):
        assert np.abs(s.at(float(k)) - keys[k]).max() < 1e-9
    assert s.frames([0.0, 2.0]).shape == (2,) + v.shape
    b = meshmorph.Blend(v, keys[1:], f)
    assert np.abs(b.at([1.0, 0.0]) - keys[1]).max() < 1e-9
    assert np.abs(b.at([0.0, 0.0]) - v).max() < 1e-9


# ---------------------------------------------------------------- arrays

@pytest.mark.parametrize("vdtype", [np.float64, np.float32])
@pytest.mark.parametrize("fdtype", [np.int32, np.int64, np.uint32])
def test_every_stated_dtype_is_taken_alike(vdtype, fdtype):
    v, f = sheet(6)
    w = bent(v, 1.0)
    reference = meshmorph.Interpolator(v.astype(np.float32).astype(np.float64), w.astype(np.float32).astype(np.float64), f).at(0.3)
    got = meshmorph.Interpolator(v.astype(vdtype), w.astype(vdtype), f.astype(fdtype)).at(0.3)
    assert got.dtype == np.float64
    if vdtype == np.float32:
        assert np.array_equal(got, reference)
    # A strided (non-contiguous) view is read as it is.
    assert np.array_equal(meshmorph.Interpolator(np.asfortranarray(v), w, f.astype(fdtype)).at(0.3), meshmorph.Interpolator(v, w, f).at(0.3))


@pytest.mark.parametrize(
    "call, says",
    [
        (lambda v, f: meshmorph.Interpolator(v.astype(np.float16), v, f), "v0: expected a (n, 2) or (n, 3) float64 or float32"),
        (lambda v, f: meshmorph.Interpolator(np.c_[v, v[:, :1]], v, f), "v0: expected"),
        (lambda v, f: meshmorph.Interpolator(v.tolist(), v, f), "v0: expected"),
        (lambda v, f: meshmorph.Interpolator(v, v, f.astype(np.int16)), "f: expected a (m, 3) int32, int64 or uint32"),
        (lambda v, f: meshmorph.Interpolator(v, v, f.astype(np.float64)), "f: expected"),
        (lambda v, f: meshmorph.Interpolator(v, v, f[:, :2]), "f: expected"),
        (lambda v, f: meshmorph.Interpolator(v, v[:-1], f), "v1: has"),
        (lambda v, f: meshmorph.Interpolator(v, v[:, :2], f), "v1: has 2 coordinates"),
        (lambda v, f: meshmorph.Interpolator(np.where(np.arange(len(v))[:, None] == 5, np.nan, v), v, f), "v0: vertex 5"),
        (lambda v, f: meshmorph.Interpolator(v, v, np.where(f == 7, -1, f)), "f: face"),
        (lambda v, f: meshmorph.Interpolator(v, v, np.where(f == 7, 10_000, f)), "f: face"),
        (lambda v, f: meshmorph.Interpolator(v, v, f, stretch="cubic"), "stretch:"),
        (lambda v, f: meshmorph.Interpolator(v, v, f).at(float("nan")), "t:"),
        (lambda v, f: meshmorph.Interpolator(v, v, f).at(0.5, out=np.zeros((3, 3))), "out:"),
        (lambda v, f: meshmorph.Interpolator(v, v, f).at(0.5, out=np.zeros(v.shape, np.float32)), "out:"),
        (lambda v, f: meshmorph.Blend(v, np.stack([v]), f).at([1.0, 2.0]), "weights:"),
        (lambda v, f: meshmorph.Sequence(np.stack([v]), f), "keys:"),
        (lambda v, f: meshmorph.positions_from_gradients(v, f, np.zeros((3, 3, 3))), "j:"),
        (lambda v, f: meshmorph.correspond(v, f, v, f, np.array([[0, 10_000]])), "marker"),
        (lambda v, f: meshmorph.correspond(v, f, v, f, "nonsense"), "markers:"),
    ],
)
def test_bad_input_raises_naming_the_argument(call, says):
    v, f = sheet(6)
    with pytest.raises(meshmorph.MeshmorphError) as caught:
        call(v, f)
    assert says in str(caught.value)
    assert isinstance(caught.value, ValueError)


# ---------------------------------------------------------------- the gradient solve

@pytest.mark.parametrize("dim", [2, 3])
def test_positions_from_gradients_returns_the_mesh_whose_gradients_it_is_given(dim):
    v, f = sheet(10)
    rest = v[:, :dim] if dim == 2 else v
    posed = bent(v, 1.3)[:, :dim] if dim == 3 else v[:, :2] * [1.3, 0.6] + 0.1 * np.sin(v[:, 1:2])
    j = meshmorph.deformation_gradients(rest, f, posed)
    assert j.shape == (len(f), dim, dim)
    x = meshmorph.positions_from_gradients(rest, f, j)
    assert np.abs((x - x.mean(0)) - (posed - posed.mean(0))).max() < 1e-9 * diagonal(posed)
    # Another centroid moves the whole (one-part) mesh by as much.
    solver = meshmorph.GradientSolver(rest, f)
    assert np.array_equal(solver.solve(j), x)
    y = solver.solve(j, centroids=np.full((1, dim), 3.0))
    moved = y - x
    assert np.abs(moved - moved[0]).max() < 1e-9 * diagonal(posed)
    assert np.abs(moved[0]).min() > 1.0


# ---------------------------------------------------------------- transfer

def sheets_and_transfer():
    vs, fs = sheet(12)
    vt, ft = sheet(18, 1.5)
    corner = lambda n: [0, n, n * (n + 1), (n + 1) ** 2 - 1]
    markers = np.array(list(zip(corner(12), corner(18))))
    c = meshmorph.correspond(vs, fs, vt, ft, markers)
    return vs, fs, vt, ft, c


def test_transfer_of_the_rest_pose_is_the_target_and_apply_all_matches_apply(tmp_path):
    vs, fs, vt, ft, c = sheets_and_transfer()
    assert c.mean_distance is not None and c.mean_distance < 0.01
    assert c.pairs.shape[1] == 2
    t = meshmorph.Transfer(vs, fs, vt, ft, c)
    assert np.abs(t.apply(vs) - vt).max() < 1e-9 * diagonal(vt)
    poses = np.stack([bent(vs, a) for a in (0.3, 0.9, 1.5)])
    seen = []
    every = t.apply_all(poses, progress=lambda done, total: seen.append((done, total)))
    assert sorted(seen) == [(1, 3), (2, 3), (3, 3)]
    for k in range(3):
        assert np.array_equal(every[k], t.apply(poses[k]))
    into = np.empty_like(every)
    assert t.apply_all(poses, out=into) is into and np.array_equal(into, every)
    path = tmp_path / "c.corr"
    c.save(path)
    again = meshmorph.Transfer(vs, fs, vt, ft, meshmorph.Correspondence.load(path))
    assert np.array_equal(again.apply_all(poses), every)
    with pytest.raises(meshmorph.MeshmorphError, match="pose:"):
        t.apply(vs[:-1])
    with pytest.raises(meshmorph.MeshmorphError, match="poses:"):
        t.apply_all(vs)


def test_correspond_reports_progress_and_passes_on_the_callbacks_error():
    vs, fs = sheet(8)
    calls = []
    meshmorph.correspond(vs, fs, vs * 2, fs, np.array([[0, 0], [8, 8], [80, 80]]), progress=lambda d, t: calls.append((d, t)))
    assert calls and calls[-1][0] == calls[-1][1]
    assert [d for d, _ in calls] == sorted(d for d, _ in calls)

    def fails(done, total):
        raise RuntimeError("stop")

    with pytest.raises(RuntimeError, match="stop"):
        meshmorph.correspond(vs, fs, vs * 2, fs, np.array([[0, 0], [8, 8], [80, 80]]), progress=fails)


def cli(*args):
    needs(BINARY, "the meshmorph program (cargo build --release)")
    subprocess.run([str(BINARY), *map(str, args)], check=True, capture_output=True)


def read_obj(path):
    return np.array([[float(x) for x in line.split()[1:4]] for line in open(path) if line.startswith("v ")])


@pytest.mark.parametrize(
    "pair, source, target, markers, poses",
    [
        ("horse-camel", "horse-poses/horse-reference.obj", "camel-poses/camel-reference.obj", "markers/horse-camel-107.cons", [f"horse-poses/horse-{k:02}.obj" for k in range(1, 11)]),
        ("face-head", "face-poses/face-reference.obj", "head-poses/head-reference.obj", "markers/face-head.txt", ["face-poses/face-02-cry.obj"]),
    ],
)
def test_transfer_equals_the_libraries_on_the_shared_pairs(tmp_path, pair, source, target, markers, poses):
    d = SHARED / pair
    needs(d, f"../shared/data/dt/{pair}")
    s, t = meshmorph.read_mesh(d / source), meshmorph.read_mesh(d / target)
    c = meshmorph.correspond(s.vertices, s.faces, t.vertices, t.faces, meshmorph.read_markers(d / markers))
    got = meshmorph.Transfer(s.vertices, s.faces, t.vertices, t.faces, c).apply_all(np.stack([meshmorph.read_mesh(d / p).vertices for p in poses]))
    cli("transfer", "--source-ref", d / source, "--target-ref", d / target, "--markers", d / markers, "-o", tmp_path / "out", "--format", "obj", *[d / p for p in poses])
    scale = diagonal(t.vertices)
    for k, p in enumerate(poses):
        expected = read_obj(tmp_path / "out" / (Path(p).stem + ".obj"))
        assert np.abs(got[k] - expected).max() <= 1e-12 * scale, p


# ---------------------------------------------------------------- files

def test_write_mesh_keeps_the_files_polygons_and_texture_coordinates(tmp_path):
    src = tmp_path / "quad.obj"
    src.write_text("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 2 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nf 1/1 2/2 3/3 4/4\nf 2/1 5/2 6/3 3/4\n")
    m = meshmorph.read_mesh(src)
    assert m.vertices.shape == (6, 3) and m.faces.shape == (4, 3)
    out = tmp_path / "moved.obj"
    meshmorph.write_mesh(out, m, m.vertices * 2)
    text = out.read_text()
    assert "vt 1 1" in text and "f 1/1 2/2 3/3 4/4" in text
    assert np.array_equal(meshmorph.read_mesh(out).vertices, m.vertices * 2)
    before = src.read_bytes()
    with pytest.raises(meshmorph.MeshmorphError, match="never writes over"):
        meshmorph.write_mesh(src, m, m.vertices)
    assert src.read_bytes() == before
    with pytest.raises(meshmorph.MeshmorphError, match="vertices:"):
        meshmorph.write_mesh(out, m, m.vertices[:3])


def test_read_markers_reads_named_points_and_pairs(tmp_path):
    (tmp_path / "a.txt").write_text('nose v 3 t 1 0.2 0.3 0.5\n"left eye" v 4 v 5\n')
    m = meshmorph.read_markers(tmp_path / "a.txt")
    assert len(m) == 2 and m.names == ["nose", "left eye"]
    assert m.pairs[0] == ({"vertex": 3}, {"triangle": 1, "barycentric": [0.2, 0.3, 0.5]})
    m.save(tmp_path / "b.txt")
    assert meshmorph.read_markers(tmp_path / "b.txt").pairs == m.pairs
    with pytest.raises(meshmorph.MeshmorphError, match="a.txt"):
        (tmp_path / "a.txt").write_text("nose v 3 t 1 0.5 0.5 0.5\n")
        meshmorph.read_markers(tmp_path / "a.txt")


def test_markers_from_points_land_on_the_vertices_they_name(tmp_path):
    vs, fs = sheet(8)
    vt, ft = sheet(11, scale=1.3)
    pick_s, pick_t = [0, 8, 72, 80, 40], [0, 11, 132, 143, 72]
    by_points = meshmorph.Markers.from_points(vs[pick_s], vt[pick_t], names=list("abcde"))
    assert len(by_points) == 5
    by_points.save(tmp_path / "m.txt")
    assert len(meshmorph.read_markers(tmp_path / "m.txt")) == 5
    a = meshmorph.correspond(vs, fs, vt, ft, by_points)
    b = meshmorph.correspond(vs, fs, vt, ft, np.stack([pick_s, pick_t], axis=1))
    assert np.array_equal(a.pairs, b.pairs)
    with pytest.raises(meshmorph.MeshmorphError, match="target:"):
        meshmorph.Markers.from_points(vs[pick_s], vt[pick_t[:4]])
    with pytest.raises(meshmorph.MeshmorphError, match="names:"):
        meshmorph.Markers.from_points(vs[pick_s], vt[pick_t], names=["a"])
    with pytest.raises(meshmorph.MeshmorphError, match="source:"):
        meshmorph.Markers.from_points(vs[pick_s][:, :2], vt[pick_t])


def test_a_trimesh_round_trip(tmp_path):
    trimesh = pytest.importorskip("trimesh")
    sphere = trimesh.creation.icosphere(subdivisions=3)
    stretched = sphere.vertices * [1.5, 1.0, 0.8]
    mid = meshmorph.Interpolator(sphere.vertices, stretched, sphere.faces).at(0.5)
    result = trimesh.Trimesh(mid, sphere.faces, process=False)
    assert result.is_watertight and result.volume > sphere.volume
    path = tmp_path / "mid.obj"
    result.export(path)
    back = meshmorph.read_mesh(path)
    loaded = trimesh.load(path, process=False)
    assert np.array_equal(back.vertices, loaded.vertices) and np.array_equal(back.faces, loaded.faces)


# ---------------------------------------------------------------- threads and memory

def rss():
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")


@pytest.mark.skipif(not Path("/proc/self/statm").exists(), reason="needs /proc")
def test_ten_thousand_calls_do_not_grow_memory():
    v, f = sheet(8)
    i = meshmorph.Interpolator(v, bent(v, 1.0), f)
    out = np.zeros_like(v)
    for _ in range(1000):
        i.at(0.5)
    before = rss()
    for k in range(10_000):
        i.at(k / 10_000)
        i.at(0.5, out=out)
        try:
            i.at(float("inf"))
        except meshmorph.MeshmorphError:
            pass
    assert rss() - before < 8 << 20
