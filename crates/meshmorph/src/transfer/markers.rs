//! Marker vertex pairs that tie a source mesh to a target mesh, given as
//! vertex indices or as points snapped to the nearest vertex. The file
//! format is read in [`crate::io`] (`io/marker_file.rs`).

use std::collections::HashMap;
use std::path::PathBuf;

use crate::error::{Error, Result};
use crate::linalg::similarity::Similarity;
use crate::linalg::vector::{norm, sub};
use crate::mesh::seams::Seams;
use crate::mesh::{used_vertices, Mesh3};

/// Where a file's vertex indices start: marker files and picking tools
/// count from 0 or from 1.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum VertexNumbering {
    /// The first vertex is 0 (as meshmorph, Python and C count).
    #[default]
    FromZero,
    /// The first vertex is 1 (as OBJ files and MATLAB count).
    FromOne,
}

/// Pairs `(source vertex, target vertex)`, 0-based, with where they came from
/// so that errors can name the file and line. A marker file may also give
/// points (`x y z` on each mesh, as picking tools write them): they become
/// vertex pairs through [`Markers::snap`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Markers {
    pub(crate) pairs: Vec<[u32; 2]>,
    /// 1-based line of each pair, when read from a file.
    pub(crate) lines: Vec<usize>,
    /// Point pairs not yet snapped to vertices, with their lines.
    pub(crate) points: Vec<([[f64; 3]; 2], usize)>,
    pub(crate) path: Option<PathBuf>,
    /// The number messages give the first vertex: 1 for a file read as
    /// 1-based, else 0.
    pub(crate) first_index: u32,
}

/// How far [`Markers::snap`] moved the marker points, as fractions of each
/// mesh's bounding-box diagonal.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Snap {
    /// Number of point pairs snapped.
    pub points: usize,
    /// The largest distance from a source point to its vertex.
    pub largest_source: f64,
    /// The largest distance from a target point to its vertex.
    pub largest_target: f64,
}

/// The farthest a marker point may lie from a vertex, as a fraction of the
/// mesh's bounding-box diagonal: farther, it is more likely a point of
/// another model (or in other units) than a point picked on this one.
pub const SNAP_LIMIT: f64 = 0.02;

impl Markers {
    /// Markers from 0-based pairs in memory.
    pub fn new(pairs: Vec<[u32; 2]>) -> Self {
        Self {
            pairs,
            lines: Vec::new(),
            points: Vec::new(),
            path: None,
            first_index: 0,
        }
    }

    /// Markers from point pairs `[source point, target point]` in memory,
    /// to be snapped to vertices with [`Markers::snap`].
    pub fn from_points(points: Vec<[[f64; 3]; 2]>) -> Self {
        Self {
            points: points.into_iter().map(|p| (p, 0)).collect(),
            ..Self::default()
        }
    }

    /// The vertex pairs, 0-based (point pairs count once snapped).
    pub fn pairs(&self) -> &[[u32; 2]] {
        &self.pairs
    }

    /// Whether some markers are points not yet snapped to vertices.
    pub fn has_points(&self) -> bool {
        !self.points.is_empty()
    }

