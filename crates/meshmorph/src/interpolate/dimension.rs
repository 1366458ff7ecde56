//! The two dimensions interpolation runs in, each compiled once in this
//! crate.
//!
//! [`Interpolator`], [`Sequence`], [`Blend`] and [`RestSystem`] are generic
//! over the dimension, and a generic function is compiled anew in every
//! crate that calls it (an optimised build shares no copies between crates).
//! Their heavy work (the setup with its factorization, a frame's pass over
//! the triangles and its substitution, the checks for turned-over
//! triangles) therefore goes through the methods of [`Dimension`], which are
//! implemented for `Space<2>` and `Space<3>` here: not generic, they are
//! compiled with this crate, and a program (or test, or example) that
//! interpolates compiles only the thin generic methods that call them.

use std::sync::Arc;

use crate::error::Result;
use crate::gradient::solve::FactorKind;
use crate::gradient::TriangleMaps;
use crate::interpolate::rotation::Rotations;
use crate::interpolate::Sequence;
use crate::interpolate::{Blend, FrameWorkspace, Interpolator, InterpolatorOptions, RestSystem};
use crate::linalg::Space;
use crate::mesh::Mesh;

mod sealed {
    pub trait Sealed {}
    impl Sealed for crate::linalg::Space<2> {}
    impl Sealed for crate::linalg::Space<3> {}
}

/// The dimensions meshmorph interpolates in: `Space<2>` (planar meshes) and
/// `Space<3>` (surfaces in space). Code generic over the dimension asks for
/// `Space<D>: Dimension<D>`.
///
/// Its methods are the work behind the generic types' methods, one copy
/// per dimension in this crate; call those types' methods instead.
pub trait Dimension<const D: usize>: Rotations<D> + TriangleMaps<D> + sealed::Sealed {
    #[doc(hidden)]
    fn new_interpolator(
        source: &Mesh<D>,
        target: &Mesh<D>,
        options: &InterpolatorOptions,
    ) -> Result<Interpolator<D>>
    where
        Space<D>: Rotations<D> + TriangleMaps<D>;
    #[doc(hidden)]
    fn interpolator_with_rest(
        rest: Arc<RestSystem<D>>,
        target: &Mesh<D>,
        options: &InterpolatorOptions,
    ) -> Result<Interpolator<D>>
    where
        Space<D>: Rotations<D> + TriangleMaps<D>;
    #[doc(hidden)]
    fn new_sequence(keys: &[Mesh<D>], options: &InterpolatorOptions) -> Result<Sequence<D>>
    where
        Space<D>: Rotations<D> + TriangleMaps<D>;
    #[doc(hidden)]
    fn sequence_with_surface(
        rest: Arc<RestSystem<D>>,
        later_keys: &[Mesh<D>],
        options: &InterpolatorOptions,
    ) -> Result<Sequence<D>>
    where
        Space<D>: Rotations<D> + TriangleMaps<D>;
    #[doc(hidden)]
    fn sequence_frames_into(
        sequence: &Sequence<D>,
        times: &[f64],
        outs: &mut [&mut [[f64; D]]],
        ws: &mut FrameWorkspace<D>,
    ) where
        Space<D>: Rotations<D> + TriangleMaps<D>;
    #[doc(hidden)]
    fn sequence_frames(sequence: &Sequence<D>, times: &[f64]) -> Vec<Vec<[f64; D]>>
    where
        Space<D>: Rotations<D> + TriangleMaps<D>;
    #[doc(hidden)]
    fn sequence_turned_over(sequence: &Sequence<D>, positions: &[[f64; D]]) -> usize
    where
        Space<D>: Rotations<D> + TriangleMaps<D>;
    #[doc(hidden)]
    fn sequence_whole_turns(sequence: &Sequence<D>) -> Vec<usize>
    where
        Space<D>: Rotations<D> + TriangleMaps<D>;
    #[doc(hidden)]
    fn new_blend(
        base: &Mesh<D>,
        shapes: &[Mesh<D>],
        options: &InterpolatorOptions,
    ) -> Result<Blend<D>>
    where
        Space<D>: Rotations<D> + TriangleMaps<D>;
    #[doc(hidden)]
    fn blend_with_surface(
        rest: Arc<RestSystem<D>>,
        shapes: &[Mesh<D>],
        options: &InterpolatorOptions,
    ) -> Result<Blend<D>>
    where
        Space<D>: Rotations<D> + TriangleMaps<D>;
    #[doc(hidden)]
    fn blend_at_into(
        blend: &Blend<D>,
        weights: &[f64],
        out: &mut [[f64; D]],
        ws: &mut FrameWorkspace<D>,
    ) where
        Space<D>: Rotations<D> + TriangleMaps<D>;
    #[doc(hidden)]
    fn blend_turned_over(blend: &Blend<D>, positions: &[[f64; D]]) -> usize
    where
        Space<D>: Rotations<D> + TriangleMaps<D>;
    #[doc(hidden)]
    fn new_rest_system(source: &Mesh<D>, name: &str, factor: FactorKind) -> Result<RestSystem<D>>
    where
        Space<D>: Rotations<D> + TriangleMaps<D>;
}

