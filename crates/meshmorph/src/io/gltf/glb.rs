//! A GLB assembled from its JSON and binary chunk, and a small builder of
//! buffer views and accessors over a growing binary chunk (for new files
//! and for the data appended to a user's file).

use serde_json::{json, Map, Value};

use super::document::{CHUNK_BIN, CHUNK_JSON, GLB_MAGIC};

/// The bytes of a GLB of `json` and `bin` (each chunk padded to 4 bytes:
/// the JSON with spaces, the binary chunk with zeros; no binary chunk when
/// `bin` is `None`).
pub(crate) fn glb_bytes(json: &[u8], bin: Option<&[u8]>) -> Vec<u8> {
    let parts = bin.map(|b| [b]);
    let parts = parts.as_ref().map(|p| &p[..]);
    let mut out = Vec::with_capacity(glb_length(json, parts));
    write_glb_parts(&mut out, json, parts).expect("writing to memory does not fail");
    out
}

/// The length of the GLB [`write_glb_parts`] writes.
pub(crate) fn glb_length(json: &[u8], bin: Option<&[&[u8]]>) -> usize {
    let bin_len: Option<usize> = bin.map(|parts| parts.iter().map(|p| p.len()).sum());
    12 + 8 + json.len().next_multiple_of(4) + bin_len.map_or(0, |b| 8 + b.next_multiple_of(4))
}

/// Writes a GLB of `json` and a binary chunk made of the `bin` parts one
/// after another (no binary chunk when `None`), as [`glb_bytes`] lays it
/// out, without assembling the parts first.
pub(crate) fn write_glb_parts(
    w: &mut dyn std::io::Write,
    json: &[u8],
    bin: Option<&[&[u8]]>,
) -> std::io::Result<()> {
    let total = glb_length(json, bin);
    let json_len = json.len().next_multiple_of(4);
    w.write_all(GLB_MAGIC)?;
    w.write_all(&2u32.to_le_bytes())?;
    w.write_all(&(total as u32).to_le_bytes())?;
    w.write_all(&(json_len as u32).to_le_bytes())?;
    w.write_all(&CHUNK_JSON.to_le_bytes())?;
    w.write_all(json)?;
    w.write_all(&b"   "[..json_len - json.len()])?;
    if let Some(parts) = bin {
        let length: usize = parts.iter().map(|p| p.len()).sum();
        let bin_len = length.next_multiple_of(4);
        w.write_all(&(bin_len as u32).to_le_bytes())?;
        w.write_all(&CHUNK_BIN.to_le_bytes())?;
        for part in parts {
            w.write_all(part)?;
        }
        w.write_all(&[0; 3][..bin_len - length])?;
    }
    Ok(())
}

/// `ARRAY_BUFFER`: a buffer view of vertex attributes.
pub(crate) const ARRAY_BUFFER: u32 = 34962;
/// `ELEMENT_ARRAY_BUFFER`: a buffer view of indices.
pub(crate) const ELEMENT_ARRAY_BUFFER: u32 = 34963;
/// `FLOAT`.
pub(crate) const FLOAT: u32 = 5126;

/// Buffer views and accessors appended to a document's JSON, their bytes
/// to a binary buffer.
pub(crate) struct Appender<'a> {
    /// The document's JSON (an object).
    pub json: &'a mut Value,
    /// The buffer the new views point into.
    pub buffer: usize,
    /// The length of that buffer before the new bytes (0 for a new one).
    pub base: usize,
    /// The new bytes of that buffer, which follow its first `base`.
    pub bin: &'a mut Pieces,
}

/// Bytes appended to a binary buffer, kept as the pieces they were made in,
/// so that joining them copies nothing until they are written.
#[derive(Debug, Default)]
pub(crate) struct Pieces {
    pieces: Vec<Vec<u8>>,
    len: usize,
}

impl Pieces {
    /// Their length in all.
    pub(crate) fn len(&self) -> usize {
        self.len
    }

    /// Appends `bytes`.
    pub(crate) fn push(&mut self, bytes: Vec<u8>) {
        self.len += bytes.len();
        if !bytes.is_empty() {
            self.pieces.push(bytes);
        }
    }

    /// The pieces in order.
    pub(crate) fn slices(&self) -> impl Iterator<Item = &[u8]> {
        self.pieces.iter().map(Vec::as_slice)
    }

    /// The pieces joined.
    pub(crate) fn concat(&self) -> Vec<u8> {
        self.pieces.concat()
    }
}

