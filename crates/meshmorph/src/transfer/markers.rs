//! Markers: pairs of points, one on the source's surface and one on the
//! target's, that tie the two meshes together. A point is a vertex, a
//! triangle with barycentric coordinates ([`SurfacePoint`]), or a position
//! in space until [`Markers::snap`] puts it on the surface. The files are
//! read in [`crate::io`] (`io/marker_file.rs` and its neighbours).

use std::collections::HashMap;
use std::path::PathBuf;

use crate::error::{Error, Result};
use crate::linalg::similarity::Similarity;
use crate::mesh::closest::SurfaceIndex;
use crate::mesh::seams::Seams;
use crate::mesh::surface_point::{nearest_surface_point, SurfacePoint};
use crate::mesh::{used_vertices, Mesh3};

/// Where a file's vertex and triangle indices start: marker files and
/// picking tools count from 0 or from 1.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum VertexNumbering {
    /// The first vertex is 0 (as meshmorph, Python and C count).
    #[default]
    FromZero,
    /// The first vertex is 1 (as OBJ files and MATLAB count).
    FromOne,
}

/// One side of a marker as given ([`Markers::entries`]): a point of the
/// surface, or a position in space to be snapped onto it ([`Markers::snap`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Side {
    /// A point of the surface: a vertex, or a triangle's point.
    On(SurfacePoint),
    /// A position in space, not yet put on the surface.
    At([f64; 3]),
}

/// A marker with a side given as a position, waiting for [`Markers::snap`].
#[derive(Clone, Debug, PartialEq)]
pub struct Pending {
    /// Its place among all the markers, in the order given.
    pub order: usize,
    pub sides: [Side; 2],
    pub name: Option<String>,
    pub(crate) lines: [usize; 2],
}

/// Where the markers came from: for each side (source, target), the file
/// and the word for an entry's place in it (`line`, or `point` for files
/// without lines), and the number its first vertex has.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Origin {
    pub(crate) files: [Option<PathBuf>; 2],
    pub(crate) units: [&'static str; 2],
    /// 1 for a file read as 1-based, else 0.
    pub(crate) first_index: [u32; 2],
}

/// Marker pairs `[source point, target point]`, with optional names and
/// where they came from, so that errors can name the file and line.
///
/// A pair may be given as vertex indices ([`Markers::new`]), as points of
/// the surfaces ([`Markers::on_surfaces`]), or as positions in space
/// ([`Markers::from_points`], `x y z` in files), which
/// [`Markers::snap`] puts on the nearest point of each surface. Files:
/// [`Markers::read`] (one file of pairs) and [`Markers::read_pair`] (a file
/// of points for each mesh).
///
/// In the correspondence a marker whose source point is a vertex holds that
/// vertex at the target point; one inside a triangle holds the point of the
/// triangle there through a stiff least-squares term, so that moving it
/// along the triangle moves the result continuously.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Markers {
    pub pairs: Vec<[SurfacePoint; 2]>,
    pub names: Vec<Option<String>>,
    /// 1-based line (or entry) of each pair's sides, when read from files.
    pub(crate) lines: Vec<[usize; 2]>,
    /// Pairs with a side given as a position, not yet snapped.
    pub points: Vec<Pending>,
    pub(crate) origin: Origin,
}

/// How far [`Markers::snap`] moved the marker points, as fractions of each
/// mesh's bounding-box diagonal.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Snap {
    /// Number of markers with a side given as a position.
    pub points: usize,
    /// The largest distance from a source position to the surface.
    pub largest_source: f64,
    /// The largest distance from a target position to the surface.
    pub largest_target: f64,
}

/// The farthest a marker position may lie from the surface, as a fraction
/// of the mesh's bounding-box diagonal: farther, it is more likely a point
/// of another model (or in other units) than a point picked on this one.
pub const SNAP_LIMIT: f64 = 0.02;

/// The stiffness of a marker inside a triangle, over the diagonal of the
/// correspondence's matrix at its vertices (see `matching.rs`).
pub const HOLD_STIFFNESS: f64 = 1e4;

/// The two sides' names in messages.
const SIDES: [&str; 2] = ["source", "target"];

impl Markers {
    /// Markers from 0-based vertex pairs `[source vertex, target vertex]`.
    pub fn new(pairs: Vec<[u32; 2]>) -> Self {
        Self::on_surfaces(
            pairs
                .into_iter()
                .map(|p| p.map(SurfacePoint::Vertex))
                .collect(),
        )
    }

