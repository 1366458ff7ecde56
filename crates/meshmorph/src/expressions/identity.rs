//! The user's head found in the template's model of heads, before the
//! correspondence: the template's neutral head plus a weighted sum of its
//! identity bases (ICT-FaceKit's linear model of head shapes, all 100 of
//! its components shipped), the weights and a similarity fitted to the landmarks
//! and to the head's surface, with the model's prior (the weights
//! standard normal) keeping the fit a plausible head.
//!
//! The correspondence that follows starts from a template of the user's
//! proportions, not the average ones: its closest points then fall where
//! the same feature lies, to a fraction of a millimetre at the creases of
//! the face (a mouth's corners, the lids), where a shape's motion changes
//! by millimetres within one millimetre of surface. A head the model
//! cannot reach is fitted as closely as it allows, and the correspondence
//! does the rest as it did without the model.
//!
//! Setup only: this runs once per head, before any shape is carried.

use faer::linalg::solvers::Solve;
use faer::{Mat, Side};
use rayon::prelude::*;

use crate::linalg::similarity::Similarity;
use crate::linalg::vector::{add, cross, dot, mean_of, norm, scale, sub};
use crate::mesh::closest::{vertex_normals, Angle, SurfaceIndex};
use crate::mesh::Mesh3;

/// At most this many rounds of closest points and solves.
const ROUNDS: usize = 12;

/// The fit has settled when a round brings the head's points closer by
/// less than this fraction of their mean distance.
const SETTLED: f64 = 0.01;

/// How far a template vertex's closest point on the head may lie and still
/// pull the fit, as a fraction of the head's diagonal (in the template's
/// space).
const REACH: f64 = 0.02;

/// How far from a vertex's normal the head's surface there may face.
const FACING: f64 = 60.0;

/// The spread of a closest point's distance that the data term expects,
/// as a fraction of the template's diagonal: each point counts
/// `1 / (SPREAD · diagonal)²` against the prior's `|w|²`.
const SPREAD: f64 = 2e-3;

/// How many surface points a landmark counts as.
const LANDMARK_WEIGHT: f64 = 20.0;

/// The template's head given the proportions of `surface`: `neutral`'s
/// positions plus `Σ w_k bases[k]`, in the template's space (so that the
/// template's shapes, landmarks and parts keep their meaning), fitted to
/// `landmarks` (template vertex, point on the head) and to the head's
/// surface at the template's vertices in `sample`. `None` where the
/// landmarks fix no similarity.
///
/// A head that is its own mirror image (modelled with symmetry, as
/// characters mostly are), where the template is too (across `x = 0`), is
/// fitted twice, as it is and mirrored, and the two fits averaged: a model
/// that is not closed under mirroring (ICT-FaceKit's components are not)
/// fits a symmetric head outside it lopsidedly, and the shapes' left and
/// right would differ (by up to 0.43 % of the diagonal at a vertex in
/// jawLeft against jawRight, measured). Only then: on heads that are not
/// symmetric the mean of the two costs accuracy (the largest vertex error
/// on heads of the model rose from 0.05 to 0.48 % to 0.53 to 2.27 %, as it
/// did with the bases and their mirror images fitted together).
pub fn fit_identity(
    neutral: &Mesh3,
    bases: &[Vec<[f64; 3]>],
    sample: &[usize],
    (surface, index): (&Mesh3, &SurfaceIndex),
    landmarks: &[(u32, [f64; 3])],
) -> Option<Vec<[f64; 3]>> {
    let symmetric =
        mirror_map(neutral).filter(|mirror| is_own_mirror_image(surface, index, landmarks, mirror));
    let Some(mirror) = symmetric else {
        return fit_once(neutral, bases, sample, (index, false), landmarks);
    };
    // The same fit of the head's mirror image (its landmarks on the
    // template's mirror vertices), mirrored back: their mean is symmetric,
    // whether or not the model holds the head. The two run side by side.
    let image_landmarks: Vec<(u32, [f64; 3])> = landmarks
        .iter()
        .map(|&(v, p)| (mirror[v as usize] as u32, reflect(p)))
        .collect();
    let mirrored_sample: Vec<usize> = sample.iter().map(|&v| mirror[v]).collect();
    let (fitted, of_image) = rayon::join(
        || fit_once(neutral, bases, sample, (index, false), landmarks),
        || {
            fit_once(
                neutral,
                bases,
                &mirrored_sample,
                (index, true),
                &image_landmarks,
            )
        },
    );
    let (fitted, of_image) = (fitted?, of_image?);
    Some(
        fitted
            .iter()
            .zip(&mirror)
            .map(|(&p, &m)| scale(add(p, reflect(of_image[m])), 0.5))
            .collect(),
    )
}

