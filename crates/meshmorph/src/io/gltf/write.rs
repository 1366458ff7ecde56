//! Binary glTF 2.0 (GLB) output: a base mesh with every frame or pose as a
//! morph target, and an animation that plays them in order.
//!
//! The file holds one mesh, with one triangle primitive per material (one
//! material of [`GltfOptions::color`] unless the base has its own,
//! [`GltfMaterials`]: colours, opacity, roughness, metallic and colour
//! textures, PNG or JPEG images embedded as they are; the primitives share
//! their vertices and morph targets):
//!
//! - the base mesh (`POSITION`, `NORMAL`, and `TEXCOORD_0` when corner
//!   texture coordinates are given): the source of an interpolation, the
//!   target reference of a transfer;
//! - one morph target per frame: `POSITION` and `NORMAL` deltas from the
//!   base, so that weight 1 on target `k` (and 0 elsewhere) shows frame `k`;
//!   the targets' names are in `mesh.extras.targetNames`, where Blender and
//!   three.js read them;
//! - unless [`GltfOptions::animation`] is off, an animation `morph` of the
//!   node's `weights`: frame `k` at time `k / fps` seconds, `LINEAR`
//!   keyframes of one-hot weight vectors (between two keyframes the shape
//!   blends linearly from one frame to the next). Without the animation
//!   every weight is 0: the targets are shape keys to dial in by hand.
//!
//! Planar meshes (`D = 2`) lie in the z = 0 plane with +z normals. glTF
//! stores attributes per vertex, so a vertex whose corners carry different
//! texture coordinates is split into one glTF vertex per coordinate pair
//! (the splits follow the original vertices, in order); vertices that no
//! triangle uses are left out. Vertex normals are the triangle normals of
//! each frame averaged with each triangle weighing its angle at the vertex
//! (as Blender computes them). Coordinates are stored as `f32`:
//! base plus delta gives each frame's positions to `f32` precision.
//!
//! # Size
//! Each frame adds 24 bytes per vertex (12 for the position delta, 12 for
//! the normal delta; planar frames share one block of zero normal deltas
//! and add 12): [`estimate_glb_bytes`] gives the figure before anything is
//! computed. A GLB holds at most 4 GiB.
//!
//! # Example
//! ```no_run
//! use meshmorph::io::gltf::{write_glb, GltfBase, GltfOptions};
//! use meshmorph::shapes;
//!
//! let bar = shapes::strip(10.0, 0.5, 40, 2);
//! let spiral = shapes::curl(&bar, 3.0 * std::f64::consts::PI);
//! let frames = [bar.positions(), spiral.positions()];
//! let base = GltfBase::new(bar.positions(), bar.triangles());
//! let names = ["bar".to_string(), "spiral".to_string()];
//! write_glb("curl.glb".as_ref(), &base, &frames, &names, &GltfOptions::default().with_fps(2.0))?;
//! # Ok::<(), meshmorph::Error>(())
//! ```

use std::collections::HashMap;
use std::io::Write;
use std::path::Path;

use gltf_json as json;
use json::validation::{Checked::Valid, USize64};
use rayon::prelude::*;

use crate::error::{Error, Result};
use crate::io::morph_storage::{normals_changed, Deltas, NormalsChanged, Quantization, Storage};
use crate::io::{write_atomic, xyz};
use crate::linalg::vector::{angle_weighted_normals, angle_weighted_vertex_normals};
use crate::mesh::check_finite;
use crate::mesh::frame_source::{map_frame, FrameSource};

/// How a GLB is written.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct GltfOptions {
    /// Frames per second of the animation. Default 25.
    pub fps: f64,
    /// Write the animation; without it the morph targets are shape keys at
    /// weight 0. Default `true`.
    pub animation: bool,
    /// The name of the mesh and of its node. Default `"meshmorph"`.
    pub name: String,
    /// Linear RGB base colour of the material. Default a light sand.
    pub color: [f32; 3],
    /// Store positions and their deltas as normalised 16-bit integers
    /// (KHR_mesh_quantization; the node's translation and scale decode
    /// them): a third smaller, each coordinate of a frame within
    /// `scale / 32767` of its own (the node's scale: the largest distance
    /// of a base coordinate from the centre of the base's bounding box,
    /// plus the largest delta). Default `false`: `f32`, exact to `f32`
    /// precision.
    pub quantize: bool,
    /// Store a morph target sparsely (glTF's sparse accessors: only the
    /// vertices it moves) when that is smaller. Default `true`; `false`
    /// writes every target densely, for tools that do not read sparse
    /// accessors.
    pub sparse: bool,
}

impl Default for GltfOptions {
    fn default() -> Self {
        GltfOptions {
            fps: 25.0,
            animation: true,
            name: "meshmorph".to_string(),
            color: [0.8, 0.62, 0.4],
            quantize: false,
            sparse: true,
        }
    }
}

impl GltfOptions {
    /// Sets [`fps`](Self::fps).
    pub fn with_fps(mut self, fps: f64) -> Self {
        self.fps = fps;
        self
    }

    /// Sets [`animation`](Self::animation).
    pub fn with_animation(mut self, animation: bool) -> Self {
        self.animation = animation;
        self
    }

    /// Sets [`name`](Self::name).
    pub fn with_name(mut self, name: impl Into<String>) -> Self {
        self.name = name.into();
        self
    }

    /// Sets [`color`](Self::color).
    pub fn with_color(mut self, color: [f32; 3]) -> Self {
        self.color = color;
        self
    }

    /// Sets [`sparse`](Self::sparse).
    pub fn with_sparse(mut self, sparse: bool) -> Self {
        self.sparse = sparse;
        self
    }

    /// Sets [`quantize`](Self::quantize).
    pub fn with_quantize(mut self, quantize: bool) -> Self {
        self.quantize = quantize;
        self
    }
}

