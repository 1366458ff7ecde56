//! glTF accessors decoded: every component type, normalised integers
//! (KHR_mesh_quantization), interleaved buffer views, sparse
//! substitutions, and accessors without a buffer view (zeros).

use serde_json::Value;

use super::document::GltfDocument;
use crate::error::Result;

/// The components of one element of an accessor's `type`.
pub(crate) fn components(kind: &str) -> Option<usize> {
    Some(match kind {
        "SCALAR" => 1,
        "VEC2" => 2,
        "VEC3" => 3,
        "VEC4" | "MAT2" => 4,
        "MAT3" => 9,
        "MAT4" => 16,
        _ => return None,
    })
}

/// Bytes of one component of `component_type` (5120 ... 5126).
pub(crate) fn component_size(component_type: u64) -> Option<usize> {
    Some(match component_type {
        5120 | 5121 => 1,
        5122 | 5123 => 2,
        5125 | 5126 => 4,
        _ => return None,
    })
}

/// One component read as a number, normalised (to −1..1 or 0..1, as glTF
/// decodes them) when `normalized`.
fn component(bytes: &[u8], component_type: u64, normalized: bool) -> f64 {
    let raw = match component_type {
        5120 => f64::from(bytes[0] as i8),
        5121 => f64::from(bytes[0]),
        5122 => f64::from(i16::from_le_bytes([bytes[0], bytes[1]])),
        5123 => f64::from(u16::from_le_bytes([bytes[0], bytes[1]])),
        5125 => f64::from(u32::from_le_bytes(bytes[..4].try_into().expect("4 bytes"))),
        _ => f64::from(f32::from_le_bytes(bytes[..4].try_into().expect("4 bytes"))),
    };
    if !normalized {
        return raw;
    }
    match component_type {
        5120 => (raw / 127.0).max(-1.0),
        5121 => raw / 255.0,
        5122 => (raw / 32767.0).max(-1.0),
        5123 => raw / 65535.0,
        _ => raw,
    }
}

/// What an accessor holds, read from its JSON.
struct Layout<'a> {
    count: usize,
    components: usize,
    component_type: u64,
    normalized: bool,
    json: &'a Value,
}

/// Accessor `index` as `count × components` numbers, row by row.
/// `components` is the element size the caller needs (an accessor of
/// another `type` is refused); `what` says what it is for messages
/// ("POSITION of primitive 0 of mesh `Body`").
pub(crate) fn read_floats(
    doc: &GltfDocument,
    index: usize,
    components: usize,
    what: &str,
) -> Result<Vec<f64>> {
    let layout = layout(doc, index, what)?;
    if layout.components != components {
        return Err(doc.error(format!(
            "accessor {index} ({what}) has {} components per element; {components} were expected",
            layout.components
        )));
    }
    let mut out = vec![0.0; layout.count * components];
    if let Some(view) = layout.json.get("bufferView") {
        let offset = layout
            .json
            .get("byteOffset")
            .and_then(Value::as_u64)
            .unwrap_or(0) as usize;
        fill(
            doc,
            view,
            offset,
            &layout,
            None,
            &mut out,
            &format!("accessor {index} ({what})"),
        )?;
    }
    if let Some(sparse) = layout.json.get("sparse") {
        apply_sparse(doc, index, sparse, &layout, &mut out, what)?;
    }
    Ok(out)
}

/// Accessor `index` as vertex indices (a SCALAR of unsigned integers).
pub(crate) fn read_indices(doc: &GltfDocument, index: usize, what: &str) -> Result<Vec<u32>> {
    let layout = layout(doc, index, what)?;
    if layout.components != 1 || !matches!(layout.component_type, 5121 | 5123 | 5125) {
        return Err(doc.error(format!(
            "accessor {index} ({what}) does not hold indices (scalars of unsigned integers)"
        )));
    }
    let floats = read_floats(doc, index, 1, what)?;
    Ok(floats.into_iter().map(|x| x as u32).collect())
}

fn layout<'a>(doc: &'a GltfDocument, index: usize, what: &str) -> Result<Layout<'a>> {
    let json = doc.item("accessors", index)?;
    let field = |name: &str| json.get(name);
    let count = field("count")
        .and_then(Value::as_u64)
        .ok_or_else(|| doc.error(format!("accessor {index} ({what}) has no `count`")))?
        as usize;
    let kind = field("type").and_then(Value::as_str).unwrap_or("");
    let components = self::components(kind).ok_or_else(|| {
        doc.error(format!(
            "accessor {index} ({what}) has the unknown type `{kind}`"
        ))
    })?;
    let component_type = field("componentType").and_then(Value::as_u64).unwrap_or(0);
    if component_size(component_type).is_none() {
        return Err(doc.error(format!(
            "accessor {index} ({what}) has the unknown component type {component_type}"
        )));
    }
    Ok(Layout {
        count,
        components,
        component_type,
        normalized: field("normalized")
            .and_then(Value::as_bool)
            .unwrap_or(false),
        json,
    })
}

