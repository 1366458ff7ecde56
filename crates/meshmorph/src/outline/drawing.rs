//! A drawing: one filled planar region given as closed loops of points,
//! checked and put in a standard orientation.

use std::ops::ControlFlow;

use super::geometry::{
    diagonal, inside_loop, near_edge_pairs, orient, point_segment_distance, segments_cross,
    segments_meet, signed_area2,
};
use crate::error::{Error, Result};

/// One filled planar region: an outer loop and any number of holes, each a
/// closed loop of points (the last point joins the first; a repeated
/// closing point is allowed).
///
/// [`Drawing::new`] checks the region and stores its loops in a standard
/// orientation: the outer loop counter-clockwise, holes clockwise (the
/// region on the left of every loop). Points repeated one after the other
/// are kept once; [`Drawing::given_index`] tells which given point each
/// stored point is.
#[derive(Clone, Debug)]
pub struct Drawing {
    loops: Vec<Vec<[f64; 2]>>,
    given: Vec<Vec<usize>>,
    stored_of_given: Vec<Vec<usize>>,
}

/// What a loop is, for messages.
pub(crate) fn loop_name(index: usize) -> String {
    if index == 0 {
        "loop 0 (the outer loop)".to_string()
    } else {
        format!("loop {index} (a hole)")
    }
}

impl Drawing {
    /// Checks and stores a region: `loops[0]` is the outer loop, the others
    /// holes; each loop is `#P × 2` points in either direction, starting
    /// anywhere.
    ///
    /// # Errors
    /// [`Error::InvalidDrawing`] naming the loop and its points (0-based, as
    /// given) when: there is no loop; a coordinate is NaN or infinite; a
    /// loop has fewer than 3 distinct points or no area; two edges of the
    /// loops cross or come closer than $10^{-9}$ of the drawing's bounding
    /// box diagonal (a loop touching itself or another); a loop folds back
    /// on itself; a hole lies outside the outer loop or inside another
    /// hole.
    ///
    /// # Performance
    /// Edges are compared after a sort along x: near $O(n \log n)$ for
    /// outlines, $O(n^2)$ at worst.
    pub fn new(loops: Vec<Vec<[f64; 2]>>) -> Result<Self> {
        if loops.is_empty() {
            return Err(Error::InvalidDrawing {
                loop_index: 0,
                message: "the drawing has no loop: give an outer loop of at least 3 points".into(),
            });
        }
        let mut stored_of_given = Vec::with_capacity(loops.len());
        let mut kept = Vec::with_capacity(loops.len());
        let mut given = Vec::with_capacity(loops.len());
        for (l, points) in loops.iter().enumerate() {
            if let Some(i) = points
                .iter()
                .position(|p| !p[0].is_finite() || !p[1].is_finite())
            {
                return Err(Error::InvalidDrawing {
                    loop_index: l,
                    message: format!(
                        "{} has a coordinate that is not a finite number at point {i}: {:?}",
                        loop_name(l),
                        points[i]
                    ),
                });
            }
            let mut pts = Vec::with_capacity(points.len());
            let mut idx = Vec::with_capacity(points.len());
            let mut of_given = Vec::with_capacity(points.len());
            for (i, &p) in points.iter().enumerate() {
                if pts.last() != Some(&p) {
                    pts.push(p);
                    idx.push(i);
                }
                of_given.push(pts.len() - 1);
            }
            while pts.len() > 1 && pts[0] == pts[pts.len() - 1] {
                pts.pop();
                idx.pop();
            }
            for s in of_given.iter_mut() {
                if *s >= pts.len() {
                    *s = 0;
                }
            }
            stored_of_given.push(of_given);
            if pts.len() < 3 {
                return Err(Error::InvalidDrawing {
                    loop_index: l,
                    message: format!(
                        "{} has {} distinct point{} where a closed loop needs at least 3",
                        loop_name(l),
                        pts.len(),
                        if pts.len() == 1 { "" } else { "s" }
                    ),
                });
            }
            kept.push(pts);
            given.push(idx);
        }
        let tol = 1e-9 * diagonal(kept.iter().flatten());
        check_edges(&kept, &given, tol)?;
        for (l, pts) in kept.iter().enumerate() {
            if signed_area2(pts).abs() <= tol * tol {
                return Err(Error::InvalidDrawing {
                    loop_index: l,
                    message: format!(
                        "{} encloses no area: its points lie on one line",
                        loop_name(l)
                    ),
                });
            }
        }
        for l in 1..kept.len() {
            let p = kept[l][0];
            if !inside_loop(p, &kept[0]) {
                return Err(Error::InvalidDrawing {
                    loop_index: l,
                    message: format!(
                        "{} lies outside loop 0 (the outer loop): a drawing is one region; give separate regions as separate drawings, and the outer loop first",
                        loop_name(l)
                    ),
                });
            }
            if let Some(h) = (1..kept.len()).find(|&h| h != l && inside_loop(p, &kept[h])) {
                return Err(Error::InvalidDrawing {
                    loop_index: l,
                    message: format!(
                        "{} lies inside {}: a shape inside a hole is a separate region; give it as a drawing of its own",
                        loop_name(l),
                        loop_name(h)
                    ),
                });
            }
        }
        for (l, (pts, idx)) in kept.iter_mut().zip(given.iter_mut()).enumerate() {
            let ccw = signed_area2(pts) > 0.0;
            if ccw != (l == 0) {
                pts.reverse();
                idx.reverse();
                let n = pts.len();
                for s in stored_of_given[l].iter_mut() {
                    *s = n - 1 - *s;
                }
            }
        }
        Ok(Self {
            loops: kept,
            given,
            stored_of_given,
        })
    }