impl Appender<'_> {
    /// The top-level array `name`, made when missing.
    pub(crate) fn array(&mut self, name: &str) -> &mut Vec<Value> {
        let root = self
            .json
            .as_object_mut()
            .expect("a glTF document is an object");
        let entry = root.entry(name).or_insert_with(|| Value::Array(Vec::new()));
        if !entry.is_array() {
            *entry = Value::Array(Vec::new());
        }
        entry.as_array_mut().expect("made an array")
    }

    /// Appends `item` to the top-level array `name`; returns its index.
    pub(crate) fn push(&mut self, name: &str, item: Value) -> usize {
        let array = self.array(name);
        array.push(item);
        array.len() - 1
    }

    /// A buffer view of `bytes` (4-byte aligned), with `target` when given.
    pub(crate) fn view(&mut self, bytes: Vec<u8>, target: Option<u32>) -> usize {
        let end = self.base + self.bin.len();
        self.bin.push(vec![0; end.next_multiple_of(4) - end]);
        let mut view = Map::new();
        view.insert("buffer".into(), json!(self.buffer));
        view.insert("byteOffset".into(), json!(self.base + self.bin.len()));
        view.insert("byteLength".into(), json!(bytes.len()));
        if let Some(t) = target {
            view.insert("target".into(), json!(t));
        }
        self.bin.push(bytes);
        self.push("bufferViews", Value::Object(view))
    }

    /// A tightly packed `f32` accessor of `values` (`components` each:
    /// `type` SCALAR, VEC2, VEC3 or VEC4), with `min`/`max` when `bounds`.
    pub(crate) fn floats(
        &mut self,
        values: &[f32],
        components: usize,
        target: Option<u32>,
        bounds: bool,
    ) -> usize {
        let view = self.view(float_bytes(values), target);
        let mut accessor = json!({
            "bufferView": view,
            "componentType": FLOAT,
            "count": values.len() / components,
            "type": kind(components),
        });
        if bounds {
            let (min, max) = bounds_of(values, components);
            accessor["min"] = json!(min);
            accessor["max"] = json!(max);
        }
        self.push("accessors", accessor)
    }

    /// An accessor of `u8`, `u16` or `u32` `values` (the smallest that holds
    /// them unless `component_type` is given), `components` each.
    pub(crate) fn integers(
        &mut self,
        values: &[u32],
        components: usize,
        component_type: Option<u32>,
        target: Option<u32>,
    ) -> usize {
        let largest = values.iter().copied().max().unwrap_or(0);
        let component_type = component_type.unwrap_or(if largest <= 0xFF {
            5121
        } else if largest <= 0xFFFF {
            5123
        } else {
            5125
        });
        let bytes = integer_bytes(values, component_type);
        let view = self.view(bytes, target);
        self.push(
            "accessors",
            json!({
                "bufferView": view,
                "componentType": component_type,
                "count": values.len() / components,
                "type": kind(components),
            }),
        )
    }

    /// An accessor of `count` zero deltas: no buffer view (glTF reads zeros).
    pub(crate) fn zeros(&mut self, count: usize) -> usize {
        self.push(
            "accessors",
            json!({"componentType": FLOAT, "count": count, "type": "VEC3",
                "min": [0.0, 0.0, 0.0], "max": [0.0, 0.0, 0.0]}),
        )
    }

    /// A `POSITION` delta accessor: none of data when every delta is zero,
    /// sparse when that is smaller (and `sparse`), else dense.
    pub(crate) fn deltas(&mut self, deltas: &[[f32; 3]], sparse: bool) -> usize {
        self.append_deltas(EncodedDeltas::new(deltas.len(), |v| deltas[v], sparse))
    }

    /// The accessor of deltas encoded by [`EncodedDeltas::new`].
    pub(crate) fn append_deltas(&mut self, e: EncodedDeltas) -> usize {
        let (count, min, max) = (e.count, e.min, e.max);
        match e.data {
            DeltaData::Zeros => self.zeros(count),
            DeltaData::Dense(bytes) => {
                let view = self.view(bytes, Some(ARRAY_BUFFER));
                self.push(
                    "accessors",
                    json!({"bufferView": view, "componentType": FLOAT, "count": count,
                        "type": "VEC3", "min": min, "max": max}),
                )
            }
            DeltaData::Sparse {
                moved,
                index_type,
                indices,
                values,
            } => {
                let indices = self.view(indices, None);
                let values = self.view(values, None);
                self.push(
                    "accessors",
                    json!({"componentType": FLOAT, "count": count, "type": "VEC3",
                        "min": min, "max": max,
                        "sparse": {"count": moved,
                            "indices": {"bufferView": indices, "componentType": index_type},
                            "values": {"bufferView": values}}}),
                )
            }
        }
    }
}

