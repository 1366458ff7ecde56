//! Frames mended where triangles turn over.
//!
//! The as-rigid-as-possible frame is the least-squares fit of each
//! triangle's own map; where neighbouring maps disagree a great deal (a
//! fat drawing into a thin curled band, whose maps stretch eight times
//! more one way than the other) the fit can turn a few triangles over
//! while the outline stays whole. Such a frame is mended where it folds:
//! the inner vertices within a few rings of the turned-over triangles are
//! moved by the untangling that makes the compatible meshes
//! ([`untangle`]: the foldover-free energy of Garanzha et al. 2021,
//! against the first key's triangles), everything else of the frame kept
//! as the fit made it, the outline to the bit. Where that stalls, the
//! last resort moves each of them in turn to where the smallest of its
//! triangles is largest ([`widen`]). Set up once per sequence
//! (which vertices are inner, which triangles meet at each); a frame with
//! nothing turned over costs one pass over its triangles.

use super::geometry::orient;
use super::mapped::all_positive;
use super::untangle::{untangle, Patience};
use super::widest::{triangles_at, widen};

/// Rings of inner vertices around the turned-over triangles moved in each
/// try: a fold is mended with as little of the frame as it needs.
const RINGS: [usize; 4] = [2, 4, 8, 16];

/// Sweeps of the last resort ([`widen`]) over the widest rings: at most
/// this many, and it stops sooner once the smallest triangle has not
/// grown for a tenth of them (the unmendable: a frame whose outline leaves
/// a free point no side of an edge it must be on).
const WIDENING_SWEEPS: usize = 1000;

/// What mending a planar sequence's frames needs from its first key.
#[derive(Debug)]
pub struct FrameMender {
    /// The first key's positions, mirrored (x negated) when its triangles
    /// run clockwise: each triangle's own shape, counter-clockwise.
    rest: Vec<[f64; 2]>,
    /// Whether the first key's triangles run clockwise (a mesh in y-down
    /// coordinates): frames are mirrored the same way while mended.
    mirrored: bool,
    triangles: Vec<[u32; 3]>,
    /// The triangles' areas in `rest` (positive).
    rest_areas: Vec<f64>,
    /// Whether a vertex is on the outline (or used by no triangle): it is
    /// never moved.
    kept: Vec<bool>,
    /// The triangles at each vertex (`at[v]` in `corners[at[v]..at[v + 1]]`).
    at: Vec<usize>,
    corners: Vec<u32>,
}

impl FrameMender {
    /// The mender of frames of the mesh `rest` with `triangles`; none when
    /// its triangles do not all run the same way (a folded first key):
    /// turned over then means nothing.
    pub(crate) fn new(rest: &[[f64; 2]], triangles: &[[u32; 3]]) -> Option<Self> {
        let n = rest.len();
        let signs: Vec<f64> = triangles
            .iter()
            .map(|t| {
                orient(
                    rest[t[0] as usize],
                    rest[t[1] as usize],
                    rest[t[2] as usize],
                )
            })
            .collect();
        let mirrored = signs.iter().all(|&a| a < 0.0);
        if !mirrored && !signs.iter().all(|&a| a > 0.0) {
            return None;
        }
        let rest: Vec<[f64; 2]> = rest.iter().map(|&p| mirror(p, mirrored)).collect();
        let rest_areas = signs.iter().map(|a| 0.5 * a.abs()).collect();
        // An edge used once is on the outline.
        let mut edges: Vec<(u32, u32)> = triangles
            .iter()
            .flat_map(|t| (0..3).map(move |k| (t[k].min(t[(k + 1) % 3]), t[k].max(t[(k + 1) % 3]))))
            .collect();
        edges.sort_unstable();
        let mut kept = vec![true; n];
        for t in triangles {
            for &v in t {
                kept[v as usize] = false;
            }
        }
        let mut k = 0;
        while k < edges.len() {
            let mut j = k + 1;
            while j < edges.len() && edges[j] == edges[k] {
                j += 1;
            }
            if j - k == 1 {
                kept[edges[k].0 as usize] = true;
                kept[edges[k].1 as usize] = true;
            }
            k = j;
        }
        let (at, corners) = triangles_at(n, triangles);
        Some(Self {
            rest,
            mirrored,
            triangles: triangles.to_vec(),
            rest_areas,
            kept,
            at,
            corners,
        })
    }

