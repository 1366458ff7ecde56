//! Deformation transfer (Sumner and Popović, SIGGRAPH 2004): markers on
//! two meshes, the similarity and mirror planes that bring the source onto
//! the target, the triangle correspondence built from them ([`matching`]),
//! separate parts carried along, and the transfer of each source pose to
//! the target by one back-substitution ([`pose_transfer`]), and how well the
//! source deformed onto the target fits it ([`fit_report`]).

pub mod carried_parts;
pub mod correspondence;
pub mod fit_report;
pub mod markers;
pub mod matching;
pub mod mirror_plane;
pub mod partner_parts;
pub mod pose_transfer;
pub mod rotation_field;