/// [`fit_identity`] without the mirror image's fit: of the head `surface`
/// indexes, or (`mirrored`) of its mirror image across `x = 0` (the
/// `landmarks` then on the mirror image).
fn fit_once(
    neutral: &Mesh3,
    bases: &[Vec<[f64; 3]>],
    sample: &[usize],
    (index, mirrored): (&SurfaceIndex, bool),
    landmarks: &[(u32, [f64; 3])],
) -> Option<Vec<[f64; 3]>> {
    let k = bases.len();
    // The unknowns: the weights, then the similarity's step.
    let n = k + 7;
    let on_template: Vec<[f64; 3]> = landmarks
        .iter()
        .map(|&(v, _)| neutral.positions()[v as usize])
        .collect();
    let on_head: Vec<[f64; 3]> = landmarks.iter().map(|&(_, p)| p).collect();
    // The head brought into the template's space.
    let mut to_template = Similarity::fit(&on_head, &on_template).ok()?;
    let diagonal = neutral.bounding_box_diagonal();
    let weight_of_point = 1.0 / (SPREAD * diagonal).powi(2);
    let mut shape = neutral.positions().to_vec();
    let image = |p: [f64; 3]| if mirrored { reflect(p) } else { p };
    let mut last_distance = f64::INFINITY;
    for _ in 0..ROUNDS {
        let to_head = to_template.inverse();
        let normals = vertex_normals(&shape, neutral.triangles());
        let reach = REACH * diagonal * to_head.scale;
        // Each sampled vertex's closest point on the head facing its way,
        // in the template's space.
        let hits: Vec<(usize, [f64; 3])> = sample
            .par_iter()
            .filter_map(|&v| {
                let hit = index.closest_compatible(
                    image(to_head.apply(shape[v])),
                    image(to_head.rotate(normals[v])),
                    reach,
                    Angle::degrees(FACING),
                )?;
                Some((v, to_template.apply(image(hit.point))))
            })
            .collect();
        if hits.len() < 3 {
            break;
        }
        // Stop once the head's points stop coming closer.
        let distance = hits
            .iter()
            .map(|&(v, c)| norm(sub(shape[v], c)))
            .sum::<f64>()
            / hits.len() as f64;
        if distance > (1.0 - SETTLED) * last_distance {
            break;
        }
        last_distance = distance;
        let landmarks_now: Vec<[f64; 3]> = on_head.iter().map(|&p| to_template.apply(p)).collect();
        // The weights and a small similarity of the head together (Gauss-
        // Newton): the point-to-plane residuals n·(x_v(w) − c') of the
        // head's points c' = c0 + (1 + δs)(c − c0) + δθ × (c − c0) + δt
        // and the landmarks' point-to-point ones, with the prior |w|².
        let c0 = mean_of(&hits.iter().map(|h| h.1).collect::<Vec<_>>());
        let surface_rows = hits.iter().map(|&(v, c)| {
            let n = normals[v];
            let d = sub(c, c0);
            let mut row: Vec<f64> = bases.iter().map(|b| dot(n, b[v])).collect();
            let dn = cross(d, n);
            row.extend([-n[0], -n[1], -n[2], -dn[0], -dn[1], -dn[2], -dot(n, d)]);
            (row, dot(n, sub(neutral.positions()[v], c)), weight_of_point)
        });
        let landmark_rows = landmarks
            .iter()
            .zip(&landmarks_now)
            .flat_map(|(&(v, _), &p)| {
                (0..3).map(move |axis| {
                    let mut e = [0.0; 3];
                    e[axis] = 1.0;
                    let d = sub(p, c0);
                    let de = cross(d, e);
                    let mut row: Vec<f64> = bases.iter().map(|b| b[v as usize][axis]).collect();
                    row.extend([-e[0], -e[1], -e[2], -de[0], -de[1], -de[2], -d[axis]]);
                    let base = neutral.positions()[v as usize][axis] - p[axis];
                    (row, base, LANDMARK_WEIGHT * weight_of_point)
                })
            });
        let rows: Vec<(Vec<f64>, f64, f64)> = surface_rows.chain(landmark_rows).collect();
        let j = Mat::<f64>::from_fn(rows.len(), n, |i, a| rows[i].0[a] * rows[i].2.sqrt());
        let b = Mat::<f64>::from_fn(rows.len(), 1, |i, _| -rows[i].1 * rows[i].2.sqrt());
        let mut ata = j.transpose() * &j;
        let atb = j.transpose() * &b;
        for a in 0..n {
            // The prior on the weights; a whisper on the similarity's step.
            ata[(a, a)] += if a < k {
                1.0
            } else {
                1e-9 * ata[(a, a)] + 1e-30
            };
        }
        let Ok(llt) = ata.llt(Side::Lower) else {
            break;
        };
        let solution = llt.solve(&atb);
        let w: Vec<f64> = (0..k).map(|a| solution[(a, 0)]).collect();
        let step: [f64; 7] = std::array::from_fn(|i| solution[(k + i, 0)]);
        to_template = to_template.then(&small_similarity(step, c0));
        shape = neutral
            .positions()
            .iter()
            .enumerate()
            .map(|(v, &p)| {
                bases
                    .iter()
                    .zip(&w)
                    .fold(p, |acc, (b, &x)| add(acc, scale(b[v], x)))
            })
            .collect();
    }
    Some(shape)
}

