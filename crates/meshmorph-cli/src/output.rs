//! What every subcommand shares: output paths, formats, reports.

use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use serde::Serialize as _;

use anyhow::{Context, Result};
use meshmorph::io::{Format, MeshFile};
use meshmorph::{Mesh3, Seams};

/// `--format` values.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum FormatArg {
    /// Wavefront OBJ.
    Obj,
    /// Object File Format.
    Off,
    /// Stanford PLY (binary).
    Ply,
    /// STL (binary).
    Stl,
}

impl From<FormatArg> for Format {
    fn from(f: FormatArg) -> Self {
        match f {
            FormatArg::Obj => Format::Obj,
            FormatArg::Off => Format::Off,
            FormatArg::Ply => Format::Ply,
            FormatArg::Stl => Format::Stl,
        }
    }
}

/// The format asked for, else the one of `like`'s extension.
pub fn format_or_like(asked: Option<FormatArg>, like: &Path) -> Result<Format> {
    match asked {
        Some(f) => Ok(f.into()),
        // A glTF reference's poses are written as OBJ.
        None if crate::gltf::is_gltf(like) => Ok(Format::Obj),
        None => Format::from_path(like).map_err(Into::into),
    }
}

/// Reads a mesh file kept whole, saying which file and what role on failure.
pub fn read_mesh_file(path: &Path, role: &str) -> Result<meshmorph::io::MeshFile> {
    meshmorph::io::MeshFile::read(path).map_err(|e| reading_error(e, role, path))
}

/// `e`, an error of reading `path` (called `role`), said as "reading
/// {role} `path`" and the library's message, the file named once: the
/// library's messages about a file begin with its name.
pub(crate) fn reading_error(e: meshmorph::Error, role: &str, path: &Path) -> anyhow::Error {
    let named = format!("`{}`", path.display());
    let text = e.to_string();
    match text.strip_prefix(&named) {
        Some(rest) => anyhow::anyhow!("reading {role} {named}{rest}"),
        None => anyhow::Error::new(e).context(format!("reading {role} {named}")),
    }
}

/// Reads `path` (called `role`) as new positions for the faces of `first`
/// (called `first_role`), each polygon split once, as `first` splits it. A
/// face that lists `first`'s corners in another order or winding is the
/// same face; their count is returned with the mesh. A file whose vertex
/// count or faces differ is refused, naming both files and the first
/// differing face.
pub fn read_pose(
    first: &meshmorph::io::MeshFile,
    first_role: &str,
    path: &Path,
    role: &str,
) -> Result<(meshmorph::Mesh3, usize)> {
    first.read_pose(path).map_err(|e| match e {
        meshmorph::Error::Mismatch(_) | meshmorph::Error::FaceMismatch { .. } => {
            anyhow::Error::new(e).context(format!(
                "the {role} `{}` does not fit the {first_role} `{}`",
                path.display(),
                first.path().display()
            ))
        }
        e => reading_error(e, role, path),
    })
}

/// The warning for `reordered` faces of the pose `path` that list the
/// corners of `first`'s faces in another order or winding.
pub fn reordered_faces_warning(path: &Path, first: &Path, reordered: usize) -> Option<String> {
    (reordered > 0).then(|| {
        let (faces, list, their) = if reordered == 1 {
            ("face", "lists", "its")
        } else {
            ("faces", "list", "their")
        };
        format!(
            "`{}`: {reordered} {faces} {list} {their} corners in another order or winding than in `{}`: read as the same {faces}",
            path.display(),
            first.display()
        )
    })
}

/// A mesh file and its copies of vertices at seams ([`Seams`]), welded
/// for the solvers: results computed on the welded mesh are written back
/// on the file's own vertices.
pub struct WeldedFile {
    pub file: MeshFile,
    pub seams: Seams,
}

