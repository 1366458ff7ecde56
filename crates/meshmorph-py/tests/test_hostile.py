"""What a hostile or careless caller gives the module: sizes that cannot
fit (broadcast arrays that own no memory), Ctrl-C in the middle of a long
call, a fork after parallel work, arguments of the wrong kind, and output
paths that are not regular files. Each is refused with a sentence naming
the argument, or handled; none aborts, panics, hangs or waits for the end
of the work. No check here depends on how fast the machine is."""

import _thread
import multiprocessing
import os
import signal
import stat
import sys
import threading
import time

import numpy as np
import pytest

import meshmorph

from test_meshmorph import bent, sheet

# Far more than any machine has: 2**40 rows of 3 float64 are 26 TB.
HUGE = 2**40


@pytest.fixture(scope="module")
def small():
    v, f = sheet(6)
    return v, f, meshmorph.Interpolator(v, bent(v, 1.0), f)


@pytest.fixture(scope="module")
def transfer():
    vs, fs = sheet(8)
    vt, ft = sheet(10, 1.3)
    c = meshmorph.correspond(vs, fs, vt, ft, np.array([[0, 0], [8, 10], [72, 110], [80, 120]]))
    return vs, fs, vt, ft, c, meshmorph.Transfer(vs, fs, vt, ft, c)


# ---------------------------------------------------------------- sizes

def broadcast(row, rows):
    return np.broadcast_to(np.asarray(row), (rows,) + np.shape(row))


@pytest.mark.parametrize(
    "call, arg",
    [
        (lambda v, f, i, t: meshmorph.Interpolator(broadcast(v[0], HUGE), v, f), "v0"),
        (lambda v, f, i, t: meshmorph.Interpolator(v, v, broadcast(f[0], HUGE)), "f"),
        (lambda v, f, i, t: meshmorph.Sequence(broadcast(v, 2**36), f), "keys"),
        (lambda v, f, i, t: meshmorph.Blend(v, broadcast(v, 2**36), f), "shapes"),
        # Frames that would not fit: their times first (the 10**7
        # frames are 2**33 here, so that no machine has room for them).
        (lambda v, f, i, t: i.frames(broadcast(0.5, 2**33)), "ts"),
        (lambda v, f, i, t: i.frames(np.broadcast_to(0.5, HUGE)), "ts"),
        (lambda v, f, i, t: t.apply_all(broadcast(np.zeros((81, 3)), 2**34)), "poses"),
        (lambda v, f, i, t: meshmorph.deformation_gradients(v, broadcast(f[0], HUGE), v), "f"),
        (lambda v, f, i, t: meshmorph.GradientSolver(v, broadcast(f[0], 2**36)), "f"),
        (lambda v, f, i, t: meshmorph.correspond(v, f, v, f, broadcast(np.array([0, 0]), HUGE)), "markers"),
        (lambda v, f, i, t: meshmorph.Markers.from_points(broadcast(v[0], HUGE), v), "source"),
    ],
)
def test_sizes_that_cannot_fit_are_refused_naming_the_argument_before_any_copy(small, transfer, call, arg):
    v, f, i = small
    with pytest.raises(MemoryError, match=f"^{arg}: .* would take about .* of memory"):
        call(v, f, i, transfer[-1])


def test_a_sequence_that_claims_a_huge_length_is_refused(small):
    v, f, i = small

    class Claims:
        def __len__(self):
            return 2**62

        def __iter__(self):
            return iter([0.5])

    with pytest.raises(MemoryError, match="^ts: "):
        i.frames(Claims())
    with pytest.raises(MemoryError, match="^names: "):
        meshmorph.Markers.from_points(v[:1], v[:1], names=Claims())


def test_a_sequence_that_understates_its_length_is_refused(small):
    """Sized by len(), then iterated: the items past it are not taken (an
    endless iterator behind a small len() once grew until memory ran out)."""
    v, f, i = small

    class Understates:
        def __len__(self):
            return 1

        def __getitem__(self, k):  # endless, as iter() uses it
            return 0.5

    with pytest.raises(meshmorph.MeshmorphError, match="^ts: its len\\(\\) says 1 items, but iterating it gives more"):
        i.frames(Understates())

    class Names(Understates):
        def __getitem__(self, k):
            return "n"

    with pytest.raises(meshmorph.MeshmorphError, match="^names: its len"):
        meshmorph.Markers.from_points(v[:1], v[:1], names=Names())


