//! Markers as points of the surfaces: MeshLab's picked points and Wrap's
//! points on triangles read into the same correspondence as the index
//! file they stand for, a point moved along its triangle moving the result
//! continuously, names and order that change nothing, and every bad input
//! refused with its file and line.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use meshmorph::shapes::{nearest_vertex_pairs, tube};
use meshmorph::{
    correspond, CorrespondOptions, CorrespondResult, Error, Markers, Mesh3, SurfacePoint,
    VertexNumbering,
};

/// A thin tube and a thick one, and marker vertex pairs between them.
fn tubes() -> (Mesh3, Mesh3, Vec<[u32; 2]>) {
    let thin = tube(2.0, 0.25, 7, 8);
    let thick = tube(2.0, 0.5, 5, 10);
    let widened: Vec<[f64; 3]> = thin
        .positions()
        .iter()
        .map(|p| [p[0], 2.0 * p[1], 2.0 * p[2]])
        .collect();
    let chosen: Vec<u32> = [0u32, 3, 6]
        .iter()
        .flat_map(|&r| [0, 2, 4, 6].map(|s| r * 8 + s))
        .collect();
    let pairs = nearest_vertex_pairs(&widened, thick.positions(), &chosen);
    (thin, thick, pairs)
}

/// The correspondence of `markers`, snapped first.
fn found(source: &Mesh3, target: &Mesh3, markers: &Markers) -> CorrespondResult {
    let (markers, _) = markers.snap(source, target).unwrap();
    correspond(source, target, &markers, &CorrespondOptions::default()).unwrap()
}

/// Asserts two results are the same, bit for bit.
fn assert_same(a: &CorrespondResult, b: &CorrespondResult, what: &str) {
    assert_eq!(a.correspondence, b.correspondence, "{what}: other pairs");
    assert_eq!(
        a.deformed_source, b.deformed_source,
        "{what}: other deformed source"
    );
}

/// A MeshLab picked-points file of `points`, with their names, in order.
fn picked_points(points: &[(String, [f64; 3])]) -> String {
    let mut s = String::from(
        "<!DOCTYPE PickedPoints>\n<PickedPoints>\n <DocumentData>\n  <DataFileName name=\"mesh.obj\"/>\n </DocumentData>\n",
    );
    for (name, p) in points {
        writeln!(
            s,
            " <point x=\"{:?}\" y=\"{:?}\" z=\"{:?}\" active=\"1\" name=\"{name}\"/>",
            p[0], p[1], p[2]
        )
        .unwrap();
    }
    s + "</PickedPoints>\n"
}

/// A triangle of `mesh` with `v` as a corner, as Wrap's `[t, u, v]`.
fn wrap_corner(mesh: &Mesh3, v: u32) -> String {
    let (t, tri) = mesh
        .triangles()
        .iter()
        .enumerate()
        .find(|(_, tri)| tri.contains(&v))
        .unwrap();
    let (u, w) = match tri.iter().position(|&c| c == v).unwrap() {
        0 => (1.0, 0.0),
        1 => (0.0, 1.0),
        _ => (0.0, 0.0),
    };
    format!("[{t}, {u:?}, {w:?}]")
}

struct Dir(tempfile::TempDir);

impl Dir {
    fn new() -> Self {
        Dir(tempfile::tempdir().unwrap())
    }
    fn write(&self, name: &str, text: &str) -> PathBuf {
        let p = self.0.path().join(name);
        std::fs::write(&p, text).unwrap();
        p
    }
}

#[test]
fn picked_points_and_wrap_files_give_the_index_files_correspondence() {
    let (thin, thick, pairs) = tubes();
    let dir = Dir::new();
    let index: String = pairs.iter().map(|[s, t]| format!("{s} {t}\n")).collect();
    let index = dir.write("markers.txt", &index);
    let want = found(
        &thin,
        &thick,
        &Markers::read(&index, VertexNumbering::FromZero).unwrap(),
    );
    // Picked points, named, the target's in reverse order: paired by name.
    let named = |mesh: &Mesh3, side: usize| -> Vec<(String, [f64; 3])> {
        pairs
            .iter()
            .enumerate()
            .map(|(k, p)| (format!("m{k}"), mesh.positions()[p[side] as usize]))
            .collect()
    };
    let mut target_points = named(&thick, 1);
    target_points.reverse();
    let (s, t) = (
        dir.write("thin.pp", &picked_points(&named(&thin, 0))),
        dir.write("thick.pp", &picked_points(&target_points)),
    );
    let picked = Markers::read_pair(&s, &t, VertexNumbering::FromZero).unwrap();
    let (snapped, snap) = picked.snap(&thin, &thick).unwrap();
    assert_eq!(
        (snap.points, snap.largest_source, snap.largest_target),
        (pairs.len(), 0.0, 0.0)
    );
    assert_eq!(snapped.pairs(), Markers::new(pairs.clone()).pairs());
    assert_same(&found(&thin, &thick, &picked), &want, "picked points");
    // Wrap: a list for the source, named points for the target (in order).
    let list: Vec<String> = pairs.iter().map(|p| wrap_corner(&thin, p[0])).collect();
    let object: Vec<String> = pairs
        .iter()
        .enumerate()
        .map(|(k, p)| format!("\"Point{k:02}\": {}", wrap_corner(&thick, p[1])))
        .collect();
    let (s, t) = (
        dir.write("thin.json", &format!("[{}]", list.join(", "))),
        dir.write("thick.json", &format!("{{{}}}", object.join(",\n"))),
    );
    let wrap = Markers::read_pair(&s, &t, VertexNumbering::FromZero).unwrap();
    assert!(wrap
        .pairs()
        .iter()
        .all(|p| matches!(p[0], SurfacePoint::Triangle { .. })));
    assert_same(&found(&thin, &thick, &wrap), &want, "Wrap points");
    // Saved in meshmorph's own format and read back: the same markers.
    let saved = dir.0.path().join("saved.txt");
    wrap.save(&saved).unwrap();
    let back = Markers::read(&saved, VertexNumbering::FromZero).unwrap();
    assert_eq!(back.pairs(), wrap.pairs());
    assert_eq!(back.name(3), Some("Point03"));
}

