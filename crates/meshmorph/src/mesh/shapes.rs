//! Procedural meshes for demos, tests and benchmarks: no files needed.

use crate::linalg::vector::{add, scale};
use crate::mesh::{Mesh2, Mesh3};

/// A `length × width` rectangle with its lower-left corner at the origin,
/// split into `nx × ny` cells of two counter-clockwise triangles each
/// (`2 nx ny` triangles, `(nx + 1)(ny + 1)` vertices, row by row).
///
/// # Panics
/// If `nx` or `ny` is 0 or the sizes are not positive.
pub fn strip(length: f64, width: f64, nx: usize, ny: usize) -> Mesh2 {
    assert!(
        nx > 0 && ny > 0 && length > 0.0 && width > 0.0,
        "empty strip"
    );
    let mut positions = Vec::with_capacity((nx + 1) * (ny + 1));
    for j in 0..=ny {
        for i in 0..=nx {
            positions.push([length * i as f64 / nx as f64, width * j as f64 / ny as f64]);
        }
    }
    let id = |i: usize, j: usize| (j * (nx + 1) + i) as u32;
    let mut triangles = Vec::with_capacity(2 * nx * ny);
    for j in 0..ny {
        for i in 0..nx {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            // Alternate the diagonal so the mesh has no preferred direction.
            if (i + j) % 2 == 0 {
                triangles.push([a, b, c]);
                triangles.push([a, c, d]);
            } else {
                triangles.push([a, b, d]);
                triangles.push([b, c, d]);
            }
        }
    }
    Mesh2::new(positions, triangles).expect("a strip is a valid mesh")
}

/// Bends a strip made by [`strip`] (`x` along its length from 0 to `length`,
/// `y` across it) into an Euler spiral: the centre line's tangent turns by
/// `total_angle · (x / length)²` radians, so the strip curls ever tighter
/// and, for angles beyond a full turn, winds into a spiral without
/// overlapping itself. Lengths along the centre line are kept.
pub fn curl(strip: &Mesh2, total_angle: f64) -> Mesh2 {
    let p = strip.positions();
    let length = p.iter().map(|q| q[0]).fold(0.0, f64::max);
    let width = p.iter().map(|q| q[1]).fold(0.0, f64::max);
    let steps = 4096;
    let ds = length / steps as f64;
    let turn = |s: f64| total_angle * (s / length).powi(2);
    // Centre line by the midpoint rule, sampled at `steps + 1` points.
    let mut centre = Vec::with_capacity(steps + 1);
    let mut c = [0.0, 0.0];
    centre.push(c);
    for k in 0..steps {
        let phi = turn((k as f64 + 0.5) * ds);
        c = add(c, [ds * phi.cos(), ds * phi.sin()]);
        centre.push(c);
    }
    let positions = p
        .iter()
        .map(|&[x, y]| {
            let u = (x / ds).clamp(0.0, steps as f64);
            let k = (u.floor() as usize).min(steps - 1);
            let f = u - k as f64;
            let on = add(scale(centre[k], 1.0 - f), scale(centre[k + 1], f));
            let phi = turn(x);
            add(on, scale([-phi.sin(), phi.cos()], y - 0.5 * width))
        })
        .collect();
    strip
        .with_positions(positions)
        .expect("bending keeps coordinates finite")
}

/// Rotates a planar mesh by `angle` radians about `centre` and translates it.
pub fn rigid_motion(mesh: &Mesh2, angle: f64, centre: [f64; 2], translation: [f64; 2]) -> Mesh2 {
    let (s, c) = angle.sin_cos();
    let positions = mesh
        .positions()
        .iter()
        .map(|p| {
            let (x, y) = (p[0] - centre[0], p[1] - centre[1]);
            [
                c * x - s * y + centre[0] + translation[0],
                s * x + c * y + centre[1] + translation[1],
            ]
        })
        .collect();
    mesh.with_positions(positions)
        .expect("a rigid motion keeps coordinates finite")
}

