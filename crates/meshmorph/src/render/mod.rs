//! Pictures of meshes: SVG, GIF.