/// `Dimension<D>` for `Space<D>`: every method calls the generic code of
/// the same name, here instantiated for `D`.
macro_rules! compiled_for {
    ($d:literal) => {
        impl Dimension<$d> for Space<$d> {
            fn new_interpolator(
                source: &Mesh<$d>,
                target: &Mesh<$d>,
                options: &InterpolatorOptions,
            ) -> Result<Interpolator<$d>> {
                Interpolator::new_generic(source, target, options)
            }
            fn interpolator_with_rest(
                rest: Arc<RestSystem<$d>>,
                target: &Mesh<$d>,
                options: &InterpolatorOptions,
            ) -> Result<Interpolator<$d>> {
                Interpolator::with_rest_generic(rest, target, options)
            }
            fn new_sequence(
                keys: &[Mesh<$d>],
                options: &InterpolatorOptions,
            ) -> Result<Sequence<$d>> {
                Sequence::new_generic(keys, options)
            }
            fn sequence_with_surface(
                rest: Arc<RestSystem<$d>>,
                later_keys: &[Mesh<$d>],
                options: &InterpolatorOptions,
            ) -> Result<Sequence<$d>> {
                Sequence::with_surface_generic(rest, later_keys, options)
            }
            fn sequence_frames_into(
                sequence: &Sequence<$d>,
                times: &[f64],
                outs: &mut [&mut [[f64; $d]]],
                ws: &mut FrameWorkspace<$d>,
            ) {
                sequence.frames_into_generic(times, outs, ws)
            }
            fn sequence_frames(sequence: &Sequence<$d>, times: &[f64]) -> Vec<Vec<[f64; $d]>> {
                sequence.frames_generic(times)
            }
            fn sequence_turned_over(sequence: &Sequence<$d>, positions: &[[f64; $d]]) -> usize {
                sequence.count_turned_over_generic(positions)
            }
            fn sequence_whole_turns(sequence: &Sequence<$d>) -> Vec<usize> {
                sequence.triangles_with_whole_turns_generic()
            }
            fn new_blend(
                base: &Mesh<$d>,
                shapes: &[Mesh<$d>],
                options: &InterpolatorOptions,
            ) -> Result<Blend<$d>> {
                Blend::new_generic(base, shapes, options)
            }
            fn blend_with_surface(
                rest: Arc<RestSystem<$d>>,
                shapes: &[Mesh<$d>],
                options: &InterpolatorOptions,
            ) -> Result<Blend<$d>> {
                Blend::with_surface_generic(rest, shapes, options)
            }
            fn blend_at_into(
                blend: &Blend<$d>,
                weights: &[f64],
                out: &mut [[f64; $d]],
                ws: &mut FrameWorkspace<$d>,
            ) {
                blend.at_into_generic(weights, out, ws)
            }
            fn blend_turned_over(blend: &Blend<$d>, positions: &[[f64; $d]]) -> usize {
                blend.count_turned_over_generic(positions)
            }
            fn new_rest_system(
                source: &Mesh<$d>,
                name: &str,
                factor: FactorKind,
            ) -> Result<RestSystem<$d>> {
                RestSystem::named_generic(source, name, factor)
            }
        }
    };
}

compiled_for!(2);
compiled_for!(3);
