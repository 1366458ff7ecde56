use meshmorph::outline::settle::*;

#[test]
fn free_points_slide_between_the_fixed_points_around_them() {
    // A square of 8 points, its corners fixed.
    let points = [
        [0.0, 0.0],
        [1.0, 0.0],
        [2.0, 0.0],
        [2.0, 1.0],
        [2.0, 2.0],
        [1.0, 2.0],
        [0.0, 2.0],
        [0.0, 1.0],
    ];
    let fixed: Vec<bool> = (0..8).map(|k| k % 2 == 0).collect();
    let s = slides(&points, &[0, 8], &fixed);
    assert_eq!(s.len(), 4);
    assert_eq!(s[0].vertex, 1);
    assert_eq!((s[0].from, s[0].to), ([0.0, 0.0], [2.0, 0.0]));
    assert_eq!(s[3].vertex, 7);
    assert_eq!((s[3].from, s[3].to), ([0.0, 2.0], [0.0, 0.0]));
    // Starting on a free point: the run wraps around.
    let fixed: Vec<bool> = (0..8).map(|k| k == 3 || k == 6).collect();
    let s = slides(&points, &[0, 8], &fixed);
    assert_eq!(s.len(), 6);
    assert_eq!(
        (s[0].vertex, s[0].from, s[0].to),
        (4, [2.0, 1.0], [0.0, 2.0])
    );
    assert_eq!(
        (s[2].vertex, s[2].from, s[2].to),
        (7, [0.0, 2.0], [2.0, 1.0])
    );
    // One fixed point: nothing slides.
    let fixed: Vec<bool> = (0..8).map(|k| k == 3).collect();
    assert!(slides(&points, &[0, 8], &fixed).is_empty());
}

#[test]
fn a_point_placed_off_its_rigid_place_slides_back() {
    // A strip of four equilateral triangles, the same in both
    // drawings; in the second the middle boundary points start slid
    // to one side.
    let h = 0.75f64.sqrt();
    let reference = [
        [0.0, 0.0],
        [1.0, 0.0],
        [2.0, 0.0],
        [2.5, h],
        [1.5, h],
        [0.5, h],
    ];
    let triangles = [[0, 1, 5], [1, 4, 5], [1, 2, 4], [2, 3, 4]];
    let mut moving = reference;
    moving[1] = [1.4, 0.0];
    moving[4] = [0.9, h];
    let fixed = [true, false, true, true, false, true];
    let s = slides(&moving, &[0, 6], &fixed);
    settle(&reference, &triangles, &mut moving, 6, &s, 200, false);
    for (p, q) in moving.iter().zip(&reference) {
        assert!(
            (p[0] - q[0]).abs() < 1e-4 && (p[1] - q[1]).abs() < 1e-9,
            "{moving:?}"
        );
    }
}
