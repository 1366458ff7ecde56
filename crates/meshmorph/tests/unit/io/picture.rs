//! Pictures made in code: traced, made compatible, drawn.

use meshmorph::error::Error;
use meshmorph::io::picture::arm::{arm_anchors, arm_sprite, ARM_SPRITE_SIZE};
#[cfg(feature = "render")]
use meshmorph::io::picture::decode::decode_picture;
use meshmorph::io::picture::outline::{picture_drawing, PictureDrawing, PictureShape};
use meshmorph::io::picture::trace::trace_alpha;

use meshmorph::io::picture::*;
use meshmorph::outline::OutlineOptions;

/// Alpha of a pixel whose centre is `d` pixels inside an edge (negative:
/// outside), anti-aliased over one pixel.
fn edge_alpha(d: f64) -> u8 {
    ((d + 0.5).clamp(0.0, 1.0) * 255.0).round() as u8
}

/// A textured colour at `(x, y)`: stripes and a gradient, so that a pixel
/// taken from the wrong place shows.
fn texture(x: f64, y: f64) -> [u8; 3] {
    [
        (128.0 + 100.0 * (x / 5.0).sin()) as u8,
        (y * 3.0).rem_euclid(256.0) as u8,
        (128.0 + 100.0 * ((x + y) / 9.0).cos()) as u8,
    ]
}

/// A ring (outer radius `r`, inner `r / 2`) centred at `c`.
fn ring(size: u32, c: [f64; 2], r: f64) -> Picture {
    Picture::from_fn(size, size, |x, y| {
        let (px, py) = (f64::from(x) + 0.5, f64::from(y) + 0.5);
        let d = (px - c[0]).hypot(py - c[1]);
        let a = edge_alpha((r - d).min(d - r / 2.0));
        let [cr, cg, cb] = texture(px, py);
        [cr, cg, cb, a]
    })
}

/// A bar `length` long and `width` wide from `pivot` at `angle` radians,
/// its far end round: an arm.
#[cfg(feature = "render")]
fn arm(size: u32, pivot: [f64; 2], length: f64, width: f64, angle: f64) -> Picture {
    let (c, s) = (angle.cos(), angle.sin());
    Picture::from_fn(size, size, |x, y| {
        let (px, py) = (f64::from(x) + 0.5 - pivot[0], f64::from(y) + 0.5 - pivot[1]);
        // In the arm's own frame.
        let (u, v) = (c * px + s * py, -s * px + c * py);
        let along = u.clamp(0.0, length);
        let d = if u < 0.0 {
            (width / 2.0 - v.abs()).min(u + width / 2.0)
        } else {
            width / 2.0 - (u - along).hypot(v)
        };
        let [cr, cg, cb] = texture(u + 40.0, v + 40.0);
        [cr, cg, cb, edge_alpha(d)]
    })
}

#[cfg(feature = "render")]
fn alpha_area(p: &Picture) -> f64 {
    p.rgba
        .chunks_exact(4)
        .map(|q| f64::from(q[3]) / 255.0)
        .sum()
}

fn area(l: &[[f64; 2]]) -> f64 {
    meshmorph::io::drawing::signed_area2(l) / 2.0
}

