//! How a GLB stores a morph target's deltas: densely (every vertex) or, when
//! that is smaller, sparsely (glTF's sparse accessors: the vertices whose
//! delta is not zero, by index, the others zero); as `f32`, or with
//! KHR_mesh_quantization positions as normalised 16-bit integers.
//!
//! Without quantisation sparse storage is lossless: only deltas that are
//! exactly zero in `f32` are left out, and a normal delta only where no
//! triangle around the vertex moved at all. With it, a position decodes
//! as `center + scale * q / 32767` (the node's translation and scale), so
//! base plus delta is within `scale / 32767` of the frame in every
//! coordinate ([`Quantization::tolerance`]), and deltas under half a step
//! are zero, which sparse storage leaves out.
//!
//! The writer asks twice for each frame (once to size the document, once
//! to stream the data): everything here is a function of the frame, so the
//! two passes agree.

use crate::io::xyz;

/// The largest normalised 16-bit integer.
const STEPS: f64 = 32767.0;

/// Positions as normalised `i16`: `center + scale * q / 32767`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Quantization {
    pub center: [f64; 3],
    pub scale: f64,
}

impl Quantization {
    /// The quantisation that holds `extent` (the largest distance of any
    /// coordinate, of the base, a frame or a delta, from `center`).
    /// Both numbers are rounded to `f32`, as the node stores them, so that
    /// the decoding uses exactly the numbers the encoding used.
    pub fn new(center: [f64; 3], extent: f64) -> Self {
        let scale = if extent > 0.0 { extent } else { 1.0 };
        Quantization {
            center: center.map(|c| f64::from(c as f32)),
            // Rounded up, so that the extent stays within the range.
            scale: f64::from((scale * (1.0 + 1e-6)) as f32),
        }
    }

    /// A bound of quantised deltas from a bound of `f32` ones.
    pub fn delta_bound(&self, b: [f32; 3]) -> [f32; 3] {
        self.delta(b.map(f64::from)).map(f32::from)
    }

    fn steps(&self, x: f64) -> i16 {
        (x / self.scale * STEPS).round().clamp(-STEPS, STEPS) as i16
    }

    /// A base position, quantised.
    pub fn position(&self, p: [f64; 3]) -> [i16; 3] {
        std::array::from_fn(|k| self.steps(p[k] - self.center[k]))
    }

    /// A delta, quantised.
    pub fn delta(&self, d: [f64; 3]) -> [i16; 3] {
        std::array::from_fn(|k| self.steps(d[k]))
    }

    /// The largest error of base plus delta, per coordinate: half a step
    /// each.
    pub fn tolerance(&self) -> f64 {
        self.scale / STEPS
    }
}

/// A target attribute's values, one per glTF vertex.
pub enum Deltas {
    F32(Vec<[f32; 3]>),
    I16(Vec<[i16; 3]>),
}

impl Deltas {
    /// The position deltas of `frame` from `base` at the glTF vertices, in
    /// `f32`.
    pub fn positions<const D: usize>(
        frame: &[[f64; D]],
        base: &[[f64; D]],
        original: &[u32],
    ) -> Deltas {
        Deltas::F32(
            original
                .iter()
                .map(|&v| {
                    let (f, b) = (xyz(&frame[v as usize]), xyz(&base[v as usize]));
                    std::array::from_fn(|k| (f[k] - b[k]) as f32)
                })
                .collect(),
        )
    }

    /// These `f32` deltas quantised (from the `f32` values, so that the
    /// quantised bounds follow from the `f32` ones: rounding keeps the
    /// order).
    ///
    /// # Panics
    /// If the deltas are quantised already.
    pub fn quantized(&self, q: &Quantization) -> Deltas {
        match self {
            Deltas::F32(v) => Deltas::I16(v.iter().map(|d| q.delta(d.map(f64::from))).collect()),
            Deltas::I16(_) => panic!("deltas quantised twice"),
        }
    }

    /// The glTF vertices whose delta is not zero.
    pub fn moved(&self) -> Vec<u32> {
        fn nonzero<T: Copy + Default + PartialEq>(values: &[[T; 3]]) -> Vec<u32> {
            let zero = T::default();
            (0..values.len() as u32)
                .filter(|&i| values[i as usize].iter().any(|&x| x != zero))
                .collect()
        }
        match self {
            Deltas::F32(v) => nonzero(v),
            Deltas::I16(v) => nonzero(v),
        }
    }

    /// Per coordinate minimum and maximum, as the accessor states them
    /// (the stored numbers: integers for quantised deltas).
    pub fn bounds(&self) -> ([f32; 3], [f32; 3]) {
        let mut lo = [f32::INFINITY; 3];
        let mut hi = [f32::NEG_INFINITY; 3];
        let mut take = |p: [f32; 3]| {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        };
        match self {
            Deltas::F32(v) => v.iter().for_each(|&p| take(p)),
            Deltas::I16(v) => v.iter().for_each(|p| take(p.map(f32::from))),
        }
        (lo, hi)
    }

    fn value_bytes(&self) -> usize {
        match self {
            Deltas::F32(_) => 12,
            Deltas::I16(_) => 6,
        }
    }

