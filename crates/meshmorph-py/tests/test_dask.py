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
