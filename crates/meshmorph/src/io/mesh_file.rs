//! A mesh file kept whole: its polygons, texture coordinates, normals and
//! everything else it holds, with the triangle mesh derived from it, written
//! back with new positions.
//!
//! Deformation transfer and interpolation change positions only. A result
//! written in the format of the file it came from is that file with new
//! positions (and normals turned with the surface): in OBJ the `vt`, `vn`,
//! `g`, `o`, `s`, `mtllib` and `usemtl` statements, the comments and the
//! polygons stay as they were, in their order; in PLY every other property
//! and element, in its type and encoding; in OFF the polygons, colours and
//! comments; in STL the header, the facet order and the facet attributes.
//! Only the numbers that change are rewritten (with the shortest
//! representation that reads back to the same `f64`; in binary PLY in the
//! property's own type), and an OBJ written to another folder has its
//! relative `mtllib` paths made to resolve from there to the same `.mtl`
//! files.

use std::io::Write;
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use super::atomic::write_atomic_with;
use super::material_paths::{folder_of, library_names, MaterialPaths};
use super::normal_groups::{NormalGroups, ShapeNormals};
use super::ply::Scalar;
use super::triangulate::{quad_split_the_other_way, Polygons, Split};
use super::vertex_attributes::{per_vertex, VertexAttributes};
use super::{push_f64, Format};
use crate::error::{Error, Result};
use crate::mesh::Mesh3;

/// What a pose of an STL file (or an STL pose) must be, said when it is
/// not: STL has no vertex indices, so a vertex's number is where its point
/// first occurs.
const STL_POSES: &str = " (STL has no vertex indices: corners at one point are one vertex, numbered in the order the points first occur, so a pose lists the reference's facets in the same order, each from the same corner; vertices that touch in one pose become one there, which STL cannot tell apart: export such poses as OBJ or PLY)";

/// No index (a corner without texture coordinates or normal).
pub const NONE: u32 = u32::MAX;

/// The byte offset of `part` (a sub-slice of `whole`) in `whole`.
#[inline]
pub(super) fn offset_in(whole: &[u8], part: &[u8]) -> usize {
    part.as_ptr() as usize - whole.as_ptr() as usize
}

/// Which number a patch rewrites.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Slot {
    /// Coordinate `axis` of vertex `v`.
    Position(u32, u8),
    /// Coordinate `axis` of normal `n`.
    Normal(u32, u8),
    /// The normal index of flat corner `c` (OBJ), rewritten only when
    /// normals are added.
    CornerNormal(u32),
    /// Where normals added after normal `n` go (an empty range at the start
    /// of the next line; `true` when the file ends its lines with CR LF).
    NormalsAfter(u32, bool),
    /// The paths of an OBJ `mtllib` statement, rewritten when the file is
    /// written to another folder (see [`MaterialPaths`]).
    MaterialLibrary,
}

/// How a patched number is written.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Coding {
    /// Replaces the text in the range.
    Text,
    /// Inserted (after a space) at the range's start, which is its end;
    /// left out while every z is 0 (planar `v x y` lines stay as they were;
    /// a file never mixes lines of 2 and of 3 coordinates).
    Appended,
    /// Binary, in the given type, big endian or not.
    Binary(Scalar, bool),
}

/// A number of the file that is rewritten with the new shape.
#[derive(Clone, Debug)]
pub(super) struct Patch {
    pub(super) bytes: Range<usize>,
    pub(super) slot: Slot,
    pub(super) coding: Coding,
}

impl Patch {
    pub(super) fn text(bytes: Range<usize>, slot: Slot) -> Self {
        Patch {
            bytes,
            slot,
            coding: Coding::Text,
        }
    }

    pub(super) fn appended(at: usize, slot: Slot) -> Self {
        Patch {
            bytes: at..at,
            slot,
            coding: Coding::Appended,
        }
    }
}

/// What a reader keeps of a file beyond its positions and polygons (the
/// file is checked whole either way).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Keep {
    /// What it takes to write the file back with new positions: a
    /// [`MeshFile`].
    Whole,
    /// Nothing more: a triangle mesh, or a pose of another file.
    Mesh,
}