    fn triangles_at(&self, v: usize) -> &[u32] {
        &self.corners[self.at[v]..self.at[v + 1]]
    }

    /// Whether triangle `t` is turned over (or flat) in `frame`, against
    /// the way the first key's triangles run.
    fn is_turned(&self, frame: &[[f64; 2]], t: usize) -> bool {
        let [a, b, c] = self.triangles[t].map(|v| mirror(frame[v as usize], self.mirrored));
        let area = orient(a, b, c);
        area.is_nan() || area <= 0.0
    }

    /// Mends `frame` where triangles are turned over: for each group of
    /// them (sharing corners), the inner vertices within two rings moved
    /// until every triangle around them is positive, with four, eight,
    /// sixteen rings where two are too few, then the widening of sixteen
    /// rings; a group none mends is left as the fit made it. The number
    /// of triangles left turned over: those of such groups (where the
    /// outline itself folds, or a triangle has its three corners on it),
    /// 0 otherwise.
    pub(crate) fn mend(&self, frame: &mut [[f64; 2]]) -> usize {
        let turned: Vec<usize> = (0..self.triangles.len())
            .filter(|&t| self.is_turned(frame, t))
            .collect();
        if turned.is_empty() {
            return 0;
        }
        for group in self.groups(&turned) {
            let mended = RINGS
                .iter()
                .find_map(|&rings| self.try_rings(frame, &group, rings))
                .or_else(|| self.try_widening(frame, &group));
            for (v, p) in mended.into_iter().flatten() {
                frame[v] = mirror(p, self.mirrored);
            }
        }
        turned.iter().filter(|&&t| self.is_turned(frame, t)).count()
    }

    /// The triangles `turned` in groups that share corners.
    fn groups(&self, turned: &[usize]) -> Vec<Vec<usize>> {
        let mut root: Vec<usize> = (0..turned.len()).collect();
        fn find(root: &mut [usize], mut k: usize) -> usize {
            while root[k] != k {
                root[k] = root[root[k]];
                k = root[k];
            }
            k
        }
        let mut first_at: std::collections::HashMap<u32, usize> = std::collections::HashMap::new();
        for (k, &t) in turned.iter().enumerate() {
            for v in self.triangles[t] {
                match first_at.get(&v) {
                    Some(&j) => {
                        let (a, b) = (find(&mut root, j), find(&mut root, k));
                        root[a] = b;
                    }
                    None => {
                        first_at.insert(v, k);
                    }
                }
            }
        }
        let mut groups: Vec<Vec<usize>> = Vec::new();
        let mut group_of: std::collections::HashMap<usize, usize> =
            std::collections::HashMap::new();
        for (k, &t) in turned.iter().enumerate() {
            let r = find(&mut root, k);
            let g = *group_of.entry(r).or_insert_with(|| {
                groups.push(Vec::new());
                groups.len() - 1
            });
            groups[g].push(t);
        }
        groups
    }

    /// The new positions of the inner vertices within `rings` rings of the
    /// triangles `turned`, when moving them makes every triangle around
    /// them positive.
    fn try_rings(
        &self,
        frame: &[[f64; 2]],
        turned: &[usize],
        rings: usize,
    ) -> Option<Vec<(usize, [f64; 2])>> {
        self.untangle_rings(frame, &self.within_rings(turned, rings), rings)
    }

    /// Whether each vertex is an inner one within `rings` rings of the
    /// triangles `turned`.
    fn within_rings(&self, turned: &[usize], rings: usize) -> Vec<bool> {
        let mut free = vec![false; self.rest.len()];
        let mut front: Vec<usize> = Vec::new();
        for &t in turned {
            for v in self.triangles[t] {
                let v = v as usize;
                if !self.kept[v] && !free[v] {
                    free[v] = true;
                    front.push(v);
                }
            }
        }
        for _ in 1..rings {
            let mut next = Vec::new();
            for &v in &front {
                for &t in self.triangles_at(v) {
                    for w in self.triangles[t as usize] {
                        let w = w as usize;
                        if !self.kept[w] && !free[w] {
                            free[w] = true;
                            next.push(w);
                        }
                    }
                }
            }
            front = next;
        }
        free
    }

