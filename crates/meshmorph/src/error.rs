//! The library's error type.

use std::path::PathBuf;

/// Every way a meshmorph call can fail on bad input.
///
/// Messages say what was wrong and where (file, line, vertex or triangle
/// index, all 0-based unless the message says otherwise). Functions that read
/// files fill in the path; functions on in-memory meshes leave it to the
/// caller to say which mesh was meant (the CLI adds the file name).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// The operating system refused a read or write. The message includes
    /// the operating system's own, so `error` is not also given as a source
    /// (printing the chain would repeat it).
    #[error("`{}`: {error}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// What the operating system said.
        error: std::io::Error,
    },

    /// A file did not parse.
    #[error("`{}`{}: {message}", path.display(), line.map(|l| format!(", line {l}")).unwrap_or_default())]
    Parse {
        /// The file.
        path: PathBuf,
        /// 1-based line number, when the format has lines.
        line: Option<usize>,
        /// What was wrong.
        message: String,
    },

    /// A file that is not read: not a regular file (a folder, a FIFO, a
    /// device such as `/dev/zero`), or larger than what it may hold.
    #[error("`{}`: {message}", path.display())]
    FileRefused {
        /// The file.
        path: PathBuf,
        /// What it is, or how large, and the limit.
        message: String,
    },

    /// A file whose extension names no format meshmorph knows.
    #[error("`{}`: {}", path.display(), unknown_format(path))]
    UnknownFormat {
        /// The file.
        path: PathBuf,
    },

    /// A mesh that breaks an invariant (bad index, NaN coordinate, empty mesh,
    /// 3D coordinates where 2D ones were expected, ...).
    #[error("{0}")]
    InvalidMesh(String),

    /// Two meshes that must share connectivity do not.
    #[error("{0}")]
    Mismatch(String),

    /// A vertex that breaks an invariant (a coordinate that is not finite,
    /// a non-zero z where a planar mesh is required).
    #[error("{message}")]
    InvalidVertex {
        /// The vertex, 0-based.
        vertex: usize,
        /// What was wrong, naming the vertex.
        message: String,
    },

    /// A triangle that breaks an invariant (a vertex index out of range, a
    /// repeated vertex, no invertible frame, an area out of range).
    #[error("{message}")]
    InvalidTriangle {
        /// The triangle, 0-based.
        triangle: usize,
        /// What was wrong, naming the triangle.
        message: String,
    },

    /// Two meshes that must have the same triangles differ first at this
    /// triangle.
    #[error("{message}")]
    TriangleMismatch {
        /// The first triangle that differs, 0-based.
        triangle: usize,
        /// Which meshes and how they differ.
        message: String,
    },

    /// A pose file whose faces differ from its reference's, first at this
    /// face.
    #[error("{message}")]
    FaceMismatch {
        /// The first face that differs, 0-based.
        face: usize,
        /// Its 1-based line in the pose file, for text formats.
        line: Option<usize>,
        /// Which files and how they differ.
        message: String,
    },

    /// A marker pair that cannot be used (out of range, repeated, paired
    /// twice, a point off the mesh, not yet snapped).
    #[error("{message}")]
    InvalidMarker {
        /// The marker, 0-based, in the order given.
        marker: usize,
        /// Its 1-based line, when read from a file.
        line: Option<usize>,
        /// What was wrong, naming the marker (file and line when read from
        /// a file).
        message: String,
    },

    /// Triangles of zero (or numerically zero) area where the method needs a
    /// proper frame.
    #[error("{count} degenerate (zero-area) triangle{} in the {mesh}: {}; {DEGENERATE_FIX}", plural(*count), list(first, *count))]
    DegenerateTriangles {
        /// Which mesh ("source", "target reference", ...).
        mesh: String,
        /// How many.
        count: usize,
        /// The first few triangle indices.
        first: Vec<usize>,
    },

    /// Triangles whose orientation is reversed between two meshes.
    #[error("{count} triangle{} reversed or collapsed between source and target: {} (set `InterpolatorOptions::allow_flips` to go on anyway)", plural(*count), list(first, *count))]
    FlippedTriangles {
        /// How many.
        count: usize,
        /// The first few triangle indices.
        first: Vec<usize>,
    },

    /// Triangles of a 3D pose (a later key, a blend shape) turned over
    /// relative to the first mesh: folded back onto their neighbours (their
    /// normal now points against most of theirs while it did not in the
    /// first mesh), or collapsed to zero area.
    #[error("{count} triangle{} of the {mesh} turned over relative to the first mesh or collapsed: {} (set `InterpolatorOptions::allow_flips` to go on anyway)", plural(*count), list(first, *count))]
    ReflectedTriangles {
        /// Which mesh ("key 2", "blend shape 1", ...).
        mesh: String,
        /// How many.
        count: usize,
        /// The first few triangle indices.
        first: Vec<usize>,
    },

    /// A bad option or argument value.
    #[error("{0}")]
    InvalidArgument(String),

    /// A correspondence found without markers fits too poorly to be used:
    /// the two shapes do not stand alike. The message says how poorly.
    #[error("{0}")]
    PoorFit(String),

    /// A drawing (a region given as an outer loop and holes) that cannot be
    /// used: a loop with fewer than 3 distinct points, a coordinate that is
    /// not finite, loops that cross or touch, a hole outside the outer loop.
    #[error("{message}")]
    InvalidDrawing {
        /// The loop, 0-based in the order given (0 is the outer loop).
        loop_index: usize,
        /// What was wrong, naming the loop and its points, and what to do.
        message: String,
    },

    /// Two drawings that cannot be made compatible as given (different
    /// numbers of loops, anchors off the outlines or out of order).
    #[error("{0}")]
    IncompatibleDrawings(String),

    /// The linear solver could not factor its matrix (it was not positive
    /// definite: usually a sign of a disconnected or degenerate input).
    #[error("linear solver: {0}")]
    Solver(String),
}