/// The bytes of buffer view `view` and its stride (0 for tightly packed).
fn view_bytes<'a>(doc: &'a GltfDocument, view: &Value, what: &str) -> Result<(&'a [u8], usize)> {
    let index = view
        .as_u64()
        .ok_or_else(|| doc.error(format!("{what}: `bufferView` is not an index")))?
        as usize;
    let json = doc.item("bufferViews", index)?;
    for compression in ["EXT_meshopt_compression", "KHR_meshopt_compression"] {
        if json
            .pointer(&format!("/extensions/{compression}"))
            .is_some()
        {
            return Err(doc.error(format!(
                "{what} is compressed with {compression}, which meshmorph does not decode: export the file without meshopt compression (gltfpack without -c, or `gltf-transform copy`)"
            )));
        }
    }
    let buffer = json
        .get("buffer")
        .and_then(Value::as_u64)
        .ok_or_else(|| doc.error(format!("buffer view {index} has no `buffer`")))?
        as usize;
    let offset = json.get("byteOffset").and_then(Value::as_u64).unwrap_or(0) as usize;
    let length = json
        .get("byteLength")
        .and_then(Value::as_u64)
        .ok_or_else(|| doc.error(format!("buffer view {index} has no `byteLength`")))?
        as usize;
    let stride = json.get("byteStride").and_then(Value::as_u64).unwrap_or(0) as usize;
    let bytes = doc.buffer(buffer)?;
    let range = offset
        .checked_add(length)
        .filter(|&end| end <= bytes.len())
        .map(|end| offset..end)
        .ok_or_else(|| {
            doc.error(format!(
                "buffer view {index} runs past the end of buffer {buffer} ({} bytes)",
                bytes.len()
            ))
        })?;
    Ok((&bytes[range], stride))
}

/// Reads `layout.count` elements (or those of `count` when given) from a
/// buffer view into `out`.
fn fill(
    doc: &GltfDocument,
    view: &Value,
    offset: usize,
    layout: &Layout<'_>,
    count: Option<usize>,
    out: &mut [f64],
    what: &str,
) -> Result<()> {
    let (bytes, stride) = view_bytes(doc, view, what)?;
    let size = component_size(layout.component_type).expect("checked");
    let element = size * layout.components;
    let stride = if stride == 0 { element } else { stride };
    let count = count.unwrap_or(layout.count);
    if count > 0 {
        let need = offset + stride * (count - 1) + element;
        if need > bytes.len() {
            return Err(doc.error(format!(
                "{what}: {count} elements need {need} bytes of its buffer view, which has {}",
                bytes.len()
            )));
        }
    }
    for (i, row) in out
        .chunks_exact_mut(layout.components)
        .take(count)
        .enumerate()
    {
        let at = offset + i * stride;
        for (c, x) in row.iter_mut().enumerate() {
            let b = &bytes[at + c * size..at + (c + 1) * size];
            *x = component(b, layout.component_type, layout.normalized);
        }
    }
    Ok(())
}

/// Substitutes a sparse accessor's values.
fn apply_sparse(
    doc: &GltfDocument,
    index: usize,
    sparse: &Value,
    layout: &Layout<'_>,
    out: &mut [f64],
    what: &str,
) -> Result<()> {
    let name = format!("the sparse values of accessor {index} ({what})");
    let count = sparse.get("count").and_then(Value::as_u64).unwrap_or(0) as usize;
    let indices = sparse.get("indices");
    let values = sparse.get("values");
    let (Some(indices), Some(values)) = (indices, values) else {
        return Err(doc.error(format!("{name}: `indices` or `values` missing")));
    };
    let index_type = indices
        .get("componentType")
        .and_then(Value::as_u64)
        .unwrap_or(0);
    if !matches!(index_type, 5121 | 5123 | 5125) {
        return Err(doc.error(format!(
            "{name}: index component type {index_type} is not an unsigned integer"
        )));
    }
    let index_layout = Layout {
        count,
        components: 1,
        component_type: index_type,
        normalized: false,
        json: indices,
    };
    let mut at = vec![0.0; count];
    let offset = |v: &Value| v.get("byteOffset").and_then(Value::as_u64).unwrap_or(0) as usize;
    let view = |v: &'_ Value| v.get("bufferView").cloned().unwrap_or(Value::Null);
    fill(
        doc,
        &view(indices),
        offset(indices),
        &index_layout,
        None,
        &mut at,
        &name,
    )?;
    let mut substituted = vec![0.0; count * layout.components];
    let value_layout = Layout {
        count,
        components: layout.components,
        component_type: layout.component_type,
        normalized: layout.normalized,
        json: values,
    };
    fill(
        doc,
        &view(values),
        offset(values),
        &value_layout,
        None,
        &mut substituted,
        &name,
    )?;
    let n = layout.components;
    for (k, &i) in at.iter().enumerate() {
        let i = i as usize;
        if i >= layout.count {
            return Err(doc.error(format!(
                "{name}: index {i} is past the accessor's {} elements",
                layout.count
            )));
        }
        out[i * n..(i + 1) * n].copy_from_slice(&substituted[k * n..(k + 1) * n]);
    }
    Ok(())
}
