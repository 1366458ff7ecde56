"""compatible_meshes: drawings (outlines with holes) to meshes with the same
triangles, every triangle positive in every mesh, the outline on the drawings,
the matching independent of where a loop starts; and every refusal naming its
argument and element."""

import numpy as np
import pytest

import meshmorph


def blob(n=60, turn=0.0, shift=(0.0, 0.0), start=0, scale=1.0):
    """An asymmetric wavy loop of n points, counter-clockwise, turned by `turn`
    radians about the origin, moved by `shift`, started `start` points later."""
    a = 2 * np.pi * np.arange(n) / n
    r = scale * (1 + 0.25 * np.cos(3 * a) + 0.1 * np.sin(5 * a + 1) + 0.4 * np.exp(-((a - 1.0) ** 2) / 0.05))
    p = np.stack([r * np.cos(a), r * np.sin(a)], axis=1)
    c, s = np.cos(turn), np.sin(turn)
    p = p @ np.array([[c, s], [-s, c]]) + np.asarray(shift)
    return np.roll(p, -start, axis=0)


def circle(n, r, centre=(0.0, 0.0), clockwise=False):
    a = 2 * np.pi * np.arange(n) / n
    if clockwise:
        a = -a
    return np.stack([centre[0] + r * np.cos(a), centre[1] + r * np.sin(a)], axis=1)


def signed_areas(v, f):
    e1, e2 = v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]]
    return 0.5 * (e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0])


def distance_to_loop(p, loop):
    """Distance from each point of p to the closed polyline `loop`."""
    a, b = loop, np.roll(loop, -1, axis=0)
    e = b - a
    s = np.clip(np.einsum("pkd,kd->pk", p[:, None, :] - a[None], e) / np.einsum("kd,kd->k", e, e), 0, 1)
    q = a[None] + s[..., None] * e[None]
    return np.linalg.norm(p[:, None, :] - q, axis=2).min(axis=1)


def check(result, drawings):
    """Same triangles, all positive in every mesh, every loop vertex on its drawing."""
    f = result.triangles
    assert f.dtype == np.int64 and f.ndim == 2 and f.shape[1] == 3
    assert len(result.vertices) == len(drawings) == len(result)
    n = result.vertices[0].shape[0]
    assert f.min() >= 0 and f.max() < n
    for v, drawing in zip(result.vertices, drawings):
        assert v.shape == (n, 2) and v.dtype == np.float64
        assert (signed_areas(v, f) > 0).all()
        size = np.linalg.norm(np.ptp(np.concatenate(drawing), axis=0))
        for loop in result.loops:
            d = np.min([distance_to_loop(v[loop], np.asarray(l, dtype=float)) for l in drawing], axis=0)
            assert d.max() < 1e-9 * size
    # Every given point is a vertex at exactly its position.
    for v, drawing, given in zip(result.vertices, drawings, result.given):
        for l, vertices in zip(drawing, given):
            np.testing.assert_array_equal(v[vertices], np.asarray(l, dtype=float))


def test_two_drawings():
    a, b = [blob(60)], [blob(45, turn=0.4, shift=(3, 1), scale=1.3)]
    result = meshmorph.compatible_meshes([a, b])
    check(result, [a, b])
    report = result.report
    assert report["triangles"] == result.triangles.shape[0]
    assert report["drawing_points"] == [60, 45]
    assert report["path"] in ("mapped", "overlay")
    assert min(report["min_angle_degrees"]) > 0
    assert isinstance(report["text"], str) and "triangles" in report["text"]
    assert "CompatibleMeshes" in repr(result)
    assert len(result.loops) == 1 and result.loops[0].dtype == np.int64


def test_a_hole_and_three_drawings():
    a = [circle(48, 2.0), circle(24, 0.8, (0.3, 0.2), clockwise=True)]
    b = [blob(60, scale=2.2), circle(30, 0.7, (0.2, 0.1))]  # the hole counter-clockwise: either way
    c = [circle(40, 2.0, (5, 0)), circle(20, 0.9, (5.2, -0.1), clockwise=True)]
    result = meshmorph.compatible_meshes([a, b, c])
    check(result, [a, b, c])
    assert len(result.loops) == 2
    assert len(result.given) == 3 and all(len(g) == 2 for g in result.given)