impl WeldedFile {
    /// Finds the seams of `file` alone and welds its mesh (with `weld`;
    /// else every vertex stays its own).
    pub fn new(file: MeshFile, weld: bool) -> (Self, Mesh3) {
        let seams = if weld {
            Seams::find(&[file.mesh()])
        } else {
            Seams::none(file.mesh().num_vertices())
        };
        let mesh = seams.weld(file.mesh());
        (Self { file, seams }, mesh)
    }

    /// Writes `welded` (positions of the welded vertices) into `w` as the
    /// file with new positions ([`MeshFile::write_to`]): `path` is where
    /// the bytes go.
    pub fn write_to(
        &self,
        w: &mut dyn std::io::Write,
        path: &Path,
        welded: &[[f64; 3]],
        format: Format,
    ) -> meshmorph::Result<Vec<String>> {
        self.file
            .write_to(w, path, &self.seams.unweld(welded), format)
    }
}

/// How far a pose's size may differ from its reference's before a warning:
/// more looks like an export in other units.
const POSE_SIZE_RATIO: f64 = 2.0;

/// The size of a mesh for comparing poses: the RMS distance of the vertices
/// that triangles use to their centroid. A rotation leaves it unchanged
/// (the diagonal of an axis-aligned bounding box grows and shrinks as the
/// mesh turns), a scaling by `s` multiplies it by `s`, and a stray unused
/// vertex does not count.
pub fn size(mesh: &Mesh3) -> f64 {
    let mut used = vec![false; mesh.num_vertices()];
    for t in mesh.triangles() {
        for &v in t {
            used[v as usize] = true;
        }
    }
    let points: Vec<[f64; 3]> = mesh
        .positions()
        .iter()
        .zip(&used)
        .filter(|(_, &u)| u)
        .map(|(p, _)| *p)
        .collect();
    let n = points.len().max(1) as f64;
    let c = points.iter().fold([0.0; 3], |c, p| {
        [c[0] + p[0] / n, c[1] + p[1] / n, c[2] + p[2] / n]
    });
    let squares: f64 = points
        .iter()
        .map(|p| p.iter().zip(&c).map(|(x, m)| (x - m).powi(2)).sum::<f64>())
        .sum();
    (squares / n).sqrt()
}

/// The warning for a pose `path` whose [`size`] is `ratio` times that of
/// `reference`, when it looks like an export in other units.
pub fn size_warning(path: &Path, ratio: f64, reference: &str) -> Option<String> {
    (!(1.0 / POSE_SIZE_RATIO..=POSE_SIZE_RATIO).contains(&ratio)).then(|| {
        format!(
            "`{}` is {ratio:.3} times the size of {reference}: exported in other units?",
            path.display()
        )
    })
}

/// Reads `paths` (called `roles`): the first kept whole, every later one
/// as a pose of it ([`read_pose`]), re-listed faces and sizes that look
/// like other units said in `warnings`;
/// with `weld`, vertices at the same place in every one of them welded
/// ([`Seams`]).
pub fn read_poses(
    paths: &[&Path],
    roles: &[&str],
    weld: bool,
    warnings: &mut Vec<String>,
) -> Result<(WeldedFile, Vec<Mesh3>)> {
    let first = read_mesh_file(paths[0], roles[0])?;
    warnings.extend(surface_warnings(&first));
    let mut meshes = vec![first.mesh().clone()];
    for (path, role) in paths.iter().zip(roles).skip(1) {
        let (mesh, reordered) = read_pose(&first, roles[0], path, role)?;
        warnings.extend(reordered_faces_warning(path, paths[0], reordered));
        warnings.extend(size_warning(
            path,
            size(&mesh) / size(first.mesh()),
            &format!("the {} `{}`", roles[0], paths[0].display()),
        ));
        meshes.push(mesh);
    }
    let seams = if weld {
        Seams::find(&meshes.iter().collect::<Vec<_>>())
    } else {
        Seams::none(first.mesh().num_vertices())
    };
    if !seams.is_empty() {
        meshes = meshes.iter().map(|m| seams.weld(m)).collect();
    }
    Ok((WeldedFile { file: first, seams }, meshes))
}

