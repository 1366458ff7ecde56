//! Placement of connected parts: the energies fix each part only up to a
//! translation, which the caller chooses from the part's area-weighted
//! centroid.

use crate::mesh::topology::Components;

/// The parts of a mesh that are moved after each solve, with the area
/// weight of each vertex in its part's centroid.
#[derive(Clone, Debug)]
pub struct Placement<const D: usize> {
    /// Part of each vertex, `u32::MAX` if it is not moved.
    vertex_part: Vec<u32>,
    vertex_weight: Vec<f64>,
    /// Total vertex weight of each part.
    part_weight: Vec<f64>,
}

impl<const D: usize> Placement<D> {
    /// The parts `c` of `components` for which `placed(c)`, numbered in
    /// order; each vertex weighs `vertex_weight` in its part's centroid.
    pub(crate) fn new(
        components: &Components,
        placed: impl Fn(usize) -> bool,
        vertex_weight: Vec<f64>,
    ) -> Self {
        let mut slot = vec![u32::MAX; components.count];
        let mut count = 0;
        for (c, s) in slot.iter_mut().enumerate() {
            if placed(c) {
                *s = count;
                count += 1;
            }
        }
        let vertex_part: Vec<u32> = components
            .of_vertex
            .iter()
            .map(|c| c.map_or(u32::MAX, |c| slot[c as usize]))
            .collect();
        let mut part_weight = vec![0.0; count as usize];
        for (&p, &w) in vertex_part.iter().zip(&vertex_weight) {
            if p != u32::MAX {
                part_weight[p as usize] += w;
            }
        }
        Self {
            vertex_part,
            vertex_weight,
            part_weight,
        }
    }

    /// Number of placed parts.
    pub(crate) fn count(&self) -> usize {
        self.part_weight.len()
    }

    /// The placed part (numbered among the placed ones) of vertex `v`, or
    /// `None` if it is not moved.
    pub(crate) fn part_of_vertex(&self, v: usize) -> Option<usize> {
        match self.vertex_part[v] {
            u32::MAX => None,
            p => Some(p as usize),
        }
    }

    /// The area-weighted centroid of every placed part of `positions`.
    ///
    /// # Panics
    /// If `out` does not have one entry per placed part.
    pub(crate) fn centroids(&self, positions: &[[f64; D]], out: &mut [[f64; D]]) {
        assert_eq!(out.len(), self.count(), "one centroid per part");
        self.weighted_sums(|v| &positions[v], out);
        for (c, w) in out.iter_mut().zip(&self.part_weight) {
            *c = c.map(|x| x / w);
        }
    }

    /// [`Placement::centroids`] of several frames at once, in one pass:
    /// `rows(v)` holds vertex `v` in each frame, `D` coordinates per frame
    /// side by side, and `out[f]` receives frame `f`'s centroids.
    #[inline]
    pub(crate) fn centroids_of_frames<'r, const K: usize>(
        &self,
        rows: impl Fn(usize) -> &'r [f64; K],
        out: &mut [Vec<[f64; D]>],
    ) {
        let mut sums = vec![[0.0; K]; self.count()];
        self.weighted_sums(rows, &mut sums);
        for (f, out) in out.iter_mut().enumerate() {
            out.clear();
            out.extend(
                sums.iter()
                    .zip(&self.part_weight)
                    .map(|(sum, w)| std::array::from_fn(|i| sum[f * D + i] / w)),
            );
        }
    }

    /// The sum over each placed part's vertices `v` of their weight times
    /// `rows(v)` (read once each, in order), into `sums`.
    #[inline]
    fn weighted_sums<'r, const K: usize>(
        &self,
        rows: impl Fn(usize) -> &'r [f64; K],
        sums: &mut [[f64; K]],
    ) {
        sums.fill([0.0; K]);
        for (v, &c) in self.vertex_part.iter().enumerate() {
            if c != u32::MAX {
                let (row, w) = (rows(v), self.vertex_weight[v]);
                let sum = &mut sums[c as usize];
                for k in 0..K {
                    sum[k] += w * row[k];
                }
            }
        }
    }

    /// Moves every vertex of each placed part by the part's `shift`.
    pub(crate) fn translate(&self, positions: &mut [[f64; D]], shifts: &[[f64; D]]) {
        for (v, p) in positions.iter_mut().enumerate() {
            let c = self.vertex_part[v];
            if c != u32::MAX {
                for i in 0..D {
                    p[i] += shifts[c as usize][i];
                }
            }
        }
    }
}
