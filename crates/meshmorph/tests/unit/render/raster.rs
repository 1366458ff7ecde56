use meshmorph::render::Rect;

use meshmorph::render::raster::*;

fn coverage(tris: &[[[f64; 2]; 3]], w: u32, h: u32) -> Vec<u8> {
    let clip = Clip::new(
        Rect {
            x: 0,
            y: 0,
            width: w,
            height: h,
        },
        w,
        h,
    );
    let mut count = vec![0u8; (w * h) as usize];
    for t in tris {
        fill_triangle(*t, &clip, |y, x0, x1| {
            for x in x0..x1 {
                count[y * w as usize + x] += 1;
            }
        });
    }
    count
}

#[test]
fn a_fan_through_pixel_centres_covers_every_pixel_once() {
    // Vertices on pixel centres and edges through many of them: the
    // hardest case for a fill rule.
    let c = [8.5, 8.5];
    let ring: Vec<[f64; 2]> = [
        [0.5, 0.5],
        [8.5, 0.5],
        [16.5, 0.5],
        [16.5, 8.5],
        [16.5, 16.5],
        [8.5, 16.5],
        [0.5, 16.5],
        [0.5, 8.5],
    ]
    .to_vec();
    let tris: Vec<_> = (0..8).map(|k| [c, ring[k], ring[(k + 1) % 8]]).collect();
    let count = coverage(&tris, 20, 20);
    for y in 0..20 {
        for x in 0..20 {
            // Samples on the outer boundary belong to the left and top
            // edges only: the tie rule nudges them right and down a hair.
            let want = u8::from(x < 16 && y < 16);
            assert_eq!(count[y * 20 + x], want, "pixel {x} {y}");
        }
    }
}

#[test]
fn huge_triangles_are_clipped_not_lost() {
    // A triangle far larger than the guard square that covers the image.
    let t = [[-1e12, -1e12], [1e13, 0.0], [0.0, 1e13]];
    let count = coverage(&[t], 8, 8);
    assert!(count.iter().all(|&c| c == 1));
    let t = [[-1e300, 4.0], [1e300, 4.0], [0.0, 1e300]];
    let count = coverage(&[t], 8, 8);
    assert_eq!(count.iter().filter(|&&c| c == 1).count(), 32);
    let count = coverage(&[[[f64::NAN, 0.0], [5.0, 0.0], [0.0, 5.0]]], 8, 8);
    assert!(count.iter().all(|&c| c == 0));
}

#[test]
fn lines_are_clipped() {
    let clip = Clip::new(
        Rect {
            x: 2,
            y: 2,
            width: 4,
            height: 4,
        },
        10,
        10,
    );
    let mut n = 0;
    draw_line([-100.0, 3.5], [100.0, 3.5], &clip, |x, y, _| {
        assert!((2..6).contains(&x) && y == 3);
        n += 1;
    });
    assert_eq!(n, 4);
    draw_line([0.0, 0.0], [1.0, 9.0], &clip, |_, _, _| panic!("outside"));
    let mut ts = vec![];
    draw_line([2.5, 2.5], [5.5, 5.5], &clip, |x, y, t| {
        assert_eq!(x, y);
        ts.push(t)
    });
    assert_eq!(ts, vec![0.0, 1.0 / 3.0, 2.0 / 3.0, 1.0]);
    draw_line([1e300, -1e300], [-1e300, 1e300], &clip, |_, _, _| {});
}