# ---------------------------------------------------------------- Ctrl-C

@pytest.fixture
def ctrl_c_raises():
    """Ctrl-C raises KeyboardInterrupt, as in a terminal: a process started
    in the background by a shell without job control inherits SIGINT
    ignored, and Python then keeps it ignored."""
    before = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, before)


def test_ctrl_c_stops_a_long_frames_call_between_frames(ctrl_c_raises):
    v, f = sheet(40)
    v = v + 10.0  # no coordinate is 0: a frame written is not all zeros
    i = meshmorph.Interpolator(v, bent(v, 1.5) * [1.3, 1.0, 0.8], f, stretch="log")
    k = 8_000  # seconds of work on two cores; only a few frames are made
    # Pages of numpy's zeros are not taken until written: only the frames
    # made before the interrupt take memory.
    out = np.zeros((k, len(v), 3))
    written = lambda: int(np.count_nonzero(out[:, 0, 0]))
    stop = threading.Event()

    def interrupt_once_frames_come():
        while not stop.is_set():
            if written() > 0:
                os.kill(os.getpid(), signal.SIGINT)
                return
            stop.wait(0.001)

    thread = threading.Thread(target=interrupt_once_frames_come)
    thread.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            i.frames(np.linspace(0.0, 1.0, k), out=out)
    finally:
        stop.set()
        thread.join()
    assert 0 < written() < k


def test_ctrl_c_stops_apply_all_between_poses_even_with_a_slow_progress_callback(transfer, ctrl_c_raises):
    vs, fs, vt, ft, c, t = transfer
    poses = np.stack([bent(vs, a) for a in np.linspace(0.0, 1.5, 400)])
    calls = []

    def slow(done, total):
        calls.append(done)
        if len(calls) == 3:
            _thread.interrupt_main()
        threading.Event().wait(0.01)

    with pytest.raises(KeyboardInterrupt):
        t.apply_all(poses, progress=slow)
    assert 3 <= len(calls) < len(poses)
    # The module works on after the interrupt.
    assert np.array_equal(t.apply_all(poses[:2]), np.stack([t.apply(poses[0]), t.apply(poses[1])]))


# ---------------------------------------------------------------- fork

def work_in_child(seed):
    """Work of every kind, parallel or not: a sequence's frames and one
    shape, a correspondence, a transfer's poses and one pose, a gradient
    solve. Returns a figure of the results."""
    v, f = sheet(10)
    keys = np.stack([v, bent(v, 0.8), bent(v, 1.6)])
    s = meshmorph.Sequence(keys, f)
    frames = s.frames(np.linspace(0.0, 2.0, 24))
    c = meshmorph.correspond(v, f, v * 1.5, f, np.array([[0, 0], [10, 10], [110, 110], [120, 120]]))
    t = meshmorph.Transfer(v, f, v * 1.5, f, c)
    moved = t.apply_all(keys)
    j = meshmorph.deformation_gradients(v, f, keys[1])
    solved = meshmorph.GradientSolver(v, f).solve(j)
    return float(frames.sum() + s.at(0.5).sum() + moved.sum() + t.apply(keys[2]).sum() + solved.sum() + seed)


@pytest.mark.filterwarnings("ignore::DeprecationWarning")
def test_a_pool_of_forked_processes_runs_parallel_calls_after_the_parent_did():
    expected = work_in_child(0)  # the parent's threads are started
    with multiprocessing.get_context("fork").Pool(2) as pool:
        got = pool.map_async(work_in_child, [0, 0]).get(timeout=120)
    assert got == [expected, expected]


