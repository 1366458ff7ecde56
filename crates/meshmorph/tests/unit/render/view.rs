use meshmorph::render::view::*;

fn inside(v: &View2d, p: [f64; 2], margin: f64) -> bool {
    let q = v.to_pixel(p);
    let eps = 1e-9;
    q[0] >= margin - eps
        && q[1] >= margin - eps
        && q[0] <= f64::from(v.width) - margin + eps
        && q[1] <= f64::from(v.height) - margin + eps
}

#[test]
fn holds_every_frame_and_keeps_the_aspect_ratio() {
    let a = vec![[0.0, 0.0], [2.0, 0.0], [2.0, 1.0]];
    let b = vec![[-1.0, 0.5], [3.0, -0.5], [0.0, 1.5]];
    let v = View2d::fitting([a.as_slice(), b.as_slice()], 400, None, 10);
    // Bounds 4 × 2 plus margins: 380 × 190 inside.
    assert_eq!(v.height, 210);
    assert!((v.scale - 95.0).abs() < 1e-12);
    for p in a.iter().chain(&b) {
        assert!(inside(&v, *p, 10.0), "{p:?} -> {:?}", v.to_pixel(*p));
    }
    // The corners of the bounds touch the margin on both axes.
    assert!((v.to_pixel([-1.0, 1.5])[0] - 10.0).abs() < 1e-9);
    assert!((v.to_pixel([-1.0, 1.5])[1] - 10.0).abs() < 1e-9);
    // Same scale on both axes: a unit square stays square.
    let (p, q) = (v.to_pixel([0.0, 0.0]), v.to_pixel([1.0, 1.0]));
    assert!(((q[0] - p[0]) + (q[1] - p[1])).abs() < 1e-9);
    assert!((v.to_world(v.to_pixel([0.3, -0.2]))[1] + 0.2).abs() < 1e-12);

    // A fixed height: the wide bounds limit the scale; everything fits.
    let v = View2d::fitting([a.as_slice(), b.as_slice()], 400, Some(400), 10);
    assert!((v.scale - 95.0).abs() < 1e-12);
    for p in a.iter().chain(&b) {
        assert!(inside(&v, *p, 10.0));
    }
}

#[test]
fn the_longest_side_holds_tall_and_wide_bounds() {
    let tall = [[0.0, 0.0], [1.0, 3.0]];
    let v = View2d::fitting_longest([tall.as_slice()], 200, 10);
    // 180 pixels for 3 units high: 60 + 20 wide.
    assert_eq!((v.width, v.height), (80, 200));
    assert!(inside(&v, tall[1], 10.0));
    let wide = [[0.0, 0.0], [3.0, 1.0]];
    let v = View2d::fitting_longest([wide.as_slice()], 200, 10);
    assert_eq!((v.width, v.height), (200, 80));
}

#[test]
fn clamps_the_chosen_height() {
    let tall = [[0.0, 0.0], [0.001, 100.0]];
    let v = View2d::fitting([tall.as_slice()], 300, None, 5);
    assert_eq!(v.height, 600);
    assert!(inside(&v, tall[1], 5.0));
    let wide = [[0.0, 0.0], [100.0, 0.0]];
    let v = View2d::fitting([wide.as_slice()], 301, None, 5);
    assert_eq!(v.height, 76);
    assert!(inside(&v, wide[1], 5.0));
    assert_eq!(v.height % 2, 0);
}

#[test]
fn degenerate_bounds_do_not_panic() {
    let same = [[3.0, 4.0]; 5];
    let v = View2d::fitting([same.as_slice()], 100, None, 10);
    assert_eq!(v.to_pixel([3.0, 4.0]), [50.0, f64::from(v.height) / 2.0]);
    let none: [&[[f64; 2]]; 0] = [];
    let v = View2d::fitting(none, 0, Some(0), 10);
    assert_eq!((v.width, v.height), (1, 1));
    assert!(v.scale.is_finite());
    let huge = [[-1e308, -1e308], [1.7e308, 1e308], [f64::NAN, 0.0]];
    let v = View2d::fitting([huge.as_slice()], 640, None, 10);
    assert!(v.scale > 0.0 && v.scale.is_finite());
    let q = v.to_pixel(huge[1]);
    assert!(q[0].is_finite() && q[0] <= 631.0);
    let tiny = [[0.0, 0.0], [1e-320, 0.0]];
    let v = View2d::fitting([tiny.as_slice()], 64, None, 4);
    assert!(v.scale > 0.0);
}