/// The base mesh of a GLB: positions (`D` = 2 or 3), triangles, and
/// optionally texture coordinates per triangle corner.
#[derive(Clone, Copy, Debug)]
pub struct GltfBase<'a, const D: usize> {
    /// `#V` positions.
    pub positions: &'a [[f64; D]],
    /// `#T` triangles, counter-clockwise seen from the front.
    pub triangles: &'a [[u32; 3]],
    /// `#T × 3` texture coordinates `(u, v)`, one per triangle corner
    /// (OBJ's convention: v up; written with glTF's v down), as
    /// [`MeshFile::triangle_corner_uvs`](crate::io::MeshFile::triangle_corner_uvs)
    /// gives them.
    pub corner_uvs: Option<&'a [[[f32; 2]; 3]]>,
    /// `#T × 3` normal groups, one per triangle corner, as
    /// [`MeshFile::triangle_corner_normal_groups`](crate::io::MeshFile::triangle_corner_normal_groups)
    /// gives them: the corners of a vertex with the same group share a
    /// normal, computed in every frame from their faces alone; corners with
    /// different groups lie on the two sides of a hard edge, and each side
    /// gets vertices of its own. Without them every vertex is smooth.
    pub corner_normal_groups: Option<&'a [[u32; 3]]>,
    /// The materials of the triangles; without them every triangle has
    /// one material of [`GltfOptions::color`] (white with vertex colours).
    pub materials: Option<GltfMaterials<'a>>,
    /// `#T × 3` linear RGBA colours, one per triangle corner (`COLOR_0`,
    /// which glTF multiplies with the material's colour); corners of a
    /// vertex with different colours get vertices of their own.
    pub corner_colors: Option<&'a [[[f32; 4]; 3]]>,
}

/// The materials of a base mesh: each triangle's material, and the images
/// their colour textures use.
#[derive(Clone, Copy, Debug)]
pub struct GltfMaterials<'a> {
    /// The materials.
    pub materials: &'a [GltfMaterial],
    /// The images of the materials' textures.
    pub images: &'a [GltfImage],
    /// `#T` indices into `materials`, one per triangle.
    pub of_triangle: &'a [u32],
}

/// A material of a GLB (glTF's metallic-roughness model).
#[derive(Clone, Debug, PartialEq)]
pub struct GltfMaterial {
    /// Its name.
    pub name: String,
    /// Linear RGBA base colour; alpha below 1 makes the material blended.
    pub base_color: [f32; 4],
    /// Metallic factor, 0 to 1.
    pub metallic: f32,
    /// Roughness factor, 0 to 1.
    pub roughness: f32,
    /// The index of the base colour's texture image in
    /// [`GltfMaterials::images`] (multiplied by `base_color`), shown
    /// through the texture coordinates of the base (without them, left
    /// out).
    pub image: Option<usize>,
}

/// An image embedded in a GLB: a PNG or JPEG file's bytes.
#[derive(Clone, Debug, PartialEq)]
pub struct GltfImage {
    /// The file's bytes.
    pub bytes: Vec<u8>,
    /// `image/png` or `image/jpeg`.
    pub mime_type: &'static str,
}

impl GltfImage {
    /// The image in `bytes` when it is a PNG or a JPEG (the formats glTF
    /// holds), told by its first bytes; `None` otherwise.
    pub fn from_bytes(bytes: Vec<u8>) -> Option<Self> {
        let mime_type = if bytes.starts_with(b"\x89PNG\r\n\x1a\n") {
            "image/png"
        } else if bytes.starts_with(&[0xFF, 0xD8, 0xFF]) {
            "image/jpeg"
        } else {
            return None;
        };
        Some(GltfImage { bytes, mime_type })
    }
}

impl<'a, const D: usize> GltfBase<'a, D> {
    /// A base mesh without texture coordinates.
    pub fn new(positions: &'a [[f64; D]], triangles: &'a [[u32; 3]]) -> Self {
        GltfBase {
            positions,
            triangles,
            corner_uvs: None,
            corner_normal_groups: None,
            materials: None,
            corner_colors: None,
        }
    }

    /// Adds a colour per triangle corner (linear RGBA).
    pub fn with_corner_colors(mut self, colors: &'a [[[f32; 4]; 3]]) -> Self {
        self.corner_colors = Some(colors);
        self
    }

    /// Adds the triangles' materials.
    pub fn with_materials(mut self, materials: GltfMaterials<'a>) -> Self {
        self.materials = Some(materials);
        self
    }

    /// Adds texture coordinates per triangle corner.
    pub fn with_corner_uvs(mut self, corner_uvs: &'a [[[f32; 2]; 3]]) -> Self {
        self.corner_uvs = Some(corner_uvs);
        self
    }

    /// Adds the normal groups of the triangle corners (hard edges).
    pub fn with_corner_normal_groups(mut self, groups: &'a [[u32; 3]]) -> Self {
        self.corner_normal_groups = Some(groups);
        self
    }
}

/// How many vertices the GLB of `base` has: one per used vertex and
/// distinct texture coordinates, normal group and colour of its corners (a
/// mesh shaded flat has three per triangle). Count them with this before
/// [`estimate_glb_bytes`].
///
/// # Errors
/// As [`write_glb`] for corner data that does not fit the triangles.
pub fn vertex_count<const D: usize>(base: &GltfBase<'_, D>) -> Result<usize> {
    Ok(split_vertices(base)?.original.len())
}

/// About how many bytes a GLB of `frames` frames of a mesh with `vertices`
/// glTF vertices ([`vertex_count`]), `triangles` triangles and `D`
/// coordinates weighs: 24 bytes per vertex and frame in space, 12 in the
/// plane, plus the base mesh, the animation and the JSON.
pub fn estimate_glb_bytes<const D: usize>(
    vertices: usize,
    triangles: usize,
    frames: usize,
    uvs: bool,
) -> u64 {
    let (v, t, f) = (vertices as u64, triangles as u64, frames as u64);
    let per_frame = if D == 3 { 24 } else { 12 };
    let planar_normals = if D == 3 { 0 } else { 12 * v };
    let base = 12 * t + v * (24 + if uvs { 8 } else { 0 }) + planar_normals;
    let animation = 4 * f * (f + 1);
    let json = 1500 + 300 * f;
    base + per_frame * v * f + animation + json
}

/// Writes a GLB atomically (see [`write_atomic`]): the base mesh, one morph
/// target per frame named by `names`, and the animation (see the
/// [module documentation](self)).
///
/// # Errors
/// [`Error::InvalidArgument`] when `names` and `frames` differ in length,
/// there are no frames, `D` is not 2 or 3, the fps is not in
/// [`FRAME_RATES`](crate::limits::FRAME_RATES), the corner texture coordinates do not match the triangles or are
/// not finite ([`Error::InvalidTriangle`]), or the file would pass 4 GiB;
/// [`Error::InvalidMesh`] naming the frame when it has the wrong number of
/// vertices, [`Error::InvalidVertex`] the frame and the vertex with a
/// coordinate that is not finite, [`Error::InvalidTriangle`] a triangle
/// whose index is out of range;
/// [`Error::Io`] naming the file when it cannot be written. Nothing is left
/// at `path` when an error occurs.
///
/// # Performance
/// Frames are prepared in parallel; the file is streamed, never held whole
/// in memory.
pub fn write_glb<const D: usize, F: AsRef<[[f64; D]]> + Sync>(
    path: &Path,
    base: &GltfBase<'_, D>,
    frames: &[F],
    names: &[String],
    options: &GltfOptions,
) -> Result<()> {
    write_glb_frames(path, base, frames, names, options)
}