#[test]
fn tracing_finds_outer_loops_and_holes() {
    for (size, r) in [(64, 25.0), (96, 40.0), (80, 21.5)] {
        let c = [f64::from(size) / 2.0 + 0.3, f64::from(size) / 2.0 - 0.2];
        let p = ring(size, c, r);
        let loops = trace_alpha(&p, 0.5);
        assert_eq!(loops.len(), 2, "ring of radius {r}");
        let areas: Vec<f64> = loops.iter().map(|l| area(l)).collect();
        let outer = areas.iter().copied().fold(f64::MIN, f64::max);
        let hole = areas.iter().copied().fold(f64::MAX, f64::min);
        let pi = std::f64::consts::PI;
        assert!((outer / (pi * r * r) - 1.0).abs() < 0.02, "{outer}");
        assert!(hole < 0.0);
        assert!((-hole / (pi * r * r / 4.0) - 1.0).abs() < 0.04, "{hole}");
        // Every traced point lies where alpha crosses a half: within half
        // a pixel of the circles.
        for l in &loops {
            for q in l {
                let d = (q[0] - c[0]).hypot(q[1] - c[1]);
                assert!(
                    (d - r).abs() < 0.75 || (d - r / 2.0).abs() < 0.75,
                    "{q:?} at {d}"
                );
            }
        }
        let pd = picture_drawing(&p, false, 0.5, 16.0, "ring").unwrap();
        assert_eq!(pd.shape, PictureShape::Sprite);
        assert_eq!(pd.drawing.num_loops(), 2);
        assert!(pd.drawing.num_points() < pd.traced_points);
        // Simplified within its tolerance: the area moves by at most the
        // tolerance times the perimeter.
        let kept: f64 = pd.drawing.loops().iter().map(|l| area(l).abs()).sum();
        let traced: f64 = areas.iter().map(|a| a.abs()).sum();
        assert!(
            (kept - traced).abs() < 0.5 * 2.0 * pi * 1.5 * r,
            "{kept} {traced}"
        );
    }
}

#[test]
fn the_largest_region_is_kept_and_the_others_named() {
    let p = Picture::from_fn(80, 40, |x, y| {
        let (px, py) = (f64::from(x) + 0.5, f64::from(y) + 0.5);
        let big = 12.0 - (px - 20.0).hypot(py - 20.0);
        let small = 6.0 - (px - 60.0).hypot(py - 20.0);
        let speck = 0.9 - (px - 75.0).hypot(py - 5.0);
        [200, 100, 50, edge_alpha(big.max(small).max(speck))]
    });
    let pd = picture_drawing(&p, false, 0.5, 16.0, "blobs").unwrap();
    assert_eq!(pd.drawing.num_loops(), 1);
    assert_eq!(pd.left_out.len(), 1);
    assert_eq!(pd.specks, 1);
    let b = pd.left_out[0].bounds;
    assert!(b[0][0] > 50.0 && b[1][0] < 70.0, "{b:?}");
    let kept = pd.drawing.loops()[0][0];
    assert!(kept[0] < 40.0);
}

#[test]
fn a_glow_under_half_opaque_is_counted_as_left_out_but_an_edge_is_not() {
    let disc = |glow: bool| {
        Picture::from_fn(64, 64, |x, y| {
            let d = 20.0 - (f64::from(x) + 0.5 - 32.0).hypot(f64::from(y) + 0.5 - 32.0);
            let a = edge_alpha(d);
            let a = if glow && a == 0 && d > -8.0 { 60 } else { a };
            [200, 100, 50, a]
        })
    };
    let plain = picture_drawing(&disc(false), false, 0.5, 16.0, "disc").unwrap();
    assert_eq!(plain.faint_left_out, 0);
    let glowing = picture_drawing(&disc(true), false, 0.5, 16.0, "glow").unwrap();
    // The glow's ring: about π (28² - 20²) = 1,200 pixels, less the
    // edge's allowance of two a pixel of outline (about 250).
    assert!(
        (800..1200).contains(&glowing.faint_left_out),
        "{}",
        glowing.faint_left_out
    );
}

#[test]
fn empty_and_transparent_pictures_are_refused() {
    assert!(matches!(
        Picture::new(0, 4, Vec::new()),
        Err(Error::InvalidArgument(_))
    ));
    assert!(matches!(
        Picture::new(2, 2, vec![0; 15]),
        Err(Error::InvalidArgument(_))
    ));
    let clear = Picture::from_fn(10, 10, |_, _| [255, 0, 0, 0]);
    let e = picture_drawing(&clear, false, 0.5, 16.0, "`clear.png`").unwrap_err();
    assert!(
        e.to_string().contains("`clear.png` is fully transparent"),
        "{e}"
    );
    let dust = Picture::from_fn(10, 10, |x, y| {
        [0, 0, 0, if (x, y) == (4, 4) { 255 } else { 0 }]
    });
    let e = picture_drawing(&dust, false, 0.5, 16.0, "`dust.png`").unwrap_err();
    assert!(e.to_string().contains("no opaque region"), "{e}");
    // Photo mode needs no opaque part.
    assert!(picture_drawing(&clear, true, 0.5, 16.0, "clear").is_ok());
}