/// What a reader found: positions, polygons, and what it takes to write the
/// file back.
pub(super) struct Parsed {
    /// Whether [`Parsed::patch`] keeps patches.
    keep: Keep,
    pub(super) positions: Vec<[f64; 3]>,
    pub(super) faces: Polygons,
    /// The numbers to rewrite, in file order.
    pub(super) patches: Vec<Patch>,
    pub(super) uvs: Vec<[f64; 2]>,
    /// The texture coordinate of each flat corner ([`NONE`] for none);
    /// empty when the file has none.
    pub(super) corner_uv: Vec<u32>,
    pub(super) normals: Vec<[f64; 3]>,
    /// The normal of each flat corner; empty when the file has none.
    pub(super) corner_normal: Vec<u32>,
    /// Whether each face is shaded flat (OBJ's `s off` or `s 0`); empty
    /// when the file does not say.
    pub(super) flat_faces: Vec<bool>,
    /// What the file holds beyond positions and polygons, for the warnings
    /// when it is written in another format.
    pub(super) extras: Vec<String>,
    /// The OBJ materials of the faces (empty for other formats).
    pub(super) materials: FaceMaterials,
    /// The colour of each vertex, RGBA from 0 to 1 as the file stores it
    /// (sRGB); empty when the file has none.
    pub(super) colors: Vec<[f32; 4]>,
    /// The faces that repeat a vertex in a row, read without the repeat.
    pub(super) repeats_in_a_row: Vec<u32>,
    /// What is odd about the file but read anyway (content past what its
    /// header announces), each naming the file.
    pub(super) warnings: Vec<String>,
}

/// The materials an OBJ file gives its faces: the `usemtl` names and the
/// `mtllib` statements that define them.
#[derive(Clone, Debug, Default)]
pub(super) struct FaceMaterials {
    /// The arguments of the `mtllib` statements, as written.
    pub(super) libraries: Vec<String>,
    /// The distinct `usemtl` names, in the order they first appear.
    pub(super) names: Vec<String>,
    /// Per face, an index into `names`, or [`NONE`] before any `usemtl`
    /// (empty when the file was not kept whole).
    pub(super) of_face: Vec<u32>,
}

impl FaceMaterials {
    /// The index of the material `name`, added when new.
    pub(super) fn index_of(&mut self, name: &str) -> u32 {
        match self.names.iter().position(|n| n == name) {
            Some(i) => i as u32,
            None => {
                self.names.push(name.to_string());
                (self.names.len() - 1) as u32
            }
        }
    }
}

impl Parsed {
    pub(super) fn new(keep: Keep) -> Self {
        Parsed {
            keep,
            positions: Vec::new(),
            faces: Polygons::default(),
            patches: Vec::new(),
            uvs: Vec::new(),
            corner_uv: Vec::new(),
            normals: Vec::new(),
            corner_normal: Vec::new(),
            flat_faces: Vec::new(),
            extras: Vec::new(),
            materials: FaceMaterials::default(),
            colors: Vec::new(),
            repeats_in_a_row: Vec::new(),
            warnings: Vec::new(),
        }
    }

    /// Whether the file is kept whole (patches are wanted).
    #[inline]
    pub(super) fn keeps_whole(&self) -> bool {
        self.keep == Keep::Whole
    }

    /// Adds a patch, when the file is kept whole.
    #[inline]
    pub(super) fn patch(&mut self, patch: Patch) {
        if self.keeps_whole() {
            self.patches.push(patch);
        }
    }

    pub(super) fn note_extra(&mut self, what: &str) {
        if !self.extras.iter().any(|e| e == what) {
            self.extras.push(what.to_string());
        }
    }
}

/// A mesh file kept whole, with the triangle mesh derived from it (each
/// polygon split once, along the split the file's own shape gives).
///
/// Deformation transfer and interpolation change positions only. A result
/// written in the format of the file it came from is that file with new
/// positions (and normals turned with the surface; where faces that shared
/// one OBJ normal turn apart, the extra normals they need are written right
/// after it and their corners renumbered): in OBJ the `vt`, `vn`,
/// `g`, `o`, `s`, `mtllib` and `usemtl` statements, the comments and the
/// polygons stay as they were, in their order; in PLY every other property
/// and element, in its type and encoding; in OFF the polygons, colours and
/// comments. Only the numbers that change are rewritten (with the shortest
/// representation that reads back to the same `f64`; in binary PLY in the
/// property's own type). An OBJ written to another folder than its source's
/// has each relative `mtllib` path rewritten to lead from there to the same
/// `.mtl` file (relative when it can be, else absolute); the `.mtl` files
/// themselves are never copied nor changed.
#[derive(Clone, Debug)]
pub struct MeshFile {
    path: PathBuf,
    format: Format,
    bytes: Vec<u8>,
    mesh: Mesh3,
    faces: Polygons,
    split: Split,
    patches: Vec<Patch>,
    uvs: Vec<[f64; 2]>,
    corner_uv: Vec<u32>,
    normals: Vec<[f64; 3]>,
    corner_normal: Vec<u32>,
    /// Whether each face is shaded flat (see [`Parsed::flat_faces`]).
    flat_faces: Vec<bool>,
    /// The corners that share each normal, turned together in a new shape;
    /// found at the first write in the file's own format (poses are read
    /// as files too, and never written).
    normal_groups: OnceLock<NormalGroups>,
    /// The texture coordinate of each vertex, when every corner of each
    /// vertex has the same (else `None`); found at the first write in a
    /// format of one value per vertex.
    vertex_uvs: OnceLock<Option<Vec<[f64; 2]>>>,
    extras: Vec<String>,
    materials: FaceMaterials,
    colors: Vec<[f32; 4]>,
    repeats_in_a_row: Vec<u32>,
    warnings: Vec<String>,
}

