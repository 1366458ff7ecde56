//! The library's tests, one binary: invariants over families of procedural
//! meshes, every bad input and the files read and written back. One binary
//! links the library once (each integration test file used to be a program
//! of its own). The real meshes of ../shared/data are checked in
//! `shared_data`, a binary whose harness reports them as ignored where the
//! folder is absent.

mod common;
mod fit;
mod gltf_files;
mod gltf_read;
mod gltf_shape_keys;
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