fn photo(w: u32, h: u32, shift: f64) -> Picture {
    Picture::from_fn(w, h, |x, y| {
        let [r, g, b] = texture(f64::from(x) + shift, f64::from(y));
        [r, g, b, 255]
    })
}

#[test]
fn photo_anchors_are_exact_vertices_of_both_meshes() {
    let (a, b) = (photo(60, 40, 0.0), photo(90, 60, 7.0));
    let da = picture_drawing(&a, false, 0.5, 16.0, "a").unwrap();
    let db = picture_drawing(&b, true, 0.5, 16.0, "b").unwrap();
    assert_eq!(
        (da.shape, db.shape),
        (PictureShape::Photo, PictureShape::Photo)
    );
    let anchors = vec![
        vec![[20.0, 15.0], [45.0, 30.0]],
        vec![[40.0, 15.0], [40.0, 20.0]],
        vec![[30.0, 30.0], [50.0, 45.0]],
    ];
    // Photos are meshed without the rigid parts, as `PictureFrames` meshes them.
    let m = picture_meshes(
        &[&a, &b],
        &[&da, &db],
        &anchors,
        (60, 40),
        &OutlineOptions::default(),
        &["a".into(), "b".into()],
    )
    .unwrap();
    assert_eq!(m.set.anchors.len(), 3);
    for (row, &v) in anchors.iter().zip(&m.set.anchors) {
        for k in 0..2 {
            let s = m.sources[k][v as usize];
            assert!((s[0] - row[k][0]).abs() < 1e-9 && (s[1] - row[k][1]).abs() < 1e-9);
        }
        // B is scaled onto A's frame: two thirds.
        let f = m.set.meshes[1].positions()[v as usize];
        assert!((f[0] - row[1][0] * 2.0 / 3.0).abs() < 1e-9);
    }
    // Anchors outside a picture are refused, naming it.
    let outside = vec![vec![[20.0, 15.0], [95.0, 30.0]]];
    let e = picture_meshes(
        &[&a, &b],
        &[&da, &db],
        &outside,
        (60, 40),
        &OutlineOptions::default(),
        &["`a.jpg`".into(), "`b.jpg`".into()],
    )
    .unwrap_err();
    assert!(
        e.to_string().contains("outside the picture") && e.to_string().contains("`b.jpg`"),
        "{e}"
    );
}

#[cfg(feature = "render")]
mod frames {
    use super::*;
    use meshmorph::mesh::map_stretch;
    use meshmorph::render::PictureMorph;
    use meshmorph::{Interpolator, InterpolatorOptions};

    /// Two photos of different sizes with anchors that move (one pair
    /// crossing another): every in-between frame is opaque to its edge,
    /// its outline the frames' rectangle (a photo's outline held on the
    /// straight blend, its edge pixels repeated past the edge).
    #[test]
    fn photo_frames_are_opaque_to_the_edge() {
        use meshmorph::render::{PictureFrames, PictureMorphOptions};
        let (a, b) = (photo(80, 60, 0.0), photo(120, 90, 9.0));
        let anchors = vec![
            vec![[20.0, 15.0], [90.0, 70.0]],
            vec![[60.0, 15.0], [30.0, 70.0]],
            vec![[40.0, 45.0], [70.0, 30.0]],
        ];
        let names = ["a.png".to_string(), "b.png".to_string()];
        let frames =
            PictureFrames::new([&a, &b], &anchors, &PictureMorphOptions::default(), &names)
                .unwrap();
        assert_eq!(frames.shape(), PictureShape::Photo);
        for t in [0.2, 0.5, 0.8] {
            let f = frames.draw(t);
            assert_eq!((f.width, f.height), (80, 60));
            let seen: Vec<u8> = f.rgba.chunks_exact(4).map(|p| p[3]).collect();
            let clear = seen.iter().filter(|&&alpha| alpha < 255).count();
            assert_eq!(clear, 0, "t = {t}: {clear} pixels not opaque");
        }
    }

