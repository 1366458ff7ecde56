//! What a file holds besides positions and polygons, in the form formats
//! of one value per vertex store it (PLY, OFF, and OBJ's vertex colours):
//! normals, texture coordinates, colours. A file written in another format
//! than its own keeps what that format can hold.
//!
//! Normals and texture coordinates are given per face corner by OBJ. Where
//! every corner of a vertex has the same one, it is the vertex's; where they
//! differ (a hard edge, a texture seam), a format of one value per vertex
//! cannot hold them, except PLY's texture coordinates, which then go per
//! face corner (the `texcoord` face lists MeshLab writes).

/// Per-vertex (or per-corner) values to write beside the positions: the
/// normals of one shape, and the file's own texture coordinates and
/// colours, borrowed.
#[derive(Clone, Debug, Default)]
pub struct VertexAttributes<'a> {
    /// One unit normal per vertex.
    pub(super) normals: Option<Vec<[f64; 3]>>,
    /// One `(u, v)` per vertex.
    pub(super) uvs: Option<&'a [[f64; 2]]>,
    /// One `(u, v)` per flat face corner, when the corners of a vertex
    /// differ (only PLY holds them): the values and the index of each
    /// corner's.
    pub(super) corner_uvs: Option<(&'a [[f64; 2]], &'a [u32])>,
    /// One RGBA colour per vertex, 0 to 1, as the file stores it.
    pub(super) colors: Option<&'a [[f32; 4]]>,
}

impl VertexAttributes<'_> {
    /// Whether any colour is not opaque.
    pub(super) fn has_alpha(&self) -> bool {
        self.colors
            .as_ref()
            .is_some_and(|c| c.iter().any(|x| x[3] < 1.0))
    }
}

/// The value of each vertex from the values of the face corners
/// (`vertex_of[c]` and `value(c)` for flat corner `c`): `None` when two
/// corners of a vertex differ. Vertices no face uses take `unused`.
pub fn per_vertex<T: Copy + PartialEq>(
    num_vertices: usize,
    vertex_of: &[u32],
    value: impl Fn(usize) -> T,
    unused: T,
) -> Option<Vec<T>> {
    let mut out: Vec<Option<T>> = vec![None; num_vertices];
    for (c, &v) in vertex_of.iter().enumerate() {
        let x = value(c);
        match &mut out[v as usize] {
            slot @ None => *slot = Some(x),
            Some(y) if *y == x => {}
            Some(_) => return None,
        }
    }
    Some(out.into_iter().map(|x| x.unwrap_or(unused)).collect())
}

/// A colour channel from 0 to 1 as a byte.
#[inline]
pub fn channel_byte(x: f32) -> u8 {
    (x.clamp(0.0, 1.0) * 255.0).round() as u8
}
