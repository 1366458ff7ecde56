//! `--gltf FILE.glb`: every frame or pose in one binary glTF file.

use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};
use meshmorph::io::gltf::{
    estimate_glb_bytes, vertex_count, write_glb, write_shape_keys, GltfBase, GltfDocument,
    GltfMesh, GltfOptions, NewShape, ShapeKeyOptions,
};
use meshmorph::io::{Appearance, MeshFile};
use meshmorph::Mesh3;

use crate::output::positive_number;
use crate::outputs::{Output, Staging};
use crate::pictures::file_named;

/// A `.glb` path, or `.vrm` and `.gltf` for a transfer into a glTF target
/// of that kind (a clap value parser).
fn glb_file(text: &str) -> Result<PathBuf, String> {
    let path = PathBuf::from(text);
    if is_gltf(&path) {
        Ok(path)
    } else {
        file_named(text, "glb", "binary glTF")
    }
}

/// Whether `path` names a glTF file (`.glb`, `.gltf` or `.vrm`).
pub fn is_gltf(path: &Path) -> bool {
    path.extension().is_some_and(|e| {
        ["glb", "gltf", "vrm"]
            .iter()
            .any(|g| e.eq_ignore_ascii_case(g))
    })
}

/// Options of the glTF output.
#[derive(Debug, Clone, clap::Args)]
pub struct GltfArgs {
    /// Also write one binary glTF (FILE.glb) for Blender, three.js or any
    /// glTF viewer: the base mesh with every frame as a morph target and an
    /// animation playing them at --fps. It weighs about 24 bytes x vertices x
    /// frames (12 for planar meshes): a 10,000-vertex mesh in space with 100
    /// frames makes 24 MB.
    #[arg(long, value_name = "FILE.glb", value_parser = glb_file)]
    pub gltf: Option<PathBuf>,
    /// Refuse to write a GLB heavier than this many megabytes (10^6 bytes).
    #[arg(long, default_value_t = 256.0, value_name = "MB", value_parser = positive_number)]
    pub max_gltf_mb: f64,
    /// With --gltf: store positions and their deltas as 16-bit integers
    /// (KHR_mesh_quantization), a third smaller, each coordinate within
    /// 1/32767 of the mesh's half-size plus its largest move.
    #[arg(long, requires = "gltf")]
    pub gltf_quantize: bool,
    /// With --gltf: store every morph target densely, for tools that do
    /// not read glTF's sparse accessors (by default a target is stored
    /// sparsely, only the vertices it moves, when that is smaller).
    #[arg(long, requires = "gltf")]
    pub gltf_dense: bool,
}

impl GltfArgs {
    /// Refuses, before any work, a GLB that would weigh more than
    /// `--max-gltf-mb`: `frames` frames of `mesh` (read from `file`, whose
    /// texture coordinates, hard edges and colours split its vertices in
    /// the GLB as they will be written, and whose colour textures it
    /// embeds), with `D` coordinates. Returns the bytes the textures may
    /// take when they are read ([`Appearance::of_file`]): the limit less
    /// the rest of the file, so that a texture that grows in the meantime
    /// is refused too.
    pub fn check<const D: usize>(
        &self,
        file: Option<&MeshFile>,
        mesh: &Mesh3,
        frames: usize,
    ) -> Result<u64> {
        self.check_targets::<D>(file, mesh, frames, "frames", "write fewer frames, ")
    }

    /// [`GltfArgs::check`] for `count` morph targets that the refusal calls
    /// `what` (frames, shapes), with `advice` on how to make fewer of them
    /// (ending in a comma and a space; empty where there is no way).
    pub fn check_targets<const D: usize>(
        &self,
        file: Option<&MeshFile>,
        mesh: &Mesh3,
        count: usize,
        what: &str,
        advice: &str,
    ) -> Result<u64> {
        let Some(path) = &self.gltf else {
            return Ok(0);
        };
        // The corners decide the vertices; the materials need not be read.
        let look = file.map(Appearance::of_corners).unwrap_or_default();
        let base = look.base(mesh.positions(), mesh.triangles());
        let vertices = vertex_count(&base)?;
        let bytes = estimate_glb_bytes::<D>(
            vertices,
            mesh.num_triangles(),
            count,
            base.corner_uvs.is_some(),
        );
        let textures = file.map_or(0, Appearance::texture_bytes);
        let total = bytes.saturating_add(textures);
        let mb = total as f64 / 1e6;
        if mb > self.max_gltf_mb {
            let (texture_part, smaller) = if textures > 0 {
                (
                    format!(", and {:.0} MB of textures", textures as f64 / 1e6),
                    "use smaller textures, ",
                )
            } else {
                (String::new(), "")
            };
            bail!(
                "`{}` would weigh about {mb:.0} MB ({count} {what} x {vertices} vertices x {} bytes, \
                 plus the base mesh{texture_part}), over the limit of {} MB: {advice}{smaller}or raise the limit \
                 with --max-gltf-mb {}",
                path.display(),
                if D == 3 { 24 } else { 12 },
                self.max_gltf_mb,
                mb.ceil()
            );
        }
        Ok(self.max_bytes().saturating_sub(bytes))
    }

    /// `options` with the storage asked for (--gltf-quantize, --gltf-dense).
    pub fn options(&self, options: GltfOptions) -> GltfOptions {
        options
            .with_quantize(self.gltf_quantize)
            .with_sparse(!self.gltf_dense)
    }

    /// `--max-gltf-mb` in bytes.
    fn max_bytes(&self) -> u64 {
        (self.max_gltf_mb * 1e6) as u64
    }

    /// Writes the GLB asked for, if any, and returns its path.
    pub fn write<const D: usize>(
        &self,
        base: &GltfBase<'_, D>,
        frames: &[impl AsRef<[[f64; D]]> + Sync],
        names: &[String],
        options: &GltfOptions,
    ) -> Result<Option<PathBuf>> {
        let Some(path) = &self.gltf else {
            return Ok(None);
        };
        write_glb(path, base, frames, names, &self.options(options.clone()))
            .with_context(|| format!("writing the glTF `{}`", path.display()))?;
        Ok(Some(path.clone()))
    }
}

/// A name for the mesh in the GLB: the file stem of `path`.
pub fn mesh_name(path: &Path) -> String {
    path.file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "meshmorph".to_string())
}

/// Writes to `output` a copy of the glTF file `source` (read as `doc`)
/// with the shapes `names` added to `mesh` as morph targets: `placed`,
/// one list of positions of the mesh's vertices a shape, in the scene (the
/// node's matrix applied), as the solvers had them.
pub fn write_shapes_into(
    staging: &Staging,
    output: Output,
    (source, doc, mesh): (&Path, &GltfDocument, &GltfMesh),
    names: &[String],
    placed: &[Vec<[f64; 3]>],
    options: &ShapeKeyOptions,
) -> Result<()> {
    let unplaced = placed
        .iter()
        .map(|p| {
            mesh.unplaced(p).with_context(|| {
                format!("mesh `{}`: its node's matrix cannot be inverted", mesh.name)
            })
        })
        .collect::<Result<Vec<_>>>()?;
    let shapes: Vec<NewShape<'_>> = names
        .iter()
        .zip(&unplaced)
        .map(|(name, positions)| NewShape { name, positions })
        .collect();
    staging.write(output, |path| {
        write_shape_keys(path, doc, mesh, &shapes, options)
            .with_context(|| format!("writing shape keys into a copy of `{}`", source.display()))?;
        Ok(())
    })
}