impl MeshFile {
    /// Reads a mesh file, choosing the format by its extension.
    ///
    /// # Errors
    /// As [`read_mesh`](super::read_mesh).
    pub fn read(path: &Path) -> Result<Self> {
        Self::read_as(path, Format::from_path(path)?)
    }

    /// Reads a mesh file in the given format.
    ///
    /// # Errors
    /// As [`read_mesh_as`](super::read_mesh_as).
    pub fn read_as(path: &Path, format: Format) -> Result<Self> {
        let bytes = super::read_mesh_bytes(path, format)?;
        Self::parse(bytes, format, path)
    }

    /// Parses a file's contents; `path` names it in messages (and in
    /// [`MeshFile::path`]).
    ///
    /// # Errors
    /// As [`parse_mesh`](super::parse_mesh).
    pub fn parse(bytes: Vec<u8>, format: Format, path: &Path) -> Result<Self> {
        let parsed = parse_parts(&bytes, format, path, Keep::Whole)?;
        let split = parsed.faces.triangulate(&parsed.positions);
        let mesh = super::finish(path, parsed.positions, split.triangles.clone())?;
        let file = MeshFile {
            path: path.to_path_buf(),
            format,
            bytes,
            mesh,
            faces: parsed.faces,
            split,
            patches: parsed.patches,
            uvs: parsed.uvs,
            corner_uv: parsed.corner_uv,
            normals: parsed.normals,
            corner_normal: parsed.corner_normal,
            flat_faces: parsed.flat_faces,
            normal_groups: OnceLock::new(),
            vertex_uvs: OnceLock::new(),
            extras: parsed.extras,
            materials: parsed.materials,
            colors: parsed.colors,
            repeats_in_a_row: parsed.repeats_in_a_row,
            warnings: parsed.warnings,
        };
        Ok(file)
    }

    /// The file's path (as given when it was read).
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The file's format.
    pub fn format(&self) -> Format {
        self.format
    }

    /// The triangle mesh: the file's positions, each polygon split once.
    pub fn mesh(&self) -> &Mesh3 {
        &self.mesh
    }

    /// The triangle mesh, without the rest of the file.
    pub fn into_mesh(self) -> Mesh3 {
        self.mesh
    }

    /// Number of polygons (faces) in the file.
    pub fn num_faces(&self) -> usize {
        self.faces.len()
    }

    /// The vertices of face `f` (0-based), in the file's order.
    ///
    /// # Panics
    /// If `f` is out of range.
    pub fn face(&self, f: usize) -> &[u32] {
        &self.faces.corner_vertices()[self.faces.range(f)]
    }

    /// The face each triangle of [`MeshFile::mesh`] was split from.
    pub fn triangle_faces(&self) -> &[u32] {
        &self.split.face
    }

    /// The texture coordinates `(u, v)` of the three corners of each
    /// triangle of [`MeshFile::mesh`], in the triangle's corner order: from
    /// OBJ `vt` (through `f v/vt`), PLY vertex properties `s t`, `u v` or
    /// `texture_u texture_v` or a face list `texcoord`, OFF `ST` files.
    /// `None` when the file has no texture coordinates or some corner lacks
    /// them. (glTF's `TEXCOORD_0` wants `v` flipped: `1 - v`.)
    pub fn triangle_corner_uvs(&self) -> Option<Vec<[[f32; 2]; 3]>> {
        if !self.has_corner_uvs() {
            return None;
        }
        Some(self.per_triangle_corner(|k| {
            let uv = self.uvs[self.corner_uv[k] as usize];
            [uv[0] as f32, uv[1] as f32]
        }))
    }

    /// The file's normal at each corner of each triangle of
    /// [`MeshFile::mesh`] (OBJ `vn` through `f v//vn`, PLY vertex
    /// properties `nx ny nz`), as `f32`. Corners of one vertex with different
    /// normals lie on the two sides of a hard edge. `None` when the file has
    /// no normals or some corner lacks one.
    pub fn triangle_corner_normals(&self) -> Option<Vec<[[f32; 3]; 3]>> {
        if !self.has_normals() || self.corner_normal.contains(&NONE) {
            return None;
        }
        Some(self.per_triangle_corner(|k| {
            self.normals[self.corner_normal[k] as usize].map(|x| x as f32)
        }))
    }

