//! Several compatible pairs made into one set: each pair is a mesh of the
//! first drawing (the same boundary points for all) with its positions in
//! one other drawing. Their edges, laid over each other in the first
//! drawing as the constraints of one constrained Delaunay triangulation
//! (`spade`, crossings split where they cross), cut the region into
//! triangles each inside one triangle of every pair's mesh. Each pair's
//! mesh maps the first drawing into its other drawing affinely on each
//! of its triangles, without turning any over, so the common triangles
//! carried by those maps stay positive in every drawing.

use rstar::primitives::{GeomWithData, Rectangle};
use rstar::RTree;
use spade::handles::FixedVertexHandle;
use spade::{ConstrainedDelaunayTriangulation, Point2, Triangulation};

use crate::error::{Error, Result};

/// A compatible pair: positions in the first drawing and in another, the
/// shared triangles; the first `n` vertices are the common boundary.
pub(crate) struct PairMesh {
    pub(crate) first: Vec<[f64; 2]>,
    pub(crate) other: Vec<[f64; 2]>,
    pub(crate) triangles: Vec<[u32; 3]>,
}

/// Where points of the first drawing fall in a pair's mesh.
struct Locator<'a> {
    mesh: &'a PairMesh,
    tree: RTree<GeomWithData<Rectangle<[f64; 2]>, usize>>,
}

impl<'a> Locator<'a> {
    fn new(mesh: &'a PairMesh) -> Self {
        let boxes = mesh
            .triangles
            .iter()
            .enumerate()
            .map(|(t, tri)| {
                let p = tri.map(|v| mesh.first[v as usize]);
                let lo = [
                    p[0][0].min(p[1][0]).min(p[2][0]),
                    p[0][1].min(p[1][1]).min(p[2][1]),
                ];
                let hi = [
                    p[0][0].max(p[1][0]).max(p[2][0]),
                    p[0][1].max(p[1][1]).max(p[2][1]),
                ];
                GeomWithData::new(Rectangle::from_corners(lo, hi), t)
            })
            .collect();
        Self {
            mesh,
            tree: RTree::bulk_load(boxes),
        }
    }

    /// Barycentric coordinates of `p` in triangle `t` of the first drawing.
    fn barycentric(&self, t: usize, p: [f64; 2]) -> [f64; 3] {
        let [a, b, c] = self.mesh.triangles[t].map(|v| self.mesh.first[v as usize]);
        let det = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]);
        let l1 = ((p[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (p[1] - a[1])) / det;
        let l2 = ((b[0] - a[0]) * (p[1] - a[1]) - (p[0] - a[0]) * (b[1] - a[1])) / det;
        [1.0 - l1 - l2, l1, l2]
    }

    /// The triangle holding `p` (the one it is deepest inside), if any
    /// holds it to within `slack` of its barycentric coordinates.
    fn locate(&self, p: [f64; 2], slack: f64) -> Option<usize> {
        let mut best: Option<(f64, usize)> = None;
        for hit in self.tree.locate_all_at_point(p) {
            let l = self.barycentric(hit.data, p);
            let depth = l[0].min(l[1]).min(l[2]);
            if depth >= -slack && best.is_none_or(|b| depth > b.0) {
                best = Some((depth, hit.data));
            }
        }
        best.map(|b| b.1)
    }

    /// Where `p` goes in the other drawing, through triangle `t`.
    fn carry(&self, t: usize, p: [f64; 2]) -> [f64; 2] {
        let l = self.barycentric(t, p);
        let [a, b, c] = self.mesh.triangles[t].map(|v| self.mesh.other[v as usize]);
        [
            l[0] * a[0] + l[1] * b[0] + l[2] * c[0],
            l[0] * a[1] + l[1] * b[1] + l[2] * c[1],
        ]
    }
}

