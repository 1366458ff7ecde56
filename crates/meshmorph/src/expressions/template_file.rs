//! Reading an expression template's GLB (the layout `tools/arkit-template/
//! build.py` writes): the meshes' positions, triangles and morph-target
//! deltas (`f32`, or KHR_mesh_quantization's normalised integers; dense or
//! sparse), `extras.targetNames`, `extras.landmarks` and `extras.regions`.

use serde_json::Value;

use crate::error::{Error, Result};
use crate::expressions::template::{ExpressionTemplate, TemplatePart};
use crate::mesh::Mesh3;

/// Reads a template GLB; `what` names it in errors.
pub(crate) fn read_template_glb(bytes: &[u8], what: &str) -> Result<ExpressionTemplate> {
    let bad = |m: &str| Error::InvalidArgument(format!("{what}: {m}"));
    let (doc, bin) = glb_chunks(bytes).ok_or_else(|| bad("not a binary glTF (GLB) file"))?;
    let doc: Value = serde_json::from_slice(doc).map_err(|e| bad(&format!("its JSON: {e}")))?;
    let file = File { doc: &doc, bin };
    let meshes = doc["meshes"].as_array().ok_or_else(|| bad("no meshes"))?;
    let mut head = None;
    let mut parts = Vec::new();
    for (m, mesh) in meshes.iter().enumerate() {
        let name = mesh["name"]
            .as_str()
            .map_or_else(|| format!("mesh {m}"), String::from);
        let read = file
            .mesh(mesh)
            .map_err(|e| bad(&format!("mesh `{name}`: {e}")))?;
        if name == "head" {
            head = Some((mesh, read));
        } else {
            parts.push((name, read));
        }
    }
    let (head_json, (head_mesh, head_deltas)) = head.ok_or_else(|| bad("no mesh named `head`"))?;
    let extras = &head_json["extras"];
    let shape_names: Vec<String> = extras["targetNames"]
        .as_array()
        .map(|a| {
            a.iter()
                .filter_map(|n| n.as_str().map(String::from))
                .collect()
        })
        .unwrap_or_else(|| {
            (0..head_deltas.len())
                .map(|k| format!("target_{k}"))
                .collect()
        });
    let landmarks = extras["landmarks"]
        .as_array()
        .ok_or_else(|| bad("the head has no `extras.landmarks`"))?
        .iter()
        .map(|l| {
            Some((
                l["name"].as_str()?.to_string(),
                u32::try_from(l["vertex"].as_u64()?).ok()?,
            ))
        })
        .collect::<Option<Vec<_>>>()
        .ok_or_else(|| bad("a landmark without a `name` and a `vertex`"))?;
    let face = extras["regions"]["face"]
        .as_array()
        .and_then(|r| Some(r.first()?.as_u64()? as usize..r.get(1)?.as_u64()? as usize + 1))
        .unwrap_or(0..head_mesh.num_vertices());
    let template = ExpressionTemplate {
        head: head_mesh,
        face,
        shape_names,
        head_deltas,
        landmarks,
        parts: parts
            .into_iter()
            .map(|(name, (mesh, deltas))| TemplatePart { name, mesh, deltas })
            .collect(),
    };
    template.check(what)?;
    Ok(template)
}

/// The JSON and binary chunks of a GLB.
fn glb_chunks(bytes: &[u8]) -> Option<(&[u8], &[u8])> {
    let word =
        |at: usize| Some(u32::from_le_bytes(bytes.get(at..at + 4)?.try_into().ok()?) as usize);
    if bytes.get(0..4)? != b"glTF" || word(4)? != 2 {
        return None;
    }
    let json_len = word(12)?;
    let json = bytes.get(20..20 + json_len)?;
    let at = 20 + json_len;
    let bin = match word(at) {
        Some(len) => bytes.get(at + 8..at + 8 + len)?,
        None => &[],
    };
    Some((json, bin))
}

/// A GLB's document and binary chunk.
struct File<'a> {
    doc: &'a Value,
    bin: &'a [u8],
}

type MeshAndDeltas = (Mesh3, Vec<Vec<[f64; 3]>>);

