//! How a mesh file looks, for a GLB made from it: its texture coordinates,
//! its hard edges, and its OBJ materials with their colours and colour
//! textures, so that a result opens in Blender or three.js looking like the
//! asset it came from.

use std::path::{Path, PathBuf};

use super::gltf::{GltfBase, GltfImage, GltfMaterial, GltfMaterials};
use super::mtl::{read_mtl, MtlMaterial};
use super::read::{human_bytes, Limit};
use super::MeshFile;
use crate::error::{Error, Result};

/// The colour of faces without a material, or with one no library defines:
/// the grey Blender shows them in.
const NO_MATERIAL_GREY: [f32; 4] = [0.8, 0.8, 0.8, 1.0];

/// What a GLB keeps of a mesh file's looks: its texture coordinates, its
/// hard edges, and its OBJ materials with their colours and colour
/// textures; [`Appearance::base`] hands them to the writer.
#[derive(Clone, Debug, Default)]
pub struct Appearance {
    /// Texture coordinates per triangle corner, when every corner has them.
    pub corner_uvs: Option<Vec<[[f32; 2]; 3]>>,
    /// Which triangle corners share a normal (which edges are hard).
    pub corner_normal_groups: Option<Vec<[u32; 3]>>,
    /// Linear RGBA per triangle corner, from the file's vertex colours
    /// (sRGB).
    pub corner_colors: Option<Vec<[[f32; 4]; 3]>>,
    /// The materials of the triangles (empty when the file names none).
    pub materials: Vec<GltfMaterial>,
    /// The images of the materials' colour textures.
    pub images: Vec<GltfImage>,
    /// Per triangle, an index into `materials` (empty without materials).
    pub of_triangle: Vec<u32>,
    /// What could not be carried: a library or texture that cannot be
    /// read, a material no library defines, what the file holds that a GLB
    /// made from it does not (groups, objects, colours, ...).
    pub warnings: Vec<String>,
}

impl Appearance {
    /// What of `file`'s looks is given per triangle corner (texture
    /// coordinates, hard edges, colours), without reading its materials:
    /// all that decides the GLB's vertices
    /// ([`vertex_count`](super::gltf::vertex_count)).
    pub fn of_corners(file: &MeshFile) -> Self {
        Appearance {
            corner_uvs: file.triangle_corner_uvs(),
            corner_normal_groups: file.triangle_corner_normal_groups(),
            corner_colors: file.triangle_corner_colors().map(|c| {
                c.iter()
                    .map(|corners| corners.map(|[r, g, b, a]| [linear(r), linear(g), linear(b), a]))
                    .collect()
            }),
            ..Default::default()
        }
    }

    /// The looks of `file`, reading its material libraries and their
    /// colour textures (PNG or JPEG, embedded as they are), which may take
    /// `max_image_bytes` together (what the GLB may still take besides its
    /// mesh: see [`Appearance::texture_bytes`]). A library or a texture
    /// that cannot be read (missing, not a regular file, ...) is left out
    /// with a warning.
    ///
    /// # Errors
    /// [`Error::FileRefused`] naming the texture that brings the images
    /// past `max_image_bytes`: its size says so before it is read, or it
    /// grows past them while it is read.
    pub fn of_file(file: &MeshFile, max_image_bytes: u64) -> Result<Self> {
        let mut look = Self::of_corners(file);
        if let Some((names, of_triangle)) = file.triangle_materials() {
            look.add_materials(file, names, &of_triangle, max_image_bytes)?;
        }
        let dropped: Vec<&str> = file
            .extras()
            .iter()
            .map(String::as_str)
            .filter(|e| {
                // Smoothing groups carry as the shading they give (flat
                // faces stay flat).
                let carried = e.starts_with("texture coordinates")
                    || e.starts_with("normals")
                    || e.starts_with("smoothing groups")
                    || (*e == "vertex colours" && look.corner_colors.is_some())
                    || (e.starts_with("materials") && !look.materials.is_empty());
                !carried
            })
            .collect();
        if !dropped.is_empty() {
            look.warnings.push(format!(
                "a GLB holds one mesh with its texture coordinates, normals computed from its shape (hard edges kept), materials and vertex colours: the {} of `{}` are not in it",
                dropped.join(", "),
                file.path().display()
            ));
        }
        Ok(look)
    }