/// [`write_glb`] with frames produced on demand: each frame is asked for
/// twice, once for the bounds of its position deltas (which the JSON at the
/// head of the file needs) and once to stream its deltas, a few frames at a
/// time. Memory for frames stays bounded however many there are.
///
/// # Errors
/// As [`write_glb`].
pub fn write_glb_frames<const D: usize, S: FrameSource<D> + ?Sized>(
    path: &Path,
    base: &GltfBase<'_, D>,
    frames: &S,
    names: &[String],
    options: &GltfOptions,
) -> Result<()> {
    let layout = Layout::new(base, frames, names, options)
        .map_err(|e| prefix(e, &format!("cannot write `{}`", path.display())))?;
    write_atomic(path, |w| layout.write(w, frames))
}

/// Writes a GLB to any writer (a buffer, a staging file): [`write_glb`]
/// without the file handling.
///
/// # Errors
/// As [`write_glb`]; a failing writer gives [`Error::Io`] naming
/// `name_for_messages`.
pub fn write_glb_to<const D: usize, F: AsRef<[[f64; D]]> + Sync>(
    w: &mut dyn Write,
    name_for_messages: &Path,
    base: &GltfBase<'_, D>,
    frames: &[F],
    names: &[String],
    options: &GltfOptions,
) -> Result<()> {
    let layout = Layout::new(base, frames, names, options)?;
    layout
        .write(w, frames)
        .map_err(|e| Error::io(name_for_messages, e))
}

fn prefix(e: Error, what: &str) -> Error {
    match e {
        Error::InvalidArgument(m) => Error::InvalidArgument(format!("{what}: {m}")),
        Error::InvalidMesh(m) => Error::InvalidMesh(format!("{what}: {m}")),
        Error::InvalidVertex { vertex, message } => Error::InvalidVertex {
            vertex,
            message: format!("{what}: {message}"),
        },
        Error::InvalidTriangle { triangle, message } => Error::InvalidTriangle {
            triangle,
            message: format!("{what}: {message}"),
        },
        other => other,
    }
}

/// Everything known before the binary data is streamed: the glTF vertices,
/// the JSON, the offsets.
struct Layout<'a, const D: usize> {
    base: &'a [[f64; D]],
    /// The base mesh's triangles, in original vertices.
    triangles: &'a [[u32; 3]],
    /// glTF vertex → original vertex.
    original: Vec<u32>,
    /// Triangles in glTF vertices, ordered by material.
    indices: Vec<[u32; 3]>,
    /// One primitive per material: the material (`None`: the default one)
    /// and the range of `indices` it draws.
    primitives: Vec<(Option<u32>, std::ops::Range<usize>)>,
    materials: Option<GltfMaterials<'a>>,
    /// Per glTF vertex, glTF's convention (v down).
    uvs: Option<Vec<[f32; 2]>>,
    /// Linear RGBA per glTF vertex.
    colors: Option<Vec<[f32; 4]>>,
    /// The normal groups of the triangle corners, and the group of each
    /// glTF vertex, when the base has them.
    groups: Option<(Vec<[u32; 3]>, Vec<u32>)>,
    base_positions: Vec<[f32; 3]>,
    base_normals: Vec<[f32; 3]>,
    /// Per frame, how its deltas are stored.
    targets: Vec<TargetPlan>,
    /// Positions as normalised `i16` ([`GltfOptions::quantize`]), and the
    /// base's so stored.
    quantization: Option<(Quantization, Deltas)>,
    fps: f64,
    animation: bool,
    json: Vec<u8>,
    bin_length: u64,
}

impl<'a, const D: usize> Layout<'a, D> {
    fn new<S: FrameSource<D> + ?Sized>(
        base: &GltfBase<'a, D>,
        frames: &S,
        names: &[String],
        options: &GltfOptions,
    ) -> Result<Self> {
        let count = frames.num_frames();
        if D != 2 && D != 3 {
            return Err(Error::InvalidArgument(format!(
                "glTF meshes have 2 or 3 coordinates per vertex, not {D}"
            )));
        }
        if count == 0 {
            return Err(Error::InvalidArgument("no frames to write".into()));
        }
        if names.len() != count {
            return Err(Error::InvalidArgument(format!(
                "{count} frames but {} names",
                names.len()
            )));
        }
        if !crate::limits::FRAME_RATES.contains(&options.fps) {
            return Err(Error::InvalidArgument(format!(
                "the frame rate must be from {} to {} frames per second, not {}",
                crate::limits::FRAME_RATES.start(),
                crate::limits::FRAME_RATES.end(),
                options.fps
            )));
        }
        check_positions(base.positions, base.triangles, "the base mesh")?;
        let Split {
            original,
            indices,
            uvs,
            colors,
            groups,
        } = split_vertices(base)?;
        let (indices, primitives) = by_material(indices, base.materials)?;
        let base_positions: Vec<[f32; 3]> = original
            .iter()
            .map(|&v| xyz(&base.positions[v as usize]).map(|x| x as f32))
            .collect();
        let base_normals =
            gltf_normals::<D>(base.positions, base.triangles, &original, &groups, None);

        // Each frame checked, with what the JSON needs before any data: its
        // position deltas' bounds and how many of its position and normal
        // deltas are not zero.
        let firsts: Vec<FrameSummary> = (0..count)
            .into_par_iter()
            .map(|k| {
                map_frame(frames, k, |f| {
                    if f.len() != base.positions.len() {
                        return Err(Error::InvalidMesh(format!(
                            "frame {k} (`{}`) has {} vertices, the base mesh {}",
                            names[k],
                            f.len(),
                            base.positions.len()
                        )));
                    }
                    check_finite(f, &format!("frame {k} (`{}`)", names[k]))?;
                    let deltas = Deltas::positions(f, base.positions, &original);
                    let normals = if D == 3 {
                        normals_changed(f, base.positions, base.triangles, &original).len()
                    } else {
                        0
                    };
                    Ok((deltas.bounds(), deltas.moved().len(), normals))
                })
            })
            .collect::<Result<_>>()?;
        let quantization = options.quantize.then(|| {
            let (lo, hi) = bounds_of(&base_positions);
            let center: [f64; 3] =
                std::array::from_fn(|k| (f64::from(lo[k]) + f64::from(hi[k])) / 2.0);
            let base_extent = original
                .iter()
                .map(|&v| {
                    let p = xyz(&base.positions[v as usize]);
                    (0..3).map(|k| (p[k] - center[k]).abs()).fold(0.0, f64::max)
                })
                .fold(0.0, f64::max);
            let delta_extent = firsts
                .iter()
                .flat_map(|((lo, hi), _, _)| lo.iter().chain(hi).map(|x| f64::from(x.abs())))
                .fold(0.0, f64::max);
            let q = Quantization::new(center, base_extent + delta_extent);
            let stored = original
                .iter()
                .map(|&v| q.position(xyz(&base.positions[v as usize])))
                .collect();
            (q, Deltas::I16(stored))
        });
        let n = original.len();
        // Dense: as many entries as vertices, never smaller.
        let entries = |moved: usize| if options.sparse { moved } else { n };
        let targets = firsts
            .iter()
            .map(|&((lo, hi), moved, normals)| TargetPlan {
                bounds: match &quantization {
                    None => (lo, hi),
                    Some((q, _)) => (q.delta_bound(lo), q.delta_bound(hi)),
                },
                positions: Storage::choose(
                    n,
                    entries(moved),
                    if quantization.is_some() { 6 } else { 12 },
                ),
                normals: (D == 3).then(|| Storage::choose(n, entries(normals), 12)),
            })
            .collect();

        let mut layout = Layout {
            base: base.positions,
            triangles: base.triangles,
            original,
            indices,
            primitives,
            materials: base.materials,
            uvs,
            colors,
            groups,
            base_positions,
            base_normals,
            targets,
            quantization,
            fps: options.fps,
            animation: options.animation,
            json: Vec::new(),
            bin_length: 0,
        };
        let (root, bin_length) = layout.root(names, options);
        layout.bin_length = bin_length;
        let mut json = root
            .to_vec()
            .map_err(|e| Error::InvalidArgument(format!("glTF JSON: {e}")))?;
        while json.len() % 4 != 0 {
            json.push(b' ');
        }
        let total = 12 + 8 + json.len() as u64 + 8 + bin_length;
        if total > u64::from(u32::MAX) {
            return Err(Error::InvalidArgument(format!(
                "the GLB would weigh {} MB; the format holds at most 4 GiB: write fewer frames",
                total / 1_000_000
            )));
        }
        layout.json = json;
        Ok(layout)
    }