/// The index pairs with marker `k`'s source side a point of a triangle.
fn with_point(pairs: &[[u32; 2]], k: usize, point: SurfacePoint) -> Markers {
    let mut surface: Vec<[SurfacePoint; 2]> = Markers::new(pairs.to_vec()).pairs().to_vec();
    surface[k][0] = point;
    Markers::on_surfaces(surface)
}

#[test]
fn a_point_moved_along_its_triangle_moves_the_result_continuously() {
    let (thin, thick, pairs) = tubes();
    // Marker 5's source vertex, moved into a triangle it is a corner of.
    let k = 5;
    let v = pairs[k][0];
    let (t, tri) = thin
        .triangles()
        .iter()
        .enumerate()
        .find(|(_, tri)| tri[0] == v)
        .unwrap();
    assert_eq!(tri[0], v);
    let at = |s: f64| {
        let point = SurfacePoint::Triangle {
            triangle: t as u32,
            barycentric: [1.0 - s, 0.5 * s, 0.5 * s],
        };
        let markers = with_point(&pairs, k, point);
        let r = found(&thin, &thick, &markers);
        (r, point)
    };
    let step = 1e-3;
    let results: Vec<Vec<[f64; 3]>> = (0..4)
        .map(|i| {
            let (r, point) = at(0.3 + step * i as f64);
            // Stiff: the point lands on its target (the alignment moved
            // the source, and the result is in the target's frame).
            let landed = point.position(&r.deformed_source);
            let goal = thick.positions()[pairs[k][1] as usize];
            let miss = (0..3)
                .map(|j| (landed[j] - goal[j]).powi(2))
                .sum::<f64>()
                .sqrt();
            assert!(
                miss < 1e-3 * thick.bounding_box_diagonal(),
                "missed by {miss}"
            );
            r.deformed_source.positions().to_vec()
        })
        .collect();
    let moved = |a: &[[f64; 3]], b: &[[f64; 3]]| {
        a.iter()
            .zip(b)
            .map(|(p, q)| (0..3).map(|j| (p[j] - q[j]).abs()).fold(0.0, f64::max))
            .fold(0.0, f64::max)
    };
    let steps: Vec<f64> = results.windows(2).map(|w| moved(&w[0], &w[1])).collect();
    // Each step moves the result a little, and about as much as the others.
    for &d in &steps {
        assert!(d > 0.0 && d < 20.0 * step, "steps {steps:?}");
    }
    let (lo, hi) = steps.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), &d| {
        (lo.min(d), hi.max(d))
    });
    assert!(hi < 1.5 * lo, "steps {steps:?}");
    // At the corner, the point is the vertex: the index file's result.
    let corner = found(
        &thin,
        &thick,
        &with_point(
            &pairs,
            k,
            SurfacePoint::Triangle {
                triangle: t as u32,
                barycentric: [1.0, 0.0, 0.0],
            },
        ),
    );
    assert_same(
        &corner,
        &found(&thin, &thick, &Markers::new(pairs.clone())),
        "corner",
    );
}