    /// The bytes of the colour textures that [`Appearance::of_file`] would
    /// embed in a GLB of `file`, from their sizes (nothing is read of them;
    /// the material libraries are read): to count them against a limit on
    /// the GLB before any work. Textures that cannot be read count 0 (they
    /// are left out).
    pub fn texture_bytes(file: &MeshFile) -> u64 {
        if file.triangle_corner_uvs().is_none() {
            return 0;
        }
        let Some((names, of_triangle)) = file.triangle_materials() else {
            return 0;
        };
        let defined: Vec<MtlMaterial> = file
            .material_libraries()
            .iter()
            .filter_map(|library| read_mtl(library).ok())
            .flatten()
            .collect();
        let mut textures: Vec<&Path> = of_triangle
            .iter()
            .flatten()
            .filter_map(|&m| defined.iter().find(|d| d.name == names[m as usize]))
            .filter_map(|d| d.diffuse_map.as_deref())
            .collect();
        textures.sort_unstable();
        textures.dedup();
        textures
            .iter()
            .filter_map(|path| super::read::open(path).ok())
            .map(|input| input.len())
            .fold(0, u64::saturating_add)
    }

    /// The base mesh of a GLB with these looks.
    pub fn base<'a, const D: usize>(
        &'a self,
        positions: &'a [[f64; D]],
        triangles: &'a [[u32; 3]],
    ) -> GltfBase<'a, D> {
        let mut base = GltfBase::new(positions, triangles);
        if let Some(uvs) = &self.corner_uvs {
            base = base.with_corner_uvs(uvs);
        }
        if let Some(groups) = &self.corner_normal_groups {
            base = base.with_corner_normal_groups(groups);
        }
        if let Some(colors) = &self.corner_colors {
            base = base.with_corner_colors(colors);
        }
        if !self.materials.is_empty() {
            base = base.with_materials(GltfMaterials {
                materials: &self.materials,
                images: &self.images,
                of_triangle: &self.of_triangle,
            });
        }
        base
    }

    /// The materials `names` that faces use, from the file's libraries, and
    /// each triangle's; faces before any `usemtl` take a grey material of
    /// their own.
    fn add_materials(
        &mut self,
        file: &MeshFile,
        names: &[String],
        of_triangle: &[Option<u32>],
        max_image_bytes: u64,
    ) -> Result<()> {
        let mut images_left = max_image_bytes;
        let mut defined: Vec<MtlMaterial> = Vec::new();
        let libraries = file.material_libraries();
        for library in &libraries {
            match read_mtl(library) {
                Ok(materials) => defined.extend(materials),
                Err(e) => self.warnings.push(format!(
                    "the materials of `{}` are not in the GLB: {e}",
                    file.path().display(),
                )),
            }
        }
        let mut image_paths: Vec<PathBuf> = Vec::new();
        // Only the materials some face uses (a `usemtl` before no face
        // names none), numbered afresh.
        let mut used = vec![false; names.len()];
        for &m in of_triangle.iter().flatten() {
            used[m as usize] = true;
        }
        let mut index_of = vec![0u32; names.len()];
        for (name, k) in names.iter().zip(0..) {
            if !used[k] {
                continue;
            }
            index_of[k] = self.materials.len() as u32;
            let material = match defined.iter().find(|m| &m.name == name) {
                Some(m) => self.material_of(m, file.path(), &mut image_paths, &mut images_left)?,
                None => {
                    if libraries.is_empty() || !defined.is_empty() {
                        self.warnings.push(format!(
                            "material `{name}` of `{}` is defined in no material library it names: grey in the GLB",
                            file.path().display()
                        ));
                    }
                    grey(name)
                }
            };
            self.materials.push(material);
        }
        let unnamed = self.materials.len() as u32;
        if of_triangle.iter().any(Option::is_none) {
            self.materials.push(grey("none"));
        }
        self.of_triangle = of_triangle
            .iter()
            .map(|m| m.map_or(unnamed, |m| index_of[m as usize]))
            .collect();
        Ok(())
    }

    /// A GLB material of an MTL one, its colour texture read once per file
    /// (taking its bytes from `images_left`).
    fn material_of(
        &mut self,
        m: &MtlMaterial,
        obj: &Path,
        image_paths: &mut Vec<PathBuf>,
        images_left: &mut u64,
    ) -> Result<GltfMaterial> {
        let mut image = None;
        if let Some(path) = &m.diffuse_map {
            if self.corner_uvs.is_none() {
                self.warnings.push(format!(
                    "the texture `{}` of material `{}` is not in the GLB: `{}` has no texture coordinates on every face",
                    path.display(),
                    m.name,
                    obj.display()
                ));
            } else if let Some(i) = image_paths.iter().position(|p| p == path) {
                image = Some(i);
            } else {
                match read_texture(path, &m.name, images_left)? {
                    Ok(Some(img)) => {
                        self.images.push(img);
                        image_paths.push(path.clone());
                        image = Some(self.images.len() - 1);
                    }
                    Ok(None) => self.warnings.push(format!(
                        "the texture `{}` of material `{}` is not in the GLB: glTF holds PNG and JPEG images only",
                        path.display(),
                        m.name
                    )),
                    Err(e) => self.warnings.push(format!(
                        "the texture `{}` of material `{}` is not in the GLB: {}",
                        path.display(),
                        m.name,
                        without_path(&e)
                    )),
                }
            }
        }
        // With a texture, the texture is the colour (as Blender's importer
        // shows it), kept translucent by the opacity.
        let [r, g, b] = if image.is_some() { [1.0; 3] } else { m.diffuse };
        Ok(GltfMaterial {
            name: m.name.clone(),
            base_color: [r, g, b, m.opacity],
            metallic: m.metallic.unwrap_or(0.0),
            roughness: m.roughness.unwrap_or(0.5),
            image,
        })
    }
}