    /// Which corners of each triangle of [`MeshFile::mesh`] share a normal,
    /// as the file shades them: a corner of a face shaded flat (OBJ `s off`
    /// or `s 0`) has its face's own normal, whatever normal it names (tools
    /// share one `vn` among coplanar faces); other corners share a normal
    /// when they name the same value (OBJ `vn`, whether the file lists it
    /// once or once per corner; PLY per vertex), and corners without one are
    /// smooth. Only equal numbers at one vertex mean anything. `None` when
    /// the file has no normals and no flat face.
    pub fn triangle_corner_normal_groups(&self) -> Option<Vec<[u32; 3]>> {
        let flat = |f: u32| self.flat_faces.get(f as usize).copied().unwrap_or(false);
        if self.corner_normal.is_empty() && !self.flat_faces.iter().any(|&f| f) {
            return None;
        }
        let smooth = u32::MAX;
        let named = self.normals.len() as u32;
        // Each normal as the first normal of the same value.
        let mut first_of_value: std::collections::HashMap<[u64; 3], u32> =
            std::collections::HashMap::new();
        let same_as: Vec<u32> = self
            .normals
            .iter()
            .enumerate()
            .map(|(n, v)| {
                *first_of_value
                    .entry(v.map(f64::to_bits))
                    .or_insert(n as u32)
            })
            .collect();
        Some(
            self.split
                .corners
                .iter()
                .zip(&self.split.face)
                .map(|(corners, &f)| {
                    corners.map(|k| {
                        if flat(f) {
                            named.saturating_add(f)
                        } else {
                            match self.corner_normal.get(k as usize) {
                                Some(&n) if n != NONE => same_as[n as usize],
                                _ => smooth,
                            }
                        }
                    })
                })
                .collect(),
        )
    }

    /// `of_corner(k)` of the file's corner `k` at each corner of each
    /// triangle of [`MeshFile::mesh`].
    fn per_triangle_corner<T>(&self, of_corner: impl Fn(usize) -> T) -> Vec<[T; 3]> {
        self.split
            .corners
            .iter()
            .map(|c| c.map(|k| of_corner(k as usize)))
            .collect()
    }

    /// The OBJ material (`usemtl`) of each triangle of [`MeshFile::mesh`]:
    /// the names, in the order they first appear in the file, and per
    /// triangle an index into them, `None` for faces before any `usemtl`.
    /// `None` when the file names no material.
    pub fn triangle_materials(&self) -> Option<(&[String], Vec<Option<u32>>)> {
        let m = &self.materials;
        if m.names.is_empty() || m.of_face.len() != self.num_faces() {
            return None;
        }
        let of_triangle = self
            .split
            .face
            .iter()
            .map(|&f| Some(m.of_face[f as usize]).filter(|&i| i != NONE))
            .collect();
        Some((&m.names, of_triangle))
    }

    /// The colour of each vertex, RGBA from 0 to 1 as the file stores them
    /// (sRGB, as files conventionally do): PLY `red green blue [alpha]`
    /// (integer types scaled by their largest value), OBJ `v x y z r g b`,
    /// OFF `COFF`. `None` when the file has no vertex colours.
    pub fn vertex_colors(&self) -> Option<&[[f32; 4]]> {
        (self.colors.len() == self.mesh.num_vertices() && !self.colors.is_empty())
            .then_some(&self.colors[..])
    }

    /// [`MeshFile::vertex_colors`] at each corner of each triangle of
    /// [`MeshFile::mesh`].
    pub fn triangle_corner_colors(&self) -> Option<Vec<[[f32; 4]; 3]>> {
        let colors = self.vertex_colors()?;
        let vertex_of = self.faces.corner_vertices();
        Some(self.per_triangle_corner(|k| colors[vertex_of[k] as usize]))
    }

    /// The faces (0-based) that list a vertex twice in a row (`f 4 5 6 6 7`,
    /// a corner of no length): each is read without the repeat.
    pub fn faces_repeating_a_vertex(&self) -> &[u32] {
        &self.repeats_in_a_row
    }

    /// What is odd about the file but was read anyway, each naming the
    /// file: an OFF or PLY file with content past what its header
    /// announces (more faces or elements, trailing bytes), which is
    /// ignored (and kept as it is when the file is written back).
    pub fn read_warnings(&self) -> &[String] {
        &self.warnings
    }

    /// The material libraries the file names (OBJ `mtllib`), resolved from
    /// its folder; they may not exist.
    pub fn material_libraries(&self) -> Vec<PathBuf> {
        let folder = folder_of(&self.path);
        self.materials
            .libraries
            .iter()
            .flat_map(|text| library_names(folder, text))
            .map(|name| folder.join(name))
            .collect()
    }

    /// Every file beside this one that reading it for an output may read
    /// or that an output keeping its materials refers to: the material
    /// libraries ([`MeshFile::material_libraries`]) and the textures each
    /// existing one names ([`crate::io::mtl::named_files`]). A library that cannot
    /// be read is listed without its textures.
    pub fn side_files(&self) -> Vec<PathBuf> {
        let mut files = Vec::new();
        for library in self.material_libraries() {
            let named = match super::mtl::read_text(&library) {
                Ok(text) => super::mtl::named_files(&text, &library),
                Err(_) => Vec::new(),
            };
            files.push(library);
            files.extend(named);
        }
        files
    }

    /// Whether every corner of every face has texture coordinates (then
    /// [`MeshFile::triangle_corner_uvs`] gives them).
    pub fn has_corner_uvs(&self) -> bool {
        !self.corner_uv.is_empty() && !self.corner_uv.contains(&NONE)
    }