/// One mesh refining every pair's: positions in the first drawing, then
/// in each pair's other drawing, and the triangles; the first `n`
/// vertices are the common boundary, where they were.
///
/// # Errors
/// [`Error::IncompatibleDrawings`] when the pairs' meshes do not cover
/// one region (not expected from compatible pairs).
pub(crate) fn merge(pairs: &[PairMesh], n: usize) -> Result<(Vec<Vec<[f64; 2]>>, Vec<[u32; 3]>)> {
    let failed = |what: &str| {
        Error::IncompatibleDrawings(format!(
            "the compatible meshes of the drawings could not be laid over each other ({what})"
        ))
    };
    let mut cdt = ConstrainedDelaunayTriangulation::<Point2<f64>>::new();
    let insert = |cdt: &mut ConstrainedDelaunayTriangulation<Point2<f64>>, p: [f64; 2]| {
        cdt.insert(Point2::new(p[0], p[1]))
            .map_err(|_| failed("a point is not finite"))
    };
    let mut handle_of: Vec<Vec<FixedVertexHandle>> = Vec::with_capacity(pairs.len());
    for (k, pair) in pairs.iter().enumerate() {
        let mut handles = Vec::with_capacity(pair.first.len());
        for (v, &p) in pair.first.iter().enumerate() {
            if k > 0 && v < n {
                handles.push(handle_of[0][v]);
            } else {
                handles.push(insert(&mut cdt, p)?);
            }
        }
        handle_of.push(handles);
    }
    for (k, pair) in pairs.iter().enumerate() {
        let mut edges: Vec<(u32, u32)> = pair
            .triangles
            .iter()
            .flat_map(|t| (0..3).map(move |i| (t[i].min(t[(i + 1) % 3]), t[i].max(t[(i + 1) % 3]))))
            .collect();
        edges.sort_unstable();
        edges.dedup();
        for (u, v) in edges {
            let (hu, hv) = (handle_of[k][u as usize], handle_of[k][v as usize]);
            if hu != hv {
                cdt.add_constraint_and_split(hu, hv, |p| p);
            }
        }
    }
    let locators: Vec<Locator> = pairs.iter().map(Locator::new).collect();
    // Which vertex of which pair each triangulation vertex is, when it is one.
    let mut own: Vec<Option<(usize, usize)>> = vec![None; cdt.num_vertices()];
    for (k, handles) in handle_of.iter().enumerate() {
        for (v, h) in handles.iter().enumerate() {
            own[h.index()].get_or_insert((k, v));
        }
    }
    let count = cdt.num_vertices();
    let mut new_index = vec![u32::MAX; count];
    let mut first: Vec<[f64; 2]> = Vec::with_capacity(count);
    let mut others: Vec<Vec<[f64; 2]>> = vec![Vec::with_capacity(count); pairs.len()];
    for v in 0..n {
        let h = handle_of[0][v];
        new_index[h.index()] = v as u32;
        first.push(pairs[0].first[v]);
        for (k, pair) in pairs.iter().enumerate() {
            others[k].push(pair.other[v]);
        }
    }
    let mut triangles = Vec::new();
    for face in cdt.inner_faces() {
        let verts = face.vertices();
        let pos = verts.map(|h| {
            let p = h.position();
            [p.x, p.y]
        });
        let centroid = [
            (pos[0][0] + pos[1][0] + pos[2][0]) / 3.0,
            (pos[0][1] + pos[1][1] + pos[2][1]) / 3.0,
        ];
        let Some(t0) = locators[0].locate(centroid, 0.0) else {
            continue;
        };
        let mut holders = Vec::with_capacity(pairs.len());
        holders.push(t0);
        for locator in &locators[1..] {
            holders.push(
                locator.locate(centroid, 1e-9).ok_or_else(|| {
                    failed("a triangle of one pair's mesh lies outside another's")
                })?,
            );
        }
        let mut tri = [0u32; 3];
        for (c, h) in verts.iter().enumerate() {
            let i = h.fix().index();
            if new_index[i] == u32::MAX {
                new_index[i] = first.len() as u32;
                first.push(pos[c]);
                for (k, locator) in locators.iter().enumerate() {
                    let p = match own[i] {
                        Some((j, v)) if j == k => pairs[k].other[v],
                        _ => locator.carry(holders[k], pos[c]),
                    };
                    others[k].push(p);
                }
            }
            tri[c] = new_index[i];
        }
        triangles.push(tri);
    }
    if triangles.is_empty() {
        return Err(failed("no triangle inside"));
    }
    let mut meshes = Vec::with_capacity(pairs.len() + 1);
    meshes.push(first);
    meshes.extend(others);
    Ok((meshes, triangles))
}
