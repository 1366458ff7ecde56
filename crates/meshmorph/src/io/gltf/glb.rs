//! A GLB assembled from its JSON and binary chunk, and a small builder of
//! buffer views and accessors over a growing binary chunk (for new files
//! and for the data appended to a user's file).

use serde_json::{json, Map, Value};

use super::document::{CHUNK_BIN, CHUNK_JSON, GLB_MAGIC};

/// The bytes of a GLB of `json` and `bin` (each chunk padded to 4 bytes:
/// the JSON with spaces, the binary chunk with zeros; no binary chunk when
/// `bin` is `None`).
pub(crate) fn glb_bytes(json: &[u8], bin: Option<&[u8]>) -> Vec<u8> {
    let json_len = json.len().next_multiple_of(4);
    let bin_len = bin.map_or(0, |b| b.len().next_multiple_of(4));
    let total = 12 + 8 + json_len + bin.map_or(0, |_| 8 + bin_len);
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(GLB_MAGIC);
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(json_len as u32).to_le_bytes());
    out.extend_from_slice(&CHUNK_JSON.to_le_bytes());
    out.extend_from_slice(json);
    out.resize(20 + json_len, b' ');
    if let Some(bin) = bin {
        out.extend_from_slice(&(bin_len as u32).to_le_bytes());
        out.extend_from_slice(&CHUNK_BIN.to_le_bytes());
        out.extend_from_slice(bin);
        out.resize(total, 0);
    }
    out
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
    /// The bytes of that buffer: new bytes go at its end.
    pub bin: &'a mut Vec<u8>,
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
    pub(crate) fn view(&mut self, bytes: &[u8], target: Option<u32>) -> usize {
        let pad = self.bin.len().next_multiple_of(4) - self.bin.len();
        self.bin.extend(std::iter::repeat_n(0, pad));
        let mut view = Map::new();
        view.insert("buffer".into(), json!(self.buffer));
        view.insert("byteOffset".into(), json!(self.bin.len()));
        view.insert("byteLength".into(), json!(bytes.len()));
        if let Some(t) = target {
            view.insert("target".into(), json!(t));
        }
        self.bin.extend_from_slice(bytes);
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
        let view = self.view(&float_bytes(values), target);
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
        let view = self.view(&bytes, target);
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
                let view = self.view(&bytes, Some(ARRAY_BUFFER));
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
                let indices = self.view(&indices, None);
                let values = self.view(&values, None);
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
    /// smaller (and `sparse`), else dense. One pass over them finds the
    /// bounds and keeps the moving vertices' deltas; a dense target takes
    /// a second.
    pub(crate) fn new(count: usize, delta: impl Fn(usize) -> [f32; 3], sparse: bool) -> Self {
        let mut min = [f32::INFINITY; 3];
        let mut max = [f32::NEG_INFINITY; 3];
        let mut moved: Vec<u32> = Vec::new();
        let mut values: Vec<u8> = Vec::new();
        for v in 0..count {
            let d = delta(v);
            for c in 0..3 {
                min[c] = min[c].min(d[c]);
                max[c] = max[c].max(d[c]);
            }
            if d != [0.0; 3] {
                moved.push(v as u32);
                for x in d {
                    values.extend_from_slice(&x.to_le_bytes());
                }
            }
        }
        if moved.is_empty() {
            return EncodedDeltas {
                count,
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
        let data = if !sparse || moved.len() * (index_bytes + 12) >= count * 12 {
            let mut dense = Vec::with_capacity(12 * count);
            for v in 0..count {
                for x in delta(v) {
                    dense.extend_from_slice(&x.to_le_bytes());
                }
            }
            DeltaData::Dense(dense)
        } else {
            DeltaData::Sparse {
                moved: moved.len(),
                index_type,
                indices: integer_bytes(&moved, index_type),
                values,
            }
        };
        EncodedDeltas {
            count,
            min,
            max,
            data,
        }
    }
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
