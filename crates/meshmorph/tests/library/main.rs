//! The library's tests, one binary: invariants over families of procedural
//! meshes, every bad input, the files read and written back, and the real
//! meshes of ../shared/data. One binary links the library once (each
//! integration test file used to be a program of its own).

mod fit;
mod gltf_files;
mod interpolate;
mod io;
mod markers;
mod properties;
mod real_meshes;
mod separate_parts;
mod stl;
mod surfaces;
mod transfer;
mod unused_vertices;
