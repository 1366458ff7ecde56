"""morph_pictures: one picture into another from numpy arrays, as the command line's
`interpolate a.png b.png` does: the ends are the pictures, the middle is between them, sprites
are traced and photos morph their rectangles (anchors driving the inside), and every refusal
names its argument."""

import numpy as np
import pytest

import meshmorph


def ring(width, height, centre, radii, hole, colour):
    """An RGBA uint8 sprite: an elliptical disc with a round hole, its edges anti-aliased
    (alpha = coverage, estimated on 4 × 4 samples a pixel), transparent pixels all zero."""
    s = (np.arange(4) + 0.5) / 4
    ys = (np.arange(height)[:, None] + s[None, :]).reshape(-1)
    xs = (np.arange(width)[:, None] + s[None, :]).reshape(-1)
    x, y = np.meshgrid(xs, ys)
    inside = ((x - centre[0]) / radii[0]) ** 2 + ((y - centre[1]) / radii[1]) ** 2 <= 1
    inside &= (x - centre[0]) ** 2 + (y - centre[1]) ** 2 >= hole**2
    cover = inside.reshape(height, 4, width, 4).mean(axis=(1, 3))
    alpha = np.round(255 * cover).astype(np.uint8)
    rgba = np.zeros((height, width, 4), np.uint8)
    rgba[..., :3] = np.where(alpha[..., None] > 0, np.asarray(colour, np.uint8), 0)
    rgba[..., 3] = alpha
    return rgba


def sprites():
    a = ring(64, 64, (32, 32), (22, 22), 8, (220, 40, 30))
    b = ring(64, 64, (30, 34), (18, 26), 7, (30, 60, 210))
    return a, b


def photo(width, height, phase):
    """An opaque RGB picture: smooth stripes and a bright square."""
    y, x = np.mgrid[0:height, 0:width]
    rgb = np.stack(
        [
            128 + 100 * np.sin(x / 5 + phase),
            128 + 100 * np.cos(y / 7 - phase),
            np.full_like(x, 90, dtype=float),
        ],
        axis=-1,
    )
    rgb[10:20, 12 + int(4 * phase) : 22 + int(4 * phase)] = 255
    return np.round(rgb).astype(np.uint8)


def test_sprites_ends_are_the_pictures():
    a, b = sprites()
    frames = meshmorph.morph_pictures(a, b, 5)
    assert frames.shape == (5, 64, 64, 4) and frames.dtype == np.uint8
    assert np.array_equal(frames[0], a)
    assert np.array_equal(frames[-1], b)


def test_middle_frame_alpha_area_is_between():
    a, b = sprites()
    frames = meshmorph.morph_pictures(a, b, 3)
    area = [f[..., 3].astype(float).sum() / 255 for f in (a, frames[1], b)]
    blend = (area[0] + area[2]) / 2
    assert abs(area[1] - blend) < 0.05 * blend
    # The hole stays a hole: the pixel at the middle of both holes is transparent.
    assert frames[1][33, 31, 3] == 0
    # Its colour is the blend of the two: half red, half blue where opaque.
    opaque = frames[1][..., 3] == 255
    assert opaque.sum() > 0.5 * area[1]
    red, blue = frames[1][opaque][:, 0].astype(int), frames[1][opaque][:, 2].astype(int)
    assert np.all(np.abs(red - 125) <= 2) and np.all(np.abs(blue - 120) <= 2)


def test_dissolve_and_size():
    a, b = sprites()
    frames = meshmorph.morph_pictures(a, b, 3, dissolve=(1.0, 1.0), size=(32, 40))
    assert frames.shape == (3, 40, 32, 4)
    # Until the end the colours are the first picture's alone: no blue.
    opaque = frames[1][..., 3] > 0
    assert opaque.any() and np.all(frames[1][opaque][:, 2] == 30)


def test_report():
    a, b = sprites()
    frames, report = meshmorph.morph_pictures(a, b, 2, return_report=True)
    assert frames.shape == (2, 64, 64, 4)
    assert report["shape"] == "sprite"
    assert report["frame_size"] == (64, 64)
    assert report["triangles"] > 20 and report["vertices"] > 20
    assert min(report["min_angle_degrees"]) > 5
    assert report["anchors"] == 0 and report["left_out"] == (0, 0)
    assert report["faint_left_out"] == (0, 0)
    assert all(n >= 8 for n in report["outline_points"])
    assert "triangles" in report["text"]
    # A soft shadow under half opaque around b: counted as left out.
    shadowed = b.copy()
    shadowed[..., 3] = np.where(shadowed[..., 3] == 0, 50, shadowed[..., 3])
    _, report = meshmorph.morph_pictures(a, shadowed, 2, return_report=True)
    assert report["faint_left_out"][0] == 0 and report["faint_left_out"][1] > 1000


