//! `--gltf FILE.glb`: every frame or pose in one binary glTF file.

use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};
use meshmorph::io::gltf::{estimate_glb_bytes, write_glb, GltfBase, GltfOptions};

use crate::output::positive_number;

/// Options of the glTF output.
#[derive(Debug, Clone, clap::Args)]
pub struct GltfArgs {
    /// Also write one binary glTF (FILE.glb) for Blender, three.js or any
    /// glTF viewer: the base mesh with every frame as a morph target and an
    /// animation playing them at --fps. It weighs about 24 bytes x vertices x
    /// frames (12 for planar meshes): a 10,000-vertex mesh in space with 100
    /// frames makes 24 MB.
    #[arg(long, value_name = "FILE.glb")]
    pub gltf: Option<PathBuf>,
    /// Refuse to write a GLB heavier than this many megabytes (10^6 bytes).
    #[arg(long, default_value_t = 256.0, value_name = "MB", value_parser = positive_number)]
    pub max_gltf_mb: f64,
}

impl GltfArgs {
    /// Refuses, before any work, a GLB path that is not `.glb` or a file
    /// that would weigh more than `--max-gltf-mb`.
    pub fn check<const D: usize>(
        &self,
        vertices: usize,
        triangles: usize,
        frames: usize,
        uvs: bool,
    ) -> Result<()> {
        let Some(path) = &self.gltf else {
            return Ok(());
        };
        let glb = path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("glb"));
        if !glb {
            bail!(
                "--gltf `{}`: the file is binary glTF; name it with the extension .glb",
                path.display()
            );
        }
        let bytes = estimate_glb_bytes::<D>(vertices, triangles, frames, uvs);
        let mb = bytes as f64 / 1e6;
        if mb > self.max_gltf_mb {
            bail!(
                "--gltf `{}` would weigh about {mb:.0} MB ({frames} frames x {vertices} vertices x {} bytes, \
                 plus the base mesh), over the limit of {} MB: write fewer frames, or raise the limit \
                 with --max-gltf-mb {}",
                path.display(),
                if D == 3 { 24 } else { 12 },
                self.max_gltf_mb,
                mb.ceil()
            );
        }
        Ok(())
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
        write_glb(path, base, frames, names, options)
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