@pytest.mark.filterwarnings("ignore::DeprecationWarning")
def test_os_fork_after_a_parallel_call_gives_a_child_that_works():
    expected = work_in_child(0)
    read, write = os.pipe()
    pid = os.fork()
    if pid == 0:
        code = 1
        try:
            os.close(read)
            os.write(write, repr(work_in_child(0)).encode())
            code = 0
        finally:
            os._exit(code)
    os.close(write)
    done = threading.Event()
    # A child that hangs is killed after two minutes: the test fails, pytest goes on.
    watchdog = threading.Timer(120, lambda: done.is_set() or os.kill(pid, signal.SIGKILL))
    watchdog.start()
    try:
        answer = b""
        while chunk := os.read(read, 4096):
            answer += chunk
        _, status = os.waitpid(pid, 0)
    finally:
        done.set()
        watchdog.cancel()
        os.close(read)
    assert os.WIFEXITED(status) and os.WEXITSTATUS(status) == 0, status
    assert float(answer) == expected


# ---------------------------------------------------------------- messages

@pytest.mark.parametrize(
    "call, says",
    [
        (lambda v, f, i: meshmorph.Interpolator(v, v, f, turns=2**40), "turns: 1099511627776 (an int) is out of range"),
        (lambda v, f, i: meshmorph.Sequence(np.stack([v, v]), f, turns=-(2**31) - 1), "turns: -2147483649 (an int) is out of range"),
        (lambda v, f, i: meshmorph.Interpolator(v, v, f, turns=1.5), "turns: expected a whole number, got 1.5 (a float)"),
        (lambda v, f, i: meshmorph.Blend(v, np.stack([v]), f, turns="2"), "turns: expected a whole number"),
        (lambda v, f, i: meshmorph.Interpolator(v, v, f, consistency="yes"), "consistency: expected True or False"),
        (lambda v, f, i: meshmorph.Interpolator(v, v, f, stretch=3), "stretch: expected \"linear\" or \"log\" or \"area\", got 3"),
        (lambda v, f, i: i.frames("abc"), "ts: expected a sequence of numbers (a list or a 1-D numpy array), got 'abc' (a str)"),
        (lambda v, f, i: i.frames(5), "ts: expected a sequence of numbers"),
        (lambda v, f, i: i.frames([0.1, "x"]), "ts[1]: expected a number, got 'x' (a str)"),
        (lambda v, f, i: i.frames([0.1, float("nan")]), "ts[1]: NaN is not a finite number"),
        (lambda v, f, i: i.frames(np.array([0.0, np.inf])), "ts[1]: inf is not a finite number"),
        (lambda v, f, i: i.frames(np.zeros((2, 2))), "ts: expected a sequence of numbers"),
        (lambda v, f, i: i.at("0.5"), "t: expected a number, got '0.5' (a str)"),
        (lambda v, f, i: i.at(1j), "t: expected a number"),
        (lambda v, f, i: meshmorph.Sequence(np.stack([v, v]), f).frames(b"ab"), "ss: expected a sequence of numbers"),
        (lambda v, f, i: meshmorph.Sequence(np.stack([v, v]), f).at(None), "s: expected a number"),
        (lambda v, f, i: meshmorph.Blend(v, np.stack([v]), f).at("1"), "weights: expected a sequence of numbers"),
        (lambda v, f, i: meshmorph.Blend(v, np.stack([v]), f).at([None]), "weights[0]: expected a number"),
        (lambda v, f, i: meshmorph.Sequence(np.stack([v, np.where(np.arange(len(v))[:, None] == 7, np.nan, v)]), f), "keys[1]: vertex 7 has a coordinate that is not finite"),
        (lambda v, f, i: meshmorph.Sequence(np.full((2,) + v.shape, np.inf, np.float32), f), "keys[0]: vertex 0 has a coordinate that is not finite"),
        (lambda v, f, i: meshmorph.Blend(v, np.stack([v, np.where(np.arange(len(v))[:, None] == 3, np.inf, v)]), f), "shapes[1]: vertex 3 has a coordinate that is not finite"),
        (lambda v, f, i: meshmorph.Sequence(np.stack([v, v])[:, :, :1].copy(), f), "keys: expected a (k, n, 2) or (k, n, 3) float64 or float32 numpy array, got a (2, 49, 1) float64 array"),
        (lambda v, f, i: meshmorph.correspond(v, f, v, f, [[0, 0], [1, "x"]]), "markers[1]: expected a pair of vertex indices"),
        (lambda v, f, i: meshmorph.correspond(v, f, v, f, np.zeros((3, 2))), "markers: expected a (m, 2) int32, int64 or uint32 numpy array, got a (3, 2) float64 array"),
        (lambda v, f, i: meshmorph.correspond(v, f, v, f, None, align="no"), "align: expected True or False"),
        (lambda v, f, i: meshmorph.correspond(v, f, v, f, None, identity_weight="big"), "identity_weight: expected a number"),
        (lambda v, f, i: meshmorph.correspond(v, f, v, f, None, match_threshold=float("inf")), "match_threshold: inf is not a finite number"),
        (lambda v, f, i: meshmorph.correspond(v, f, v, f, None, progress=3), "progress: expected a callable progress(done, total) or None, got 3 (an int)"),
        (lambda v, f, i: meshmorph.Transfer(v, f, v, f, "c"), "correspondence: expected a Correspondence"),
        (lambda v, f, i: meshmorph.positions_from_gradients(v, f, [[1.0]]), "j: expected a (72, 3, 3) float64 or float32 numpy array, got a list"),
        (lambda v, f, i: meshmorph.read_mesh(3), "path: expected a path"),
        (lambda v, f, i: meshmorph.read_markers("a.txt", 3), "target_path: expected a path"),
        (lambda v, f, i: meshmorph.read_markers("a.txt", one_based="1"), "one_based: expected True or False"),
        (lambda v, f, i: meshmorph.write_mesh("x.obj", "mesh", v), "mesh: expected a Mesh"),
        (lambda v, f, i: meshmorph.Correspondence.load(None), "path: expected a path"),
        (lambda v, f, i: meshmorph.Markers.from_points(v[:2], v[:2], names=["a", 2]), "names[1]: expected a str or None, got 2 (an int)"),
        (lambda v, f, i: meshmorph.Markers.from_points(v[:2], v[:2], names="ab"), "names: expected a list of names"),
    ],
)
def test_every_refusal_names_the_argument_and_what_is_wrong(small, call, says):
    v, f, i = small
    with pytest.raises(meshmorph.MeshmorphError) as caught:
        call(v, f, i)
    assert str(caught.value).startswith(says), str(caught.value)