    /// Every point pair snapped to the nearest vertex (that a triangle uses)
    /// of each mesh, added to the vertex pairs.
    ///
    /// # Errors
    /// [`Error::InvalidMarker`] naming the marker (file and line when read
    /// from a file) whose point lies farther than [`SNAP_LIMIT`] of the
    /// mesh's bounding-box diagonal from every vertex.
    pub fn snap(&self, source: &Mesh3, target: &Mesh3) -> Result<(Markers, Snap)> {
        let mut out = Markers {
            pairs: self.pairs.clone(),
            lines: self.lines.clone(),
            points: Vec::new(),
            path: self.path.clone(),
            first_index: self.first_index,
        };
        let mut snap = Snap {
            points: self.points.len(),
            ..Snap::default()
        };
        let (ds, dt) = (
            source.bounding_box_diagonal(),
            target.bounding_box_diagonal(),
        );
        let (us, ut) = (
            used_vertices(source.num_vertices(), source.triangles()),
            used_vertices(target.num_vertices(), target.triangles()),
        );
        for (k, &([ps, pt], line)) in self.points.iter().enumerate() {
            let name = match &self.path {
                Some(p) => format!("`{}`, line {line}", p.display()),
                None => format!("marker point {k}"),
            };
            let mut pair = [0u32; 2];
            for (slot, (mesh, used, point, diagonal, which, largest)) in [
                (source, &us, ps, ds, "source", &mut snap.largest_source),
                (target, &ut, pt, dt, "target", &mut snap.largest_target),
            ]
            .into_iter()
            .enumerate()
            {
                let (v, d) = nearest(mesh.positions(), used, point);
                if d.is_nan() || d > SNAP_LIMIT * diagonal {
                    return Err(Error::InvalidMarker {
                        marker: self.pairs.len() + k,
                        line: self.path.as_ref().map(|_| line),
                        message: format!(
                            "{name}: the {which} point {point:?} is {:.3} % of the {which} mesh's diagonal from its nearest vertex ({which} vertex {}, numbered from {}); \
                             marker points must lie on the mesh (within {} %)",
                            100.0 * d / diagonal,
                            self.number(v),
                            self.first_index,
                            100.0 * SNAP_LIMIT
                        ),
                    });
                }
                *largest = largest.max(d / diagonal);
                pair[slot] = v;
            }
            out.pairs.push(pair);
            out.lines.push(line);
        }
        Ok((out, snap))
    }

    /// Checks every pair against meshes of `source_vertices` and
    /// `target_vertices` vertices: indices in range, no pair repeated, no
    /// source vertex paired with two targets.
    ///
    /// # Errors
    /// [`Error::InvalidMarker`] naming the marker (and file and line, when
    /// read from a file).
    pub fn validate(&self, source_vertices: usize, target_vertices: usize) -> Result<()> {
        if let Some((_, line)) = self.points.first() {
            return Err(Error::InvalidMarker {
                marker: self.pairs.len(),
                line: self.path.as_ref().map(|_| *line),
                message: format!(
                    "{}: a marker given as points must be snapped to vertices first (Markers::snap)",
                    match &self.path {
                        Some(p) => format!("`{}`, line {line}", p.display()),
                        None => "marker point 0".into(),
                    }
                ),
            });
        }
        self.check_ranges(source_vertices, target_vertices)?;
        let mut seen: HashMap<u32, usize> = HashMap::with_capacity(self.pairs.len());
        for (k, &[s, t]) in self.pairs.iter().enumerate() {
            let fail = |msg: String| {
                Err(Error::InvalidMarker {
                    marker: k,
                    line: self.path.as_ref().and(self.lines.get(k).copied()),
                    message: format!("{}: {msg}", self.name(k)),
                })
            };
            if let Some(&j) = seen.get(&s) {
                let other = self.pairs[j][1];
                return if other == t {
                    fail(format!(
                        "the pair {} {} repeats {}",
                        self.number(s),
                        self.number(t),
                        self.name(j)
                    ))
                } else {
                    fail(format!(
                        "source vertex {} is paired with target vertex {} here and with {} in {}",
                        self.number(s),
                        self.number(t),
                        self.number(other),
                        self.name(j)
                    ))
                };
            }
            seen.insert(s, k);
        }
        Ok(())
    }

