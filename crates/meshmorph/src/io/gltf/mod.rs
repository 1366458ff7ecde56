//! glTF 2.0: reading a mesh of a user's file (`.glb`, `.gltf`, `.vrm`),
//! and writing animations and shape keys as binary glTF.
//!
//! - Reading ([`read`], [`GltfDocument`], [`GltfMesh`]): the file is kept
//!   whole (its JSON as a [`serde_json::Value`], its buffers), and one mesh
//!   of it is read for the solvers: the vertices of all its triangle
//!   primitives side by side, their triangles, its morph targets as poses
//!   (names from `mesh.extras.targetNames`), in the mesh's own space (the
//!   bind pose of a skinned mesh), with the node's matrix beside them for
//!   markers and pictures. Sparse accessors, normalised integers
//!   (`KHR_mesh_quantization`), interleaved views and strips and fans are
//!   read; Draco and meshopt compression are refused naming the extension.
//!   Everything else the file holds is kept and not looked at.
//! - Writing back ([`add_shape_keys`], [`write_shape_keys`]): new shapes
//!   added to the user's own file as morph targets of the mesh read, the
//!   rest of the file kept as it was (`shape_keys.rs`).
//! - A character made in code ([`SampleCharacter`]): the demo's and the
//!   tests' rig.
//! - Writing a new GLB of a mesh and its frames ([`write_glb`] and its
//!   kin, `write.rs`).

#[doc(hidden)]
pub mod accessor;
#[doc(hidden)]
pub mod base64;
#[doc(hidden)]
pub mod document;
#[doc(hidden)]
pub mod glb;
#[doc(hidden)]
pub mod mesh;
#[doc(hidden)]
pub mod sample;
#[doc(hidden)]
pub mod shape_keys;
#[doc(hidden)]
pub mod write;

pub use document::{Container, GltfDocument};
pub use mesh::{read, GltfMesh, GltfPrimitive, MorphTarget, VertexBlock};
pub use sample::{SampleCharacter, SampleVrm};
pub use shape_keys::{add_shape_keys, write_shape_keys, NewShape, ShapeKeyOptions};
pub use write::{
    estimate_glb_bytes, vertex_count, write_glb, write_glb_frames, write_glb_to, GltfBase,
    GltfImage, GltfMaterial, GltfMaterials, GltfOptions,
};