/// How `file`'s format numbers its vertices and faces, the first number
/// and its words: from 1 in OBJ, from 0 in PLY and OFF (as the tools that
/// read them count), from 1 in STL (vertices in the order their points
/// first occur).
fn numbering(file: &MeshFile) -> (u64, &'static str) {
    match file.format() {
        meshmorph::io::Format::Obj => (1, "numbered from 1, as in OBJ"),
        meshmorph::io::Format::Stl => (1, "numbered from 1 in the order of the file's facets"),
        _ => (0, "numbered from 0, as PLY and OFF count"),
    }
}

/// What is odd about a file's surface, as warnings: what its reading
/// noticed, faces that fold onto others, faces that list a vertex twice in
/// a row ([`MeshFile::surface_issues`]). Faces and vertices are numbered as
/// the file's format counts ([`numbering`]).
pub fn surface_warnings(file: &MeshFile) -> Vec<String> {
    let mut warnings: Vec<String> = file.read_warnings().to_vec();
    let issues = file.surface_issues();
    let (base, words) = numbering(file);
    let mut what = Vec::new();
    if let Some(&[later, earlier]) = issues.repeated_faces.first() {
        what.push(format!(
            "{} the corners of another (face {} repeats face {})",
            count_doing(issues.repeated_faces.len(), "face", "repeats", "repeat"),
            u64::from(later) + base,
            u64::from(earlier) + base
        ));
    }
    if let Some(e) = issues.crowded_edges.first() {
        what.push(format!(
            "{} shared by more than two faces (the first between vertices {} and {})",
            count_doing(issues.crowded_edges.len(), "edge", "is", "are"),
            u64::from(e[0]) + base,
            u64::from(e[1]) + base
        ));
    }
    if !what.is_empty() {
        warnings.push(format!(
            "`{}`: {} ({words}): the surface folds onto itself there, and results may crease",
            file.path().display(),
            what.join(" and ")
        ));
    }
    let repeats = &issues.faces_repeating_a_vertex;
    if let Some(&first) = repeats.first() {
        warnings.push(format!(
            "`{}`: {} a vertex twice in a row (the first is face {}, {words}), read without the repeat",
            file.path().display(),
            count_doing(repeats.len(), "face", "lists", "list"),
            u64::from(first) + base
        ));
    }
    warnings
}

/// "face 7" or "faces 7, 12, ...": the faces of `file` (numbered as its
/// format counts, [`numbering`]) that hold the triangles `first` (0-based,
/// after splitting), the first few of `count`, and how they are numbered.
fn faces_holding(file: &MeshFile, first: &[usize], count: usize) -> String {
    let faces = file.triangle_faces();
    let (base, words) = numbering(file);
    let mut named: Vec<String> = Vec::new();
    for &t in first {
        let f = (u64::from(faces[t]) + base).to_string();
        if !named.contains(&f) {
            named.push(f);
        }
    }
    format!(
        "face{} {}{} ({words})",
        if named.len() == 1 { "" } else { "s" },
        named.join(", "),
        if count > first.len() { ", ..." } else { "" }
    )
}

/// `e` with the degenerate triangles of the mesh the library calls `label`
/// (read from `file`) named as `file`'s faces ([`numbering`]); any other
/// error as it is.
pub fn degenerate_faces(e: meshmorph::Error, file: &MeshFile, label: &str) -> meshmorph::Error {
    match e {
        meshmorph::Error::DegenerateTriangles { mesh, count, first } if mesh == label => {
            meshmorph::Error::InvalidMesh(format!(
                "{} degenerate (zero-area) triangle{} in the {label} `{}`: in {}; {}",
                count,
                if count == 1 { "" } else { "s" },
                file.path().display(),
                faces_holding(file, &first, count),
                meshmorph::Error::DEGENERATE_FIX,
            ))
        }
        e => e,
    }
}