#[test]
fn renamed_or_reordered_markers_change_nothing() {
    let (thin, thick, pairs) = tubes();
    // Some source points inside triangles, some positions off the vertices.
    let points: Vec<([f64; 3], [f64; 3])> = pairs
        .iter()
        .enumerate()
        .map(|(k, &[s, t])| {
            let mut p = thin.positions()[s as usize];
            if k % 3 == 1 {
                p[0] += if p[0] < 1.0 { 0.05 } else { -0.05 };
            }
            (p, thick.positions()[t as usize])
        })
        .collect();
    let dir = Dir::new();
    // The target's file in another order than the source's.
    let files = |order: &[usize], name: &dyn Fn(usize) -> String, tag: &str| {
        let file = |order: &[usize], side: usize| -> String {
            picked_points(
                &order
                    .iter()
                    .map(|&k| (name(k), if side == 0 { points[k].0 } else { points[k].1 }))
                    .collect::<Vec<_>>(),
            )
        };
        let a = dir.write(&format!("{tag}-source.pp"), &file(order, 0));
        let mut turned = order.to_vec();
        turned.rotate_left(order.len() / 3);
        let b = dir.write(&format!("{tag}-target.pp"), &file(&turned, 1));
        found(
            &thin,
            &thick,
            &Markers::read_pair(&a, &b, VertexNumbering::FromZero).unwrap(),
        )
    };
    let n = pairs.len();
    let natural: Vec<usize> = (0..n).collect();
    let want = files(&natural, &|k| format!("m{k}"), "a");
    let shuffled: Vec<usize> = (0..n).map(|k| (7 * k + 3) % n).collect();
    let mut sorted = shuffled.clone();
    sorted.sort_unstable();
    assert_eq!(sorted, natural);
    assert_same(
        &files(&shuffled, &|k| format!("m{k}"), "b"),
        &want,
        "reordered",
    );
    assert_same(
        &files(&natural, &|k| format!("point {}", n - k), "c"),
        &want,
        "renamed",
    );
}

/// Asserts `e` is refused naming each of `needles`.
fn refused(e: Error, needles: &[&str]) {
    let text = e.to_string();
    for n in needles {
        assert!(text.contains(n), "`{n}` not in: {text}");
    }
}

#[test]
fn every_bad_marker_input_is_refused_with_its_place() {
    let (thin, thick, pairs) = tubes();
    let dir = Dir::new();
    let pp = |name: &str, points: &[(&str, [f64; 3])]| {
        dir.write(
            name,
            &picked_points(
                &points
                    .iter()
                    .map(|(n, p)| (n.to_string(), *p))
                    .collect::<Vec<_>>(),
            ),
        )
    };
    let o = [0.0; 3];
    let read_pair = |a: &Path, b: &Path| Markers::read_pair(a, b, VertexNumbering::FromZero);
    // A name on one side only.
    let (a, b) = (
        pp("a.pp", &[("nose", o), ("eye", o)]),
        pp("b.pp", &[("nose", o), ("ear", o)]),
    );
    refused(
        read_pair(&a, &b).unwrap_err(),
        &["a.pp", "line 7", "`eye`", "b.pp"],
    );
    // A name given twice in one file.
    let twice = pp("twice.pp", &[("nose", o), ("nose", o)]);
    refused(
        read_pair(&twice, &b).unwrap_err(),
        &["twice.pp", "line 7", "`nose` is given twice"],
    );
    // Files without names of other lengths.
    let (c, d) = (
        dir.write("c.json", "[[0, 1, 0]]"),
        dir.write("d.json", "[[0, 1, 0], [1, 1, 0]]"),
    );
    refused(
        read_pair(&c, &d).unwrap_err(),
        &["c.json", "1 point here and 2 in", "d.json"],
    );
    // A point far from the surface.
    let far = pp("far.pp", &[("nose", o), ("eye", [0.5, 3.0, 0.0])]);
    let near = pp("near.pp", &[("nose", o), ("eye", o)]);
    let m = read_pair(&far, &near).unwrap();
    refused(
        m.snap(&thin, &thick).unwrap_err(),
        &[
            "far.pp",
            "line 7",
            "`eye`",
            "from the source mesh's surface",
            "within 2 %",
        ],
    );
    // A triangle out of range.
    let nt = thick.num_triangles();
    let (e, f) = (
        dir.write("e.json", "[[0, 1, 0], [1, 0, 1], [2, 0, 0]]"),
        dir.write(
            "f.json",
            &format!("[[0, 1, 0], [1, 0, 1], [{nt}, 0.5, 0.5]]"),
        ),
    );
    let m = read_pair(&e, &f).unwrap();
    refused(
        m.validate(&thin, &thick).unwrap_err(),
        &[
            "f.json",
            "point 3",
            &format!("target triangle {nt} is out of range (the target has {nt} triangles)"),
        ],
    );
    // Barycentric coordinates that do not sum to 1.
    let g = dir.write("g.txt", "0 0\nv 1 t 2 0.5 0.5 0.5\n");
    refused(
        Markers::read(&g, VertexNumbering::FromZero).unwrap_err(),
        &["g.txt", "line 2", "sum to 1.5, not 1"],
    );
    // Two markers on one point with different partners.
    let [s, t] = pairs[0];
    let h = dir.write("h.txt", &format!("{s} {t}\n1 1\n{s} {}\n", t + 1));
    refused(
        Markers::read(&h, VertexNumbering::FromZero)
            .unwrap()
            .validate(&thin, &thick)
            .unwrap_err(),
        &[
            "h.txt",
            "line 3",
            "two markers on one source point with different partners",
        ],
    );
    // A file of one mesh's points given alone.
    refused(
        Markers::read(&a, VertexNumbering::FromZero).unwrap_err(),
        &[
            "a.pp",
            "a MeshLab picked-points file holds the points of one mesh",
        ],
    );
}