    fn vertex_count(&self) -> usize {
        self.original.len()
    }

    /// Whether frames carry their own normals (planar ones share zeros).
    fn frame_normals(&self) -> bool {
        D == 3
    }

    /// The glTF document and the length of the binary chunk.
    fn root(&self, names: &[String], options: &GltfOptions) -> (json::Root, u64) {
        let n = self.vertex_count() as u64;
        let mut root = json::Root::default();
        let mut offset = 0u64;
        let buffer = json::Index::new(0);
        let mut view =
            |root: &mut json::Root, length: u64, target: Option<json::buffer::Target>| {
                let v = root.push(json::buffer::View {
                    buffer,
                    byte_length: USize64(length),
                    byte_offset: Some(USize64(offset)),
                    byte_stride: None,
                    name: None,
                    target: target.map(Valid),
                    extensions: None,
                    extras: None,
                });
                // Every view starts on a multiple of 4 bytes.
                offset += length.next_multiple_of(4);
                v
            };
        let vec3 = |root: &mut json::Root,
                    view: json::Index<json::buffer::View>,
                    bounds: Option<([f32; 3], [f32; 3])>| {
            root.push(accessor(
                view,
                n,
                json::accessor::ComponentType::F32,
                json::accessor::Type::Vec3,
                bounds.map(|(lo, hi)| (lo.to_vec(), hi.to_vec())),
            ))
        };
        use json::buffer::Target::{ArrayBuffer, ElementArrayBuffer};

        let index_view = view(
            &mut root,
            12 * self.indices.len() as u64,
            Some(ElementArrayBuffer),
        );
        let index_accessors: Vec<json::Index<json::Accessor>> = self
            .primitives
            .iter()
            .map(|(_, range)| {
                let mut a = accessor(
                    index_view,
                    3 * range.len() as u64,
                    json::accessor::ComponentType::U32,
                    json::accessor::Type::Scalar,
                    None,
                );
                a.byte_offset = Some(USize64(12 * range.start as u64));
                root.push(a)
            })
            .collect();
        let positions = match &self.quantization {
            None => {
                let position_view = view(&mut root, 12 * n, Some(ArrayBuffer));
                vec3(
                    &mut root,
                    position_view,
                    Some(bounds_of(&self.base_positions)),
                )
            }
            Some((_, stored)) => {
                let position_view = view(&mut root, 8 * n, Some(ArrayBuffer));
                root.buffer_views[position_view.value()].byte_stride =
                    Some(json::buffer::Stride(8));
                let (lo, hi) = stored.bounds();
                let mut a = accessor(
                    position_view,
                    n,
                    json::accessor::ComponentType::I16,
                    json::accessor::Type::Vec3,
                    Some((lo.to_vec(), hi.to_vec())),
                );
                a.normalized = true;
                root.push(a)
            }
        };
        let normal_view = view(&mut root, 12 * n, Some(ArrayBuffer));
        let normals = vec3(&mut root, normal_view, None);
        let mut attributes = std::collections::BTreeMap::new();
        attributes.insert(Valid(json::mesh::Semantic::Positions), positions);
        attributes.insert(Valid(json::mesh::Semantic::Normals), normals);
        // The optional attributes of the base, `f32` each: texture
        // coordinates, colours.
        use json::accessor::Type::{Vec2, Vec4};
        use json::mesh::Semantic::{Colors, TexCoords};
        for (present, kind, components, semantic) in [
            (self.uvs.is_some(), Vec2, 2, TexCoords(0)),
            (self.colors.is_some(), Vec4, 4, Colors(0)),
        ] {
            if present {
                let v = view(&mut root, 4 * components * n, Some(ArrayBuffer));
                let a = root.push(accessor(
                    v,
                    n,
                    json::accessor::ComponentType::F32,
                    kind,
                    None,
                ));
                attributes.insert(Valid(semantic), a);
            }
        }
        let shared_zero_normals = if self.frame_normals() {
            None
        } else {
            let v = view(&mut root, 12 * n, Some(ArrayBuffer));
            Some(vec3(&mut root, v, None))
        };
        // A target attribute, dense (a view of every vertex) or sparse (two
        // views: the indices and the values of the vertices that move).
        let mut stored = |root: &mut json::Root,
                          storage: Storage,
                          bounds: Option<([f32; 3], [f32; 3])>| {
            let quantized = storage.quantized();
            let component = if quantized {
                json::accessor::ComponentType::I16
            } else {
                json::accessor::ComponentType::F32
            };
            let views = storage.views();
            let mut a = match storage.entries {
                None => {
                    let v = view(root, views[0] as u64, Some(ArrayBuffer));
                    if quantized {
                        root.buffer_views[v.value()].byte_stride =
                            Some(json::buffer::Stride(storage.stride()));
                    }
                    accessor(v, n, component, json::accessor::Type::Vec3, None)
                }
                Some(k) => {
                    let indices = view(root, views[0] as u64, None);
                    let values = view(root, views[1] as u64, None);
                    let index_type = if storage.index_bytes() == 2 {
                        json::accessor::ComponentType::U16
                    } else {
                        json::accessor::ComponentType::U32
                    };
                    let mut a = accessor(indices, n, component, json::accessor::Type::Vec3, None);
                    a.buffer_view = None;
                    a.sparse = Some(json::accessor::sparse::Sparse {
                        count: USize64(k as u64),
                        indices: json::accessor::sparse::Indices {
                            buffer_view: indices,
                            byte_offset: USize64(0),
                            component_type: Valid(json::accessor::IndexComponentType(index_type)),
                            extensions: None,
                            extras: Default::default(),
                        },
                        values: json::accessor::sparse::Values {
                            buffer_view: values,
                            byte_offset: USize64(0),
                            extensions: None,
                            extras: Default::default(),
                        },
                        extensions: None,
                        extras: Default::default(),
                    });
                    a
                }
            };
            a.normalized = quantized;
            if let Some((lo, hi)) = bounds {
                a.min = Some(json::Value::from(lo.to_vec()));
                a.max = Some(json::Value::from(hi.to_vec()));
            }
            root.push(a)
        };
        let targets: Vec<json::mesh::MorphTarget> = self
            .targets
            .iter()
            .map(|plan| {
                let positions = stored(&mut root, plan.positions, Some(plan.bounds));
                let normals = match (shared_zero_normals, plan.normals) {
                    (Some(a), _) => a,
                    (None, Some(storage)) => stored(&mut root, storage, None),
                    (None, None) => unreachable!("frames in space have their normals' storage"),
                };
                json::mesh::MorphTarget {
                    positions: Some(positions),
                    normals: Some(normals),
                    tangents: None,
                }
            })
            .collect();
        let frames = self.targets.len() as u64;

        let materials = self.materials_json(&mut root, options);
        let target_names = json::Value::from(names.to_vec());
        let extras = json::Value::Object(
            [("targetNames".to_string(), target_names)]
                .into_iter()
                .collect(),
        );
        let mesh = root.push(json::Mesh {
            extensions: None,
            extras: json::extras::RawValue::from_string(extras.to_string()).ok(),
            name: Some(options.name.clone()),
            primitives: self
                .primitives
                .iter()
                .zip(index_accessors)
                .map(|((material, _), indices)| json::mesh::Primitive {
                    attributes: attributes.clone(),
                    extensions: None,
                    extras: None,
                    indices: Some(indices),
                    material: Some(materials[material.map_or(0, |m| m as usize)]),
                    mode: Valid(json::mesh::Mode::Triangles),
                    targets: Some(targets.clone()),
                })
                .collect(),
            weights: Some(vec![0.0; frames as usize]),
        });
        let node = root.push(json::Node {
            mesh: Some(mesh),
            name: Some(options.name.clone()),
            // The quantised positions' decoding.
            translation: self
                .quantization
                .as_ref()
                .map(|(q, _)| q.center.map(|c| c as f32)),
            scale: self.quantization.as_ref().map(|(q, _)| [q.scale as f32; 3]),
            ..Default::default()
        });
        if self.quantization.is_some() {
            root.extensions_used.push("KHR_mesh_quantization".into());
            root.extensions_required
                .push("KHR_mesh_quantization".into());
        }
        let scene = root.push(json::Scene {
            extensions: None,
            extras: None,
            name: Some(options.name.clone()),
            nodes: vec![node],
        });
        root.scene = Some(scene);

        if self.animation {
            let times_view = view(&mut root, 4 * frames, None);
            let last = ((frames - 1) as f64 / self.fps) as f32;
            let times = root.push(accessor(
                times_view,
                frames,
                json::accessor::ComponentType::F32,
                json::accessor::Type::Scalar,
                Some((vec![0.0], vec![last])),
            ));
            let weights_view = view(&mut root, 4 * frames * frames, None);
            let weights = root.push(accessor(
                weights_view,
                frames * frames,
                json::accessor::ComponentType::F32,
                json::accessor::Type::Scalar,
                None,
            ));
            root.push(json::Animation {
                extensions: None,
                extras: None,
                name: Some("morph".into()),
                channels: vec![json::animation::Channel {
                    sampler: json::Index::new(0),
                    target: json::animation::Target {
                        extensions: None,
                        extras: None,
                        node,
                        path: Valid(json::animation::Property::MorphTargetWeights),
                    },
                    extensions: None,
                    extras: None,
                }],
                samplers: vec![json::animation::Sampler {
                    extensions: None,
                    extras: None,
                    input: times,
                    interpolation: Valid(json::animation::Interpolation::Linear),
                    output: weights,
                }],
            });
        }
        // The images, last, each view starting on a multiple of 4 bytes.
        if let Some(m) = self.materials.filter(|_| self.uvs.is_some()) {
            for (k, image) in m.images.iter().enumerate() {
                let v = view(&mut root, image.bytes.len() as u64, None);
                root.images[k].buffer_view = Some(v);
            }
        }
        root.push(json::Buffer {
            byte_length: USize64(offset),
            name: None,
            uri: None,
            extensions: None,
            extras: None,
        });
        root.asset = json::Asset {
            generator: Some(format!("meshmorph {}", env!("CARGO_PKG_VERSION"))),
            ..Default::default()
        };
        (root, offset)
    }