    /// Checks that a triangle of each mesh uses every marker's vertex: a
    /// vertex in no triangle (a loose `v` line of an OBJ file) is no point
    /// of the surface, and pinning it would throw the alignment off. Check
    /// the indices first ([`Markers::validate`]).
    ///
    /// # Errors
    /// [`Error::InvalidMarker`] naming the marker (and file and line, when
    /// read from a file) and the vertex.
    ///
    /// # Panics
    /// If a vertex is out of range.
    pub fn validate_on_triangles(&self, source: &Mesh3, target: &Mesh3) -> Result<()> {
        let used = [
            used_vertices(source.num_vertices(), source.triangles()),
            used_vertices(target.num_vertices(), target.triangles()),
        ];
        for (k, pair) in self.pairs.iter().enumerate() {
            for (slot, which) in ["source", "target"].into_iter().enumerate() {
                let v = pair[slot];
                if !used[slot][v as usize] {
                    return Err(Error::InvalidMarker {
                        marker: k,
                        line: self.path.as_ref().and(self.lines.get(k).copied()),
                        message: format!(
                            "{}: {which} vertex {v} is in no triangle of the {which} mesh; \
                             markers must lie on the surface",
                            self.name(k)
                        ),
                    });
                }
            }
        }
        Ok(())
    }

    /// The positions of the markers' vertices in `source` and in `target`,
    /// in the markers' order.
    ///
    /// # Panics
    /// If a vertex is out of range (see [`Markers::validate`]).
    pub fn positions(&self, source: &Mesh3, target: &Mesh3) -> (Vec<[f64; 3]>, Vec<[f64; 3]>) {
        let at = |mesh: &Mesh3, k: usize| -> Vec<[f64; 3]> {
            self.pairs
                .iter()
                .map(|p| mesh.positions()[p[k] as usize])
                .collect()
        };
        (at(source, 0), at(target, 1))
    }

    /// The similarity (rotation, uniform scale, translation) that best fits
    /// the markers' source vertices onto their target vertices, markers far
    /// off the others' fit left out ([`Similarity::fit`] made robust), and
    /// each marker's distance from its partner after it, in the target's
    /// units: what tells whether a pair of meshes stands apart or a marker
    /// is on the wrong feature.
    ///
    /// # Errors
    /// [`Error::InvalidArgument`] for fewer than three markers or markers
    /// that fix no orientation (all on one line).
    ///
    /// # Panics
    /// If a vertex is out of range (see [`Markers::validate`]).
    pub fn fit(&self, source: &Mesh3, target: &Mesh3) -> Result<(Similarity, Vec<f64>)> {
        let (from, to) = self.positions(source, target);
        let fit = crate::linalg::similarity::fit_robust(&from, &to)?.0;
        let residuals = crate::linalg::similarity::residuals(&fit, &from, &to);
        Ok((fit, residuals))
    }

    /// Checks that every marker's vertices are in range of meshes of these
    /// vertex counts (part of [`Markers::validate`]).
    ///
    /// # Errors
    /// [`Error::InvalidMarker`] naming the first marker out of range.
    pub fn check_ranges(&self, source_vertices: usize, target_vertices: usize) -> Result<()> {
        // Counting from 0, the last vertex is numbered one less than the
        // count: a marker naming the count itself most likely counts from 1.
        let hint = |v: u32, count: usize| {
            if self.first_index == 0 && v as usize == count {
                "; if the file counts vertices from 1, read it so (--one-based on the command line)"
            } else {
                ""
            }
        };
        for (k, &[s, t]) in self.pairs.iter().enumerate() {
            let message = if s as usize >= source_vertices {
                format!(
                    "source vertex {} is out of range (the source has {source_vertices} vertices){}",
                    self.number(s),
                    hint(s, source_vertices)
                )
            } else if t as usize >= target_vertices {
                format!(
                    "target vertex {} is out of range (the target has {target_vertices} vertices){}",
                    self.number(t),
                    hint(t, target_vertices)
                )
            } else {
                continue;
            };
            return Err(Error::InvalidMarker {
                marker: k,
                line: self.path.as_ref().and(self.lines.get(k).copied()),
                message: format!("{}: {message}", self.name(k)),
            });
        }
        Ok(())
    }