def test_float32_and_the_interpolator():
    a, b = [blob(50).astype(np.float32)], [blob(50, turn=2.0).astype(np.float32)]
    result = meshmorph.compatible_meshes([a, b])
    v0, v1 = result.vertices
    morph = meshmorph.Interpolator(v0, v1, result.triangles)
    np.testing.assert_allclose(morph.at(0.0), v0, atol=1e-9)
    np.testing.assert_allclose(morph.at(1.0), v1, atol=1e-9)
    assert (signed_areas(morph.at(0.5), result.triangles) > 0).all()


def test_rotation_start_point_invariance():
    """A shape and itself turned by 120 degrees: point i goes to point i turned,
    wherever the second loop starts."""
    turn = 2 * np.pi / 3
    a = blob(80)
    for start in (0, 17, 55):
        b = blob(80, turn=turn, shift=(4.0, -2.0), start=start)
        result = meshmorph.compatible_meshes([[a], [b]])
        check(result, [[a], [b]])
        va, vb = result.vertices
        c, s = np.cos(turn), np.sin(turn)
        turned = va @ np.array([[c, s], [-s, c]]) + [4.0, -2.0]
        loop = result.loops[0]
        np.testing.assert_allclose(vb[loop], turned[loop], atol=1e-6)
        # Each given point of the second drawing is where the first's went.
        np.testing.assert_array_equal(result.given[1][0], np.roll(result.given[0][0], -start))


def test_anchors():
    a, b = blob(60), blob(60, turn=0.3, scale=1.2)
    anchors = np.array([[a[0], b[20]]])
    result = meshmorph.compatible_meshes([[a], [b]], anchors=anchors)
    check(result, [[a], [b]])
    (k,) = result.anchors
    np.testing.assert_allclose(result.vertices[0][k], a[0], atol=1e-9)
    np.testing.assert_allclose(result.vertices[1][k], b[20], atol=1e-9)
    same = meshmorph.compatible_meshes([[a], [b]], anchors=None)
    assert same.anchors.shape == (0,)


