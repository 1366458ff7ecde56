use meshmorph::gradient::GradientOperators;
use meshmorph::linalg::matrix::{identity, mul_vec, Mat3};
use meshmorph::transfer::mirror_plane::MirrorPlane;

use meshmorph::gradient::spatial::fourth_vertex;
use meshmorph::linalg::matrix::mul;
use meshmorph::mesh::shapes::{bend, tube};
use meshmorph::transfer::matching::*;

#[test]
fn the_turn_keeps_mirror_planes_together_and_its_turn_about_them() {
    let about = |axis: usize, a: f64| -> Mat3 {
        let (s, c) = a.sin_cos();
        let (i, j) = [(1, 2), (2, 0), (0, 1)][axis];
        let mut m = identity();
        m[i][i] = c;
        m[j][j] = c;
        m[i][j] = -s;
        m[j][i] = s;
        m
    };
    let plane = |normal: [f64; 3]| MirrorPlane {
        normal,
        offset: 0.0,
        misfit: 0.0,
    };
    // A turn of 0.3 about the planes' normal (z), tilted by 0.02 about x.
    let turn = mul(about(0, 0.02), about(2, 0.3));
    let (kept, together) = mirror_planes_together(
        turn,
        (Some(plane([0.0, 0.0, 1.0])), Some(plane([0.0, 0.0, -1.0]))),
    );
    let z = mul_vec(&kept, [0.0, 0.0, 1.0]);
    assert!((z[2] - 1.0).abs() < 1e-12, "{z:?}");
    let angle = kept[1][0].atan2(kept[0][0]);
    assert!((angle - 0.3).abs() < 1e-3, "turn about the normal {angle}");
    assert!(together.is_some());
    // Planes the turn leaves far apart, or a missing plane: unchanged.
    let tilted = mul(about(0, 0.5), about(2, 0.3));
    let planes = (Some(plane([0.0, 0.0, 1.0])), Some(plane([0.0, 0.0, 1.0])));
    assert_eq!(mirror_planes_together(tilted, planes), (tilted, None));
    assert_eq!(mirror_planes_together(turn, (None, planes.1)), (turn, None));
}

#[test]
fn a_similar_copy_gives_every_triangle_its_similarity_as_shape_target() {
    let rest = bend(&tube(2.0, 0.3, 7, 8), 2.0, 1.0);
    let ops = GradientOperators::spatial(&rest, "rest").unwrap();
    let (a, b) = (0.6f64, -1.1f64);
    let about_z = [
        [a.cos(), -a.sin(), 0.0],
        [a.sin(), a.cos(), 0.0],
        [0.0, 0.0, 1.0],
    ];
    let about_x = [
        [1.0, 0.0, 0.0],
        [0.0, b.cos(), -b.sin()],
        [0.0, b.sin(), b.cos()],
    ];
    let R = mul(about_z, about_x);
    let s = 1.7;
    let map = |p: [f64; 3]| -> [f64; 3] {
        std::array::from_fn(|i| {
            s * (R[i][0] * p[0] + R[i][1] * p[1] + R[i][2] * p[2]) + [0.3, -1.0, 2.0][i]
        })
    };
    let (n, m) = (rest.num_vertices(), ops.num_unknowns());
    let mut x = vec![0.0; 3 * m];
    let moved = (0..n)
        .map(|v| map(rest.positions()[v]))
        .chain((0..rest.num_triangles()).map(|t| map(fourth_vertex(rest.corners(t)))));
    for (u, q) in moved.enumerate() {
        for i in 0..3 {
            x[i * m + u] = q[i];
        }
    }
    for (t, S) in nearest_similarities(&ops, &x).iter().enumerate() {
        for i in 0..3 {
            for j in 0..3 {
                let d = (S[i][j] - s * R[i][j]).abs();
                assert!(d < 1e-9, "triangle {t}: entry ({i}, {j}) off by {d}");
            }
        }
    }
}