    /// The materials of the document: the base's, with their textures and
    /// images (whose buffer views come last, see [`Layout::root`]), or
    /// without them one of [`GltfOptions::color`].
    fn materials_json(
        &self,
        root: &mut json::Root,
        options: &GltfOptions,
    ) -> Vec<json::Index<json::Material>> {
        let translucent = self
            .colors
            .as_ref()
            .is_some_and(|c| c.iter().any(|x| x[3] < 1.0));
        let Some(m) = self.materials else {
            // Vertex colours are the colour.
            let [r, g, b] = if self.colors.is_some() {
                [1.0; 3]
            } else {
                options.color
            };
            return vec![root.push(material_json(
                "meshmorph",
                [r, g, b, 1.0],
                (0.0, 0.7),
                None,
                translucent,
            ))];
        };
        // Textures need texture coordinates.
        let textures: Vec<json::Index<json::Texture>> = if self.uvs.is_some() {
            let sampler = root.push(json::texture::Sampler {
                wrap_s: Valid(json::texture::WrappingMode::Repeat),
                wrap_t: Valid(json::texture::WrappingMode::Repeat),
                ..Default::default()
            });
            m.images
                .iter()
                .map(|image| {
                    let source = root.push(json::Image {
                        buffer_view: None,
                        mime_type: Some(json::image::MimeType(image.mime_type.to_string())),
                        name: None,
                        uri: None,
                        extensions: None,
                        extras: None,
                    });
                    root.push(json::Texture {
                        name: None,
                        sampler: Some(sampler),
                        source,
                        extensions: None,
                        extras: None,
                    })
                })
                .collect()
        } else {
            Vec::new()
        };
        m.materials
            .iter()
            .map(|mat| {
                let texture = mat.image.and_then(|i| textures.get(i).copied());
                root.push(material_json(
                    &mat.name,
                    mat.base_color,
                    (mat.metallic, mat.roughness),
                    texture,
                    translucent,
                ))
            })
            .collect()
    }

