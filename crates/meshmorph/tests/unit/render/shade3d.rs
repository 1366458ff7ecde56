use meshmorph::linalg::vector::{dot, norm};
use meshmorph::render::canvas::Canvas;
use meshmorph::render::palette::Ramp;
use meshmorph::render::Rect;

use meshmorph::render::palette::{slot, Palette};
use meshmorph::render::shade3d::*;

/// A unit cube, triangles counter-clockwise seen from outside.
pub(crate) fn cube() -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    let p = (0..8)
        .map(|i| {
            [
                f64::from(i & 1),
                f64::from((i >> 1) & 1),
                f64::from((i >> 2) & 1),
            ]
        })
        .collect();
    let quads = [
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ];
    let t = quads
        .iter()
        .flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]])
        .collect();
    (p, t)
}

#[test]
fn camera_axes_and_fit() {
    let c = Camera3d::orbit(0.0, 0.0);
    assert_eq!(c.forward, [-0.0, -0.0, -1.0]);
    assert!((c.right[0] - 1.0).abs() < 1e-12 && (c.up[1] - 1.0).abs() < 1e-12);
    let c = Camera3d::orbit(90.0, 0.0);
    assert!((c.forward[0] + 1.0).abs() < 1e-12);
    // Looking straight down y with y "up": a perpendicular up is chosen.
    let c = Camera3d::looking([0.0, -1.0, 0.0], [0.0, 1.0, 0.0]);
    assert!(dot(c.up, c.forward).abs() < 1e-12 && (norm(c.up) - 1.0).abs() < 1e-12);
    let c = Camera3d::looking([0.0; 3], [0.0; 3]);
    assert_eq!(c.forward, [0.0, 0.0, -1.0]);

    let (p, _) = cube();
    let shifted: Vec<[f64; 3]> = p.iter().map(|q| [q[0] * 2.0 + 5.0, q[1], q[2]]).collect();
    let c = Camera3d::orbit(0.0, 0.0).fitted([p.as_slice(), shifted.as_slice()]);
    assert!((c.half_size[0] - 3.5).abs() < 1e-12 && (c.half_size[1] - 0.5).abs() < 1e-12);
    let vp = Rect {
        x: 10,
        y: 20,
        width: 70,
        height: 50,
    };
    let q = c.project([0.0, 0.0, 0.0], vp);
    assert!(
        (q[0] - 10.0).abs() < 1e-9 && (q[1] - (45.0 + 5.0)).abs() < 1e-9,
        "{q:?}"
    );
    let q = c.project([7.0, 1.0, 1.0], vp);
    assert!(
        (q[0] - 80.0).abs() < 1e-9 && (q[1] - 40.0).abs() < 1e-9 && q[2] < 0.0,
        "{q:?}"
    );
    // All points equal: a region of size 1.
    let one = [[1.0, 2.0, 3.0]];
    let c = Camera3d::orbit(30.0, 20.0).fitted([one.as_slice()]);
    assert_eq!(c.half_size, [1.0, 1.0]);
    assert!(c.project(one[0], vp).iter().all(|x| x.is_finite()));
}