    fn visible(p: &Picture) -> Vec<[u8; 4]> {
        p.rgba
            .chunks_exact(4)
            .map(|q| {
                if q[3] == 0 {
                    [0; 4]
                } else {
                    [q[0], q[1], q[2], q[3]]
                }
            })
            .collect()
    }

    /// Compatible meshes of two sprites, their morph and its frames' setup.
    fn morph<'a>(
        a: &'a Picture,
        b: &'a Picture,
        anchors: &[Vec<[f64; 2]>],
    ) -> (PictureMeshes, Interpolator<2>, PictureMorph<'a>) {
        let da = picture_drawing(a, false, 0.5, 16.0, "a").unwrap();
        let db = picture_drawing(b, false, 0.5, 16.0, "b").unwrap();
        let m = picture_meshes(
            &[a, b],
            &[&da, &db],
            anchors,
            (a.width, a.height),
            &OutlineOptions::for_pictures(),
            &[],
        )
        .unwrap();
        let i = Interpolator::new(
            &m.set.meshes[0],
            &m.set.meshes[1],
            &InterpolatorOptions::default(),
        )
        .unwrap();
        let r = PictureMorph::new(
            [a, b],
            &m.sources,
            m.set.meshes[0].triangles(),
            &m.set.loops,
            (a.width, a.height),
            2.0,
            PictureShape::Sprite,
        )
        .unwrap();
        (m, i, r)
    }

    /// The meshes' vertices moved on straight lines from the first mesh
    /// to the second, at `t`.
    fn linear_warp(m: &PictureMeshes, t: f64) -> Vec<[f64; 2]> {
        m.set.meshes[0]
            .positions()
            .iter()
            .zip(m.set.meshes[1].positions())
            .map(|(p, q)| [p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])])
            .collect()
    }

    /// Pixels whose alpha is above one half.
    fn opaque_area(p: &Picture) -> f64 {
        p.rgba.chunks_exact(4).filter(|q| q[3] > 127).count() as f64
    }

    /// The demo's arm sprite, its forearm turning 150° at the elbow with
    /// the demo's five anchors (`examples/picture_benchmark.rs` measures
    /// it): at every one of 11 frames the as-rigid-as-possible frame keeps
    /// the straight blend of the two pictures' areas (measured: 1.00 to
    /// 1.07), where the linear warp of the same meshes loses a tenth of it
    /// and more at all but the ends and over a third mid-turn (measured:
    /// 0.86 at t = 0.1, 0.62 at t = 0.5).
    #[test]
    fn the_demo_arm_keeps_its_area_where_a_linear_warp_shrinks_it() {
        let bend = 150f64.to_radians();
        let (a, b) = (
            arm_sprite(0.0, ARM_SPRITE_SIZE),
            arm_sprite(bend, ARM_SPRITE_SIZE),
        );
        let anchors: Vec<Vec<[f64; 2]>> = arm_anchors(bend, ARM_SPRITE_SIZE)
            .iter()
            .map(|(_, p, q)| vec![*p, *q])
            .collect();
        let (m, i, r) = morph(&a, &b, &anchors);
        let (area_a, area_b) = (opaque_area(&a), opaque_area(&b));
        for k in 1..10 {
            let t = f64::from(k) / 10.0;
            let straight = (1.0 - t) * area_a + t * area_b;
            let arap = opaque_area(&r.draw(&i.at(t), t)) / straight;
            let linear = opaque_area(&r.draw(&linear_warp(&m, t), t)) / straight;
            assert!(
                (0.95..=1.1).contains(&arap),
                "t = {t}: the frame's area is {arap} of the straight blend"
            );
            assert!(
                linear < 0.9 && (k != 5 || linear < 0.7),
                "t = {t}: the linear warp keeps {linear} of the area"
            );
        }
    }

    /// The demo's arm sprite with its five anchors, morphed as pictures
    /// are (`PictureMorphOptions`' interpolation): half-way, most of the
    /// forearm's texture (each triangle weighed by its share of the two
    /// pictures) is stretched or squeezed by at most a quarter in any
    /// direction (measured: 76 %; 65 % without the rigid parts), where
    /// the linear warp of the same meshes keeps none of it so (measured:
    /// 0 %, its forearm pulled across the turn's chord).
    #[test]
    fn the_demo_arms_forearm_keeps_its_texture_where_a_linear_warp_smears_it() {
        let bend = 150f64.to_radians();
        let (a, b) = (
            arm_sprite(0.0, ARM_SPRITE_SIZE),
            arm_sprite(bend, ARM_SPRITE_SIZE),
        );
        let named = arm_anchors(bend, ARM_SPRITE_SIZE);
        let anchors: Vec<Vec<[f64; 2]>> = named.iter().map(|(_, p, q)| vec![*p, *q]).collect();
        let (m, _, _) = morph(&a, &b, &anchors);
        let i = Interpolator::new(
            &m.set.meshes[0],
            &m.set.meshes[1],
            &meshmorph::render::PictureMorphOptions::default().interpolation,
        )
        .unwrap();
        // The forearm: triangles of A past a half width beyond the elbow.
        let at = |n: &str| named.iter().find(|x| x.0 == n).unwrap().1;
        let half_width = at("elbow")[1] - at("shoulder")[1];
        let past = at("elbow")[0] + half_width;
        let [pa, pb] = [0, 1].map(|k| m.set.meshes[k].positions());
        let texture_within = |frame: &[[f64; 2]], t: f64, limit: f64| {
            let (mut within, mut total) = (0.0, 0.0);
            for tri in m.set.meshes[0].triangles() {
                let corners = |p: &[[f64; 2]]| tri.map(|v| p[v as usize]);
                let (ca, cb, cf) = (corners(pa), corners(pb), corners(frame));
                if (ca[0][0] + ca[1][0] + ca[2][0]) / 3.0 <= past {
                    continue;
                }
                let area = |c: [[f64; 2]; 3]| {
                    0.5 * ((c[1][0] - c[0][0]) * (c[2][1] - c[0][1])
                        - (c[1][1] - c[0][1]) * (c[2][0] - c[0][0]))
                        .abs()
                };
                let weight = (1.0 - t) * area(ca) + t * area(cb);
                let stretch = (1.0 - t) * map_stretch(ca, cf) + t * map_stretch(cb, cf);
                total += weight;
                if stretch <= limit {
                    within += weight;
                }
            }
            within / total
        };
        let arap = texture_within(&i.at(0.5), 0.5, 1.25);
        let linear = texture_within(&linear_warp(&m, 0.5), 0.5, 1.25);
        assert!(
            arap > 0.7,
            "{arap:.3} of the forearm's texture within 25 % half-way"
        );
        assert!(
            linear < 0.1,
            "the linear warp keeps {linear:.3} of it within 25 %"
        );
    }

    #[test]
    fn pictures_too_large_are_refused_before_decoding() {
        let p = ring(40, [20.0, 20.0], 15.0);
        let mut bytes = Vec::new();
        meshmorph::render::write_picture_png(&mut bytes, &p).unwrap();
        let path = std::path::Path::new("big.png");
        assert_eq!(decode_picture(&bytes, path, u64::MAX).unwrap(), p);
        let e = decode_picture(&bytes, path, 1000).unwrap_err();
        assert!(
            e.to_string()
                .contains("40 × 40 pixels is more than the 1000 pixels"),
            "{e}"
        );
        let e = decode_picture(b"GIF89a", path, u64::MAX).unwrap_err();
        assert!(e.to_string().contains("neither a PNG nor a JPEG"), "{e}");
    }

    #[test]
    fn the_ends_are_the_pictures_pixel_for_pixel() {
        for (a, b) in [
            (ring(72, [36.0, 36.0], 28.0), ring(72, [30.5, 40.0], 22.0)),
            (
                arm(96, [30.0, 48.0], 50.0, 16.0, 0.2),
                arm(96, [30.0, 48.0], 44.0, 20.0, 2.0),
            ),
        ] {
            let (_, i, r) = morph(&a, &b, &[]);
            let first = r.draw(&i.at(0.0), 0.0);
            assert_eq!(visible(&first), visible(&a));
            let last = r.draw(&i.at(1.0), 1.0);
            assert_eq!(visible(&last), visible(&b));
        }
    }

    #[test]
    fn a_turning_arm_keeps_its_area_and_texture() {
        let pivot = [72.0, 72.0];
        let a = arm(144, pivot, 56.0, 18.0, 0.0);
        let b = arm(144, pivot, 56.0, 18.0, 150f64.to_radians());
        // The tip and the shoulder matched: without them the outlines'
        // best match turns the arm end for end, by -30°.
        let at = |d: f64, angle: f64| [pivot[0] + d * angle.cos(), pivot[1] + d * angle.sin()];
        let turn = 150f64.to_radians();
        let anchors = vec![
            vec![at(65.0, 0.0), at(65.0, turn)],
            vec![at(-9.0, 0.0), at(-9.0, turn)],
        ];
        let (m, i, r) = morph(&a, &b, &anchors);
        let (area_a, area_b) = (alpha_area(&a), alpha_area(&b));
        for t in [0.25, 0.5, 0.75] {
            let f = r.draw(&i.at(t), t);
            let ratio = alpha_area(&f) / ((1.0 - t) * area_a + t * area_b);
            assert!((ratio - 1.0).abs() < 0.04, "t = {t}: area ratio {ratio}");
            // The linear warp of the same meshes shrinks it.
            let linear = linear_warp(&m, t);
            if t == 0.5 {
                let l = r.draw(&linear, t);
                assert!(
                    alpha_area(&l) / area_a < 0.8,
                    "linear warp keeps {}",
                    alpha_area(&l) / area_a
                );
            }
        }
    }

    #[test]
    fn frames_of_another_size_and_transparent_outside() {
        let a = ring(64, [32.0, 32.0], 26.0);
        let b = ring(96, [48.0, 48.0], 30.0);
        let da = picture_drawing(&a, false, 0.5, 16.0, "a").unwrap();
        let db = picture_drawing(&b, false, 0.5, 16.0, "b").unwrap();
        let m = picture_meshes(
            &[&a, &b],
            &[&da, &db],
            &[],
            (32, 32),
            &OutlineOptions::for_pictures(),
            &[],
        )
        .unwrap();
        let r = PictureMorph::new(
            [&a, &b],
            &m.sources,
            m.set.meshes[0].triangles(),
            &m.set.loops,
            (32, 32),
            1.0,
            PictureShape::Sprite,
        )
        .unwrap();
        let f = r.draw(m.set.meshes[0].positions(), 0.0);
        assert_eq!((f.width, f.height), (32, 32));
        // Half the size: a quarter of the alpha area, the corners clear.
        assert!((alpha_area(&f) / (alpha_area(&a) / 4.0) - 1.0).abs() < 0.05);
        assert_eq!(f.pixel(0, 0)[3], 0);
        assert_eq!(f.pixel(16, 16)[3], 0);
    }
}