    /// Markers from pairs of surface points `[source point, target point]`.
    /// Barycentric coordinates within [`BARYCENTRIC_TOLERANCE`] of a point
    /// are made exact ([`SurfacePoint::normalized`]); others are kept as
    /// given, for [`Markers::validate`] to refuse.
    ///
    /// [`BARYCENTRIC_TOLERANCE`]: crate::mesh::surface_point::BARYCENTRIC_TOLERANCE
    pub fn on_surfaces(pairs: Vec<[SurfacePoint; 2]>) -> Self {
        let pairs = pairs
            .into_iter()
            .map(|pair| pair.map(|p| p.normalized().unwrap_or(p)))
            .collect::<Vec<_>>();
        Self {
            names: vec![None; pairs.len()],
            lines: vec![[0; 2]; pairs.len()],
            pairs,
            ..Self::default()
        }
    }

    /// Markers from position pairs `[source position, target position]`,
    /// to be put on the surfaces with [`Markers::snap`].
    pub fn from_points(points: Vec<[[f64; 3]; 2]>) -> Self {
        Self {
            points: points
                .into_iter()
                .enumerate()
                .map(|(order, p)| Pending {
                    order,
                    sides: p.map(Side::At),
                    name: None,
                    lines: [0; 2],
                })
                .collect(),
            ..Self::default()
        }
    }

    /// The same markers named `names` (one per marker, in order, the
    /// markers given as positions included).
    ///
    /// # Panics
    /// If there are not as many names as markers.
    #[track_caller]
    pub fn with_names(mut self, names: Vec<Option<String>>) -> Self {
        assert_eq!(names.len(), self.len(), "one name per marker");
        let mut names = names.into_iter();
        let total = self.len();
        let mut located = self.names.iter_mut();
        let mut pending = self.points.iter_mut().peekable();
        for order in 0..total {
            let name = names.next().expect("counted");
            match pending.peek_mut() {
                Some(p) if p.order == order => pending.next().expect("peeked").name = name,
                _ => *located.next().expect("counted") = name,
            }
        }
        self
    }

    /// The pairs on the surfaces, in the order given (pairs given as
    /// positions count once snapped).
    pub fn pairs(&self) -> &[[SurfacePoint; 2]] {
        &self.pairs
    }

    /// The pairs as vertex indices `[source vertex, target vertex]`, when
    /// every point is a vertex (as [`Markers::new`] takes them).
    pub fn vertex_pairs(&self) -> Option<Vec<[u32; 2]>> {
        let vertex = |p: &SurfacePoint| match *p {
            SurfacePoint::Vertex(v) => Some(v),
            SurfacePoint::Triangle { .. } => None,
        };
        self.pairs
            .iter()
            .map(|[s, t]| Some([vertex(s)?, vertex(t)?]))
            .collect()
    }

    /// The name of pair `k` of [`Markers::pairs`], if it has one.
    ///
    /// # Panics
    /// If `k` is out of range.
    pub fn name(&self, k: usize) -> Option<&str> {
        self.names[k].as_deref()
    }

    /// How many markers there are, those given as positions included.
    pub fn len(&self) -> usize {
        self.pairs.len() + self.points.len()
    }

    /// Whether there are no markers at all.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Whether some markers have a side given as a position, not yet
    /// snapped.
    pub fn has_points(&self) -> bool {
        !self.points.is_empty()
    }

