//! A GLB assembled from its JSON and binary chunk, and a small builder of
//! buffer views and accessors over a growing binary chunk (for new files
//! and for the data appended to a user's file).

use std::io::Write;

use rayon::prelude::*;
use serde_json::{json, Map, Value};

use super::document::{CHUNK_BIN, CHUNK_JSON, GLB_MAGIC};

/// The bytes of a GLB of `json` and `bin` (each chunk padded to 4 bytes:
/// the JSON with spaces, the binary chunk with zeros; no binary chunk when
/// `bin` is `None`).
pub(crate) fn glb_bytes(json: &[u8], bin: Option<&[u8]>) -> Vec<u8> {
    let mut out = Vec::with_capacity(glb_length(json.len(), bin.map(<[u8]>::len)));
    let mut write_bin = |w: &mut dyn Write| w.write_all(bin.unwrap_or_default());
    let bin = bin.map(|b| (b.len(), &mut write_bin as &mut BinWriter<'_>));
    write_glb(&mut out, json, bin).expect("writing to memory does not fail");
    out
}

/// What writes a binary chunk's bytes (without its padding).
pub(crate) type BinWriter<'a> = dyn FnMut(&mut dyn Write) -> std::io::Result<()> + 'a;

/// The length of a GLB of `json_len` bytes of JSON and `bin_len` of binary
/// chunk (none when `None`), with their padding.
pub(crate) fn glb_length(json_len: usize, bin_len: Option<usize>) -> usize {
    12 + 8 + json_len.next_multiple_of(4) + bin_len.map_or(0, |b| 8 + b.next_multiple_of(4))
}

/// Writes a GLB of `json` and a binary chunk of the given length whose
/// bytes the function writes (no binary chunk when `None`), as
/// [`glb_bytes`] lays it out, without assembling it first.
pub(crate) fn write_glb(
    w: &mut dyn Write,
    json: &[u8],
    bin: Option<(usize, &mut BinWriter<'_>)>,
) -> std::io::Result<()> {
    let total = glb_length(json.len(), bin.as_ref().map(|b| b.0));
    let json_len = json.len().next_multiple_of(4);
    w.write_all(GLB_MAGIC)?;
    w.write_all(&2u32.to_le_bytes())?;
    w.write_all(&(total as u32).to_le_bytes())?;
    w.write_all(&(json_len as u32).to_le_bytes())?;
    w.write_all(&CHUNK_JSON.to_le_bytes())?;
    w.write_all(json)?;
    w.write_all(&b"   "[..json_len - json.len()])?;
    if let Some((length, write_bin)) = bin {
        let bin_len = length.next_multiple_of(4);
        w.write_all(&(bin_len as u32).to_le_bytes())?;
        w.write_all(&CHUNK_BIN.to_le_bytes())?;
        write_bin(w)?;
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
pub(crate) struct Appender<'a, 'p> {
    /// The document's JSON (an object).
    pub json: &'a mut Value,
    /// The buffer the new views point into.
    pub buffer: usize,
    /// The length of that buffer before the new bytes (0 for a new one).
    pub base: usize,
    /// The new bytes of that buffer, which follow its first `base`.
    pub bin: &'a mut Pieces<'p>,
}

/// Bytes appended to a binary buffer, in order: pieces made already, kept
/// as they were made (joining them copies nothing until they are written),
/// and pieces made only as the buffer is written (a morph target's deltas:
/// a batch at a time on every thread while the writer writes the ones
/// before, so that no more than a few are held at once).
#[derive(Default)]
pub struct Pieces<'a> {
    pieces: Vec<Piece<'a>>,
    len: usize,
}

/// One piece of [`Pieces`].
enum Piece<'a> {
    /// Bytes made already.
    Made(Vec<u8>),
    /// A piece of this many bytes, made by the function when written.
    Later(usize, Box<LaterBytes<'a>>),
}

/// What makes a later piece: its bytes, appended to the vector given.
type LaterBytes<'a> = dyn Fn(&mut Vec<u8>) + Send + Sync + 'a;

/// The bytes of a later piece of `len` bytes.
fn make(len: usize, fill: &LaterBytes<'_>) -> Vec<u8> {
    let mut bytes = Vec::with_capacity(len);
    fill(&mut bytes);
    debug_assert_eq!(bytes.len(), len, "a later piece is of the length given");
    bytes
}

impl<'a> Pieces<'a> {
    /// Their length in all.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether they hold no byte.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Appends `bytes`.
    pub fn push(&mut self, bytes: Vec<u8>) {
        self.len += bytes.len();
        if !bytes.is_empty() {
            self.pieces.push(Piece::Made(bytes));
        }
    }

    /// Appends `len` bytes that `fill` makes when they are written.
    pub fn push_later(&mut self, len: usize, fill: impl Fn(&mut Vec<u8>) + Send + Sync + 'a) {
        self.len += len;
        self.pieces.push(Piece::Later(len, Box::new(fill)));
    }

    /// Writes the pieces in order: the later ones made a batch at a time on
    /// every thread, on a thread beside this one, which writes.
    pub fn write_to(&self, w: &mut dyn Write) -> std::io::Result<()> {
        let later: Vec<(usize, &LaterBytes<'a>)> = self
            .pieces
            .iter()
            .filter_map(|p| match p {
                Piece::Later(len, fill) => Some((*len, &**fill)),
                Piece::Made(_) => None,
            })
            .collect();
        let batch = crate::limits::FRAMES_IN_FLIGHT_PER_THREAD * rayon::current_num_threads();
        std::thread::scope(|scope| {
            let (made, ready) = std::sync::mpsc::sync_channel::<Vec<u8>>(batch);
            scope.spawn(move || {
                for some in later.chunks(batch) {
                    let bytes: Vec<Vec<u8>> = some
                        .par_iter()
                        .map(|&(len, fill)| make(len, fill))
                        .collect();
                    for b in bytes {
                        if made.send(b).is_err() {
                            return; // the writer has stopped
                        }
                    }
                }
            });
            for piece in &self.pieces {
                match piece {
                    Piece::Made(bytes) => w.write_all(bytes)?,
                    Piece::Later(..) => {
                        let bytes = ready.recv().expect("every later piece is made");
                        w.write_all(&bytes)?;
                    }
                }
            }
            Ok(())
        })
    }

    /// The pieces joined.
    pub fn concat(&self) -> Vec<u8> {
        let mut bytes = Vec::with_capacity(self.len);
        self.write_to(&mut bytes)
            .expect("writing to memory does not fail");
        bytes
    }
}

impl<'p> Appender<'_, 'p> {
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
        let offset = self.align();
        let length = bytes.len();
        self.bin.push(bytes);
        self.view_at(offset, length, target)
    }

    /// Pads the buffer to 4 bytes; the offset of what comes next.
    fn align(&mut self) -> usize {
        let end = self.base + self.bin.len();
        self.bin.push(vec![0; end.next_multiple_of(4) - end]);
        self.base + self.bin.len()
    }

    /// A buffer view of `length` bytes at `offset`, with `target` when given.
    fn view_at(&mut self, offset: usize, length: usize, target: Option<u32>) -> usize {
        let mut view = Map::new();
        view.insert("buffer".into(), json!(self.buffer));
        view.insert("byteOffset".into(), json!(offset));
        view.insert("byteLength".into(), json!(length));
        if let Some(t) = target {
            view.insert("target".into(), json!(t));
        }
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
        let delta = |v: usize| deltas[v];
        let summary = DeltaSummary::of(deltas.len(), delta);
        let layout = summary.layout(sparse);
        let mut bytes = Vec::with_capacity(layout.len);
        layout.fill(delta, &mut bytes);
        self.delta_accessor(&summary, &layout, |at| at.push(bytes))
    }

    /// The accessor of [`deltas`](Self::deltas) for deltas summed up in
    /// `summary`, whose bytes `delta` makes only when the buffer is written
    /// (see [`Pieces`]).
    pub(crate) fn deltas_later(
        &mut self,
        summary: &DeltaSummary,
        sparse: bool,
        delta: impl Fn(usize) -> [f32; 3] + Send + Sync + 'p,
    ) -> usize {
        let layout = summary.layout(sparse);
        let fill = layout.clone();
        self.delta_accessor(summary, &layout, move |at| {
            at.push_later(fill.len, move |bytes| fill.fill(&delta, bytes))
        })
    }

    /// The accessor of deltas laid out by `layout`, its bytes appended by
    /// `append` (after padding to 4 bytes).
    fn delta_accessor(
        &mut self,
        summary: &DeltaSummary,
        layout: &DeltaLayout,
        append: impl FnOnce(&mut Pieces<'p>),
    ) -> usize {
        let (count, min, max) = (summary.count, summary.min, summary.max);
        if layout.len == 0 {
            return self.zeros(count);
        }
        let offset = self.align();
        append(self.bin);
        match layout.index_type {
            None => {
                let dense = self.view_at(offset, layout.len, Some(ARRAY_BUFFER));
                self.push(
                    "accessors",
                    json!({"bufferView": dense, "componentType": FLOAT, "count": count,
                        "type": "VEC3", "min": min, "max": max}),
                )
            }
            Some(index_type) => {
                let indices = self.view_at(offset, layout.values_at - layout.padding, None);
                let values = self.view_at(
                    offset + layout.values_at,
                    layout.len - layout.values_at,
                    None,
                );
                self.push(
                    "accessors",
                    json!({"componentType": FLOAT, "count": count, "type": "VEC3",
                        "min": min, "max": max,
                        "sparse": {"count": summary.moved,
                            "indices": {"bufferView": indices, "componentType": index_type},
                            "values": {"bufferView": values}}}),
                )
            }
        }
    }
}

/// What one pass over a morph target's deltas finds: their bounds, how
/// many vertices move, and whether every delta is finite.
pub struct DeltaSummary {
    count: usize,
    /// Every delta is finite.
    pub finite: bool,
    min: [f32; 3],
    max: [f32; 3],
    pub moved: usize,
}

impl DeltaSummary {
    /// The summary of `delta(0)`, ..., `delta(count - 1)`.
    pub fn of(count: usize, delta: impl Fn(usize) -> [f32; 3]) -> Self {
        let mut min = [f32::INFINITY; 3];
        let mut max = [f32::NEG_INFINITY; 3];
        let mut moved = 0;
        let mut finite = true;
        for v in 0..count {
            let d = delta(v);
            for c in 0..3 {
                finite &= d[c].is_finite();
                // Not `f32::min`, whose care for NaN keeps the loop from
                // being vectorised (a NaN is caught by `finite`).
                min[c] = if d[c] < min[c] { d[c] } else { min[c] };
                max[c] = if d[c] > max[c] { d[c] } else { max[c] };
            }
            moved += usize::from(d != [0.0; 3]);
        }
        if moved == 0 {
            (min, max) = ([0.0; 3], [0.0; 3]);
        }
        DeltaSummary {
            count,
            finite,
            min,
            max,
            moved,
        }
    }

    /// How the deltas are stored: no data when none moves, sparse when that
    /// is smaller (and `sparse`), else dense.
    pub fn layout(&self, sparse: bool) -> DeltaLayout {
        let (index_type, index_bytes) = match self.count {
            0..=256 => (5121, 1),
            257..=65536 => (5123, 2),
            _ => (5125, 4),
        };
        if self.moved == 0 {
            DeltaLayout {
                index_type: None,
                index_bytes,
                padding: 0,
                values_at: 0,
                len: 0,
            }
        } else if !sparse || self.moved * (index_bytes + 12) >= self.count * 12 {
            DeltaLayout {
                index_type: None,
                index_bytes,
                padding: 0,
                values_at: 0,
                len: 12 * self.count,
            }
        } else {
            let indices = index_bytes * self.moved;
            let padding = indices.next_multiple_of(4) - indices;
            DeltaLayout {
                index_type: Some(index_type),
                index_bytes,
                padding,
                values_at: indices + padding,
                len: indices + padding + 12 * self.moved,
            }
        }
    }
}

/// The bytes of a morph target's deltas: dense (every delta), or sparse
/// (the moving vertices' indices, padding to 4 bytes, their deltas).
#[derive(Clone, Debug)]
pub struct DeltaLayout {
    /// The sparse indices' component type; `None` for dense deltas.
    pub index_type: Option<u32>,
    index_bytes: usize,
    padding: usize,
    /// Where the sparse deltas start.
    pub values_at: usize,
    /// The bytes in all (0: no data).
    pub len: usize,
}

impl DeltaLayout {
    /// Appends the bytes of `delta(0)`, ... to `bytes`.
    pub fn fill(&self, delta: impl Fn(usize) -> [f32; 3], bytes: &mut Vec<u8>) {
        let start = bytes.len();
        match self.index_type {
            None if self.len > 0 => {
                for v in 0..self.len / 12 {
                    bytes.extend_from_slice(&vector_bytes(delta(v)));
                }
            }
            None => {}
            Some(_) => {
                bytes.resize(start + self.len, 0);
                let (indices, values) = bytes[start..].split_at_mut(self.values_at);
                let (mut i, mut k) = (0, 0);
                for v in 0.. {
                    if k == values.len() {
                        break;
                    }
                    let d = delta(v);
                    if d != [0.0; 3] {
                        indices[i..i + self.index_bytes]
                            .copy_from_slice(&(v as u32).to_le_bytes()[..self.index_bytes]);
                        values[k..k + 12].copy_from_slice(&vector_bytes(d));
                        i += self.index_bytes;
                        k += 12;
                    }
                }
            }
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
pub fn float_bytes(values: &[f32]) -> Vec<u8> {
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
