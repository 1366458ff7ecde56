//! Small fixed-size vector helpers used by the numeric kernels.

/// `a - b`.
#[inline]
pub fn sub<const D: usize>(a: [f64; D], b: [f64; D]) -> [f64; D] {
    std::array::from_fn(|k| a[k] - b[k])
}

/// `a + b`.
#[inline]
pub fn add<const D: usize>(a: [f64; D], b: [f64; D]) -> [f64; D] {
    std::array::from_fn(|k| a[k] + b[k])
}

/// `s a`.
#[inline]
pub fn scale<const D: usize>(a: [f64; D], s: f64) -> [f64; D] {
    a.map(|x| x * s)
}

/// Dot product.
#[inline]
pub fn dot<const D: usize>(a: [f64; D], b: [f64; D]) -> f64 {
    (0..D).map(|k| a[k] * b[k]).sum()
}

/// Euclidean length.
#[inline]
pub fn norm<const D: usize>(a: [f64; D]) -> f64 {
    dot(a, a).sqrt()
}

/// Cross product.
#[inline]
pub fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// Signed area of the planar triangle `abc`: positive when counter-clockwise.
#[inline]
pub fn signed_area2(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))
}

/// Centroid of a triangle.
#[inline]
pub fn centroid<const D: usize>(p: [[f64; D]; 3]) -> [f64; D] {
    std::array::from_fn(|k| (p[0][k] + p[1][k] + p[2][k]) / 3.0)
}

/// The mean of `points` (the origin for none).
pub fn mean_of<const D: usize>(points: &[[f64; D]]) -> [f64; D] {
    let sum = points.iter().fold([0.0; D], |acc, &p| add(acc, p));
    scale(sum, 1.0 / points.len().max(1) as f64)
}

/// The angle between two vectors from `y = |a × b|` and `x = a · b`
/// (`atan2(y, x)` for `y ≥ 0`, to 1e-7 radian; 0 when both are 0).
#[inline]
pub fn corner_angle(y: f64, x: f64) -> f64 {
    // Reduced to an arctangent of [0, 1].
    if y <= x.abs() {
        if x == 0.0 {
            return 0.0;
        }
        let a = atan_unit(y / x.abs());
        if x > 0.0 {
            a
        } else {
            std::f64::consts::PI - a
        }
    } else {
        std::f64::consts::FRAC_PI_2 - atan_unit(x / y)
    }
}

/// `atan(z)` for `|z| ≤ 1`, within 9e-8: `z P(z²)` with `P` the degree-7
/// least-squares fit of `atan(z) / z` at Chebyshev points of [0, 1] (a
/// weight only ever compared with weights computed the same way).
#[inline]
fn atan_unit(z: f64) -> f64 {
    const P: [f64; 8] = [
        0.999_999_958_195_305_7,
        -0.333_323_028_277_101_25,
        0.199_736_813_634_497_9,
        -0.140_401_388_912_063_88,
        0.099_679_236_189_595_25,
        -0.060_219_127_990_394_89,
        0.024_756_780_690_648_406,
        -0.004_831_168_387_439_688,
    ];
    let t = z * z;
    let mut p = P[7];
    for c in P[..7].iter().rev() {
        p = p * t + c;
    }
    z * p
}

/// Unit vertex normals of a triangle mesh in space, each triangle weighing
/// its angle at the vertex (the rule of Blender and most modellers; zero for
/// vertices no triangle uses).
pub fn angle_weighted_vertex_normals(
    positions: &[[f64; 3]],
    triangles: &[[u32; 3]],
) -> Vec<[f64; 3]> {
    angle_weighted_normals(positions, triangles, positions.len(), |t, k| {
        triangles[t][k] as usize
    })
}

/// [`angle_weighted_vertex_normals`] of `count` groups of triangle corners:
/// corner `k` of triangle `t` adds to group `group(t, k)` (a vertex, or a
/// vertex on one side of a hard edge). Zero for groups no corner adds to.
pub fn angle_weighted_normals(
    positions: &[[f64; 3]],
    triangles: &[[u32; 3]],
    count: usize,
    group: impl Fn(usize, usize) -> usize,
) -> Vec<[f64; 3]> {
    let mut normals = vec![[0.0; 3]; count];
    for (i, t) in triangles.iter().enumerate() {
        let p = t.map(|v| positions[v as usize]);
        let n = cross(sub(p[1], p[0]), sub(p[2], p[0]));
        let len = norm(n);
        if len == 0.0 {
            continue;
        }
        for k in 0..3 {
            let (a, b) = (sub(p[(k + 1) % 3], p[k]), sub(p[(k + 2) % 3], p[k]));
            // |a × b| is twice the triangle's area at every corner.
            let weight = corner_angle(len, dot(a, b)) / len;
            let g = group(i, k);
            normals[g] = add(normals[g], scale(n, weight));
        }
    }
    for n in &mut normals {
        let len = norm(*n);
        if len > 0.0 {
            *n = scale(*n, 1.0 / len);
        }
    }
    normals
}

/// `v` turned by the smallest rotation taking unit `from` to unit `to`
/// (unchanged when either is zero or they coincide; for opposite
/// directions, the half turn about an axis orthogonal to `from`).
pub fn least_turn(v: [f64; 3], from: [f64; 3], to: [f64; 3]) -> [f64; 3] {
    if from == to || v.iter().any(|x| !x.is_finite()) || norm(from) == 0.0 || norm(to) == 0.0 {
        return v;
    }
    let c = dot(from, to);
    let axis = cross(from, to);
    if c <= -1.0 + 1e-12 {
        // Half turn about any axis orthogonal to `from`.
        let e = if from[0].abs() < 0.9 {
            [1.0, 0.0, 0.0]
        } else {
            [0.0, 1.0, 0.0]
        };
        let k = cross(from, e);
        let k = scale(k, 1.0 / norm(k));
        return sub(scale(k, 2.0 * dot(k, v)), v);
    }
    // Rodrigues with the unnormalised axis: v c + (a × v) + a (a·v) / (1 + c).
    add(
        add(scale(v, c), cross(axis, v)),
        scale(axis, dot(axis, v) / (1.0 + c)),
    )
}
