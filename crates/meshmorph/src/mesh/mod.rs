//! The triangle mesh and its queries: adjacency and edges, welded seams,
//! bounding-volume trees, closest points and nearest vertices, frames of
//! positions, and procedural shapes for tests, examples and benchmarks.

pub mod bvh;
pub mod closest;
pub mod frame_source;
pub mod map_stretch;
pub mod nearest_vertices;
pub mod seams;
pub mod shapes;
pub mod surface_point;
pub mod topology;
pub mod triangle_mesh;

pub use map_stretch::map_stretch;
pub use surface_point::SurfacePoint;
pub use triangle_mesh::signed_areas;
pub use triangle_mesh::{
    bounding_box_diagonal, check_areas, check_finite, check_overflow, used_vertices,
};
pub use triangle_mesh::{Mesh, Mesh2, Mesh3};