    /// Streams the GLB: header, JSON chunk, binary chunk, in the order
    /// [`Layout::root`] laid the buffer views out.
    fn write<S: FrameSource<D> + ?Sized>(
        &self,
        w: &mut dyn Write,
        frames: &S,
    ) -> std::io::Result<()> {
        let count = frames.num_frames();
        let total = 12 + 8 + self.json.len() as u64 + 8 + self.bin_length;
        w.write_all(b"glTF")?;
        w.write_all(&2u32.to_le_bytes())?;
        w.write_all(&(total as u32).to_le_bytes())?;
        w.write_all(&(self.json.len() as u32).to_le_bytes())?;
        w.write_all(b"JSON")?;
        w.write_all(&self.json)?;
        w.write_all(&(self.bin_length as u32).to_le_bytes())?;
        w.write_all(b"BIN\0")?;

        let mut buf = Vec::with_capacity(12 * self.indices.len());
        for i in self.indices.iter().flatten() {
            buf.extend_from_slice(&i.to_le_bytes());
        }
        w.write_all(&buf)?;
        match &self.quantization {
            None => write_f32s(w, self.base_positions.iter().flatten().copied())?,
            Some((_, stored)) => {
                let mut bytes = Vec::with_capacity(8 * self.vertex_count());
                Storage::choose(self.vertex_count(), self.vertex_count(), 6).write(
                    &mut bytes,
                    stored,
                    &[],
                );
                w.write_all(&bytes)?;
            }
        }
        write_f32s(w, self.base_normals.iter().flatten().copied())?;
        if let Some(uvs) = &self.uvs {
            write_f32s(w, uvs.iter().flatten().copied())?;
        }
        if let Some(colors) = &self.colors {
            write_f32s(w, colors.iter().flatten().copied())?;
        }
        if !self.frame_normals() {
            write_f32s(w, std::iter::repeat_n(0.0, 3 * self.vertex_count()))?;
        }
        // A batch of frames is prepared in parallel, then written in order.
        let batch = crate::limits::FRAMES_IN_FLIGHT_PER_THREAD * rayon::current_num_threads();
        for first in (0..count).step_by(batch) {
            let blocks: Vec<Vec<u8>> = (first..(first + batch).min(count))
                .into_par_iter()
                .map(|k| map_frame(frames, k, |f| self.frame_bytes(&self.targets[k], f)))
                .collect();
            for b in blocks {
                w.write_all(&b)?;
            }
        }
        if self.animation {
            let n = count;
            write_f32s(w, (0..n).map(|k| (k as f64 / self.fps) as f32))?;
            write_f32s(
                w,
                (0..n * n).map(|i| if i / n == i % n { 1.0 } else { 0.0 }),
            )?;
        }
        if let Some(m) = self.materials.filter(|_| self.uvs.is_some()) {
            for image in m.images {
                w.write_all(&image.bytes)?;
                let pad = image.bytes.len().next_multiple_of(4) - image.bytes.len();
                w.write_all(&[0; 3][..pad])?;
            }
        }
        Ok(())
    }

    /// A frame's position deltas, then (for meshes in space) its normal
    /// deltas, little-endian, stored as `plan` says.
    fn frame_bytes(&self, plan: &TargetPlan, frame: &[[f64; D]]) -> Vec<u8> {
        let mut out =
            Vec::with_capacity(plan.positions.bytes() + plan.normals.map_or(0, |s| s.bytes()));
        let exact = Deltas::positions(frame, self.base, &self.original);
        let moved = exact.moved();
        let deltas = match &self.quantization {
            None => exact,
            Some((q, _)) => exact.quantized(q),
        };
        plan.positions.write(&mut out, &deltas, &moved);
        if let Some(storage) = plan.normals {
            // Only the normals around the vertices the frame moves are
            // made afresh: elsewhere their deltas are zero.
            let changed = NormalsChanged::find(frame, self.base, self.triangles, &self.original);
            let normals = gltf_normals::<D>(
                frame,
                self.triangles,
                &self.original,
                &self.groups,
                Some(&changed.around),
            );
            let mut deltas = vec![[0.0; 3]; self.original.len()];
            for &i in &changed.vertices {
                let (a, b) = (normals[i as usize], self.base_normals[i as usize]);
                deltas[i as usize] = std::array::from_fn(|k| a[k] - b[k]);
            }
            storage.write(&mut out, &Deltas::F32(deltas), &changed.vertices);
        }
        out
    }
}

/// A frame's position deltas' bounds, and how many of its position and
/// normal deltas are not zero.
type FrameSummary = (([f32; 3], [f32; 3]), usize, usize);

/// How one frame's morph target is stored.
struct TargetPlan {
    /// Its position deltas' bounds, as stored (integers when quantised).
    bounds: ([f32; 3], [f32; 3]),
    positions: Storage,
    /// `None` for planar meshes, whose frames share zero normal deltas.
    normals: Option<Storage>,
}