    /// Whether the file holds normals (which are turned with the surface
    /// when it is written with new positions).
    pub fn has_normals(&self) -> bool {
        !self.corner_normal.is_empty()
    }

    /// What the file holds beyond positions and polygons ("texture
    /// coordinates (`vt`)", "vertex colours", "vertex property `quality`", ...).
    pub fn extras(&self) -> &[String] {
        &self.extras
    }

    /// Writes the file with new `positions` to `path`, in the format its
    /// extension names: [`MeshFile::write`] in that format. Writing in the
    /// file's own format keeps its polygons, texture coordinates, normals,
    /// groups and materials; the returned warnings say what another format
    /// could not hold.
    ///
    /// # Errors
    /// [`Error::UnknownFormat`] for an unknown extension; as
    /// [`MeshFile::write`].
    pub fn save(&self, path: &Path, positions: &[[f64; 3]]) -> Result<Vec<String>> {
        self.write(path, positions, Format::from_path(path)?)
    }

    /// Writes the file with new `positions` in `format`, atomically. In the
    /// file's own format everything but the positions (and normals, turned
    /// with the surface, and relative OBJ `mtllib` paths when `path` is in
    /// another folder) is kept byte for byte. In another format the
    /// polygons are kept (in OBJ, also the texture coordinates and the
    /// normals, turned) and what that format cannot hold here is dropped:
    /// the returned warnings say what (empty when nothing was dropped).
    ///
    /// # Errors
    /// [`Error::InvalidMesh`] when a position is not finite or their count is
    /// not the file's; [`Error::Io`] when the file cannot be written (nothing
    /// is left at `path` then).
    pub fn write(
        &self,
        path: &Path,
        positions: &[[f64; 3]],
        format: Format,
    ) -> Result<Vec<String>> {
        write_atomic_with(path, |w| self.write_to(w, path, positions, format))
    }

    /// [`MeshFile::write`] into `w`, for a file made otherwise (see
    /// [`write_new`](super::write_new)): `path` is where the bytes go,
    /// named in messages and the folder that relative material library
    /// paths are written from. The same checks come before any byte is
    /// written.
    ///
    /// # Errors
    /// Those of [`MeshFile::write`]; `w`'s errors as [`Error::Io`] naming
    /// `path`.
    pub fn write_to(
        &self,
        w: &mut dyn Write,
        path: &Path,
        positions: &[[f64; 3]],
        format: Format,
    ) -> Result<Vec<String>> {
        if positions.len() != self.mesh.num_vertices() {
            return Err(Error::InvalidMesh(format!(
                "cannot write `{}`: {} positions given for the {} vertices of `{}`",
                path.display(),
                positions.len(),
                self.mesh.num_vertices(),
                self.path.display()
            )));
        }
        super::check_writable(path, positions, &[])?;
        // A binary STL's patches are all binary; an ASCII one's all text.
        let binary = || {
            self.patches
                .first()
                .is_some_and(|p| matches!(p.coding, Coding::Binary(..)))
        };
        if format == Format::Stl && (format != self.format || binary()) {
            super::stl::check_float_corners(path, positions, self.mesh.triangles())?;
        }
        let io = |e| Error::io(path, e);
        if format == self.format {
            let normals = self.normals_for_shape(positions);
            self.write_patched(w, path, positions, &normals)
                .map_err(io)?;
            return Ok(Vec::new());
        }
        let faces = || (0..self.faces.len()).map(|f| self.face(f));
        let extra = self.vertex_attributes(format, positions);
        // What the output holds of what the file holds: OBJ every texture
        // coordinate and normal, by corner.
        let to_obj = format == Format::Obj;
        let uvs_kept = if to_obj {
            !self.corner_uv.is_empty()
        } else {
            extra.uvs.is_some() || extra.corner_uvs.is_some()
        };
        let normals_kept = if to_obj {
            self.has_normals()
        } else {
            extra.normals.is_some()
        };
        let carried = |e: &&String| {
            (e.starts_with("texture coordinates") && uvs_kept)
                || (e.starts_with("normals") && normals_kept)
                || (e.as_str() == "vertex colours" && extra.colors.is_some())
        };
        match format {
            Format::Obj => self.write_obj(w, positions, &extra),
            Format::Off => super::off::write(w, positions, faces(), self.faces.len(), &extra),
            Format::Ply => super::ply::write(w, positions, faces(), self.faces.len(), &extra),
            Format::Stl => super::stl::write(w, positions, self.mesh.triangles()),
        }
        .map_err(io)?;
        Ok(self
            .extras
            .iter()
            .filter(|e| !carried(e))
            .map(|e| {
                format!(
                    "`{}`: the {} of `{}` cannot be carried over to {format}: dropped",
                    path.display(),
                    e,
                    self.path.display()
                )
            })
            .collect())
    }

