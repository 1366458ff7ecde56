use meshmorph::render::canvas::Canvas;
use meshmorph::render::palette::slot;
use meshmorph::render::style::Style2d;
use meshmorph::render::view::View2d;

use meshmorph::render::mesh2d::*;
use meshmorph::render::style::{Edges, Flipped};

fn square() -> (Vec<[f64; 2]>, Vec<[u32; 3]>) {
    (
        vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]],
        vec![[0, 1, 2], [0, 2, 3]],
    )
}

#[test]
fn a_square_of_two_triangles_is_filled_exactly() {
    let (p, t) = square();
    // 40 × 40 pixels inside a 10-pixel margin: the square covers pixels
    // 10..50 on both axes.
    let view = View2d::fitting([p.as_slice()], 60, Some(60), 10);
    let style = Style2d {
        edges: Edges::None,
        ..Style2d::default()
    };
    let mut c = Canvas::with_style(60, 60, &style);
    draw_mesh_2d(&mut c, &p, &t, &view, &style);
    assert_eq!(c.count(slot::FILL), 1600);
    for y in 0..60 {
        for x in 0..60 {
            let inside = (10..50).contains(&x) && (10..50).contains(&y);
            assert_eq!(c.get(x, y) == Some(slot::FILL), inside, "{x} {y}");
        }
    }
    // Each triangle alone: the two halves add up with no pixel twice.
    let mut halves = 0;
    for tri in &t {
        let mut c = Canvas::with_style(60, 60, &style);
        draw_mesh_2d(&mut c, &p, std::slice::from_ref(tri), &view, &style);
        halves += c.count(slot::FILL);
    }
    assert_eq!(halves, 1600);
}

#[test]
fn flipped_triangles_use_the_warning_colour() {
    let (mut p, t) = square();
    p[2] = [0.5, -0.5]; // folds triangle 0 over
    let style = Style2d::default();
    let view = View2d::fitting([p.as_slice()], 100, Some(100), 5);
    let areas = meshmorph::mesh::signed_areas(&p, &t);
    assert!(areas[0] < 0.0 && areas[1] > 0.0);
    let mut c = Canvas::with_style(100, 100, &style);
    draw_mesh_2d(&mut c, &p, &[t[0]], &view, &style);
    assert!(c.count(slot::FLIPPED_FILL) > 100);
    assert_eq!(c.count(slot::FILL), 0);
    let style = Style2d {
        flipped: Flipped::Mask(vec![false, true]),
        edges: Edges::All,
        ..style
    };
    let mut c = Canvas::with_style(100, 100, &style);
    draw_mesh_2d(&mut c, &p, &t, &view, &style);
    assert!(c.count(slot::FILL) > 100);
    assert!(c.count(slot::FLIPPED_FILL) > 100);
    assert!(c.count(slot::FLIPPED_EDGE) > 50);
}

#[test]
fn degenerate_input_does_not_panic() {
    let style = Style2d {
        edges: Edges::All,
        ..Style2d::default()
    };
    let cases: Vec<Vec<[f64; 2]>> = vec![
        vec![[1.0, 1.0]; 4],
        vec![[0.0, 0.0], [1.0, 1.0], [2.0, 2.0], [3.0, 3.0]],
        vec![
            [-1e300, 0.0],
            [1e300, 1e-300],
            [0.0, 1e300],
            [1e-300, -1e300],
        ],
    ];
    let t = vec![[0, 1, 2], [0, 2, 3], [0, 2, 7]];
    for p in &cases {
        let view = View2d::fitting([p.as_slice()], 64, None, 4);
        let mut c = Canvas::with_style(view.width, view.height, &style);
        draw_mesh_2d(&mut c, p, &t, &view, &style);
        // A view fitted elsewhere puts the points far outside.
        let far = View2d {
            scale: 1e300,
            ..view
        };
        draw_mesh_2d(&mut c, p, &t, &far, &style);
    }
    let mut c = Canvas::with_style(0, 0, &style);
    let view = View2d::fitting([cases[1].as_slice()], 0, Some(0), 4);
    draw_mesh_2d(&mut c, &cases[1], &t, &view, &style);
}
