//! The triangle mesh and its queries: adjacency and edges, welded seams,
//! bounding-volume trees, closest points and nearest vertices, frames of
//! positions, and procedural shapes for tests, examples and benchmarks.

pub(crate) mod bvh;
pub(crate) mod closest;
pub(crate) mod frame_source;
pub(crate) mod nearest_vertices;
pub(crate) mod seams;
pub mod shapes;
pub(crate) mod surface_point;
pub(crate) mod topology;
mod triangle_mesh;

pub use surface_point::SurfacePoint;
pub(crate) use triangle_mesh::signed_areas;
pub(crate) use triangle_mesh::{
    bounding_box_diagonal, check_areas, check_finite, check_overflow, used_vertices,
};
pub use triangle_mesh::{Mesh, Mesh2, Mesh3};