/// A morph target's `POSITION` deltas as bytes, made apart from the file
/// (on any thread) and appended by [`Appender::append_deltas`].
pub(crate) struct EncodedDeltas {
    count: usize,
    /// Every delta is finite.
    pub(crate) finite: bool,
    min: [f32; 3],
    max: [f32; 3],
    data: DeltaData,
}

/// How a target's deltas are stored.
enum DeltaData {
    /// Every delta is zero: an accessor without data.
    Zeros,
    /// Every delta, little-endian.
    Dense(Vec<u8>),
    /// The indices of the vertices that move and their deltas.
    Sparse {
        moved: usize,
        index_type: u32,
        indices: Vec<u8>,
        values: Vec<u8>,
    },
}

impl EncodedDeltas {
    /// The deltas `delta(0)`, ..., `delta(count - 1)`: sparse when that is
    /// smaller (and `sparse`), else dense. A first pass finds the bounds
    /// and counts the moving vertices; a second lays out their bytes, in
    /// buffers of the size they end with.
    pub(crate) fn new(count: usize, delta: impl Fn(usize) -> [f32; 3], sparse: bool) -> Self {
        let mut min = [f32::INFINITY; 3];
        let mut max = [f32::NEG_INFINITY; 3];
        let mut moved = 0;
        let mut finite = true;
        for v in 0..count {
            let d = delta(v);
            for c in 0..3 {
                finite &= d[c].is_finite();
                min[c] = if d[c] < min[c] { d[c] } else { min[c] };
                max[c] = if d[c] > max[c] { d[c] } else { max[c] };
            }
            moved += usize::from(d != [0.0; 3]);
        }
        if moved == 0 {
            return EncodedDeltas {
                count,
                finite,
                min: [0.0; 3],
                max: [0.0; 3],
                data: DeltaData::Zeros,
            };
        }
        let (index_type, index_bytes) = match count {
            0..=256 => (5121, 1),
            257..=65536 => (5123, 2),
            _ => (5125, 4),
        };
        let data = if !sparse || moved * (index_bytes + 12) >= count * 12 {
            let mut dense = Vec::with_capacity(12 * count);
            for v in 0..count {
                dense.extend_from_slice(&vector_bytes(delta(v)));
            }
            DeltaData::Dense(dense)
        } else {
            let mut indices = Vec::with_capacity(index_bytes * moved);
            let mut values = Vec::with_capacity(12 * moved);
            for v in 0..count {
                let d = delta(v);
                if d != [0.0; 3] {
                    indices.extend_from_slice(&(v as u32).to_le_bytes()[..index_bytes]);
                    values.extend_from_slice(&vector_bytes(d));
                }
            }
            DeltaData::Sparse {
                moved,
                index_type,
                indices,
                values,
            }
        };
        EncodedDeltas {
            count,
            finite,
            min,
            max,
            data,
        }
    }
}

/// Little-endian bytes of `d`.
fn vector_bytes(d: [f32; 3]) -> [u8; 12] {
    let mut bytes = [0; 12];
    for (c, x) in d.iter().enumerate() {
        bytes[4 * c..4 * c + 4].copy_from_slice(&x.to_le_bytes());
    }
    bytes
}

/// Little-endian bytes of `values`.
pub(crate) fn float_bytes(values: &[f32]) -> Vec<u8> {
    let mut bytes = Vec::with_capacity(4 * values.len());
    for x in values {
        bytes.extend_from_slice(&x.to_le_bytes());
    }
    bytes
}

/// Little-endian bytes of `values` as `component_type` (5121, 5123 or
/// 5125), each element padded to 4 bytes as vertex attributes need.
pub(crate) fn integer_bytes(values: &[u32], component_type: u32) -> Vec<u8> {
    match component_type {
        5121 => values.iter().map(|&v| v as u8).collect(),
        5123 => values
            .iter()
            .flat_map(|&v| (v as u16).to_le_bytes())
            .collect(),
        _ => values.iter().flat_map(|&v| v.to_le_bytes()).collect(),
    }
}

/// glTF's `type` of `components`.
pub(crate) fn kind(components: usize) -> &'static str {
    match components {
        1 => "SCALAR",
        2 => "VEC2",
        3 => "VEC3",
        _ => "VEC4",
    }
}

/// Component-wise minimum and maximum of `values` (`components` each).
pub(crate) fn bounds_of(values: &[f32], components: usize) -> (Vec<f32>, Vec<f32>) {
    let mut min = vec![f32::INFINITY; components];
    let mut max = vec![f32::NEG_INFINITY; components];
    for row in values.chunks_exact(components) {
        for c in 0..components {
            min[c] = min[c].min(row[c]);
            max[c] = max[c].max(row[c]);
        }
    }
    if values.is_empty() {
        (vec![0.0; components], vec![0.0; components])
    } else {
        (min, max)
    }
}