/// The texture at `path` (of the material `material`) as an image, taking
/// its bytes from `left`: `Ok(Err(e))` when it cannot be read (left out
/// with a warning), `Ok(Ok(None))` when it is no PNG or JPEG.
///
/// # Errors
/// [`Error::FileRefused`] when it holds more than `left` bytes.
fn read_texture(
    path: &Path,
    material: &str,
    left: &mut u64,
) -> Result<std::result::Result<Option<GltfImage>, Error>> {
    let input = match super::read::open(path) {
        Ok(input) => input,
        Err(e) => return Ok(Err(e)),
    };
    let limit = Limit {
        bytes: *left,
        why: format!(
            "the {} left for the images of the GLB (the texture of material `{material}`)",
            human_bytes(*left)
        ),
    };
    let bytes = match input.read_to_end(&limit) {
        Ok(bytes) => bytes,
        Err(e @ Error::FileRefused { .. }) => return Err(e),
        Err(e) => return Ok(Err(e)),
    };
    *left -= bytes.len() as u64;
    Ok(Ok(GltfImage::from_bytes(bytes)))
}

/// What `e`, an error reading a file named beside it, says of it.
fn without_path(e: &Error) -> String {
    match e {
        Error::Io { error, .. } => error.to_string(),
        Error::FileRefused { message, .. } => message.clone(),
        other => other.to_string(),
    }
}

/// An sRGB-encoded colour channel (0 to 1), linear.
fn linear(c: f32) -> f32 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// A grey material named `name`.
fn grey(name: &str) -> GltfMaterial {
    GltfMaterial {
        name: name.to_string(),
        base_color: NO_MATERIAL_GREY,
        metallic: 0.0,
        roughness: 0.5,
        image: None,
    }
}
