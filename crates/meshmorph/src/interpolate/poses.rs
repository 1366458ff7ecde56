//! The per-triangle maps from a rest mesh to its poses (later keys, blend
//! shapes), decomposed into rotations and stretches, and the checks a pose
//! must pass, in the plane and in space.
#![allow(non_snake_case)]

use rayon::prelude::*;

use super::InterpolatorOptions;
use crate::error::{Error, Result, LIST_LIMIT};
use crate::gradient::TriangleMaps;
use crate::interpolate::rotation::Rotations;
use crate::interpolate::Dimension;
use crate::linalg::matrix::Mat;
use crate::linalg::Space;
use crate::mesh::topology::TriangleAdjacency;
use crate::mesh::{check_overflow, Mesh};

/// A pose's principal rotations and symmetric stretches `S`, `A = R S`
/// for the map `A` of each triangle from the rest.
#[derive(Debug)]
pub struct PoseMaps<const D: usize>
where
    Space<D>: Rotations<D>,
{
    pub rotations: Vec<<Space<D> as Rotations<D>>::Principal>,
    pub stretches: Vec<Mat<D>>,
}

/// The maps from `rest` to `pose` (called `name`), decomposed (in
/// parallel); rotations of exactly half a turn settled by their neighbours
/// over `adjacency`.
///
/// # Errors
/// [`Error::InvalidTriangle`] for the first triangle whose map is too
/// large to decompose in floating point (its squares overflow): a pose
/// far larger than the rest.
pub fn decompose<const D: usize>(
    rest: &Mesh<D>,
    adjacency: &TriangleAdjacency,
    pose: &Mesh<D>,
    name: &str,
) -> Result<PoseMaps<D>>
where
    Space<D>: Dimension<D>,
{
    type S<const D: usize> = Space<D>;
    let (mut rotations, stretches): (Vec<_>, Vec<Mat<D>>) = (0..pose.num_triangles())
        .into_par_iter()
        .map(|t| {
            let corners = rest.corners(t);
            let gradients = S::<D>::hat_gradients(&corners, S::<D>::area(&corners));
            let map = S::<D>::linear_map(&corners, &gradients, &pose.corners(t));
            S::<D>::polar(&map)
        })
        .unzip();
    let finite = |t: &usize| {
        S::<D>::angle(&rotations[*t]).is_finite()
            && stretches[*t].iter().flatten().all(|x| x.is_finite())
    };
    if let Some(t) = (0..rotations.len()).find(|t| !finite(t)) {
        return Err(Error::InvalidTriangle {
            triangle: t,
            message: format!(
                "the {name}'s triangle {t} overflows: its map from the first mesh exceeds the range of floating-point numbers; scale the meshes down"
            ),
        });
    }
    S::<D>::settle_half_turns(&mut rotations, adjacency);
    Ok(PoseMaps {
        rotations,
        stretches,
    })
}

/// Checks that each of `poses` has the rest's connectivity, coordinates
/// whose products do not overflow, and no triangle turned over (unless
/// allowed); `role` names them ("key", "blend shape"), numbered from 1.
pub fn check_poses<const D: usize>(
    rest: &Mesh<D>,
    adjacency: &TriangleAdjacency,
    poses: &[Mesh<D>],
    role: &str,
    options: &InterpolatorOptions,
) -> Result<()>
where
    Space<D>: TriangleMaps<D>,
{
    let mut folds = None;
    for (k, pose) in poses.iter().enumerate() {
        let name = format!("{role} {}", k + 1);
        rest.check_same_connectivity(pose, ["the first mesh", &name])?;
        let areas: Vec<f64> = (0..pose.num_triangles())
            .map(|t| Space::<D>::area(&pose.corners(t)))
            .collect();
        check_overflow(&areas, pose.bounding_box_diagonal(), &name)?;
        if !options.allow_flips {
            let folds = folds.get_or_insert_with(|| Space::<D>::rest_folds(rest, adjacency));
            let bad = Space::<D>::turned_over(rest, adjacency, folds, pose.positions());
            if !bad.is_empty() {
                return Err(Error::ReflectedTriangles {
                    mesh: name,
                    count: bad.len(),
                    first: bad.into_iter().take(LIST_LIMIT).collect(),
                });
            }
        }
    }
    Ok(())
}