    /// The file's normals turned to the shape `positions` (see
    /// [`NormalGroups`]).
    fn normals_for_shape(&self, positions: &[[f64; 3]]) -> ShapeNormals {
        self.groups()
            .for_shape(&self.normals, &self.faces, positions)
    }

    /// The groups of corners that share a normal, made at the first call.
    fn groups(&self) -> &NormalGroups {
        self.normal_groups.get_or_init(|| {
            NormalGroups::new(
                &self.faces,
                &self.corner_normal,
                &self.flat_faces,
                self.mesh.positions(),
            )
        })
    }

    /// What `format`, another than the file's, holds of its normals (turned
    /// to the shape `positions`), texture coordinates and vertex colours:
    /// OBJ all of them (per corner, with `VertexAttributes::normals` and
    /// `uvs` left empty: see [`MeshFile::write_obj`]), PLY and OFF what
    /// is one per vertex, and PLY's texture coordinates per corner where a
    /// vertex has several; STL none.
    fn vertex_attributes(&self, format: Format, positions: &[[f64; 3]]) -> VertexAttributes<'_> {
        let n = self.mesh.num_vertices();
        let corners = self.faces.corner_vertices();
        if format == Format::Stl {
            return VertexAttributes::default();
        }
        let colors = (!self.colors.is_empty()).then_some(&self.colors[..]);
        if format == Format::Obj {
            return VertexAttributes {
                colors,
                ..Default::default()
            };
        }
        let normals = (self.has_normals() && !self.corner_normal.contains(&NONE))
            .then(|| {
                let (all, index) = self.written_normals(positions);
                per_vertex(n, corners, |c| all[index[c] as usize], [0.0, 0.0, 1.0])
            })
            .flatten();
        let (mut uvs, mut corner_uvs) = (None, None);
        if self.has_corner_uvs() {
            uvs = self
                .vertex_uvs
                .get_or_init(|| {
                    per_vertex(
                        n,
                        corners,
                        |c| self.uvs[self.corner_uv[c] as usize],
                        [0.0; 2],
                    )
                })
                .as_deref();
            if uvs.is_none() && format == Format::Ply {
                corner_uvs = Some((&self.uvs[..], &self.corner_uv[..]));
            }
        }
        VertexAttributes {
            normals,
            uvs,
            corner_uvs,
            colors,
        }
    }

    /// The normals an OBJ of the shape `positions` lists (each added one
    /// right after the normal it was split from), and the index of each
    /// flat corner's.
    fn written_normals(&self, positions: &[[f64; 3]]) -> (Vec<[f64; 3]>, Vec<u32>) {
        let t = self.normals_for_shape(positions);
        let mut added = t.added.iter().peekable();
        let mut all = Vec::with_capacity(t.normals.len() + t.added.len());
        for (n, normal) in t.normals.iter().enumerate() {
            all.push(*normal);
            while let Some((_, extra)) = added.next_if(|&&(m, _)| m as usize == n) {
                all.push(*extra);
            }
        }
        let index = if t.corner_index.is_empty() {
            self.corner_normal.clone()
        } else {
            t.corner_index
        };
        (all, index)
    }

    /// The file, of another format, as OBJ with new `positions`: its
    /// polygons, texture coordinates and normals (turned with the surface),
    /// each corner indexing its own, and its vertex colours (`v x y z r g
    /// b`).
    fn write_obj(
        &self,
        w: &mut dyn Write,
        positions: &[[f64; 3]],
        extra: &VertexAttributes,
    ) -> std::io::Result<()> {
        let (normals, corner_normal) = if self.has_normals() {
            self.written_normals(positions)
        } else {
            (Vec::new(), self.corner_normal.clone())
        };
        let uvs = if self.corner_uv.is_empty() {
            &[][..]
        } else {
            &self.uvs[..]
        };
        super::obj::write_with_corners(
            w,
            positions,
            extra.colors,
            &self.faces,
            (uvs, &self.corner_uv),
            (&normals, &corner_normal),
        )
    }

    /// The file's bytes with every patched number rewritten (and material
    /// library paths made to resolve from `output`'s folder).
    fn write_patched(
        &self,
        w: &mut dyn Write,
        output: &Path,
        positions: &[[f64; 3]],
        normals: &ShapeNormals,
    ) -> std::io::Result<()> {
        let mut buf: Vec<u8> = Vec::with_capacity(super::CHUNK + 1024);
        let mut at = 0;
        let mut added = normals.added.iter().peekable();
        let planar = positions.iter().all(|p| p[2] == 0.0);
        // Found at the first `mtllib`: `None` in the source's own folder.
        let mut materials: Option<Option<MaterialPaths>> = None;
        for p in &self.patches {
            let mut library = None;
            match p.slot {
                Slot::MaterialLibrary => {
                    library = materials
                        .get_or_insert_with(|| MaterialPaths::new(&self.path, output))
                        .as_ref()
                        .and_then(|m| m.rewrite(&self.bytes[p.bytes.clone()]));
                    if library.is_none() {
                        continue;
                    }
                }
                // Kept as written unless normals were added, and no normals
                // to add here: the text around them is copied with them.
                Slot::CornerNormal(_) if normals.corner_index.is_empty() => continue,
                Slot::NormalsAfter(n, _) if added.peek().is_none_or(|&&(m, _)| m != n) => continue,
                _ => {}
            }
            if buf.len() >= super::CHUNK {
                w.write_all(&buf)?;
                buf.clear();
            }
            buf.extend_from_slice(&self.bytes[at..p.bytes.start]);
            at = p.bytes.end;
            let value = match p.slot {
                Slot::Position(v, k) => positions[v as usize][k as usize],
                Slot::Normal(n, k) => normals.normals[n as usize][k as usize],
                Slot::CornerNormal(c) => {
                    match normals.corner_index.get(c as usize) {
                        Some(&i) => super::push_uint(&mut buf, u64::from(i) + 1),
                        None => buf.extend_from_slice(&self.bytes[p.bytes.clone()]),
                    }
                    continue;
                }
                Slot::MaterialLibrary => {
                    buf.extend_from_slice(library.as_deref().unwrap_or_default());
                    continue;
                }
                Slot::NormalsAfter(n, crlf) => {
                    let end: &[u8] = if crlf { b"\r\n" } else { b"\n" };
                    let mut ended = self.bytes[..p.bytes.start]
                        .last()
                        .is_none_or(|&b| b == b'\n');
                    while let Some((_, v)) = added.next_if(|&&(m, _)| m == n) {
                        if !ended {
                            // After the file's last line, which has no line end.
                            buf.extend_from_slice(end);
                            ended = true;
                        }
                        buf.extend_from_slice(b"vn");
                        for x in v {
                            buf.push(b' ');
                            push_f64(&mut buf, *x);
                        }
                        buf.extend_from_slice(end);
                    }
                    continue;
                }
            };
            match p.coding {
                // A value that was not a number in the file stays as written.
                Coding::Text if !value.is_finite() => {
                    buf.extend_from_slice(&self.bytes[p.bytes.clone()])
                }
                Coding::Text => push_f64(&mut buf, value),
                // Planar lines (`v x y`) stay planar while the shape is.
                Coding::Appended if planar => {}
                Coding::Appended => {
                    buf.push(b' ');
                    push_f64(&mut buf, value);
                }
                Coding::Binary(ty, big) => ty.encode(value, big, &mut buf),
            }
        }
        buf.extend_from_slice(&self.bytes[at..]);
        w.write_all(&buf)
    }

    /// The triangle mesh of a pose of this file: `pose`'s positions on this
    /// file's triangles (each polygon split as this file splits it, so every
    /// pose triangulates the same). A pose face that lists a face's corners
    /// in another order or winding is the same face; the count of such faces
    /// is returned with the mesh.
    ///
    /// # Errors
    /// [`Error::Mismatch`] naming `pose`'s file when the vertex or face
    /// counts differ; [`Error::FaceMismatch`] naming the file and its first
    /// face (and 1-based line, for text formats) with other corners.
    pub fn pose(&self, pose: &MeshFile) -> Result<(Mesh3, usize)> {
        self.fit_pose(
            &pose.path,
            pose.format,
            pose.mesh.positions().to_vec(),
            &pose.faces,
        )
    }

    /// Reads the file at `path` (its format chosen by its extension) as a
    /// pose of this file: as [`MeshFile::read`] then [`MeshFile::pose`], but
    /// keeping of it only what a pose needs (its positions, and its faces
    /// to compare), so that reading the poses of an animation costs little
    /// more than parsing them.
    ///
    /// # Errors
    /// The errors of [`MeshFile::read`] (the file cannot be read, or is not
    /// a valid mesh), then the errors of [`MeshFile::pose`]
    /// ([`Error::Mismatch`] and [`Error::FaceMismatch`]: it is a mesh, but
    /// not a pose of this one).
    ///
    /// # Performance
    /// No write-back information, no triangulation and no copy of the
    /// positions of the pose's own: on the horse poses of Sumner's data
    /// (1.4 MB OBJ files) 0.85 of the time of [`MeshFile::read`] alone.
    pub fn read_pose(&self, path: &Path) -> Result<(Mesh3, usize)> {
        let format = Format::from_path(path)?;
        let bytes = super::read_mesh_bytes(path, format)?;
        let parsed = parse_parts(&bytes, format, path, Keep::Mesh)?;
        super::check_has_faces(path, parsed.positions.len(), parsed.faces.len())?;
        self.fit_pose(path, format, parsed.positions, &parsed.faces)
    }

    /// [`MeshFile::pose`] of the `positions` and `faces` read from the file
    /// `path` in `format`.
    fn fit_pose(
        &self,
        path: &Path,
        format: Format,
        positions: Vec<[f64; 3]>,
        faces: &Polygons,
    ) -> Result<(Mesh3, usize)> {
        let (mine, theirs) = (self.path.display(), path.display());
        // STL numbers vertices by where their points first occur.
        let stl = if format == Format::Stl || self.format == Format::Stl {
            STL_POSES
        } else {
            ""
        };
        if positions.len() != self.mesh.num_vertices() {
            return Err(Error::Mismatch(format!(
                "`{theirs}` has {} vertices but `{mine}` has {}: a pose (or a later key) has the vertices of its reference (the first key){stl}",
                positions.len(),
                self.mesh.num_vertices()
            )));
        }
        let mut reordered = 0;
        let mut a: Vec<u32> = Vec::new();
        let mut b: Vec<u32> = Vec::new();
        // The faces both have first: a differing face before the end of the
        // shorter list is named as such.
        for f in 0..self.faces.len().min(faces.len()) {
            let own = self.face(f);
            let other = &faces.corner_vertices()[faces.range(f)];
            if own == other {
                continue;
            }
            a.clear();
            a.extend_from_slice(own);
            a.sort_unstable();
            b.clear();
            b.extend_from_slice(other);
            b.sort_unstable();
            if a != b {
                let line = Some(faces.line(f)).filter(|&l| l > 0 && format != Format::Ply);
                return Err(Error::FaceMismatch {
                    face: f,
                    line,
                    message: self.face_mismatch(f, &theirs, faces, line) + stl,
                });
            }
            reordered += 1;
        }
        if faces.len() != self.faces.len() {
            return Err(Error::Mismatch(format!(
                "`{theirs}` has {} faces but `{mine}` has {}: a pose (or a later key) has the faces of its reference (the first key){stl}",
                faces.len(),
                self.faces.len()
            )));
        }
        let mesh = self.mesh.with_positions(positions)?;
        Ok((mesh, reordered))
    }

    /// Why face `f` (0-based) of the pose `faces`, read from the file named
    /// `theirs`, is not this file's face `f` (its corners differ): said with
    /// faces and vertices numbered from 1, as lines are (`line` is its line,
    /// for text formats). When it and the pose's face at the place of the
    /// other half of its quad in this file split that quad along the other
    /// diagonal, as exporters that triangulate by the shape do for a bent
    /// pose, that is what is said, with how to avoid it. (Blender writes
    /// the second halves of its quads after all the first halves, so the
    /// other half is looked for among every face; it comes after `f`,
    /// since the faces before `f` have their reference's corners.)
    fn face_mismatch(
        &self,
        f: usize,
        theirs: &impl std::fmt::Display,
        faces: &Polygons,
        line: Option<usize>,
    ) -> String {
        let mine = self.path.display();
        let other = |g: usize| &faces.corner_vertices()[faces.range(g)];
        let number = f + 1;
        let split = (f + 1..faces.len().min(self.faces.len())).find_map(|g| {
            quad_split_the_other_way([self.face(f), self.face(g)], [other(f), other(g)])
                .map(|quad| (g, quad))
        });
        if let Some((g, quad)) = split {
            let lines = match line {
                Some(l) => format!(" (lines {l} and {})", faces.line(g)),
                None => String::new(),
            };
            let corner = |k: usize| u64::from(quad[k]) + 1;
            return format!(
                "`{theirs}`, faces {number} and {}{lines}: the pose splits the quad {} along its diagonal {}-{} where `{mine}` splits it along {}-{} (faces and vertices numbered from 1): \
                 exporters that triangulate choose each quad's diagonal by its shape, so a bent pose can split some quads the other way. \
                 Export the reference and its poses without triangulating (each quad is then split the same way in every pose), or with the same triangulation (triangulate the reference once and export every pose from that mesh)",
                g + 1,
                show_face(&quad),
                corner(1),
                corner(3),
                corner(0),
                corner(2),
            );
        }
        let place = match line {
            Some(l) => format!("face {number} (line {l})"),
            None => format!("face {number}"),
        };
        format!(
            "`{theirs}`, {place}: vertices {} but face {number} of `{mine}` has {} (faces and vertices numbered from 1): a pose (or a later key) has the faces of its reference (the first key)",
            show_face(other(f)),
            show_face(self.face(f))
        )
    }
}

/// Parses a file's contents in `format`, keeping what `keep` says.
pub(super) fn parse_parts(bytes: &[u8], format: Format, path: &Path, keep: Keep) -> Result<Parsed> {
    match format {
        Format::Obj => super::obj::parse(bytes, path, keep),
        Format::Off => super::off::parse(bytes, path, keep),
        Format::Ply => super::ply::parse(bytes, path, keep),
        Format::Stl => super::stl::parse(bytes, path, keep),
    }
}

/// `[1, 2, 3]` from 0-based indices.
fn show_face(face: &[u32]) -> String {
    let items: Vec<String> = face
        .iter()
        .map(|i| (u64::from(*i) + 1).to_string())
        .collect();
    format!("[{}]", items.join(", "))
}