/// The files of a run whose later meshes must not turn triangles of the
/// first over: what [`turned_over_faces`] names.
pub struct PoseFiles<'a> {
    /// The first mesh's file (its faces number the triangles).
    pub first: &'a MeshFile,
    /// What the first is called ("first key", "base").
    pub first_role: &'a str,
    /// What the library calls the later meshes, followed by their number
    /// from 1 ("key", "blend shape").
    pub label: &'a str,
    /// What the later meshes are called here, and their files, in order.
    pub poses: Vec<(&'a str, &'a Path)>,
}

/// `e` with the triangles reversed or turned over between the first mesh
/// and a later one (the library's [`meshmorph::Error::FlippedTriangles`]
/// and [`meshmorph::Error::ReflectedTriangles`], numbered after splitting
/// polygons, from 0) said as the first file's faces ([`numbering`]),
/// naming both files and the command-line flag that goes on
/// anyway; any other error as it is.
pub fn turned_over_faces(e: meshmorph::Error, files: &PoseFiles<'_>) -> anyhow::Error {
    let (pose, count, first, what) = match e {
        meshmorph::Error::FlippedTriangles { count, first } => {
            (files.poses.first(), count, first, "reversed or collapsed")
        }
        meshmorph::Error::ReflectedTriangles { mesh, count, first } => {
            let k = mesh
                .strip_prefix(files.label)
                .and_then(|n| n.trim().parse::<usize>().ok());
            match k.and_then(|k| files.poses.get(k.wrapping_sub(1))) {
                Some(pose) => (Some(pose), count, first, "turned over or collapsed"),
                None => return meshmorph::Error::ReflectedTriangles { mesh, count, first }.into(),
            }
        }
        e => return e.into(),
    };
    let Some((role, path)) = pose else {
        return meshmorph::Error::FlippedTriangles { count, first }.into();
    };
    anyhow::anyhow!(
        "{count} triangle{} {what} in the {role} `{}` relative to the {} `{}`: in {}; pass --allow-flips to go on anyway",
        if count == 1 { "" } else { "s" },
        path.display(),
        files.first_role,
        files.first.path().display(),
        faces_holding(files.first, &first, count),
    )
}

/// `text` (a library message) with each `label` ("the first key", "key 2")
/// followed by `path` in backquotes, unless a name in backquotes already
/// follows it or it is part of a longer number ("key 2" in "key 21").
pub fn name_label(text: &str, label: &str, path: &Path) -> String {
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while let Some(i) = rest.find(label) {
        let after = &rest[i + label.len()..];
        out.push_str(&rest[..i]);
        out.push_str(label);
        if !after.starts_with(" `") && !after.starts_with(|c: char| c.is_ascii_digit()) {
            out.push_str(&format!(" `{}`", path.display()));
        }
        rest = after;
    }
    out.push_str(rest);
    out
}

/// The report's line for vertices welded at seams, if any.
pub fn welded_line(welded: usize) -> Option<String> {
    (welded > 0).then(|| {
        format!(
            "{} at the same place as another (copies at seams) welded for the solve; the files keep them",
            vertices(welded)
        )
    })
}

/// What the reports of interpolations and blends say of separate parts
/// placed by the surface they sit in, if any.
pub fn following_line(parts: usize) -> Option<String> {
    (parts > 0).then(|| {
        format!(
            "{} (eyes, teeth, ...) kept in place in the part around {} and turned with it",
            count(parts, "separate part"),
            if parts == 1 { "it" } else { "them" }
        )
    })
}

/// The library's warnings of what an output format could not hold of a
/// file (each naming the file it wrote, here a staged one), said for
/// `output`, the name the user gave.
pub fn dropped_for(output: &Path, dropped: &[String]) -> Vec<String> {
    dropped
        .iter()
        .map(|d| {
            let what = d.split_once(": ").map_or(d.as_str(), |x| x.1);
            format!("{}: {what}", output.display())
        })
        .collect()
}