#[test]
fn the_near_face_hides_the_far_one_and_shading_follows_the_normal() {
    let (p, t) = cube();
    let cam = Camera3d::orbit(0.0, 0.0).fitted([p.as_slice()]);
    let mut canvas = Canvas::new(40, 40, Palette::standard());
    let vp = canvas.bounds();
    draw_mesh_3d(&mut canvas, &p, &t, &cam, vp, &Style3d::default());
    // Front view of a cube: one face fills the viewport, one shade (the
    // creases keep the sides' normals out), dithered between two
    // neighbouring levels.
    let lo = *canvas.pixels.iter().min().unwrap();
    let hi = *canvas.pixels.iter().max().unwrap();
    assert!(hi - lo <= 1, "{lo} {hi}");
    let r = Ramp::BLUE;
    assert!((r.first..r.first + r.len).contains(&lo));
    assert!((r.first..r.first + r.len).contains(&hi));
    // Depth test: a square facing the camera in front of a tilted one
    // drawn after it in the same call keeps the middle of the picture.
    let sq = [
        [0.0, 0.0, 1.0],
        [1.0, 0.0, 1.0],
        [1.0, 1.0, 1.0],
        [0.0, 1.0, 1.0],
    ];
    let tilted = [
        [-1.0, -1.0, -1.0],
        [2.0, -1.0, 0.0],
        [2.0, 2.0, 0.0],
        [-1.0, 2.0, -1.0],
    ];
    let pq: Vec<[f64; 3]> = sq.iter().chain(&tilted).copied().collect();
    let near = [[0, 1, 2], [0, 2, 3]];
    let far = [[4, 5, 6], [4, 6, 7]];
    let cam = Camera3d::orbit(0.0, 0.0).fitted([sq.as_slice()]);
    let shade_of = |tris: &[[u32; 3]]| {
        let mut c = Canvas::new(20, 20, Palette::standard());
        let vp = c.bounds();
        draw_mesh_3d(&mut c, &pq, tris, &cam, vp, &Style3d::default());
        c.get(10, 10).unwrap()
    };
    let (near_shade, far_shade) = (shade_of(&near), shade_of(&far));
    assert_ne!(near_shade, far_shade);
    assert_eq!(shade_of(&[near[0], near[1], far[0], far[1]]), near_shade);
    assert_eq!(shade_of(&[far[0], far[1], near[0], near[1]]), near_shade);
    // Three-quarter view from above: three faces, three shades, and the
    // background around it; a second ramp changes only the colours.
    let cam = Camera3d::orbit(35.0, 30.0).fitted([p.as_slice()]);
    let mut c = Canvas::new(60, 60, Palette::standard());
    draw_mesh_3d(
        &mut c,
        &p,
        &t,
        &cam,
        Rect {
            x: 5,
            y: 5,
            width: 50,
            height: 50,
        },
        &Style3d::default(),
    );
    // Three faces: three shades, each dithered between two neighbouring
    // levels, and the background.
    let mut shades: Vec<u8> = c.pixels.clone();
    shades.sort_unstable();
    shades.dedup();
    assert!((4..=7).contains(&shades.len()), "{shades:?}");
    assert_eq!(c.get(2, 2), Some(slot::BACKGROUND));
    let mut d = Canvas::new(60, 60, Palette::standard());
    let sand = Style3d::with_ramp(Ramp::SAND).with_edges();
    draw_mesh_3d(
        &mut d,
        &p,
        &t,
        &cam,
        Rect {
            x: 5,
            y: 5,
            width: 50,
            height: 50,
        },
        &sand,
    );
    let edge = sand.edges.unwrap();
    assert!(d.count(edge) > 50);
    assert!(d
        .pixels
        .iter()
        .all(|&i| i == slot::BACKGROUND || (Ramp::SAND.first..Ramp::SAND.first + 32).contains(&i)));
    assert!(c.count(edge) == 0 && c.count(Ramp::BLUE.index(0.06)) == 0);
}

#[test]
fn degenerate_input_does_not_panic() {
    let mut c = Canvas::new(30, 20, Palette::standard());
    let t = [[0, 1, 2], [0, 1, 3], [0, 0, 0]];
    let style = Style3d::default().with_edges();
    for p in [
        vec![[1.0; 3]; 3],
        vec![[0.0, 0.0, 0.0], [1.0, 1.0, 1.0], [2.0, 2.0, 2.0]],
        vec![
            [1e300, -1e300, 0.0],
            [-1e300, 1e300, 1e300],
            [0.0, 0.0, -1e300],
        ],
    ] {
        let cam = Camera3d::orbit(10.0, 10.0).fitted([p.as_slice()]);
        for vp in [
            c.bounds(),
            Rect {
                x: 25,
                y: 15,
                width: 100,
                height: 100,
            },
            Rect {
                x: 99,
                y: 0,
                width: 5,
                height: 5,
            },
        ] {
            draw_mesh_3d(&mut c, &p, &t, &cam, vp, &style);
        }
    }
}