/// `p` mirrored across the plane `x = 0`.
fn reflect([x, y, z]: [f64; 3]) -> [f64; 3] {
    [-x, y, z]
}

/// How far from a vertex's mirror image another vertex may lie and still
/// be taken for it, as a fraction of the diagonal.
const MIRROR_TOLERANCE: f64 = 1e-3;

/// Each vertex's mirror image across the plane `x = 0` (the nearest corner
/// of the nearest triangle to its reflection), where the whole head is its
/// own mirror image within [`MIRROR_TOLERANCE`]; else `None`.
fn mirror_map(neutral: &Mesh3) -> Option<Vec<usize>> {
    let index = SurfaceIndex::new(neutral.positions(), neutral.triangles());
    let tolerance = MIRROR_TOLERANCE * neutral.bounding_box_diagonal();
    neutral
        .positions()
        .par_iter()
        .map(|&p| {
            let q = reflect(p);
            let hit = index.closest(q)?;
            let (v, d) = neutral.triangles()[hit.triangle as usize]
                .iter()
                .map(|&c| (c as usize, norm(sub(neutral.positions()[c as usize], q))))
                .min_by(|a, b| a.1.total_cmp(&b.1))?;
            (d <= tolerance).then_some(v)
        })
        .collect()
}

/// How many rounds of closest points lay a head's mirror image onto it.
const MIRROR_ROUNDS: usize = 4;

/// How far from a head its laid mirror image may lie, as a fraction of its
/// diagonal, for the head to count as its own mirror image: a head
/// modelled with symmetry is so to its coordinates' rounding; heads of the
/// FaceKit's model are not, by a tenth of a millimetre and more.
const SYMMETRIC: f64 = 1e-4;

/// Whether `surface` is its own mirror image: reflected, then laid onto
/// itself (first by the similarity that best takes each landmark's mirror
/// partner, its template vertex's mirror, onto it, then by closest
/// points), every 16th vertex lies within [`SYMMETRIC`] of the diagonal of
/// the surface.
fn is_own_mirror_image(
    surface: &Mesh3,
    index: &SurfaceIndex,
    landmarks: &[(u32, [f64; 3])],
    mirror: &[usize],
) -> bool {
    let (from, to): (Vec<[f64; 3]>, Vec<[f64; 3]>) = landmarks
        .iter()
        .filter_map(|&(v, p)| {
            let partner = mirror[v as usize] as u32;
            let (_, q) = landmarks.iter().find(|l| l.0 == partner)?;
            Some((reflect(*q), p))
        })
        .unzip();
    let Ok(mut lay) = Similarity::fit(&from, &to) else {
        return false;
    };
    // The landmarks, placed by hand, lay it roughly; closest points
    // finish it.
    let probes: Vec<[f64; 3]> = surface.positions().iter().step_by(16).copied().collect();
    for _ in 0..MIRROR_ROUNDS {
        let (moved, onto): (Vec<[f64; 3]>, Vec<[f64; 3]>) = probes
            .par_iter()
            .filter_map(|&p| {
                let hit = index.closest(lay.apply(reflect(p)))?;
                Some((reflect(p), hit.point))
            })
            .unzip();
        match Similarity::fit(&moved, &onto) {
            Ok(better) => lay = better,
            Err(_) => return false,
        }
    }
    let tolerance = SYMMETRIC * surface.bounding_box_diagonal();
    probes.par_iter().all(|&p| {
        index
            .closest(lay.apply(reflect(p)))
            .is_some_and(|hit| hit.distance <= tolerance)
    })
}

/// The similarity `p ↦ c0 + (1 + δs) R(δθ) (p − c0) + δt` of a step
/// `[δt, δθ, δs]` (`R(δθ)` the turn by `|δθ|` about `δθ`).
fn small_similarity(step: [f64; 7], c0: [f64; 3]) -> Similarity {
    let t = [step[0], step[1], step[2]];
    let axis = [step[3], step[4], step[5]];
    let angle = norm(axis);
    let rotation = if angle > 0.0 {
        let u = scale(axis, 1.0 / angle);
        let (s, c) = angle.sin_cos();
        std::array::from_fn(|i| {
            std::array::from_fn(|j| {
                let k = [[0.0, -u[2], u[1]], [u[2], 0.0, -u[0]], [-u[1], u[0], 0.0]][i][j];
                let id = if i == j { 1.0 } else { 0.0 };
                id + s * k + (1.0 - c) * (u[i] * u[j] - id)
            })
        })
    } else {
        Similarity::IDENTITY.rotation
    };
    let turn = Similarity {
        rotation,
        scale: 1.0 + step[6],
        translation: [0.0; 3],
    };
    Similarity {
        translation: add(sub(c0, turn.apply(c0)), t),
        ..turn
    }
}