/// Prints a report's lines for the files a run wrote beside its main
/// output, those written only: each label ("picture:", "animation:", ...)
/// padded so that the names begin in `column`, as the report's other values.
pub fn print_files(files: &[(&str, Option<&Path>)], column: usize) {
    for (label, file) in files {
        if let Some(f) = file {
            say!("{label:<column$}{}", f.display());
        }
    }
}

/// `n` and the noun, plural unless `n` is 1: "1 pose", "2 poses".
pub fn count(n: usize, noun: &str) -> String {
    if n == 1 {
        format!("1 {noun}")
    } else {
        format!("{n} {noun}s")
    }
}

/// "1 vertex" or "2 vertices": `n` and how many vertices.
pub fn vertices(n: usize) -> String {
    if n == 1 {
        "1 vertex".to_string()
    } else {
        format!("{n} vertices")
    }
}

/// "1 face lists" or "3 faces list": [`count`] with the verb that agrees.
pub fn count_doing(n: usize, noun: &str, one: &str, many: &str) -> String {
    format!("{} {}", count(n, noun), if n == 1 { one } else { many })
}

/// Seconds as a short human string.
pub fn human_seconds(s: f64) -> String {
    if s >= 1.0 {
        format!("{s:.2} s")
    } else if s >= 1e-3 {
        format!("{:.2} ms", s * 1e3)
    } else {
        format!("{:.1} µs", s * 1e6)
    }
}

/// The first failure to print on stdout, said once the run is over.
static STDOUT_FAILURE: Mutex<Option<std::io::Error>> = Mutex::new(None);

/// Adds the files beside `file` (its material libraries and their
/// textures) to the run's inputs, so that no output replaces one.
///
/// # Errors
/// An output that is one of them, naming both.
pub fn protect_side_files(
    staging: &crate::outputs::Staging,
    file: &MeshFile,
    role: &str,
) -> Result<()> {
    let role = format!("material file of the {role} `{}`", file.path().display());
    staging.also_reads(&file.side_files(), &role)
}

/// Prints bytes on stdout, as every report line does (the `say!` macro).
/// A stdout that is closed (`| head -1`) or full (`> /dev/full`) does not
/// stop the run, whose outputs are written regardless: the first failure
/// is kept for [`finish_stdout`] and later prints are dropped.
pub fn print_bytes(bytes: &[u8]) {
    let mut failure = STDOUT_FAILURE.lock().unwrap_or_else(|e| e.into_inner());
    if failure.is_none() {
        let mut out = std::io::stdout().lock();
        if let Err(e) = out.write_all(bytes).and_then(|()| out.flush()) {
            *failure = Some(e);
        }
    }
}

/// One line on stdout (see [`print_bytes`]).
pub fn print_line(line: std::fmt::Arguments) {
    let mut text = line.to_string();
    text.push('\n');
    print_bytes(text.as_bytes());
}

/// Whether everything printed on stdout reached it.
///
/// # Errors
/// The first failure to print, once the run is over.
pub fn finish_stdout() -> std::io::Result<()> {
    let failure = STDOUT_FAILURE
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .take();
    failure.map_or(Ok(()), Err)
}

/// Prints a report as one line of JSON on stdout.
pub fn print_json(report: &impl serde::Serialize) {
    match serde_json::to_string(report) {
        Ok(line) => print_line(format_args!("{line}")),
        // Reports hold numbers, strings and paths written lossily
        // ([`lossy`]): nothing in them fails to serialise.
        Err(e) => tell!("error: the report cannot be written as JSON: {e}"),
    }
}

/// Paths in JSON reports, as strings: a name that is not UTF-8 is written
/// with U+FFFD for the bytes that are not (`#[serde(serialize_with =
/// "output::lossy")]`); serde's own would refuse it.
pub fn lossy<S: serde::Serializer, P: LossyPaths>(paths: &P, s: S) -> Result<S::Ok, S::Error> {
    paths.lossy().serialize(s)
}

