//! interpolate
/// Placeholder.
pub struct Interpolator;
/// Placeholder.
pub struct InterpolatorOptions;
/// Placeholder.
pub enum StretchMode {}
