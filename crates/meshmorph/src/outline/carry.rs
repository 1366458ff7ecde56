//! A compatible pair as a map: a mesh of the first drawing with its
//! positions in another drawing maps the first drawing onto the other,
//! affinely on each triangle, turning none over. Points of the first
//! drawing (the vertices of another mesh of it) are carried through it by
//! their barycentric coordinates in the triangle that holds them.

use rstar::primitives::{GeomWithData, Rectangle};
use rstar::RTree;

/// A compatible pair: positions in the first drawing and in another, the
/// shared triangles; the first `n` vertices are the common boundary.
pub(crate) struct PairMesh {
    pub(crate) first: Vec<[f64; 2]>,
    pub(crate) other: Vec<[f64; 2]>,
    pub(crate) triangles: Vec<[u32; 3]>,
}

/// Where points of the first drawing fall in a pair's mesh.
pub(crate) struct Locator<'a> {
    mesh: &'a PairMesh,
    tree: RTree<GeomWithData<Rectangle<[f64; 2]>, usize>>,
}

impl<'a> Locator<'a> {
    pub(crate) fn new(mesh: &'a PairMesh) -> Self {
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
    pub(crate) fn locate(&self, p: [f64; 2], slack: f64) -> Option<usize> {
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
    pub(crate) fn carry(&self, t: usize, p: [f64; 2]) -> [f64; 2] {
        let l = self.barycentric(t, p);
        let [a, b, c] = self.mesh.triangles[t].map(|v| self.mesh.other[v as usize]);
        [
            l[0] * a[0] + l[1] * b[0] + l[2] * c[0],
            l[0] * a[1] + l[1] * b[1] + l[2] * c[1],
        ]
    }
}

/// Every point of `points` (in the first drawing) carried into the pair's
/// other drawing; a point no triangle holds (off the region by rounding)
/// goes through the triangle it is closest to being inside.
pub(crate) fn carry_all(pair: &PairMesh, points: &[[f64; 2]]) -> Vec<[f64; 2]> {
    let locator = Locator::new(pair);
    points
        .iter()
        .map(|&p| {
            let t = locator.locate(p, 1e-9).unwrap_or_else(|| {
                (0..pair.triangles.len())
                    .max_by(|&x, &y| {
                        let depth = |t| {
                            let l = locator.barycentric(t, p);
                            l[0].min(l[1]).min(l[2])
                        };
                        depth(x).total_cmp(&depth(y))
                    })
                    .unwrap_or(0)
            });
            locator.carry(t, p)
        })
        .collect()
}