def test_photos_with_anchors():
    a, b = photo(64, 48, 0.0), photo(64, 48, 1.0)
    anchors = np.array([[[17.0, 15.0], [21.0, 15.0]], [[40.0, 30.0], [38.0, 33.0]]])
    frames, report = meshmorph.morph_pictures(a, b, 4, anchors, return_report=True)
    assert report["shape"] == "photo" and report["anchors"] == 2
    assert frames.shape == (4, 48, 64, 4)
    opaque = lambda rgb: np.concatenate([rgb, np.full(rgb.shape[:2] + (1,), 255, np.uint8)], axis=-1)
    assert np.array_equal(frames[0], opaque(a))
    assert np.array_equal(frames[-1], opaque(b))
    # Opaque inside; the border is the photos' own soft edge, carried.
    assert np.all(frames[1:-1, 3:-3, 3:-3, 3] == 255)
    # Two (k, 2) arrays mean the same as one (k, 2, 2).
    pair = (anchors[:, 0].astype(np.float32), anchors[:, 1].astype(np.float32))
    assert np.array_equal(meshmorph.morph_pictures(a, b, 4, pair), frames)


def test_frame_only_morphs_sprites_as_rectangles():
    a, b = sprites()
    _, report = meshmorph.morph_pictures(a, b, 2, frame_only=True, return_report=True)
    assert report["shape"] == "photo"


def test_one_frame_is_the_first_picture():
    a, b = sprites()
    frames = meshmorph.morph_pictures(a, b, 1)
    assert frames.shape == (1, 64, 64, 4) and np.array_equal(frames[0], a)


@pytest.mark.parametrize(
    "change, words",
    [
        (lambda a: a[..., 0], ["a:", "(height, width, 4)"]),
        (lambda a: np.zeros((8, 8, 5), np.uint8), ["a:", "(8, 8, 5)"]),
        (lambda a: a.astype(np.float64) / 255, ["a:", "uint8", "float64"]),
        (lambda a: a.tolist(), ["a:", "list"]),
        (lambda a: np.zeros((0, 8, 4), np.uint8), ["a:", "empty"]),
        (lambda a: np.zeros((16, 16, 4), np.uint8), ["`a`", "fully transparent"]),
        (lambda a: a[..., :3], ["`b`", "has transparency", "frame_only=True"]),
    ],
)
def test_refuses_bad_pictures(change, words):
    a, b = sprites()
    with pytest.raises(meshmorph.MeshmorphError) as e:
        meshmorph.morph_pictures(change(a), b, 3)
    for w in words:
        assert w in str(e.value)


@pytest.mark.parametrize(
    "anchors, words",
    [
        (np.array([[[10.0, 10.0], [70.0, 10.0]]]), ["anchor 1", "`b`", "outside the picture"]),
        (np.array([[[-1.0, 10.0], [10.0, 10.0]]]), ["anchor 1", "`a`", "outside the picture"]),
        (np.array([[[np.nan, 10.0], [10.0, 10.0]]]), ["anchors:", "anchors[0, 0] (anchor 1", "not finite"]),
        ((np.zeros((2, 2)), np.zeros((3, 2))), ["anchors:", "2 points on a but 3 on b"]),
        ((np.zeros((2, 2)),), ["anchors:", "a sequence of 1"]),
        ((np.zeros((2, 2)), np.zeros((2, 3))), ["anchors[1]:"]),
        (np.zeros((2, 3, 2)), ["anchors:", "(k, 2, 2)"]),
        (np.zeros((2, 2, 2), np.int64), ["anchors:", "int64"]),
    ],
)
def test_refuses_bad_anchors(anchors, words):
    a, b = photo(64, 48, 0.0), photo(64, 48, 1.0)
    with pytest.raises(meshmorph.MeshmorphError) as e:
        meshmorph.morph_pictures(a, b, 3, anchors)
    for w in words:
        assert w in str(e.value)


@pytest.mark.parametrize(
    "arguments, words",
    [
        (dict(frames=0), ["frames:", "from 1 to"]),
        (dict(frames=-3), ["frames:", "from 1 to"]),
        (dict(frames=10**12), ["frames:", "from 1 to"]),
        (dict(frames=2.5), ["frames:", "whole number"]),
        (dict(frames=True), ["frames:", "whole number"]),
        (dict(frames=3, dissolve=(0.2, 1.5)), ["dissolve:", "fractions"]),
        (dict(frames=3, dissolve=0.5), ["dissolve:", "(start, end)"]),
        (dict(frames=3, dissolve=(0.7, 0.3)), ["dissolve:", "ends before it starts"]),
        (dict(frames=3, size=(0, 10)), ["size:", "(width, height)"]),
        (dict(frames=3, size=(10**6, 10)), ["size:", "16384"]),
        (dict(frames=3, trace_tolerance=0.0), ["trace_tolerance:"]),
        (dict(frames=3, trace_tolerance=float("nan")), ["trace_tolerance:", "not a finite"]),
        (dict(frames=3, frame_only="yes"), ["frame_only:", "True or False"]),
        (dict(frames=3, stretch="cubic"), ["stretch:"]),
    ],
)
def test_refuses_bad_arguments(arguments, words):
    a, b = sprites()
    with pytest.raises(meshmorph.MeshmorphError) as e:
        meshmorph.morph_pictures(a, b, **arguments)
    for w in words:
        assert w in str(e.value)