/// Short for `Result<T, meshmorph::Error>`.
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// How many indices an error message lists before "...".
pub(crate) const LIST_LIMIT: usize = 5;

/// Why a path names no mesh file: what it is when it is not a regular
/// file (a folder, a device, ...), else its extension.
fn unknown_format(path: &std::path::Path) -> String {
    match std::fs::metadata(path)
        .ok()
        .and_then(|m| crate::io::read::not_a_file(&m))
    {
        Some(what) => format!("{what}, not a mesh file"),
        None => "unknown mesh format (expected .obj, .off, .ply or .stl)".to_string(),
    }
}

fn plural(n: usize) -> &'static str {
    if n == 1 {
        ""
    } else {
        "s"
    }
}

impl Error {
    /// The advice that ends the message of [`Error::DegenerateTriangles`],
    /// for a front end that names the triangles its own way (as the faces
    /// of the user's file).
    pub const DEGENERATE_FIX: &'static str = DEGENERATE_FIX;
}

/// How degenerate triangles are removed, for the messages that name them.
const DEGENERATE_FIX: &str =
    "a modeller's clean-up removes them, e.g. Blender's Mesh > Clean Up > Degenerate Dissolve";

/// "triangles 3, 9, 12, ..." for the first few of `count` triangle indices.
pub(crate) fn list(items: &[usize], count: usize) -> String {
    let mut s = String::from(if count == 1 { "triangle" } else { "triangles" });
    for (i, t) in items.iter().enumerate() {
        s.push_str(if i == 0 { " " } else { ", " });
        s.push_str(&t.to_string());
    }
    if count > items.len() {
        s.push_str(", ...");
    }
    s
}

impl Error {
    pub fn io(path: impl Into<PathBuf>, error: std::io::Error) -> Self {
        Error::Io {
            path: path.into(),
            error,
        }
    }

    pub(crate) fn parse(
        path: impl Into<PathBuf>,
        line: Option<usize>,
        message: impl Into<String>,
    ) -> Self {
        Error::Parse {
            path: path.into(),
            line,
            message: message.into(),
        }
    }
}