impl File<'_> {
    /// A mesh's first primitive: its positions and triangles, and each
    /// morph target's position deltas.
    fn mesh(&self, mesh: &Value) -> std::result::Result<MeshAndDeltas, String> {
        let prim = &mesh["primitives"][0];
        let positions = self.vec3(&prim["attributes"]["POSITION"])?;
        let indices = self.scalars(&prim["indices"])?;
        if indices.len() % 3 != 0 {
            return Err("an index count that is not a multiple of 3".into());
        }
        let triangles = indices
            .chunks_exact(3)
            .map(|t| [t[0] as u32, t[1] as u32, t[2] as u32])
            .collect();
        let deltas = prim["targets"]
            .as_array()
            .map(|ts| ts.iter().map(|t| self.vec3(&t["POSITION"])).collect())
            .transpose()?
            .unwrap_or_default();
        let mesh = Mesh3::new(positions, triangles).map_err(|e| e.to_string())?;
        Ok((mesh, deltas))
    }

    fn accessor(&self, index: &Value) -> std::result::Result<&Value, String> {
        let i = index.as_u64().ok_or("an attribute without an accessor")?;
        self.doc["accessors"]
            .get(i as usize)
            .ok_or_else(|| format!("accessor {i} does not exist"))
    }

    /// The bytes of buffer view `view` from `offset` on.
    fn view(&self, view: &Value, offset: u64) -> std::result::Result<&[u8], String> {
        let i = view.as_u64().ok_or("a buffer view that is not a number")? as usize;
        let v = &self.doc["bufferViews"][i];
        if v["buffer"].as_u64().unwrap_or(0) != 0 || v.get("byteStride").is_some() {
            return Err(format!(
                "buffer view {i} is not tightly packed in the GLB's buffer"
            ));
        }
        let start = (v["byteOffset"].as_u64().unwrap_or(0) + offset) as usize;
        let end = v["byteOffset"].as_u64().unwrap_or(0) as usize
            + v["byteLength"]
                .as_u64()
                .ok_or("a buffer view without a length")? as usize;
        self.bin
            .get(start..end)
            .ok_or_else(|| format!("buffer view {i} reaches past the buffer"))
    }

    /// The components of `count` elements of `width` components each.
    fn components(
        &self,
        bytes: &[u8],
        ctype: u64,
        normalized: bool,
        n: usize,
    ) -> std::result::Result<Vec<f64>, String> {
        let size = match ctype {
            5120 | 5121 => 1,
            5122 | 5123 => 2,
            5125 | 5126 => 4,
            _ => return Err(format!("component type {ctype}")),
        };
        let bytes = bytes
            .get(..n * size)
            .ok_or("an accessor longer than its view")?;
        Ok(bytes
            .chunks_exact(size)
            .map(|b| match (ctype, normalized) {
                (5120, false) => b[0] as i8 as f64,
                (5120, true) => (b[0] as i8 as f64 / 127.0).max(-1.0),
                (5121, false) => b[0] as f64,
                (5121, true) => b[0] as f64 / 255.0,
                (5122, false) => i16::from_le_bytes([b[0], b[1]]) as f64,
                (5122, true) => (i16::from_le_bytes([b[0], b[1]]) as f64 / 32767.0).max(-1.0),
                (5123, false) => u16::from_le_bytes([b[0], b[1]]) as f64,
                (5123, true) => u16::from_le_bytes([b[0], b[1]]) as f64 / 65535.0,
                (5125, _) => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
                _ => f32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
            })
            .collect())
    }

    /// An accessor's values, `width` components per element, sparse
    /// substitutions applied.
    fn values(&self, index: &Value, width: usize) -> std::result::Result<Vec<f64>, String> {
        let a = self.accessor(index)?;
        let count = a["count"].as_u64().ok_or("an accessor without a count")? as usize;
        let ctype = a["componentType"].as_u64().unwrap_or(0);
        let normalized = a["normalized"].as_bool().unwrap_or(false);
        let mut out = match a.get("bufferView") {
            Some(view) => self.components(
                self.view(view, a["byteOffset"].as_u64().unwrap_or(0))?,
                ctype,
                normalized,
                count * width,
            )?,
            None => vec![0.0; count * width],
        };
        if let Some(sparse) = a.get("sparse") {
            let n = sparse["count"].as_u64().unwrap_or(0) as usize;
            let ind = &sparse["indices"];
            let idx = self.components(
                self.view(&ind["bufferView"], ind["byteOffset"].as_u64().unwrap_or(0))?,
                ind["componentType"].as_u64().unwrap_or(0),
                false,
                n,
            )?;
            let val = &sparse["values"];
            let vals = self.components(
                self.view(&val["bufferView"], val["byteOffset"].as_u64().unwrap_or(0))?,
                ctype,
                normalized,
                n * width,
            )?;
            for (k, &i) in idx.iter().enumerate() {
                let i = i as usize;
                if i >= count {
                    return Err(format!("a sparse index {i} past the accessor's {count}"));
                }
                out[i * width..(i + 1) * width].copy_from_slice(&vals[k * width..(k + 1) * width]);
            }
        }
        Ok(out)
    }

    fn vec3(&self, index: &Value) -> std::result::Result<Vec<[f64; 3]>, String> {
        Ok(self
            .values(index, 3)?
            .chunks_exact(3)
            .map(|c| [c[0], c[1], c[2]])
            .collect())
    }

    fn scalars(&self, index: &Value) -> std::result::Result<Vec<f64>, String> {
        self.values(index, 1)
    }
}
