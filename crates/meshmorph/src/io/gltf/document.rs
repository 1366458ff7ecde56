//! A glTF 2.0 file held whole: its JSON as it was (every member, known or
//! not) and its buffers, read from a GLB's binary chunk, from files beside
//! a `.gltf` or from `data:` URIs when first needed.

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use serde_json::Value;

use super::base64;
use crate::error::{Error, Result};
use crate::io::read::{read_file, Limit};

/// The four bytes that open a GLB.
pub const GLB_MAGIC: &[u8; 4] = b"glTF";
/// The type of a GLB's JSON chunk.
pub const CHUNK_JSON: u32 = 0x4E4F_534A;
/// The type of a GLB's binary chunk.
pub const CHUNK_BIN: u32 = 0x004E_4942;

/// How a glTF file holds its JSON.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum Container {
    /// Binary glTF (`.glb`, `.vrm`): a JSON chunk and a binary chunk, which
    /// is the buffer without a URI.
    Glb,
    /// JSON text (`.gltf`); buffers and images are files beside it or
    /// `data:` URIs.
    Json,
}

/// A glTF file as it was read: the JSON whole (so that what meshmorph does
/// not know survives a write back) and its buffers.
#[derive(Debug)]
pub struct GltfDocument {
    path: PathBuf,
    container: Container,
    json: Value,
    /// A GLB's binary chunk (the buffer without a URI).
    bin: Option<Vec<u8>>,
    /// Each buffer's bytes, loaded when first asked for.
    buffers: Vec<OnceLock<Vec<u8>>>,
}

impl GltfDocument {
    /// Reads a `.glb`, `.vrm` or `.gltf` file (told by its first bytes, not
    /// its name). Buffers are read when first needed.
    ///
    /// # Errors
    /// [`Error::Io`] or [`Error::FileRefused`] when the file cannot be
    /// read; [`Error::Parse`] naming the file when it is not glTF 2.0.
    pub fn read(path: &Path) -> Result<Self> {
        let bytes = read_file(path, &Limit::memory())?;
        Self::parse(bytes, path)
    }

    /// Parses a file's bytes; `path` names it in messages and places the
    /// files its URIs name.
    ///
    /// # Errors
    /// As [`GltfDocument::read`].
    pub fn parse(bytes: Vec<u8>, path: &Path) -> Result<Self> {
        let bad = |message: String| Error::parse(path, None, message);
        let (container, json_bytes, bin) = if bytes.starts_with(GLB_MAGIC) {
            let (json, bin) = split_glb(&bytes).map_err(bad)?;
            (Container::Glb, json, bin)
        } else {
            (Container::Json, &bytes[..], None)
        };
        let json: Value = serde_json::from_slice(json_bytes).map_err(|e| {
            bad(format!(
                "not glTF: neither a GLB (which starts with `glTF`) nor glTF JSON ({e})"
            ))
        })?;
        if !json.is_object() {
            return Err(bad("the glTF JSON is not an object".into()));
        }
        let version = json.pointer("/asset/version").and_then(Value::as_str);
        match version {
            Some(v) if v.starts_with("2.") => {}
            Some(v) => {
                return Err(bad(format!(
                    "glTF version {v}: only glTF 2.0 is read (convert the file, e.g. by opening it in Blender and exporting glTF 2.0)"
                )))
            }
            None => return Err(bad("no `asset.version`: not a glTF 2.0 file".into())),
        }
        let bin = bin.map(<[u8]>::to_vec);
        let count = json
            .get("buffers")
            .and_then(Value::as_array)
            .map_or(0, Vec::len);
        Ok(GltfDocument {
            path: path.to_path_buf(),
            container,
            json,
            bin,
            buffers: (0..count).map(|_| OnceLock::new()).collect(),
        })
    }

    /// The file's path, as given.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// How the file holds its JSON.
    pub fn container(&self) -> Container {
        self.container
    }

    /// The JSON, whole.
    pub fn json(&self) -> &Value {
        &self.json
    }

    /// A GLB's binary chunk.
    pub fn bin(&self) -> Option<&[u8]> {
        self.bin.as_deref()
    }

    /// An error about this file.
    pub(crate) fn error(&self, message: impl Into<String>) -> Error {
        Error::parse(&self.path, None, message)
    }

    /// The `index`-th element of the top-level array `name`
    /// (`"accessors"`, ...).
    pub(crate) fn item(&self, name: &str, index: usize) -> Result<&Value> {
        self.json
            .get(name)
            .and_then(Value::as_array)
            .and_then(|a| a.get(index))
            .ok_or_else(|| {
                self.error(format!(
                    "{} {index} is referred to but the file has {}",
                    singular(name),
                    self.count(name)
                ))
            })
    }

    /// The length of the top-level array `name`.
    pub(crate) fn count(&self, name: &str) -> usize {
        self.json
            .get(name)
            .and_then(Value::as_array)
            .map_or(0, Vec::len)
    }

