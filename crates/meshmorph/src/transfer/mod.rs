//! Deformation transfer (Sumner and Popović, SIGGRAPH 2004): markers on
//! two meshes, the similarity and mirror planes that bring the source onto
//! the target, the triangle correspondence built from them ([`matching`]),
//! separate parts carried along, and the transfer of each source pose to
//! the target by one back-substitution ([`pose_transfer`]), and how well the
//! source deformed onto the target fits it ([`fit_report`]).

pub(crate) mod carried_parts;
pub(crate) mod correspondence;
pub(crate) mod fit_report;
pub(crate) mod markers;
pub(crate) mod matching;
pub(crate) mod mirror_plane;
pub(crate) mod partner_parts;
pub(crate) mod pose_transfer;
pub(crate) mod rotation_field;