    /// The values of `entries` (all, when dense), little-endian, each
    /// vertex `stride` bytes (padded with zeros).
    fn write_values(&self, out: &mut Vec<u8>, entries: Option<&[u32]>, stride: usize) {
        let mut one = |i: usize| {
            let start = out.len();
            match self {
                Deltas::F32(v) => v[i]
                    .iter()
                    .for_each(|x| out.extend_from_slice(&x.to_le_bytes())),
                Deltas::I16(v) => v[i]
                    .iter()
                    .for_each(|x| out.extend_from_slice(&x.to_le_bytes())),
            }
            out.resize(start + stride, 0);
        };
        match entries {
            None => (0..self.len()).for_each(&mut one),
            Some(e) => e.iter().for_each(|&i| one(i as usize)),
        }
    }

    fn len(&self) -> usize {
        match self {
            Deltas::F32(v) => v.len(),
            Deltas::I16(v) => v.len(),
        }
    }
}

/// The glTF vertices whose normal may differ from the base's: those with
/// a triangle around their original vertex that has a corner where `frame`
/// differs from `base` at all. Elsewhere the normal is computed from the
/// same positions, so its delta is exactly zero.
pub(crate) fn normals_changed<const D: usize>(
    frame: &[[f64; D]],
    base: &[[f64; D]],
    triangles: &[[u32; 3]],
    original: &[u32],
) -> Vec<u32> {
    NormalsChanged::find(frame, base, triangles, original).vertices
}

/// Where a frame's normals may differ from the base's.
pub(crate) struct NormalsChanged {
    /// The glTF vertices ([`normals_changed`]).
    pub vertices: Vec<u32>,
    /// The triangles around their original vertices: all a changed
    /// normal is made of.
    pub around: Vec<u32>,
}

impl NormalsChanged {
    /// See [`normals_changed`].
    pub fn find<const D: usize>(
        frame: &[[f64; D]],
        base: &[[f64; D]],
        triangles: &[[u32; 3]],
        original: &[u32],
    ) -> Self {
        let mut touched = vec![false; base.len()];
        for t in triangles {
            if t.iter().any(|&v| frame[v as usize] != base[v as usize]) {
                for &v in t {
                    touched[v as usize] = true;
                }
            }
        }
        let around = (0..triangles.len() as u32)
            .filter(|&t| triangles[t as usize].iter().any(|&v| touched[v as usize]))
            .collect();
        let vertices = (0..original.len() as u32)
            .filter(|&i| touched[original[i as usize] as usize])
            .collect();
        Self { vertices, around }
    }
}

/// How one target attribute is stored: its size decides.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Storage {
    /// glTF vertices.
    pub vertices: usize,
    /// `Some(k)`: sparsely, `k` entries (at least one: glTF's sparse
    /// accessors list one or more); `None`: densely.
    pub entries: Option<usize>,
    /// Bytes of one value: 12 (`f32`) or 6 (`i16`).
    pub value_bytes: usize,
}

impl Storage {
    /// Sparse with `moved` entries when that is smaller than dense.
    pub fn choose(vertices: usize, moved: usize, value_bytes: usize) -> Storage {
        let dense = Storage {
            vertices,
            entries: None,
            value_bytes,
        };
        let sparse = Storage {
            entries: Some(moved.max(1)),
            ..dense
        };
        if sparse.bytes() < dense.bytes() {
            sparse
        } else {
            dense
        }
    }

    /// Whether the values are normalised `i16` (else `f32`).
    pub fn quantized(&self) -> bool {
        self.value_bytes == 6
    }

    /// Bytes a dense vertex takes: attributes start every 4 bytes.
    pub fn stride(&self) -> usize {
        self.value_bytes.next_multiple_of(4)
    }

    /// Bytes of a sparse index.
    pub fn index_bytes(&self) -> usize {
        if self.vertices <= usize::from(u16::MAX) + 1 {
            2
        } else {
            4
        }
    }

    /// The sizes of the buffer views it takes, in order: the dense values,
    /// or the sparse indices and values.
    pub fn views(&self) -> Vec<usize> {
        match self.entries {
            None => vec![self.vertices * self.stride()],
            Some(k) => vec![k * self.index_bytes(), k * self.value_bytes],
        }
    }

    /// Bytes in the buffer, each view padded to 4.
    pub fn bytes(&self) -> usize {
        self.views().iter().map(|b| b.next_multiple_of(4)).sum()
    }

    /// Appends the attribute's views as laid out by [`Storage::views`]:
    /// `moved` are the entries (an empty list stands for vertex 0, whose
    /// delta is then zero).
    pub fn write(&self, out: &mut Vec<u8>, deltas: &Deltas, moved: &[u32]) {
        let pad = |out: &mut Vec<u8>| out.resize(out.len().next_multiple_of(4), 0);
        match self.entries {
            None => deltas.write_values(out, None, self.stride()),
            Some(_) => {
                let entries: &[u32] = if moved.is_empty() { &[0] } else { moved };
                for &i in entries {
                    if self.index_bytes() == 2 {
                        out.extend_from_slice(&(i as u16).to_le_bytes());
                    } else {
                        out.extend_from_slice(&i.to_le_bytes());
                    }
                }
                pad(out);
                deltas.write_values(out, Some(entries), deltas.value_bytes());
            }
        }
        pad(out);
    }
}
