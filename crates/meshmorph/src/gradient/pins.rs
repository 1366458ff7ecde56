//! Pinned unknowns: vertices held at given positions, and one vertex held
//! in every connected part that nothing else holds.
//!
//! The energies see only gradients, so each connected part of a mesh is
//! free to translate and its normal matrix is singular. Holding one vertex
//! of such a part makes it definite; the part is moved afterwards (see
//! [`Placement`](super::Placement)), so which vertex does not matter.
//! Pinned unknowns are eliminated from the system, which keeps it symmetric
//! positive definite (`solve::PinnedSystem`).

use crate::mesh::topology::Components;

/// Vertices held at given positions, in the order they were pinned.
#[derive(Clone, Debug)]
pub struct Pins<const D: usize> {
    vertices: Vec<usize>,
    values: Vec<[f64; D]>,
    is_pinned: Vec<bool>,
}

impl<const D: usize> Pins<D> {
    /// No pins over `num_vertices` vertices.
    pub(crate) fn new(num_vertices: usize) -> Self {
        Self {
            vertices: Vec::new(),
            values: Vec::new(),
            is_pinned: vec![false; num_vertices],
        }
    }

    /// Holds vertex `v` at `position`; `false` (and nothing held) when `v`
    /// is out of range or already held.
    #[must_use]
    pub(crate) fn pin(&mut self, v: usize, position: [f64; D]) -> bool {
        match self.is_pinned.get_mut(v) {
            Some(p) if !*p => {
                *p = true;
                self.vertices.push(v);
                self.values.push(position);
                true
            }
            _ => false,
        }
    }

    /// Holds one vertex (the first) of every connected part that holds no
    /// pinned vertex, and every unpinned vertex that no triangle uses, at
    /// `rest(v)`, in vertex order. Returns, for each part, whether a pin
    /// given before holds it.
    pub(crate) fn hold_free_parts(
        &mut self,
        parts: &Components,
        rest: impl Fn(usize) -> [f64; D],
    ) -> Vec<bool> {
        let mut held_by_pin = vec![false; parts.count];
        for &v in &self.vertices {
            if let Some(c) = parts.of_vertex[v] {
                held_by_pin[c as usize] = true;
            }
        }
        let mut held = held_by_pin.clone();
        for (v, c) in parts.of_vertex.iter().enumerate() {
            let hold = match c {
                Some(c) => !std::mem::replace(&mut held[*c as usize], true),
                None => !self.is_pinned[v],
            };
            if hold {
                self.is_pinned[v] = true;
                self.vertices.push(v);
                self.values.push(rest(v));
            }
        }
        held_by_pin
    }

    /// Whether vertex `v` is held.
    pub(crate) fn is_pinned(&self, v: usize) -> bool {
        self.is_pinned[v]
    }

    /// The pinned vertices (unknowns), in the order they were pinned.
    pub(crate) fn vertices(&self) -> &[usize] {
        &self.vertices
    }

    /// The values, column-major `#pinned × D`, as the solver takes them.
    pub(crate) fn packed_values(&self) -> Vec<f64> {
        let np = self.values.len();
        let mut packed = vec![0.0; D * np];
        for (q, p) in self.values.iter().enumerate() {
            for i in 0..D {
                packed[i * np + q] = p[i];
            }
        }
        packed
    }
}