def test_apply_all_refuses_a_progress_that_is_not_callable_before_the_work(transfer):
    vs, fs, vt, ft, c, t = transfer
    with pytest.raises(meshmorph.MeshmorphError, match="^progress: expected a callable"):
        t.apply_all(np.stack([vs]), progress="print")


def test_the_defaults_still_hold_and_are_shown(small):
    v, f, i = small
    w = bent(v, 1.0)
    assert np.array_equal(meshmorph.Interpolator(v, w, f, consistency=True, turns=0, stretch="linear").at(0.3), i.at(0.3))
    assert np.array_equal(meshmorph.Interpolator(v, w, f, turns=np.int64(0), consistency=np.bool_(True)).at(0.3), i.at(0.3))
    assert np.array_equal(i.frames(range(2)), i.frames([0.0, 1.0]))
    assert np.array_equal(i.frames((np.float32(0.5),)), i.frames(np.array([0.5], np.float32)))
    assert "turns=0" in meshmorph.Interpolator.__text_signature__


def test_markers_from_named_points_keep_their_names_and_positions(tmp_path):
    v, f = sheet(6)
    picks = [0, 6, 42, 48]
    m = meshmorph.Markers.from_points(v[picks], v[picks] * 2, names=["a", None, 'say "b"', "c\\d"])
    assert len(m) == 4
    assert m.names == ["a", None, 'say "b"', "c\\d"]
    assert m.pairs == [({"position": v[p].tolist()}, {"position": (v[p] * 2).tolist()}) for p in picks]
    m.save(tmp_path / "m.txt")
    again = meshmorph.read_markers(tmp_path / "m.txt")
    assert again.names == m.names and again.pairs == m.pairs
    # Once put on the surfaces, they name vertices.
    c = meshmorph.correspond(v, f, v * 2, f, m)
    assert c.pairs.shape[1] == 2