/// A point of the arm sprite bent by `bend` ([`arm_sprite`], its 320 ×
/// 240 size): `along` pixels along its axis from the shoulder (the upper
/// arm's 110, then the forearm's), `across` to the side that faces down
/// when straight.
fn on_arm(along: f64, across: f64, bend: f64) -> [f64; 2] {
    let (elbow, upper) = ([160.0, 170.0], 110.0);
    if along <= upper {
        [elbow[0] - upper + along, elbow[1] + across]
    } else {
        let f = along - upper;
        [
            elbow[0] + f * bend.cos() + across * bend.sin(),
            elbow[1] - f * bend.sin() + across * bend.cos(),
        ]
    }
}

/// Anchors inside the arm as well as its five on the outlines: the
/// elbow's centre, the middle of the forearm and of the upper arm, and
/// points 3 pixels from the outline (bent by 150°, the one 70 pixels down
/// the forearm once turned a triangle over whichever drawing's mesh was
/// mapped into the other, and was refused). With 1, 2
/// and 3 of them and the forearm bent by 90° and 150°: every triangle
/// positive in both meshes, every anchor a vertex at exactly its point in
/// each, every outline point given a vertex at exactly its place, and the
/// smallest angle above 1° (measured: 2.5° at the least, 3 pixels from
/// the outline with the forearm bent by 90°; 7.8° to 10.8° with the
/// anchors on the axis).
#[test]
fn anchors_inside_the_arm_are_vertices_of_both_meshes() {
    use meshmorph::outline::{compatible_set, OutlineOptions};
    let families: [&[(f64, f64)]; 7] = [
        &[(110.0, 0.0)],
        &[(160.0, 0.0)],
        &[(180.0, -10.0)],
        &[(110.0, 0.0), (160.0, 0.0)],
        &[(55.0, 10.0), (205.0, -10.0)],
        &[(110.0, 0.0), (160.0, 0.0), (55.0, 0.0)],
        &[(100.0, 10.0), (120.0, -10.0), (180.0, -10.0)],
    ];
    let mut worst = f64::INFINITY;
    for bend in [90f64.to_radians(), 150f64.to_radians()] {
        let pictures = [
            arm_sprite(0.0, ARM_SPRITE_SIZE),
            arm_sprite(bend, ARM_SPRITE_SIZE),
        ];
        let drawings: Vec<PictureDrawing> = pictures
            .iter()
            .map(|p| picture_drawing(p, false, 0.5, 16.0, "arm").unwrap())
            .collect();
        let drawings: Vec<_> = drawings.into_iter().map(|d| d.drawing).collect();
        let on_outlines = arm_anchors(bend, ARM_SPRITE_SIZE).map(|(_, a, b)| vec![a, b]);
        for inside in families {
            let mut anchors = on_outlines.to_vec();
            anchors.extend(
                inside
                    .iter()
                    .map(|&(s, o)| vec![on_arm(s, o, 0.0), on_arm(s, o, bend)]),
            );
            let set = compatible_set(&drawings, &anchors, &OutlineOptions::for_pictures())
                .unwrap_or_else(|e| panic!("{inside:?} bent {bend}: {e}"));
            eprintln!("{inside:?} bent {:.0}°: {}", bend.to_degrees(), set.report);
            assert_eq!(set.report.inside_anchors, inside.len());
            for mesh in &set.meshes {
                let areas = meshmorph::mesh::signed_areas(mesh.positions(), mesh.triangles());
                assert!(
                    areas.iter().all(|&a| a > 0.0),
                    "{inside:?}: a triangle turned over"
                );
            }
            for (k, anchor) in anchors.iter().enumerate().skip(on_outlines.len()) {
                let v = set.anchors[k] as usize;
                for (d, mesh) in set.meshes.iter().enumerate() {
                    assert_eq!(mesh.positions()[v], anchor[d], "anchor {k} in drawing {d}");
                }
            }
            for (d, (mesh, drawing)) in set.meshes.iter().zip(&drawings).enumerate() {
                for (l, stored) in drawing.loops().iter().enumerate() {
                    for (i, p) in stored.iter().enumerate() {
                        let v = set.given[d][l][drawing.given_index(l, i)] as usize;
                        assert_eq!(mesh.positions()[v], *p, "drawing {d}, loop {l}, point {i}");
                    }
                }
            }
            let smallest = set
                .report
                .min_angle_degrees
                .iter()
                .copied()
                .fold(f64::INFINITY, f64::min);
            assert!(smallest > 1.0, "{inside:?} bent {bend}: {smallest}°");
            worst = worst.min(smallest);
        }
    }
    eprintln!("smallest angle over the family: {worst:.2}°");
}