    /// The markers on the welded vertices of each mesh ([`Seams`]): what
    /// the solvers of welded meshes take, a pair given twice through copies
    /// once. Lines and file stay, for messages. Check the pairs against the meshes' own vertex counts
    /// first ([`Markers::validate`]).
    ///
    /// # Panics
    /// If a vertex is out of range of its seams.
    pub fn welded(&self, source: &Seams, target: &Seams) -> Markers {
        let mut out = Markers {
            pairs: Vec::with_capacity(self.pairs.len()),
            lines: Vec::with_capacity(self.lines.len()),
            ..self.clone()
        };
        // Markers on two copies of one vertex, to two copies of another,
        // are one marker (a pair given twice as it is stays twice, for
        // [`Markers::validate`] to refuse).
        // The pair first given for each welded pair kept (a welded pair is
        // kept again only as an exact repeat of it): linear in the markers.
        let mut given: HashMap<[u32; 2], [u32; 2]> = HashMap::with_capacity(self.pairs.len());
        for (k, &[s, t]) in self.pairs.iter().enumerate() {
            let pair = [source.welded(s), target.welded(t)];
            let first = *given.entry(pair).or_insert([s, t]);
            if first == [s, t] {
                out.pairs.push(pair);
                out.lines.extend(self.lines.get(k));
            }
        }
        out
    }

    /// Marker `k` for messages: "marker 3 (source vertex 10, target vertex
    /// 52)" or "`file.cons`, line 5 (...)".
    pub fn describe(&self, k: usize) -> String {
        let [s, t] = self.pairs[k];
        format!(
            "{} (source vertex {}, target vertex {})",
            self.name(k),
            self.number(s),
            self.number(t)
        )
    }

    /// Vertex `v` (0-based) numbered as the marker file numbers it.
    fn number(&self, v: u32) -> u64 {
        u64::from(v) + u64::from(self.first_index)
    }

    /// "marker 3" or "`file.cons`, line 5".
    fn name(&self, k: usize) -> String {
        match (&self.path, self.lines.get(k)) {
            (Some(p), Some(l)) => format!("`{}`, line {l}", p.display()),
            _ => format!("marker {k}"),
        }
    }
}

/// The used vertex nearest to `p` (the lowest index among equals) and its
/// distance.
fn nearest(positions: &[[f64; 3]], used: &[bool], p: [f64; 3]) -> (u32, f64) {
    let mut best = (0u32, f64::INFINITY);
    for (v, q) in positions.iter().enumerate() {
        if used[v] {
            let d = norm(sub(*q, p));
            if d < best.1 {
                best = (v as u32, d);
            }
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    #[test]
    fn validation() {
        let p = Path::new("m.txt");
        let m = Markers::parse("0 1\n5 2\n", p, VertexNumbering::FromZero).unwrap();
        assert!(m.validate(6, 3).is_ok());
        let e = m.validate(5, 3).unwrap_err();
        assert!(
            matches!(
                e,
                Error::InvalidMarker {
                    marker: 1,
                    line: Some(2),
                    ..
                }
            ),
            "{e:?}"
        );
        let e = e.to_string();
        assert!(e.contains("line 2") && e.contains("source vertex 5"), "{e}");
        let e = m.validate(6, 2).unwrap_err().to_string();
        assert!(e.contains("target vertex 2"), "{e}");
        let e = Markers::new(vec![[0, 1], [0, 1]])
            .validate(6, 6)
            .unwrap_err()
            .to_string();
        assert!(e.contains("repeats marker 0"), "{e}");
        let e = Markers::new(vec![[0, 1], [0, 2]])
            .validate(6, 6)
            .unwrap_err();
        assert!(
            matches!(
                e,
                Error::InvalidMarker {
                    marker: 1,
                    line: None,
                    ..
                }
            ),
            "{e:?}"
        );
        let e = e.to_string();
        assert!(
            e.contains("paired with target vertex 2 here and with 1"),
            "{e}"
        );
    }
}