    /// The loops in standard orientation: `loops()[0]` the outer loop,
    /// counter-clockwise; the holes clockwise.
    pub fn loops(&self) -> &[Vec<[f64; 2]>] {
        &self.loops
    }

    /// Number of loops (1 + the number of holes).
    pub fn num_loops(&self) -> usize {
        self.loops.len()
    }

    /// Number of points stored, over every loop.
    pub fn num_points(&self) -> usize {
        self.loops.iter().map(Vec::len).sum()
    }

    /// The index, in the loop as given to [`Drawing::new`], of stored point
    /// `point` of loop `loop_index`.
    ///
    /// # Panics
    /// If either index is out of range.
    #[track_caller]
    pub fn given_index(&self, loop_index: usize, point: usize) -> usize {
        self.given[loop_index][point]
    }

    /// For each given point of each loop, the stored point it became (a
    /// point repeated one after the other, or a closing point equal to the
    /// first, becomes the point it repeats).
    pub fn stored_of_given(&self) -> &[Vec<usize>] {
        &self.stored_of_given
    }
}

/// Fails on the first two edges that cross or touch, and on a loop that
/// folds back on itself.
fn check_edges(loops: &[Vec<[f64; 2]>], given: &[Vec<usize>], tol: f64) -> Result<()> {
    let name_edge = |l: usize, i: usize| {
        let n = loops[l].len();
        format!("{}-{}", given[l][i], given[l][(i + 1) % n])
    };
    let failure = near_edge_pairs(loops, tol, |e, f| {
        if e.l == f.l {
            let n = loops[e.l].len();
            let (i, j) = (e.i, f.i);
            let shared = if (i + 1) % n == j {
                Some((j, e.a, f.b))
            } else if (j + 1) % n == i {
                Some((i, f.a, e.b))
            } else {
                None
            };
            if let Some((k, before, after)) = shared {
                let p = loops[e.l][k];
                let folds = orient(before, p, after).abs()
                    <= tol * super::geometry::dist(before, after).max(tol)
                    && ((p[0] - before[0]) * (after[0] - p[0])
                        + (p[1] - before[1]) * (after[1] - p[1]))
                        < 0.0;
                let reaches = point_segment_distance(before, p, after) <= tol
                    || point_segment_distance(after, before, p) <= tol;
                if folds || reaches {
                    return ControlFlow::Break(Error::InvalidDrawing {
                        loop_index: e.l,
                        message: format!(
                            "{} folds back on itself at point {}: remove the spike there",
                            loop_name(e.l),
                            given[e.l][k]
                        ),
                    });
                }
                return ControlFlow::Continue(());
            }
        }
        if !segments_meet(e.a, e.b, f.a, f.b, tol) {
            return ControlFlow::Continue(());
        }
        let verb = if segments_cross(e.a, e.b, f.a, f.b) {
            "crosses"
        } else {
            "touches"
        };
        let (first, second) = if (e.l, e.i) <= (f.l, f.i) {
            (f, e)
        } else {
            (e, f)
        };
        let message = if first.l == second.l {
            format!(
                "{} {verb} itself at points {} and {}: a loop must be simple; split it where it meets itself",
                loop_name(first.l),
                name_edge(first.l, first.i),
                name_edge(second.l, second.i)
            )
        } else {
            format!(
                "{} {verb} {} at points {} and {}: loops must keep apart; move one of them",
                loop_name(first.l),
                loop_name(second.l),
                name_edge(first.l, first.i),
                name_edge(second.l, second.i)
            )
        };
        ControlFlow::Break(Error::InvalidDrawing {
            loop_index: first.l,
            message,
        })
    });
    failure.map_or(Ok(()), Err)
}
