//! An expression template: a neutral head with named shapes (deltas of its
//! vertices), its separate parts (eyes, teeth, ...) with the same shapes,
//! and named landmark vertices. [`ExpressionTemplate::arkit`] is the one
//! meshmorph ships (`templates/arkit.glb`, built from ICT-FaceKit by
//! `tools/arkit-template/build.py`; MIT licence, `templates/LICENSE-ICT-FaceKit`).

use std::ops::Range;

use crate::error::{Error, Result};
use crate::expressions::arkit_names::ShapeRecipe;
use crate::expressions::template_file::read_template_glb;
use crate::linalg::vector::add;
use crate::mesh::Mesh3;

/// The template meshmorph ships: the ICT-FaceKit head in metres, its
/// eyeballs, teeth and gums with tongue, 57 shapes and the 68 iBUG
/// landmarks.
pub const ARKIT_TEMPLATE_GLB: &[u8] = include_bytes!("../../templates/arkit.glb");

/// A neutral head, its shapes, parts and landmarks.
#[derive(Clone, Debug)]
pub struct ExpressionTemplate {
    /// The neutral head (one surface).
    pub head: Mesh3,
    /// The vertices of the face (the region whose error is measured),
    /// all of the head's when the template does not say.
    pub face: Range<usize>,
    /// The shapes' names, in order.
    pub shape_names: Vec<String>,
    /// Each shape's delta of every head vertex.
    pub head_deltas: Vec<Vec<[f64; 3]>>,
    /// Landmark names with their head vertex.
    pub landmarks: Vec<(String, u32)>,
    /// The separate parts, each with a delta of every vertex in every shape.
    pub parts: Vec<TemplatePart>,
    /// The head's identity bases (a linear model of head shapes: the
    /// neutral plus a standard-normal weighted sum of these deltas of every
    /// head vertex is a plausible head), largest first; empty when the
    /// template has none.
    pub identity: Vec<Vec<[f64; 3]>>,
    /// The head's outer surface (the face, the head and the neck, without
    /// the mouth's and eyes' sockets), the vertices fitted to a user's head
    /// with the identity bases; all of the head when the template does not
    /// say.
    pub outer: Range<usize>,
}

/// A separate part of a template (an eyeball, the teeth, ...).
#[derive(Clone, Debug)]
pub struct TemplatePart {
    /// Its name in the template (`eyeLeft`, `teethLower`, ...).
    pub name: String,
    /// Its neutral mesh.
    pub mesh: Mesh3,
    /// Each shape's delta of every vertex.
    pub deltas: Vec<Vec<[f64; 3]>>,
}

impl ExpressionTemplate {
    /// The template meshmorph ships ([`ARKIT_TEMPLATE_GLB`]).
    pub fn arkit() -> Self {
        read_template_glb(ARKIT_TEMPLATE_GLB, "the built-in template")
            .expect("the built-in template reads")
    }

    /// A template from a GLB holding a mesh `head` with named morph targets
    /// (`extras.targetNames`) and landmarks (`extras.landmarks`, a list of
    /// `{"name", "vertex"}`), and other meshes with the same targets as its
    /// parts (the layout of `templates/arkit.glb`). Targets of the head
    /// that `extras.identityBases` names (the last ones) are its identity
    /// model, not shapes: they are fitted to a head before the
    /// correspondence.
    ///
    /// # Errors
    /// [`Error::Parse`] or [`Error::InvalidArgument`] naming the file
    /// `name` (its path, as the user gave it) and the element that is
    /// missing or malformed.
    pub fn from_glb(bytes: &[u8], name: &str) -> Result<Self> {
        read_template_glb(bytes, name)
    }

    /// The index of the shape named `name`.
    pub fn shape(&self, name: &str) -> Option<usize> {
        self.shape_names.iter().position(|n| n == name)
    }

    /// The head vertex of the landmark `name`.
    pub fn landmark(&self, name: &str) -> Option<u32> {
        self.landmarks
            .iter()
            .find(|(n, _)| n == name)
            .map(|&(_, v)| v)
    }

    /// The head in shape `k` (its neutral positions plus the deltas).
    pub fn posed_head(&self, k: usize) -> Vec<[f64; 3]> {
        self.head
            .positions()
            .iter()
            .zip(&self.head_deltas[k])
            .map(|(p, d)| std::array::from_fn(|i| p[i] + d[i]))
            .collect()
    }

    /// The head's delta of vertex `v` in recipe `r`: the sum of its
    /// sources' deltas.
    pub fn recipe_delta(&self, r: &ShapeRecipe, v: usize) -> [f64; 3] {
        r.sources
            .iter()
            .fold([0.0; 3], |acc, &k| add(acc, self.head_deltas[k][v]))
    }

    /// Checks that every shape has a delta for every vertex.
    pub(crate) fn check(&self, what: &str) -> Result<()> {
        let bad = |m: String| Err(Error::InvalidArgument(format!("`{what}`: {m}")));
        if self.head_deltas.len() != self.shape_names.len() {
            return bad(format!(
                "{} shape names for {} shapes",
                self.shape_names.len(),
                self.head_deltas.len()
            ));
        }
        if let Some(d) = self
            .head_deltas
            .iter()
            .position(|d| d.len() != self.head.num_vertices())
        {
            return bad(format!(
                "shape `{}` has {} deltas for a head of {} vertices",
                self.shape_names[d],
                self.head_deltas[d].len(),
                self.head.num_vertices()
            ));
        }
        if let Some((name, v)) = self
            .landmarks
            .iter()
            .find(|(_, v)| *v as usize >= self.head.num_vertices())
        {
            return bad(format!(
                "landmark `{name}` is vertex {v}, the head has {}",
                self.head.num_vertices()
            ));
        }
        if let Some(k) = self
            .identity
            .iter()
            .position(|b| b.len() != self.head.num_vertices())
        {
            return bad(format!(
                "identity basis {k} has {} deltas for a head of {} vertices",
                self.identity[k].len(),
                self.head.num_vertices()
            ));
        }
        if self.outer.start > self.outer.end || self.outer.end > self.head.num_vertices() {
            return bad(format!(
                "the regions `face` and `headNeck` reach vertex {}, the head has {}",
                self.outer.end.max(self.outer.start),
                self.head.num_vertices()
            ));
        }
        for part in &self.parts {
            if part.deltas.len() != self.shape_names.len()
                || part
                    .deltas
                    .iter()
                    .any(|d| d.len() != part.mesh.num_vertices())
            {
                return bad(format!(
                    "part `{}` does not have every shape for every vertex",
                    part.name
                ));
            }
        }
        Ok(())
    }
}