/// A closed tube (a cylinder with capped ends) of the given `radius` along
/// the x axis from 0 to `length`: `rings` rings of `segments` vertices, plus
/// one centre vertex per cap. Triangles face outwards.
///
/// # Panics
/// If `rings < 2` or `segments < 3`.
pub fn tube(length: f64, radius: f64, rings: usize, segments: usize) -> Mesh3 {
    assert!(rings >= 2 && segments >= 3, "tube too coarse");
    let mut positions = Vec::with_capacity(rings * segments + 2);
    for r in 0..rings {
        let x = length * r as f64 / (rings - 1) as f64;
        for s in 0..segments {
            let a = std::f64::consts::TAU * s as f64 / segments as f64;
            positions.push([x, radius * a.cos(), radius * a.sin()]);
        }
    }
    let id = |r: usize, s: usize| (r * segments + s % segments) as u32;
    let mut triangles = Vec::with_capacity(2 * rings * segments);
    for r in 0..rings - 1 {
        for s in 0..segments {
            let (a, b, c, d) = (id(r, s), id(r, s + 1), id(r + 1, s + 1), id(r + 1, s));
            triangles.push([a, b, c]);
            triangles.push([a, c, d]);
        }
    }
    let start = positions.len() as u32;
    positions.push([0.0, 0.0, 0.0]);
    positions.push([length, 0.0, 0.0]);
    for s in 0..segments {
        triangles.push([start, id(0, s + 1), id(0, s)]);
        triangles.push([start + 1, id(rings - 1, s), id(rings - 1, s + 1)]);
    }
    Mesh3::new(positions, triangles).expect("a tube is a valid mesh")
}

/// A regular octahedron of `radius` (centre to vertex) centred at `centre`:
/// a small closed part (an eye, a ball) for tests of separate parts.
/// Triangles face outwards.
pub fn octahedron(centre: [f64; 3], radius: f64) -> Mesh3 {
    // Vertices +x -x +y -y +z -z; each face takes one of each axis.
    let mut positions = Vec::with_capacity(6);
    for axis in 0..3 {
        for sign in [1.0, -1.0] {
            let mut p = centre;
            p[axis] += sign * radius;
            positions.push(p);
        }
    }
    let triangles = vec![
        [0, 2, 4],
        [2, 1, 4],
        [1, 3, 4],
        [3, 0, 4],
        [2, 0, 5],
        [1, 2, 5],
        [3, 1, 5],
        [0, 3, 5],
    ];
    Mesh3::new(positions, triangles).expect("an octahedron is a valid mesh")
}

/// Bends a mesh lying along the x axis from 0 to `length` in the x-y plane:
/// the point at `x` turns about the z axis by `angle · (x / length)`,
/// following a circular arc, so a straight tube becomes a bent one with
/// lengths along its axis kept.
pub fn bend(mesh: &Mesh3, length: f64, angle: f64) -> Mesh3 {
    if angle == 0.0 {
        return mesh.clone();
    }
    let radius = length / angle;
    let positions = mesh
        .positions()
        .iter()
        .map(|&[x, y, z]| {
            let phi = angle * (x / length);
            let r = radius - y;
            [r * phi.sin(), radius - r * phi.cos(), z]
        })
        .collect();
    mesh.with_positions(positions)
        .expect("bending keeps coordinates finite")
}

/// Twists a mesh lying along the x axis from 0 to `length` about that axis:
/// the point at `x` turns about the x axis by `angle · (x / length)`
/// radians (counter-clockwise seen from +x), so a straight tube becomes a
/// twisted one.
pub fn twist(mesh: &Mesh3, length: f64, angle: f64) -> Mesh3 {
    let positions = mesh
        .positions()
        .iter()
        .map(|&[x, y, z]| {
            let (s, c) = (angle * (x / length)).sin_cos();
            [x, c * y - s * z, s * y + c * z]
        })
        .collect();
    mesh.with_positions(positions)
        .expect("twisting keeps coordinates finite")
}

/// The rotation matrix (row-major) of the rotation vector `w`: a turn
/// about the axis `w / |w|` by `|w|` radians, counter-clockwise seen from
/// the axis' tip. For [`rigid_motion3`].
pub fn rotation_matrix(w: [f64; 3]) -> [[f64; 3]; 3] {
    crate::linalg::quaternion::exp_rotation(w)
}

/// Applies the rotation matrix `rotation` (row-major) about the origin and
/// then `translation` to every vertex.
pub fn rigid_motion3(mesh: &Mesh3, rotation: [[f64; 3]; 3], translation: [f64; 3]) -> Mesh3 {
    let positions = mesh
        .positions()
        .iter()
        .map(|p| {
            std::array::from_fn(|i| {
                (0..3).map(|k| rotation[i][k] * p[k]).sum::<f64>() + translation[i]
            })
        })
        .collect();
    mesh.with_positions(positions)
        .expect("a rigid motion keeps coordinates finite")
}

