//! Material libraries of OBJ files (`.mtl`): what a viewer needs to show a
//! material, read so that a GLB can carry the materials of the OBJ it comes
//! from.
//!
//! Read per `newmtl`: the diffuse colour `Kd`, the opacity `d` (or `Tr`,
//! its complement), the diffuse texture `map_Kd` (with its options skipped),
//! and the physically based `Pr` (roughness) and `Pm` (metallic) that
//! Blender and other tools write; without `Pr`, the roughness follows from
//! the specular exponent `Ns` as Blender's importer converts it
//! (`1 − √(Ns / 1000)`). Every other statement is ignored: a material
//! library describes looks, and nothing in it changes a shape.

use std::path::{Path, PathBuf};

use crate::error::{Error, Result};

/// One material of a library.
#[derive(Clone, Debug, PartialEq)]
pub struct MtlMaterial {
    /// Its name (`newmtl`).
    pub name: String,
    /// Diffuse colour `Kd` (linear RGB). Default white.
    pub diffuse: [f32; 3],
    /// Opacity: `d`, or `1 − Tr`. Default 1.
    pub opacity: f32,
    /// Roughness from `Pr`, or from `Ns`; `None` when the file gives
    /// neither.
    pub roughness: Option<f32>,
    /// Metallic from `Pm`; `None` when not given.
    pub metallic: Option<f32>,
    /// The diffuse texture (`map_Kd`) as written in the file, resolved
    /// from the library's folder when relative.
    pub diffuse_map: Option<PathBuf>,
}

impl MtlMaterial {
    fn named(name: String) -> Self {
        MtlMaterial {
            name,
            diffuse: [1.0; 3],
            opacity: 1.0,
            roughness: None,
            metallic: None,
            diffuse_map: None,
        }
    }
}

/// Reads the material library at `path`.
///
/// # Errors
/// [`Error::Io`] when it cannot be read; [`Error::FileRefused`] when it is
/// not a regular file or holds more than
/// [`MAX_MATERIAL_LIBRARY_BYTES`](super::read::MAX_MATERIAL_LIBRARY_BYTES);
/// [`Error::Parse`] naming the line when a number of a statement read here
/// is not a number.
pub fn read_mtl(path: &Path) -> Result<Vec<MtlMaterial>> {
    parse_mtl(&read_text(path)?, path)
}

/// The text of the material library at `path` (bytes that are not UTF-8
/// replaced), read through the bounded reads: a regular file of at most
/// 64 MiB.
pub(crate) fn read_text(path: &Path) -> Result<String> {
    let limit = super::read::Limit {
        bytes: super::read::MAX_MATERIAL_LIBRARY_BYTES,
        why: "the 64 MiB a material library may hold".to_string(),
    };
    let bytes = super::read::read_file(path, &limit)?;
    Ok(String::from_utf8_lossy(&bytes).into_owned())
}