# ---------------------------------------------------------------- output paths

def not_regular_files(tmp_path):
    """Paths that exist and are not regular files, with how to check that
    each is left as it was."""
    fifo = tmp_path / "fifo.obj"
    os.mkfifo(fifo)
    found = {
        "a FIFO": (fifo, stat.S_ISFIFO),
        "a link to a FIFO": (tmp_path / "to-fifo.obj", stat.S_ISFIFO),
        "a link to /dev/null": (tmp_path / "to-null.obj", stat.S_ISCHR),
        "a folder": (tmp_path / "folder.obj", stat.S_ISDIR),
    }
    os.symlink(fifo, tmp_path / "to-fifo.obj")
    os.symlink("/dev/null", tmp_path / "to-null.obj")
    os.mkdir(tmp_path / "folder.obj")
    try:
        os.mknod(tmp_path / "null.obj", 0o666 | stat.S_IFCHR, os.makedev(1, 3))
        found["a copy of /dev/null"] = (tmp_path / "null.obj", stat.S_ISCHR)
    except PermissionError:
        pass  # mknod needs root
    return found


def test_writing_over_what_is_not_a_regular_file_is_refused_naming_the_path(tmp_path):
    src = tmp_path / "tri.obj"
    src.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    mesh = meshmorph.read_mesh(src)
    markers = meshmorph.Markers.from_points(mesh.vertices[:1], mesh.vertices[:1])
    v, f = sheet(4)
    c = meshmorph.correspond(v, f, v, f, np.array([[0, 0], [4, 4], [20, 20]]))
    for what, (path, kind) in not_regular_files(tmp_path).items():
        for name, write in [
            ("write_mesh", lambda p: meshmorph.write_mesh(p, mesh, mesh.vertices * 2)),
            ("Markers.save", markers.save),
            ("Correspondence.save", c.save),
        ]:
            with pytest.raises(meshmorph.MeshmorphError) as caught:
                write(path)
            message = str(caught.value)
            assert message.startswith(f"path: `{path}`: ") and "not a regular file" in message, (what, name, message)
            assert kind(os.stat(path).st_mode), (what, name)
    # A link to a regular file is written through.
    os.symlink(tmp_path / "out.obj", tmp_path / "to-out.obj")
    (tmp_path / "out.obj").write_text("old\n")
    meshmorph.write_mesh(tmp_path / "to-out.obj", mesh, mesh.vertices * 2)
    assert np.array_equal(meshmorph.read_mesh(tmp_path / "to-out.obj").vertices, mesh.vertices * 2)


# ---------------------------------------------------------------- the GIL

def test_a_python_thread_runs_while_apply_and_apply_all_work(transfer):
    """The GIL released by the work itself, seen without timing anything:
    with a switch interval of minutes, a thread that counts in Python can
    only take the GIL when the main thread lets it go, and the count can
    only move during a call that releases it."""
    vs, fs, vt, ft, c, t = transfer
    poses = np.stack([bent(vs, a) for a in np.linspace(0.0, 1.5, 16)])
    count = [0]
    stop = threading.Event()

    def counter():
        while not stop.is_set():
            count[0] += 1
            time.sleep(0)  # lets the GIL go, as the main thread waits for it

    calls = {"apply": lambda: t.apply(poses[5]), "apply_all": lambda: t.apply_all(poses)}
    moved = dict.fromkeys(calls, 0)
    interval = sys.getswitchinterval()
    sys.setswitchinterval(300)
    thread = threading.Thread(target=counter)
    thread.start()
    try:
        # A call may end before the thread wakes: until the count has moved
        # during each, a thousand calls at most.
        for _ in range(1000):
            for name, call in calls.items():
                if moved[name] == 0:
                    before = count[0]
                    call()
                    moved[name] = count[0] - before
            if all(moved.values()):
                break
    finally:
        stop.set()
        thread.join()
        sys.setswitchinterval(interval)
    assert all(moved.values()), moved
