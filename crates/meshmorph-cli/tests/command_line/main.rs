//! The command line end to end, one binary: every subcommand on procedural
//! and real meshes, the catalogue of hostile inputs and outputs, and
//! interrupts. (The glTF client checks, which need Chromium and node, and
//! the README's paths into ../shared/data are a binary of their own:
//! `external`.)

mod cli;
mod common;
mod drawings;
mod expressions;
mod gltf_rigs;
mod hostile;
mod hostile_meshes;
mod hostile_outputs;
mod hostile_reads;
mod interrupt;
mod pick_door;
mod pick_pictures;
mod pick_session;
mod pictures;