/// A double-sided material (OBJ files do not say which side shows), blended
/// when its alpha, or a vertex colour's, is below 1.
fn material_json(
    name: &str,
    base_color: [f32; 4],
    (metallic, roughness): (f32, f32),
    texture: Option<json::Index<json::Texture>>,
    translucent_vertices: bool,
) -> json::Material {
    json::Material {
        double_sided: true,
        name: Some(name.to_string()),
        alpha_mode: Valid(if base_color[3] < 1.0 || translucent_vertices {
            json::material::AlphaMode::Blend
        } else {
            json::material::AlphaMode::Opaque
        }),
        pbr_metallic_roughness: json::material::PbrMetallicRoughness {
            base_color_factor: json::material::PbrBaseColorFactor(base_color),
            metallic_factor: json::material::StrengthFactor(metallic),
            roughness_factor: json::material::StrengthFactor(roughness),
            base_color_texture: texture.map(|index| json::texture::Info {
                index,
                tex_coord: 0,
                extensions: None,
                extras: None,
            }),
            ..Default::default()
        },
        ..Default::default()
    }
}

/// The triangles (in glTF vertices) ordered by material, and one primitive
/// per material used: all in one primitive of the default material without
/// `materials`.
///
/// # Errors
/// When `materials` does not give every triangle a material it holds, or an
/// image it holds.
#[allow(clippy::type_complexity)]
fn by_material(
    indices: Vec<[u32; 3]>,
    materials: Option<GltfMaterials<'_>>,
) -> Result<(Vec<[u32; 3]>, Vec<(Option<u32>, std::ops::Range<usize>)>)> {
    let Some(m) = materials else {
        let all = 0..indices.len();
        return Ok((indices, vec![(None, all)]));
    };
    if m.of_triangle.len() != indices.len() {
        return Err(Error::InvalidArgument(format!(
            "{} triangles but materials for {}",
            indices.len(),
            m.of_triangle.len()
        )));
    }
    if let Some(t) = m
        .of_triangle
        .iter()
        .position(|&i| i as usize >= m.materials.len())
    {
        return Err(Error::InvalidTriangle {
            triangle: t,
            message: format!(
                "triangle {t} has material {}, of {} materials",
                m.of_triangle[t],
                m.materials.len()
            ),
        });
    }
    if let Some(mat) = m
        .materials
        .iter()
        .find(|mat| mat.image.is_some_and(|i| i >= m.images.len()))
    {
        return Err(Error::InvalidArgument(format!(
            "material `{}` has an image index past the {} images",
            mat.name,
            m.images.len()
        )));
    }
    // A counting sort: the triangles of each material in their order.
    let mut start = vec![0usize; m.materials.len() + 1];
    for &i in m.of_triangle {
        start[i as usize + 1] += 1;
    }
    for i in 0..m.materials.len() {
        start[i + 1] += start[i];
    }
    let primitives = (0..m.materials.len())
        .filter(|&i| start[i + 1] > start[i])
        .map(|i| (Some(i as u32), start[i]..start[i + 1]))
        .collect();
    let mut next = start;
    let mut sorted = vec![[0; 3]; indices.len()];
    for (tri, &i) in indices.into_iter().zip(m.of_triangle) {
        sorted[next[i as usize]] = tri;
        next[i as usize] += 1;
    }
    Ok((sorted, primitives))
}

/// Writes `f32`s little-endian through a buffer.
fn write_f32s(w: &mut dyn Write, values: impl Iterator<Item = f32>) -> std::io::Result<()> {
    let mut buf = Vec::with_capacity(1 << 16);
    for x in values {
        buf.extend_from_slice(&x.to_le_bytes());
        if buf.len() >= 1 << 16 {
            w.write_all(&buf)?;
            buf.clear();
        }
    }
    w.write_all(&buf)
}

/// Per-coordinate minimum and maximum of `f32` vectors.
fn bounds_of(values: &[[f32; 3]]) -> ([f32; 3], [f32; 3]) {
    values.iter().fold(
        ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]),
        |(lo, hi), p| {
            (
                std::array::from_fn(|k| lo[k].min(p[k])),
                std::array::from_fn(|k| hi[k].max(p[k])),
            )
        },
    )
}

/// An accessor of tightly packed data at the start of a buffer view.
fn accessor(
    view: json::Index<json::buffer::View>,
    count: u64,
    component: json::accessor::ComponentType,
    kind: json::accessor::Type,
    bounds: Option<(Vec<f32>, Vec<f32>)>,
) -> json::Accessor {
    let (min, max) = match bounds {
        Some((lo, hi)) => (Some(json::Value::from(lo)), Some(json::Value::from(hi))),
        None => (None, None),
    };
    json::Accessor {
        buffer_view: Some(view),
        byte_offset: None,
        count: USize64(count),
        component_type: Valid(json::accessor::GenericComponentType(component)),
        extensions: None,
        extras: None,
        type_: Valid(kind),
        min,
        max,
        name: None,
        normalized: false,
        sparse: None,
    }
}

/// Unit vertex normals for the glTF vertices: +z for planar meshes, in
/// space the triangle normals each weighing its angle at the vertex, as
/// Blender computes them (+z where they cancel out); with normal `groups`
/// (the triangle corners' and each glTF vertex's), over the corners of the
/// vertex's group only, so hard edges stay hard. With `only`, from those
/// triangles alone: right at the vertices all of whose triangles they are.
fn gltf_normals<const D: usize>(
    positions: &[[f64; D]],
    triangles: &[[u32; 3]],
    original: &[u32],
    groups: &Option<(Vec<[u32; 3]>, Vec<u32>)>,
    only: Option<&[u32]>,
) -> Vec<[f32; 3]> {
    if D != 3 {
        return vec![[0.0, 0.0, 1.0]; original.len()];
    }
    let space: Vec<[f64; 3]> = positions.iter().map(xyz).collect();
    // The triangles used, by their number in `triangles`.
    let used: Vec<usize> = match only {
        Some(only) => only.iter().map(|&t| t as usize).collect(),
        None => (0..triangles.len()).collect(),
    };
    let corners: Vec<[u32; 3]> = used.iter().map(|&t| triangles[t]).collect();
    let unit = |n: [f64; 3]| {
        if n == [0.0; 3] {
            [0.0, 0.0, 1.0]
        } else {
            let m = n.map(|x| x as f32);
            let len = (m[0] * m[0] + m[1] * m[1] + m[2] * m[2]).sqrt();
            m.map(|x| x / len)
        }
    };
    match groups {
        Some((corner_groups, vertex_group)) => {
            let count = vertex_group.iter().max().map_or(0, |&g| g as usize + 1);
            let normals = angle_weighted_normals(&space, &corners, count, |t, k| {
                corner_groups[used[t]][k] as usize
            });
            vertex_group
                .iter()
                .map(|&g| unit(normals[g as usize]))
                .collect()
        }
        None => {
            let normals = angle_weighted_vertex_normals(&space, &corners);
            original
                .iter()
                .map(|&v| unit(normals[v as usize]))
                .collect()
        }
    }
}