    /// The bytes of buffer `index`, read on first use.
    pub(crate) fn buffer(&self, index: usize) -> Result<&[u8]> {
        let cell = self.buffers.get(index).ok_or_else(|| {
            self.error(format!(
                "buffer {index} is referred to but the file has {}",
                self.buffers.len()
            ))
        })?;
        if let Some(bytes) = cell.get() {
            return Ok(bytes);
        }
        let bytes = self.load_buffer(index)?;
        Ok(cell.get_or_init(|| bytes))
    }

    fn load_buffer(&self, index: usize) -> Result<Vec<u8>> {
        let buffer = self.item("buffers", index)?;
        let length = buffer
            .get("byteLength")
            .and_then(Value::as_u64)
            .ok_or_else(|| self.error(format!("buffer {index} has no `byteLength`")))?;
        let bytes = match buffer.get("uri").and_then(Value::as_str) {
            None => self.bin.clone().ok_or_else(|| {
                self.error(format!(
                    "buffer {index} has no URI and the file has no binary chunk"
                ))
            })?,
            Some(uri) => self.uri_bytes(uri, &format!("buffer {index}"))?,
        };
        if (bytes.len() as u64) < length {
            return Err(self.error(format!(
                "buffer {index} holds {} bytes but its `byteLength` is {length}",
                bytes.len()
            )));
        }
        Ok(bytes)
    }

    /// The bytes a URI names: a `data:` URI's, or a file's relative to this
    /// file's folder.
    pub(crate) fn uri_bytes(&self, uri: &str, what: &str) -> Result<Vec<u8>> {
        if let Some(data) = uri.strip_prefix("data:") {
            let (_, payload) = data
                .split_once(";base64,")
                .ok_or_else(|| self.error(format!("{what}: a `data:` URI that is not base64")))?;
            return base64::decode(payload)
                .ok_or_else(|| self.error(format!("{what}: its `data:` URI is not valid base64")));
        }
        if uri.contains("://") {
            return Err(self.error(format!(
                "{what}: `{uri}` is not a file beside the glTF; only relative paths and `data:` URIs are read"
            )));
        }
        let file = self.folder().join(percent_decode(uri));
        read_file(&file, &Limit::memory())
            .map_err(|e| self.error(format!("{what}: cannot read `{}` ({e})", file.display())))
    }

    /// The folder the file's relative URIs start from.
    pub(crate) fn folder(&self) -> PathBuf {
        self.path
            .parent()
            .map(Path::to_path_buf)
            .unwrap_or_default()
    }
}

/// "accessors" → "accessor", for messages.
fn singular(name: &str) -> &str {
    match name {
        "accessors" => "accessor",
        "bufferViews" => "buffer view",
        "buffers" => "buffer",
        "meshes" => "mesh",
        "nodes" => "node",
        "skins" => "skin",
        _ => name,
    }
}

/// The JSON and binary chunks of a GLB.
fn split_glb(bytes: &[u8]) -> std::result::Result<(&[u8], Option<&[u8]>), String> {
    let word = |at: usize| -> Option<u32> {
        bytes
            .get(at..at + 4)
            .map(|b| u32::from_le_bytes(b.try_into().expect("four bytes")))
    };
    let version = word(4).ok_or("a GLB shorter than its 12-byte header")?;
    if version != 2 {
        return Err(format!(
            "GLB version {version}: only glTF 2.0 is read (convert the file, e.g. by opening it in Blender and exporting glTF 2.0)"
        ));
    }
    let total = (word(8).ok_or("a GLB shorter than its header")? as usize).min(bytes.len());
    let (mut json, mut bin) = (None, None);
    let mut at = 12;
    while at + 8 <= total {
        let length = word(at).expect("within the file") as usize;
        let kind = word(at + 4).expect("within the file");
        let start = at + 8;
        let end = start
            .checked_add(length)
            .filter(|&e| e <= total)
            .ok_or_else(|| format!("GLB chunk at byte {at} runs past the end of the file"))?;
        match kind {
            CHUNK_JSON if json.is_none() => json = Some(&bytes[start..end]),
            CHUNK_BIN if bin.is_none() => bin = Some(&bytes[start..end]),
            _ => {}
        }
        at = end.next_multiple_of(4);
    }
    let json = json.ok_or("a GLB without a JSON chunk")?;
    Ok((json, bin))
}

/// `%20` → ` ` and the like in a URI's path.
fn percent_decode(uri: &str) -> String {
    let bytes = uri.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' && i + 2 < bytes.len() {
            let hex = std::str::from_utf8(&bytes[i + 1..i + 3]).unwrap_or("");
            if let Ok(b) = u8::from_str_radix(hex, 16) {
                out.push(b);
                i += 3;
                continue;
            }
        }
        out.push(bytes[i]);
        i += 1;
    }
    String::from_utf8_lossy(&out).into_owned()
}