/// A path, or paths, as [`lossy`] writes them.
pub trait LossyPaths {
    /// JSON's value: a string, null or a list of strings.
    fn lossy(&self) -> serde_json::Value;
}

impl LossyPaths for PathBuf {
    fn lossy(&self) -> serde_json::Value {
        self.to_string_lossy().into()
    }
}

impl LossyPaths for Option<PathBuf> {
    fn lossy(&self) -> serde_json::Value {
        self.as_ref()
            .map_or(serde_json::Value::Null, LossyPaths::lossy)
    }
}

impl LossyPaths for Vec<PathBuf> {
    fn lossy(&self) -> serde_json::Value {
        self.iter().map(LossyPaths::lossy).collect()
    }
}

/// What `--json` prints on stdout for a run that fails or is interrupted,
/// where its report would have been, so that a pipeline reading stdout has
/// one object to parse (the message also goes to stderr, as without
/// `--json`).
#[derive(serde::Serialize)]
struct ErrorReport<'a> {
    /// The message, as after `error: ` on stderr.
    error: &'a str,
    /// The process's exit status.
    exit_status: i32,
}

/// Prints `{"error": message, "exit_status": status}` as one line on stdout.
pub fn print_json_error(message: &str, status: i32) {
    print_json(&ErrorReport {
        error: message,
        exit_status: status,
    });
}

/// A finite number above zero (a clap value parser).
pub fn positive_number(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(x) if x.is_finite() && x > 0.0 => Ok(x),
        _ => Err(format!("`{text}` is not a finite number above 0")),
    }
}

/// A finite number (a clap value parser): NaN and infinities are refused
/// with the command line's other mistakes.
pub fn finite_number(text: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(x) if x.is_finite() => Ok(x),
        _ => Err(format!("`{text}` is not a finite number")),
    }
}

/// A frame rate in [`meshmorph::limits::FRAME_RATES`] (a clap value parser).
pub fn frame_rate(text: &str) -> Result<f64, String> {
    let rates = meshmorph::limits::FRAME_RATES;
    match text.parse::<f64>() {
        Ok(x) if rates.contains(&x) => Ok(x),
        _ => Err(format!(
            "`{text}` is not a frame rate from {} to {} frames per second",
            rates.start(),
            rates.end()
        )),
    }
}

/// The warning that a GIF plays `fps` above 50 at 50 (its delays are whole
/// hundredths of a second, and browsers slow down shorter ones), when a GIF
/// is written; the GLB keeps the rate.
pub fn gif_rate_warning(gif: bool, fps: f64) -> Option<String> {
    (gif && fps > 50.0).then(|| {
        format!("the GIF plays at 50 frames per second, not {fps}: its delays are whole hundredths of a second, and browsers slow down shorter ones (a GLB keeps {fps})")
    })
}

/// Prints each warning on stderr.
pub fn print_warnings(warnings: &[String]) {
    for w in warnings {
        tell!("warning: {w}");
    }
}

/// Whether `meshes` are interpolated in the plane: with `--dim 2` (each
/// then refused, named by `name(k)`, unless its z are all 0), never with
/// `--dim 3`, and without `--dim` when every z of every mesh is 0.
pub fn is_planar(
    dim: Option<u8>,
    meshes: &[&meshmorph::Mesh3],
    name: impl Fn(usize) -> String,
) -> Result<bool> {
    match dim {
        Some(2) => {
            for (k, mesh) in meshes.iter().enumerate() {
                mesh.to_2d()
                    .with_context(|| format!("--dim 2: {} is not planar", name(k)))?;
            }
            Ok(true)
        }
        Some(_) => Ok(false),
        None => Ok(meshes
            .iter()
            .all(|m| m.positions().iter().all(|p| p[2] == 0.0))),
    }
}