    /// Every position put on the nearest point of its mesh's surface (a
    /// triangle with barycentric coordinates, or a vertex when the nearest
    /// point is a corner), in the order given.
    ///
    /// # Errors
    /// [`Error::InvalidMarker`] naming the marker (file and line when read
    /// from a file) whose position lies farther than [`SNAP_LIMIT`] of the
    /// mesh's bounding-box diagonal from the surface.
    pub fn snap(&self, source: &Mesh3, target: &Mesh3) -> Result<(Markers, Snap)> {
        let total = self.len();
        let mut out = Markers {
            pairs: Vec::with_capacity(total),
            names: Vec::with_capacity(total),
            lines: Vec::with_capacity(total),
            points: Vec::new(),
            origin: self.origin.clone(),
        };
        let mut snap = Snap {
            points: self.points.len(),
            ..Snap::default()
        };
        let meshes = [source, target];
        let needed = |s: usize| {
            self.points
                .iter()
                .any(|p| matches!(p.sides[s], Side::At(_)))
        };
        let indices: [Option<SurfaceIndex>; 2] = std::array::from_fn(|s| {
            needed(s).then(|| SurfaceIndex::new(meshes[s].positions(), meshes[s].triangles()))
        });
        let mut located = 0..self.pairs.len();
        let mut pending = self.points.iter().peekable();
        for order in 0..total {
            let p = match pending.peek() {
                Some(p) if p.order == order => pending.next().expect("peeked"),
                _ => {
                    let k = located.next().expect("counted");
                    out.pairs.push(self.pairs[k]);
                    out.names.push(self.names[k].clone());
                    out.lines.push(self.lines[k]);
                    continue;
                }
            };
            let mut pair = [SurfacePoint::Vertex(0); 2];
            for s in 0..2 {
                pair[s] = match p.sides[s] {
                    Side::On(point) => point,
                    Side::At(q) => {
                        let diagonal = meshes[s].bounding_box_diagonal();
                        let index = indices[s].as_ref().expect("built when needed");
                        let found = nearest_surface_point(index, meshes[s], q);
                        let far = |d: Option<f64>| {
                            Error::InvalidMarker {
                                marker: order,
                                line: self.line_of(p.lines[s], s),
                                message: format!(
                                    "{}: the {which} point {} {} {} is {} from the {which} mesh's surface; marker points must lie on the mesh (within {} % of its bounding-box diagonal)",
                                    self.place(order, p.lines, p.name.as_deref(), Some(s)),
                                    q[0],
                                    q[1],
                                    q[2],
                                    match d {
                                        Some(d) => format!("{:.3} % of the diagonal", 100.0 * d / diagonal),
                                        None => "far".into(),
                                    },
                                    100.0 * SNAP_LIMIT,
                                    which = SIDES[s],
                                ),
                            }
                        };
                        let (point, d) = found.ok_or_else(|| far(None))?;
                        if d.is_nan() || d > SNAP_LIMIT * diagonal {
                            return Err(far(Some(d)));
                        }
                        let largest = [&mut snap.largest_source, &mut snap.largest_target];
                        *largest[s] = largest[s].max(d / diagonal);
                        point
                    }
                };
            }
            out.pairs.push(pair);
            out.names.push(p.name.clone());
            out.lines.push(p.lines);
        }
        Ok((out, snap))
    }

    /// Checks every pair against the meshes: vertices and triangles in
    /// range, barycentric coordinates in `[0, 1]` summing to 1, every vertex
    /// on a triangle (a vertex in no triangle, a loose `v` line of an OBJ
    /// file, is no point of the surface), every position snapped, no pair
    /// repeated, and no source point paired with two different target
    /// points (a target point may have several source partners: the
    /// source is then drawn together there).
    ///
    /// # Errors
    /// [`Error::InvalidMarker`] naming the marker (and file and line, when
    /// read from a file).
    pub fn validate(&self, source: &Mesh3, target: &Mesh3) -> Result<()> {
        if let Some(p) = self.points.first() {
            return Err(Error::InvalidMarker {
                marker: p.order,
                line: self.line_of(p.lines[0], 0),
                message: format!(
                    "{}: a marker given as a position must be put on the surface first (Markers::snap)",
                    self.place(p.order, p.lines, p.name.as_deref(), None)
                ),
            });
        }
        self.check_ranges(source, target)?;
        let used = [
            used_vertices(source.num_vertices(), source.triangles()),
            used_vertices(target.num_vertices(), target.triangles()),
        ];
        let meshes = [source, target];
        for (k, pair) in self.pairs.iter().enumerate() {
            for s in 0..2 {
                if let SurfacePoint::Vertex(v) = pair[s] {
                    if !used[s][v as usize] {
                        return Err(self.invalid(
                            k,
                            Some(s),
                            format!(
                                "{} vertex {} is in no triangle of the {} mesh; markers must lie on the surface",
                                SIDES[s],
                                self.number(v, s),
                                SIDES[s]
                            ),
                        ));
                    }
                }
            }
        }
        let keys: Vec<[Key; 2]> = self
            .pairs
            .iter()
            .map(|pair| std::array::from_fn(|s| key(&pair[s], meshes[s].triangles())))
            .collect();
        let mut seen: HashMap<Key, usize> = HashMap::with_capacity(self.pairs.len());
        for (k, &[s, t]) in keys.iter().enumerate() {
            if let Some(&j) = seen.get(&s) {
                let message = if keys[j][1] == t {
                    format!("the pair {} repeats {}", self.pair_text(k), self.name_of(j))
                } else {
                    format!(
                        "two markers on one source point with different partners: {} is paired with {} here and with {} in {}",
                        self.point_text(&self.pairs[k][0], 0),
                        self.point_text(&self.pairs[k][1], 1),
                        self.point_text(&self.pairs[j][1], 1),
                        self.name_of(j)
                    )
                };
                return Err(self.invalid(k, None, message));
            }
            seen.insert(s, k);
        }
        Ok(())
    }

