use meshmorph::interpolate::rotation::Rotations;
use meshmorph::interpolate::Dimension;
use meshmorph::interpolate::{InterpolatorOptions, TRIANGLES_PER_STEP as STEP};
use meshmorph::linalg::matrix::{identity, lerp, mul};
use meshmorph::linalg::Space;
use meshmorph::mesh::Mesh;

use meshmorph::interpolate::sequence::*;
use meshmorph::mesh::shapes::{bend, curl, strip, tube, twist};

/// The folded rows of every triangle, segment and a few times are the
/// rows of its map `R_u S_u` (the rotation from key 0, the stretch
/// interpolated linearly) computed the long way.
fn folded_rows_are_the_maps_rows<const D: usize>(keys: &[Mesh<D>])
where
    Space<D>: Dimension<D>,
{
    let options = InterpolatorOptions::default();
    let sequence = Sequence::new(keys, &options).unwrap();
    let rest = &*sequence.rest;
    let (unfolded, _) = segments(&keys[0], &sequence.adjacency, &keys[1..], &options).unwrap();
    let mut turns_at = Vec::new();
    for (folded, long) in sequence.segments.iter().zip(&unfolded) {
        let SegmentStretches::Fitted(fits) = &folded.stretches else {
            panic!("linear stretches are folded");
        };
        for u in [0.3, 0.8, 1.7] {
            Space::<D>::turns_at(&long.turns, u, &mut turns_at);
            for t in 0..keys[0].num_triangles() {
                let R = Space::<D>::segment_at(&long.rotations[t], &turns_at, u, long.first);
                let S = match &long.stretches {
                    SegmentStretches::FromIdentity(v) => lerp(&identity(), &v[t], u),
                    SegmentStretches::Linear(v) => lerp(&v[t].0, &v[t].1, u),
                    _ => unreachable!(),
                };
                let expected = rest.fit_rows(t, &mul(R, S));
                // One frame, and two frames side by side, with the
                // triangle first and last in a step.
                let both = [turns_at.clone(), turns_at.clone()];
                let mut one = [[[0.0; D]; 3]; STEP];
                fitted_rows_of_step::<D, 1, STEP>(folded, fits, t, &both, &[u], &mut one[..1]);
                let mut two = [[[0.0; D]; 3]; 2 * STEP];
                let start = t.saturating_sub(STEP - 1);
                let (rows, at) = (&mut two[..2 * (t - start + 1)], 2 * (t - start));
                fitted_rows_of_step::<D, 2, { 2 * STEP }>(
                    folded,
                    fits,
                    start,
                    &both,
                    &[u, u],
                    rows,
                );
                let two = [rows[at], rows[at + 1]];
                let scale = expected
                    .iter()
                    .flatten()
                    .fold(1.0f64, |m, x| m.max(x.abs()));
                for got in [one[0], two[0], two[1]] {
                    for (e, g) in expected.iter().flatten().zip(got.iter().flatten()) {
                        assert!(
                            (e - g).abs() < 1e-12 * scale,
                            "triangle {t} at {u}: {e} against {g}"
                        );
                    }
                }
            }
        }
    }
}

#[test]
fn folded_rows_in_space_and_in_the_plane() {
    let t = tube(4.0, 0.3, 21, 10);
    folded_rows_are_the_maps_rows(&[
        t.clone(),
        bend(&t, 4.0, 3.0 * std::f64::consts::PI),
        twist(&bend(&t, 4.0, 1.0), 4.0, 2.0),
    ]);
    let s = strip(10.0, 0.5, 40, 2);
    folded_rows_are_the_maps_rows(&[s.clone(), curl(&s, 2.0), curl(&s, 7.0)]);
}