    /// The last resort for a group no ring mends: the inner vertices
    /// within the widest rings moved each in turn to where its smallest
    /// triangle is largest ([`widen`]), when that makes every triangle
    /// around them positive.
    fn try_widening(&self, frame: &[[f64; 2]], turned: &[usize]) -> Option<Vec<(usize, [f64; 2])>> {
        let free = self.within_rings(turned, RINGS[RINGS.len() - 1]);
        let moved: Vec<usize> = (0..free.len()).filter(|&v| free[v]).collect();
        if moved.is_empty() {
            return None;
        }
        let mut positions: Vec<[f64; 2]> =
            frame.iter().map(|&p| mirror(p, self.mirrored)).collect();
        widen(
            &mut positions,
            &self.triangles,
            &self.rest_areas,
            &moved,
            (&self.at, &self.corners),
            WIDENING_SWEEPS,
        )
        .then(|| moved.iter().map(|&v| (v, positions[v])).collect())
    }

    /// The positions of the `free` vertices (those within `rings` rings
    /// of the turned-over triangles), placed by the untangling around them.
    fn untangle_rings(
        &self,
        frame: &[[f64; 2]],
        free: &[bool],
        rings: usize,
    ) -> Option<Vec<(usize, [f64; 2])>> {
        let n = self.rest.len();
        let moved: Vec<usize> = (0..n).filter(|&v| free[v]).collect();
        if moved.is_empty() {
            return None;
        }
        // The patch: every triangle at a moved vertex, its other vertices
        // held, numbered first.
        let mut patch: Vec<u32> = Vec::new();
        let mut in_patch = vec![false; self.triangles.len()];
        for &v in &moved {
            for &t in self.triangles_at(v) {
                if !in_patch[t as usize] {
                    in_patch[t as usize] = true;
                    patch.push(t);
                }
            }
        }
        let mut local = vec![u32::MAX; n];
        let mut order: Vec<usize> = Vec::new();
        for &t in &patch {
            for v in self.triangles[t as usize] {
                let v = v as usize;
                if !free[v] && local[v] == u32::MAX {
                    local[v] = order.len() as u32;
                    order.push(v);
                }
            }
        }
        let held = order.len();
        for &v in &moved {
            local[v] = order.len() as u32;
            order.push(v);
        }
        let triangles: Vec<[u32; 3]> = patch
            .iter()
            .map(|&t| self.triangles[t as usize].map(|v| local[v as usize]))
            .collect();
        let reference: Vec<[f64; 2]> = order.iter().map(|&v| self.rest[v]).collect();
        let start: Vec<[f64; 2]> = order
            .iter()
            .map(|&v| mirror(frame[v], self.mirrored))
            .collect();
        // The smallest patch is given up on quickly: the next is bigger.
        // The regularisation is lowered briskly: a patch's last turned-over
        // triangle waits on it (on the 500-point star to curl a frame's
        // patches took 105 and 81 rounds at the paper's pace, 51 and 41
        // briskly; the drawings' benchmark and the stress pairs mend the
        // same frames either way, in a third of the time on star to curl).
        // The widest patch, given up on briskly, is untangled again at the
        // paper's pace (which untangles some that the brisk one does not)
        // before the last resort.
        let patience = if rings == RINGS[0] {
            Patience::SHORT
        } else {
            Patience::LONG
        };
        let mut mended = untangle(
            &reference,
            &triangles,
            start.clone(),
            held,
            patience.brisk(),
        );
        if rings == RINGS[RINGS.len() - 1] && !all_positive(&mended, &triangles) {
            mended = untangle(&reference, &triangles, start, held, patience);
        }
        all_positive(&mended, &triangles).then(|| {
            order[held..]
                .iter()
                .copied()
                .zip(mended[held..].iter().copied())
                .collect()
        })
    }
}

/// `p` with its x negated when `mirrored`.
fn mirror(p: [f64; 2], mirrored: bool) -> [f64; 2] {
    if mirrored {
        [-p[0], p[1]]
    } else {
        p
    }
}