def test_the_gil_is_released():
    """Two threads at once both finish, each with its own answer."""
    import threading

    drawings = [[[blob(200)], [blob(150, turn=2.5, scale=1.4)]], [[blob(120)], [blob(90, turn=-1.0)]]]
    results = [None, None]

    def run(k):
        results[k] = meshmorph.compatible_meshes(drawings[k])

    threads = [threading.Thread(target=run, args=(k,)) for k in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for r, d in zip(results, drawings):
        check(r, d)


@pytest.mark.parametrize(
    "drawings, anchors, message",
    [
        ("abc", None, "drawings: expected a list of 2 or more drawings"),
        ([[blob()]], None, "drawings: expected 2 or more drawings, got 1"),
        ([blob(), blob()], None, "drawings[0]: expected a list of loops"),
        ([[blob()], [blob()[:, :1]]], None, "drawings[1][0]: expected a (n, 2) or (n, 3)"),
        ([[blob()], [np.pad(blob(), ((0, 0), (0, 1)))]], None, "drawings[1][0]: expected 2 coordinates a vertex, got 3"),
        ([[blob()], [blob().astype(np.int64)]], None, "drawings[1][0]: expected a (n, 2) or (n, 3) float64 or float32"),
        ([[blob()], [np.where(np.arange(60)[:, None] == 7, np.nan, blob())]], None, "drawings[1][0]: vertex 7 has a coordinate that is not finite"),
        ([[blob()], [blob()[:2]]], None, "drawings[1]:"),
        ([[blob()], [np.array([[0.0, 0.0], [1.0, 1.0], [1.0, 0.0], [0.0, 1.0]])]], None, "drawings[1]:"),
        ([[blob()], [circle(40, 3), circle(10, 0.5, (0.5, 0))]], None, "the first drawing has 1 loop"),
        ([[blob()], [blob()]], np.zeros((2, 3, 2)), "anchors: expected the shape (k, 2, 2)"),
        ([[blob()], [blob()]], np.zeros((2, 2)), "anchors: expected a (k, 2, 2) float64 or float32 numpy array or None"),
        ([[blob()], [blob()]], np.array([[[np.inf, 0], [0, 0]]]), "anchors: anchors[0, 0] (anchor 1, its point on drawing 1) is not finite"),
        ([[blob()], [blob()]], np.array([[[0.0, 0.0], [1.0, 0.0]], [[10.0, 10.0], [1.0, 0.0]]]), "anchor"),
    ],
)
def test_refusals(drawings, anchors, message):
    with pytest.raises(meshmorph.MeshmorphError) as e:
        meshmorph.compatible_meshes(drawings, anchors)
    assert message in str(e.value)
    assert isinstance(e.value, ValueError)


def spiral_band(n=160, width=0.12):
    """A thick band along a spiral, n points round, counter-clockwise."""
    def centre(t):
        a = 0.5 + 3.2 * np.pi * t
        r = 0.3 + 0.25 * a
        return np.stack([r * np.cos(a), r * np.sin(a)], axis=-1)

    def side(t, sign):
        d = centre(np.minimum(t + 1e-4, 1.0)) - centre(np.maximum(t - 1e-4, 0.0))
        d /= np.linalg.norm(d, axis=-1, keepdims=True)
        return centre(t) + sign * width * np.stack([-d[:, 1], d[:, 0]], axis=-1)

    half = n // 2
    t = np.linspace(0.0, 1.0, half)
    return np.concatenate([side(t, -1.0), side(t[::-1][: n - half], 1.0)])


def test_mend_folds_leaves_no_triangle_turned_over_inside_and_keeps_the_outline():
    """A round drawing into a thin spiral band: the fit turns triangles over
    inside; mend_folds=True moves the inside only where they are."""
    a, b = [blob(90)], [spiral_band()]
    result = meshmorph.compatible_meshes([a, b])
    v0, v1 = result.vertices
    f = result.triangles
    fit = meshmorph.Interpolator(v0, v1, f)
    mended = meshmorph.Interpolator(v0, v1, f, mend_folds=True)
    outline = np.concatenate(result.loops)
    inside = ~np.isin(f, outline).any(axis=1)
    ts = np.linspace(0.0, 1.0, 11)
    x, y = fit.frames(ts), mended.frames(ts)
    turned = lambda v: signed_areas(v, f) <= 0
    assert sum(turned(k).sum() for k in x) > 0, "the pair no longer folds: choose another"
    for k, (xk, yk) in enumerate(zip(x, y)):
        assert not (turned(yk) & inside).any(), f"frame {k}"
        np.testing.assert_array_equal(xk[outline], yk[outline])
        if not turned(xk).any():
            np.testing.assert_array_equal(xk, yk)
    with pytest.raises(meshmorph.MeshmorphError, match="mend_folds"):
        meshmorph.Interpolator(v0, v1, f, mend_folds="yes")


def outline_crosses(p):
    """Whether the closed polyline p has two edges, not neighbours, that cross
    (each pair's orientations at once, as arrays)."""
    p = np.asarray(p, dtype=float)
    n = len(p)
    a, b = p, np.roll(p, -1, axis=0)
    i, j = np.triu_indices(n, 2)
    keep = (j + 1) % n != i
    i, j = i[keep], j[keep]

    def orient(u, v, w):
        return (v[:, 0] - u[:, 0]) * (w[:, 1] - u[:, 1]) - (v[:, 1] - u[:, 1]) * (w[:, 0] - u[:, 0])

    ai, bi, aj, bj = a[i], b[i], a[j], b[j]
    return bool(
        ((orient(ai, bi, aj) * orient(ai, bi, bj) < 0) & (orient(aj, bj, ai) * orient(aj, bj, bi) < 0)).any()
    )


def spiky(n, seed):
    """A random star-shaped polygon of n points, counter-clockwise."""
    rng = np.random.default_rng(seed)
    a = np.sort(rng.uniform(0.0, 2 * np.pi, n))
    r = rng.uniform(0.4, 1.0, n)
    return np.stack([r * np.cos(a), r * np.sin(a)], axis=1)


def test_untie_outlines_leaves_no_outline_crossed_and_keeps_simple_frames():
    """Spiky polygons into a spiral band: the fit twists short stretches of
    the outline through themselves in some frames; untie_outlines=True cuts
    them, moving a few outline points, and leaves frames whose outline is
    simple as the fit made them, the keys to the bit."""
    knotted = 0
    for seed in range(3):
        result = meshmorph.compatible_meshes([[spiky(50, seed)], [spiral_band()]])
        v0, v1 = result.vertices
        f, loop = result.triangles, np.asarray(result.loops[0])
        fit = meshmorph.Interpolator(v0, v1, f)
        untied = meshmorph.Interpolator(v0, v1, f, untie_outlines=True)
        for t in np.linspace(0.0, 1.0, 11):
            x, y = fit.at(t), untied.at(t)
            assert not outline_crosses(y[loop]), f"seed {seed}, t = {t}"
            if outline_crosses(x[loop]):
                knotted += 1
                assert (np.linalg.norm(x - y, axis=1) > 0).sum() <= len(loop) // 8
            else:
                np.testing.assert_array_equal(x, y)
        np.testing.assert_array_equal(untied.at(1.0), v1)
    assert knotted > 0, "the pairs no longer knot: choose others"
    with pytest.raises(meshmorph.MeshmorphError, match="untie_outlines"):
        meshmorph.Interpolator(v0, v1, f, untie_outlines=2)


def test_area_stretch_keeps_an_unlike_pair_near_the_blended_area():
    """A spiky polygon into a thick band: the paper's linear blend of the
    stretches swells the middle frames above the straight blend of the two
    areas; stretch="area" (as drawings and pictures are morphed) keeps each
    triangle's area on that blend, the frames near it, the keys exact."""
    def area(p):
        return 0.5 * abs(np.dot(p[:, 0], np.roll(p[:, 1], -1)) - np.dot(p[:, 1], np.roll(p[:, 0], -1)))

    result = meshmorph.compatible_meshes([[spiky(50, 1)], [spiral_band()]])
    v0, v1 = result.vertices
    f, loop = result.triangles, np.asarray(result.loops[0])
    linear = meshmorph.Interpolator(v0, v1, f, untie_outlines=True)
    kept = meshmorph.Interpolator(v0, v1, f, untie_outlines=True, stretch="area")
    ends = area(v0[loop]), area(v1[loop])
    for t in np.linspace(0.0, 1.0, 11):
        blend = (1 - t) * ends[0] + t * ends[1]
        by_linear, by_kept = area(linear.at(t)[loop]) / blend, area(kept.at(t)[loop]) / blend
        assert by_kept <= max(by_linear, 1.0) + 1e-9, f"t = {t}: {by_kept} against {by_linear}"
    np.testing.assert_allclose(kept.at(1.0), v1, atol=1e-9 * np.ptp(v1))


def test_outline_lengths_keep_the_edges_on_their_blend_and_the_area():
    """A star into a spiral band: the fit alone shortens the outline's edges
    (several per cent off the blend of their lengths at half-way);
    outline_lengths=True puts them within a per cent or two of it, with the
    outline's area the fit's, and the keys to the bit."""
    result = meshmorph.compatible_meshes([[spiky(60, 7)], [spiral_band()]])
    v0, v1 = result.vertices
    f, loop = result.triangles, np.asarray(result.loops[0])
    fit = meshmorph.Interpolator(v0, v1, f, stretch="area")
    kept = meshmorph.Interpolator(v0, v1, f, stretch="area", outline_lengths=True)

    def lengths(x):
        return np.linalg.norm(x[np.roll(loop, -1)] - x[loop], axis=1)

    def area(x):
        p, q = x[loop], x[np.roll(loop, -1)]
        return 0.5 * abs((p[:, 0] * q[:, 1] - q[:, 0] * p[:, 1]).sum())

    def off(x, t):
        blend = (1 - t) * lengths(v0) + t * lengths(v1)
        return np.mean(np.abs(lengths(x) - blend) / blend)

    assert off(fit.at(0.5), 0.5) > 0.03, "the fit no longer shortens the edges: choose another pair"
    for t in np.linspace(0.1, 0.9, 9):
        x, y = fit.at(t), kept.at(t)
        assert off(y, t) < 0.5 * off(x, t), f"t = {t}"
        assert abs(area(y) / area(x) - 1) < 1e-9, f"t = {t}"
    np.testing.assert_array_equal(kept.at(0.0), v0)
    np.testing.assert_array_equal(kept.at(1.0), v1)
    with pytest.raises(meshmorph.MeshmorphError, match="outline_lengths"):
        meshmorph.Interpolator(v0, v1, f, outline_lengths="yes")