/// For each of `source_vertices`, the index of the nearest of `target`
/// positions: marker pairs for meshes that are already aligned (by brute
/// force: meant for a few dozen markers).
pub fn nearest_vertex_pairs(
    source: &[[f64; 3]],
    target: &[[f64; 3]],
    source_vertices: &[u32],
) -> Vec<[u32; 2]> {
    source_vertices
        .iter()
        .filter_map(|&s| {
            let p = source[s as usize];
            let t = (0..target.len()).min_by(|&a, &b| {
                let da = crate::linalg::vector::norm(crate::linalg::vector::sub(target[a], p));
                let db = crate::linalg::vector::norm(crate::linalg::vector::sub(target[b], p));
                da.total_cmp(&db)
            })?;
            Some([s, t as u32])
        })
        .collect()
}

/// The outline of a stroke drawn along a turtle's path, for drawings made
/// in code: counter-clockwise, one loop, points about `spacing` apart.
///
/// The path starts at `start` heading `heading` (radians,
/// counter-clockwise from +x); each step is `(length, turn)`, the turn
/// (radians, positive to the left) spread evenly over its length, so each
/// step is a straight piece or an arc. `half_width(s)` is the stroke's
/// half-width at the fraction `s` (0 to 1) of the path's length; both ends
/// are capped by half circles. The outline is simple when every arc's
/// radius exceeds the half-width there and the path stays more than a
/// width away from itself.
///
/// # Panics
/// If `spacing` is not positive or there are no steps.
pub fn stroke_outline(
    start: [f64; 2],
    heading: f64,
    steps: &[(f64, f64)],
    half_width: &dyn Fn(f64) -> f64,
    spacing: f64,
) -> Vec<[f64; 2]> {
    use std::f64::consts::PI;
    assert!(spacing > 0.0 && !steps.is_empty(), "empty stroke");
    let total: f64 = steps.iter().map(|s| s.0).sum();
    // The centre line: (point, heading, arc length) every `spacing` or so.
    let mut centre = vec![(start, heading, 0.0)];
    let (mut p, mut h, mut s) = (start, heading, 0.0);
    for &(length, turn) in steps {
        let n = ((length / spacing).ceil() as usize).max(1);
        let (ds, dh) = (length / n as f64, turn / n as f64);
        for _ in 0..n {
            // Exact on an arc: the chord follows the mean heading.
            let chord = if dh.abs() < 1e-12 {
                ds
            } else {
                2.0 * ds / dh * (0.5 * dh).sin()
            };
            let mid = h + 0.5 * dh;
            p = [p[0] + chord * mid.cos(), p[1] + chord * mid.sin()];
            h += dh;
            s += ds;
            centre.push((p, h, s));
        }
    }
    let at = |(p, h, s): ([f64; 2], f64, f64), side: f64, angle: f64| {
        let w = half_width((s / total).clamp(0.0, 1.0));
        let a = h + side * angle;
        [p[0] + w * a.cos(), p[1] + w * a.sin()]
    };
    let cap = |c: ([f64; 2], f64, f64)| {
        ((PI * half_width((c.2 / total).clamp(0.0, 1.0)) / spacing).ceil() as usize).max(2)
    };
    let last = centre[centre.len() - 1];
    let mut out: Vec<[f64; 2]> = centre.iter().map(|&c| at(c, -1.0, PI / 2.0)).collect();
    let n = cap(last);
    out.extend((1..n).map(|k| at(last, 1.0, -PI / 2.0 + PI * k as f64 / n as f64)));
    out.extend(centre.iter().rev().map(|&c| at(c, 1.0, PI / 2.0)));
    let n = cap(centre[0]);
    out.extend((1..n).map(|k| at(centre[0], 1.0, PI / 2.0 + PI * k as f64 / n as f64)));
    out
}

/// `mesh` with each triangle split in four at its edges' midpoints (the
/// same surface with four times the triangles and about four times the
/// vertices): a denser mesh of a shape, for benchmarks.
pub fn subdivide(mesh: &Mesh3) -> Mesh3 {
    use std::collections::HashMap;
    let mut positions = mesh.positions().to_vec();
    let mut midpoint: HashMap<(u32, u32), u32> = HashMap::new();
    let mut triangles = Vec::with_capacity(4 * mesh.num_triangles());
    for &[a, b, c] in mesh.triangles() {
        let mut mid = |u: u32, v: u32| {
            *midpoint.entry((u.min(v), u.max(v))).or_insert_with(|| {
                let (p, q) = (positions[u as usize], positions[v as usize]);
                positions.push(scale(add(p, q), 0.5));
                positions.len() as u32 - 1
            })
        };
        let (ab, bc, ca) = (mid(a, b), mid(b, c), mid(c, a));
        triangles.extend([[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]);
    }
    Mesh3::new(positions, triangles).expect("a subdivided mesh is a valid mesh")
}