    /// The positions of the markers' points on `source` and on `target`,
    /// in the markers' order.
    ///
    /// # Panics
    /// If a point is out of range (see [`Markers::validate`]).
    pub fn positions(&self, source: &Mesh3, target: &Mesh3) -> (Vec<[f64; 3]>, Vec<[f64; 3]>) {
        let at = |mesh: &Mesh3, s: usize| -> Vec<[f64; 3]> {
            self.pairs.iter().map(|p| p[s].position(mesh)).collect()
        };
        (at(source, 0), at(target, 1))
    }

    /// The similarity (rotation, uniform scale, translation) that best fits
    /// the markers' source points onto their target points, markers far
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
    /// If a point is out of range (see [`Markers::validate`]).
    pub fn fit(&self, source: &Mesh3, target: &Mesh3) -> Result<(Similarity, Vec<f64>)> {
        let (from, to) = self.positions(source, target);
        let fit = crate::linalg::similarity::fit_robust(&from, &to)?.0;
        let residuals = crate::linalg::similarity::residuals(&fit, &from, &to);
        Ok((fit, residuals))
    }

    /// Checks that every marker's vertices and triangles are in range of
    /// the meshes and its barycentric coordinates make a point of its
    /// triangle (part of [`Markers::validate`]): what [`Markers::welded`]
    /// needs of markers on a file's own vertices, where two markers on
    /// copies of one vertex are still one marker.
    ///
    /// # Errors
    /// [`Error::InvalidMarker`] naming the first marker out of range.
    pub fn check_ranges(&self, source: &Mesh3, target: &Mesh3) -> Result<()> {
        let counts = [
            [source.num_vertices(), source.num_triangles()],
            [target.num_vertices(), target.num_triangles()],
        ];
        for (k, pair) in self.pairs.iter().enumerate() {
            for s in 0..2 {
                let (index, what, count) = match pair[s] {
                    SurfacePoint::Vertex(v) => (v, "vertex", counts[s][0]),
                    SurfacePoint::Triangle { triangle, .. } => (triangle, "triangle", counts[s][1]),
                };
                if index as usize >= count {
                    // Counting from 0, the last is numbered one less than
                    // the count: a marker naming the count itself most
                    // likely counts from 1.
                    let plural = if what == "vertex" {
                        "vertices"
                    } else {
                        "triangles"
                    };
                    let hint = if self.origin.first_index[s] == 0
                        && index as usize == count
                        && self.origin.units[s] != "point"
                    {
                        format!("; if the file counts {plural} from 1, read it so (--one-based on the command line)")
                    } else {
                        String::new()
                    };
                    return Err(self.invalid(
                        k,
                        Some(s),
                        format!(
                            "{} {what} {} is out of range (the {} has {count} {plural}){hint}",
                            SIDES[s],
                            self.number(index, s),
                            SIDES[s],
                        ),
                    ));
                }
                if let Some(problem) = pair[s].barycentric_problem() {
                    return Err(self.invalid(
                        k,
                        Some(s),
                        format!("{} triangle point: {problem}", SIDES[s]),
                    ));
                }
            }
        }
        Ok(())
    }

    /// The markers on the welded vertices of each mesh ([`Seams`]): what
    /// the solvers of welded meshes take, a pair given twice through copies
    /// once. Welding keeps the triangles, so points of triangles stay as
    /// they are. Names, lines and files stay, for messages. Check the pairs
    /// against the meshes' own vertex counts first ([`Markers::validate`]).
    ///
    /// # Panics
    /// If a vertex is out of range of its seams.
    pub fn welded(&self, source: &Seams, target: &Seams) -> Markers {
        let mut out = Markers {
            pairs: Vec::with_capacity(self.pairs.len()),
            names: Vec::with_capacity(self.names.len()),
            lines: Vec::with_capacity(self.lines.len()),
            ..self.clone()
        };
        let weld = |p: SurfacePoint, seams: &Seams| match p {
            SurfacePoint::Vertex(v) => SurfacePoint::Vertex(seams.welded(v)),
            p => p,
        };
        // Markers on two copies of one vertex, to two copies of another,
        // are one marker (a pair given twice as it is stays twice, for
        // [`Markers::validate`] to refuse). The pair first given for each
        // welded pair is kept (a welded pair is kept again only as an exact
        // repeat of it): linear in the markers.
        let mut given: HashMap<[Key; 2], [Key; 2]> = HashMap::with_capacity(self.pairs.len());
        for (k, &[s, t]) in self.pairs.iter().enumerate() {
            let pair = [weld(s, source), weld(t, target)];
            let as_given = [raw_key(&s), raw_key(&t)];
            let first = *given
                .entry([raw_key(&pair[0]), raw_key(&pair[1])])
                .or_insert(as_given);
            if first == as_given {
                out.pairs.push(pair);
                out.names.push(self.names[k].clone());
                out.lines.push(self.lines[k]);
            }
        }
        out
    }

