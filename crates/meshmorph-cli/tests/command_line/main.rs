//! The command line end to end, one binary: every subcommand on procedural
//! and real meshes, the catalogue of hostile inputs and outputs, and
//! interrupts. (The glTF client checks, which need Chromium and node, are
//! a binary of their own: `gltf_clients.rs`.)

mod cli;
mod hostile;
mod hostile_meshes;
mod hostile_outputs;
mod hostile_reads;
mod interrupt;