/// Parses a material library's text; `path` names it in messages, and
/// relative texture paths are resolved from its folder.
///
/// # Errors
/// As [`read_mtl`].
pub fn parse_mtl(text: &str, path: &Path) -> Result<Vec<MtlMaterial>> {
    let folder = path.parent().unwrap_or(Path::new(""));
    let mut materials: Vec<MtlMaterial> = Vec::new();
    // Whether each material has its own `Pr`, which `Ns` then does not
    // override.
    let mut has_pr: Vec<bool> = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let line_no = i + 1;
        let line = line.split('#').next().unwrap_or("").trim();
        let Some((keyword, rest)) = split_keyword(line) else {
            continue;
        };
        let err = |message: String| Error::Parse {
            path: path.to_path_buf(),
            line: Some(line_no),
            message,
        };
        if keyword == "newmtl" {
            materials.push(MtlMaterial::named(rest.to_string()));
            has_pr.push(false);
            continue;
        }
        let Some(material) = materials.last_mut() else {
            continue;
        };
        let numbers = |count: usize| -> Result<Vec<f32>> {
            let values: Vec<f32> = rest
                .split_whitespace()
                .take(count)
                .map(|t| t.parse::<f32>().ok().filter(|x| x.is_finite()))
                .collect::<Option<_>>()
                .ok_or_else(|| err(format!("`{keyword}` takes numbers, found `{rest}`")))?;
            if values.is_empty() {
                return Err(err(format!("`{keyword}` needs a number")));
            }
            Ok(values)
        };
        match keyword {
            "Kd" => {
                // `Kd spectral ...` and `Kd xyz ...` are not colours read here.
                if rest.starts_with("spectral") || rest.starts_with("xyz") {
                    continue;
                }
                let v = numbers(3)?;
                // One number is a grey.
                material.diffuse = [v[0], *v.get(1).unwrap_or(&v[0]), *v.get(2).unwrap_or(&v[0])]
                    .map(|x| x.clamp(0.0, 1.0));
            }
            "d" => {
                // `d -halo f`: the halo form is read as its factor.
                let rest = rest.strip_prefix("-halo").unwrap_or(rest).trim();
                if let Some(v) = rest.split_whitespace().next() {
                    let d: f32 = v
                        .parse()
                        .ok()
                        .filter(|x: &f32| x.is_finite())
                        .ok_or_else(|| err(format!("`d` takes a number, found `{rest}`")))?;
                    material.opacity = d.clamp(0.0, 1.0);
                }
            }
            "Tr" => material.opacity = (1.0 - numbers(1)?[0]).clamp(0.0, 1.0),
            "Pr" => {
                material.roughness = Some(numbers(1)?[0].clamp(0.0, 1.0));
                *has_pr.last_mut().expect("one per material") = true;
            }
            "Pm" => material.metallic = Some(numbers(1)?[0].clamp(0.0, 1.0)),
            // `Pr`, when the material has it, wins over `Ns`.
            "Ns" if !has_pr.last().expect("one per material") => {
                let ns = numbers(1)?[0].clamp(0.0, 1000.0);
                material.roughness = Some(1.0 - (ns / 1000.0).sqrt());
            }
            "map_Kd" => {
                let file = texture_file(rest);
                if !file.is_empty() {
                    let file = Path::new(&file);
                    material.diffuse_map = Some(if file.is_absolute() {
                        file.to_path_buf()
                    } else {
                        folder.join(file)
                    });
                }
            }
            _ => {}
        }
    }
    Ok(materials)
}

/// Every file a material library's text names (`map_Kd` and the other
/// texture maps, `bump`, `disp`, `decal`, `refl`), resolved from the
/// folder of `path` when relative: the files an output that keeps the
/// library refers to, so that a run never writes over one.
pub fn named_files(text: &str, path: &Path) -> Vec<PathBuf> {
    let folder = path.parent().unwrap_or(Path::new(""));
    let mut files: Vec<PathBuf> = Vec::new();
    for line in text.lines() {
        let line = line.split('#').next().unwrap_or("").trim();
        let Some((keyword, rest)) = split_keyword(line) else {
            continue;
        };
        let names_file =
            keyword.starts_with("map_") || matches!(keyword, "bump" | "disp" | "decal" | "refl");
        let file = if names_file {
            texture_file(rest)
        } else {
            String::new()
        };
        if !file.is_empty() {
            let file = folder.join(file);
            if !files.contains(&file) {
                files.push(file);
            }
        }
    }
    files
}

/// The keyword of a statement and the rest of the line, trimmed.
fn split_keyword(line: &str) -> Option<(&str, &str)> {
    if line.is_empty() {
        return None;
    }
    Some(match line.split_once(char::is_whitespace) {
        Some((k, rest)) => (k, rest.trim()),
        None => (line, ""),
    })
}

/// The file name of a texture statement: the text after its options
/// (`-o 0 0 0`, `-bm 1`, `-clamp on`, ...), which may hold spaces.
pub fn texture_file(rest: &str) -> String {
    let tokens: Vec<&str> = rest.split_whitespace().collect();
    let mut i = 0;
    while i < tokens.len() && tokens[i].starts_with('-') {
        let option = tokens[i];
        i += 1;
        // Options with up to three numbers (`-o`, `-s`, `-t`), two (`-mm`)
        // or one argument.
        let (least, most) = match option {
            "-o" | "-s" | "-t" => (1, 3),
            "-mm" => (2, 2),
            _ => (1, 1),
        };
        let mut taken = 0;
        while taken < most && i < tokens.len() {
            let numeric = tokens[i].parse::<f64>().is_ok();
            if taken >= least && !numeric {
                break;
            }
            i += 1;
            taken += 1;
        }
    }
    tokens[i.min(tokens.len())..].join(" ")
}
