//! The library's own unit tests, module by module (one file per module of
//! `src/`, at the same path), run against the library as it is built.
#![allow(non_snake_case)]
#![allow(clippy::needless_range_loop)]

mod expressions;
mod gradient;
mod interpolate;
mod io;
mod linalg;
mod mesh;
mod outline;
mod playback;
#[cfg(feature = "render")]
mod render;
mod transfer;