    /// Marker `k` for messages: "marker 3 (source vertex 10, target vertex
    /// 52)" or "`file.cons`, line 5 (...)", with its name when it has one.
    ///
    /// # Panics
    /// If `k` is out of range of [`Markers::pairs`].
    pub fn describe(&self, k: usize) -> String {
        format!("{} ({})", self.name_of(k), self.pair_text(k))
    }

    /// "source vertex 10, target triangle 4 at 0.2 0.3 0.5".
    fn pair_text(&self, k: usize) -> String {
        let [s, t] = &self.pairs[k];
        format!("{}, {}", self.point_text(s, 0), self.point_text(t, 1))
    }

    /// "source vertex 10", "target triangle 4 at 0.2 0.3 0.5" (numbered as
    /// the file numbers them).
    fn point_text(&self, p: &SurfacePoint, s: usize) -> String {
        match *p {
            SurfacePoint::Vertex(v) => format!("{} vertex {}", SIDES[s], self.number(v, s)),
            SurfacePoint::Triangle {
                triangle,
                barycentric: b,
            } => format!(
                "{} triangle {} at {} {} {}",
                SIDES[s],
                self.number(triangle, s),
                b[0],
                b[1],
                b[2]
            ),
        }
    }

    /// Index `i` (0-based) of side `s` numbered as its file numbers them.
    fn number(&self, i: u32, s: usize) -> u64 {
        u64::from(i) + u64::from(self.origin.first_index[s])
    }

    /// Pair `k` for messages: "marker 3" or "`file.cons`, line 5", with its
    /// name.
    fn name_of(&self, k: usize) -> String {
        self.place(k, self.lines[k], self.names[k].as_deref(), None)
    }

    /// A marker's place for messages: "`a.txt`, line 5 (`nose`)", "`a.pp`,
    /// line 5 and `b.json`, point 2", or "marker 3"; of one side only
    /// when `side` is given.
    pub(crate) fn place(
        &self,
        k: usize,
        lines: [usize; 2],
        name: Option<&str>,
        side: Option<usize>,
    ) -> String {
        let of = |s: usize| -> Option<String> {
            let path = self.origin.files[s].as_ref()?;
            Some(format!(
                "`{}`, {} {}",
                path.display(),
                self.origin.units[s],
                lines[s]
            ))
        };
        let same_file = self.origin.files[0] == self.origin.files[1] && lines[0] == lines[1];
        let place = match side {
            Some(s) => of(s),
            None if same_file => of(0),
            None => match (of(0), of(1)) {
                (Some(a), Some(b)) => Some(format!("{a} and {b}")),
                (a, b) => a.or(b),
            },
        };
        let place = place.unwrap_or_else(|| format!("marker {k}"));
        match name {
            Some(n) => format!("{place} (`{n}`)"),
            None => place,
        }
    }

    /// The 1-based line of a side, when read from a file with lines.
    fn line_of(&self, line: usize, s: usize) -> Option<usize> {
        (self.origin.files[s].is_some() && line > 0).then_some(line)
    }

    /// The error for pair `k`, of side `side` or of both.
    fn invalid(&self, k: usize, side: Option<usize>, message: String) -> Error {
        Error::InvalidMarker {
            marker: k,
            line: self.line_of(self.lines[k][side.unwrap_or(0)], side.unwrap_or(0)),
            message: format!(
                "{}: {message}",
                self.place(k, self.lines[k], self.names[k].as_deref(), side)
            ),
        }
    }
}

/// A point as a key that can be hashed and sorted: vertices before
/// triangle points, each by index (so that vertex pairs sort as their
/// indices do).
pub type Key = (u8, u32, [u64; 3]);

/// `p` as a [`Key`], as given.
pub(crate) fn raw_key(p: &SurfacePoint) -> Key {
    match *p {
        SurfacePoint::Vertex(v) => (0, v, [0; 3]),
        SurfacePoint::Triangle {
            triangle,
            barycentric,
        } => (1, triangle, barycentric.map(f64::to_bits)),
    }
}

/// `p` as a [`Key`], a corner of a triangle as its vertex.
pub fn key(p: &SurfacePoint, triangles: &[[u32; 3]]) -> Key {
    match p.as_vertex(triangles) {
        Some(v) => raw_key(&SurfacePoint::Vertex(v)),
        None => raw_key(p),
    }
}