/// Refuses a base mesh whose coordinates are not finite or whose triangles
/// point past its vertices.
fn check_positions<const D: usize>(
    positions: &[[f64; D]],
    triangles: &[[u32; 3]],
    what: &str,
) -> Result<()> {
    check_finite(positions, what)?;
    if triangles.is_empty() {
        return Err(Error::InvalidMesh(format!("{what} has no triangles")));
    }
    let n = positions.len();
    if let Some(t) = triangles
        .iter()
        .position(|t| t.iter().any(|&i| i as usize >= n))
    {
        return Err(Error::InvalidTriangle {
            triangle: t,
            message: format!(
                "{what}: triangle {t} {:?} uses a vertex index out of range (the mesh has {n} vertices)",
                triangles[t]
            ),
        });
    }
    Ok(())
}

/// glTF's vertices and what each carries.
struct Split {
    /// glTF vertex → original vertex.
    original: Vec<u32>,
    /// Triangles in glTF vertices.
    indices: Vec<[u32; 3]>,
    /// Texture coordinates per glTF vertex (glTF's v down).
    uvs: Option<Vec<[f32; 2]>>,
    /// Colours per glTF vertex.
    colors: Option<Vec<[f32; 4]>>,
    /// With normals per corner: the normal group of each triangle corner
    /// (the corners of one vertex that share a normal) and of each glTF
    /// vertex.
    groups: Option<(Vec<[u32; 3]>, Vec<u32>)>,
}

/// Refuses values per triangle corner (`what`) that are not one per corner
/// of `triangles` triangles, or not finite.
fn check_corners<const N: usize>(
    values: Option<&[[[f32; N]; 3]]>,
    triangles: usize,
    what: &str,
) -> Result<()> {
    let Some(values) = values else {
        return Ok(());
    };
    if values.len() != triangles {
        return Err(Error::InvalidArgument(format!(
            "{triangles} triangles but {what} for {}",
            values.len()
        )));
    }
    if let Some(t) = values
        .iter()
        .position(|c| c.iter().flatten().any(|x| !x.is_finite()))
    {
        return Err(Error::InvalidTriangle {
            triangle: t,
            message: format!(
                "triangle {t}'s {what} are not finite numbers: {:?}",
                values[t]
            ),
        });
    }
    Ok(())
}

/// What a triangle corner carries to its glTF vertex: texture coordinates,
/// colour, normal group.
type Corner = ([f32; 2], [f32; 4], u32);
/// A [`Corner`] compared bit for bit.
type CornerKey = ([u32; 2], [u32; 4], u32);

/// glTF's vertices: one per used original vertex and distinct pair of
/// texture coordinates and normal group of its corners, original vertices
/// first (in order, each with its first corner's), further pairs after.
fn split_vertices<const D: usize>(base: &GltfBase<'_, D>) -> Result<Split> {
    let n = base.positions.len();
    check_corners(base.corner_uvs, base.triangles.len(), "texture coordinates")?;
    check_corners(base.corner_colors, base.triangles.len(), "colours")?;
    // The corners of one vertex that share a normal are one group: the
    // groups are numbered afresh per (vertex, group).
    let corner_groups: Option<Vec<[u32; 3]>> = match base.corner_normal_groups {
        None => None,
        Some(groups) if groups.len() != base.triangles.len() => {
            return Err(Error::InvalidArgument(format!(
                "{} triangles but normal groups for {}",
                base.triangles.len(),
                groups.len()
            )))
        }
        Some(groups) => {
            let mut ids: HashMap<(u32, u32), u32> = HashMap::new();
            Some(
                base.triangles
                    .iter()
                    .zip(groups)
                    .map(|(t, g)| {
                        std::array::from_fn(|k| {
                            let next = ids.len() as u32;
                            *ids.entry((t[k], g[k])).or_insert(next)
                        })
                    })
                    .collect(),
            )
        }
    };
    // glTF's v runs down the image, OBJ's up.
    let corner = |t: usize, k: usize| -> Corner {
        let uv = base
            .corner_uvs
            .map_or([0.0; 2], |c| [c[t][k][0], 1.0 - c[t][k][1]]);
        let color = base.corner_colors.map_or([0.0; 4], |c| c[t][k]);
        (uv, color, corner_groups.as_ref().map_or(0, |g| g[t][k]))
    };
    let key = |(uv, color, g): Corner| (uv.map(f32::to_bits), color.map(f32::to_bits), g);
    let mut first: Vec<Option<Corner>> = vec![None; n];
    for (t, tri) in base.triangles.iter().enumerate() {
        for k in 0..3 {
            first[tri[k] as usize].get_or_insert(corner(t, k));
        }
    }
    let mut new_index = vec![u32::MAX; n];
    let mut original = Vec::with_capacity(n);
    let mut attributes = Vec::with_capacity(n);
    for v in 0..n {
        if let Some(a) = first[v] {
            new_index[v] = original.len() as u32;
            original.push(v as u32);
            attributes.push(a);
        }
    }
    let mut extra: HashMap<(u32, CornerKey), u32> = HashMap::new();
    let indices = base
        .triangles
        .iter()
        .enumerate()
        .map(|(t, tri)| {
            std::array::from_fn(|k| {
                let v = tri[k];
                let a = corner(t, k);
                let own = new_index[v as usize];
                if key(attributes[own as usize]) == key(a) {
                    return own;
                }
                *extra.entry((v, key(a))).or_insert_with(|| {
                    original.push(v);
                    attributes.push(a);
                    (original.len() - 1) as u32
                })
            })
        })
        .collect();
    Ok(Split {
        original,
        indices,
        uvs: base
            .corner_uvs
            .map(|_| attributes.iter().map(|a| a.0).collect()),
        colors: base
            .corner_colors
            .map(|_| attributes.iter().map(|a| a.1).collect()),
        groups: corner_groups.map(|g| (g, attributes.iter().map(|a| a.2).collect())),
    })
}
