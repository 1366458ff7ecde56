//! A template's shapes put on a user's head from named landmarks.
//!
//! 1. The landmarks (iBUG numbers or aliases, [`landmarks`](super::landmarks))
//!    pair template vertices with points on the head, and the existing
//!    fitting ([`correspond`]) deforms the template head onto the user's
//!    head: the similarity that best fits the landmarks, then the
//!    template's own shape kept while closest points pull it onto the
//!    head.
//! 2. Each vertex of the head finds its place on the deformed template
//!    ([`places`](super::places)): the closest point of a template triangle
//!    facing its way, so that a point of a closed upper lip finds the upper
//!    lip, whose surface faces down there, not the lower one facing up; the
//!    same for eyelids. A few vertices whose places are cut off from all
//!    around them (one lip's vertices that found the other lip, near a
//!    mouth's corner) take their places again from their neighbours'.
//! 3. Each shape is carried by one of two ways ([`CarryMethod`]): the
//!    template's displacements copied through that place (turned and
//!    scaled by the landmarks' similarity), or deformation transfer
//!    ([`Transfer`]) over the triangle correspondence. A vertex whose place
//!    lies on a triangle the template's shape leaves still keeps a delta of
//!    exactly zero either way.
//! 4. The head's separate parts (connected components other than the
//!    largest: eyes, teeth, tongue) each follow the template part nearest
//!    to them rigidly: the turn and shift that best fit that part's own
//!    motion in the shape.

use rayon::prelude::*;

use crate::error::{Error, Result};
use crate::expressions::arkit_names::{arkit_recipes, ShapeRecipe};
use crate::expressions::identity::fit_identity;
use crate::expressions::landmarks::{
    check_landmarks, landmark_name, landmark_number, misplaced_landmarks,
};
use crate::expressions::openings::joined_openings;
use crate::expressions::places::{find_places, Place};
use crate::expressions::template::ExpressionTemplate;
use crate::linalg::matrix::mul_vec;
use crate::linalg::similarity::Similarity;
use crate::linalg::vector::{add, mean_of, scale, sub};
use crate::mesh::closest::{closest_region, SurfaceIndex};
use crate::mesh::seams::Seams;
use crate::mesh::topology::connected_components;
use crate::mesh::Mesh3;
use crate::transfer::markers::Markers;
use crate::transfer::matching::{correspond, deform_onto, CorrespondOptions};
use crate::transfer::pose_transfer::{Transfer, TransferOptions};

/// How the shapes are carried onto the head.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum CarryMethod {
    /// The template's displacements, interpolated at each vertex's place
    /// on the deformed template, turned and scaled by the landmarks' fit.
    #[default]
    Displacements,
    /// Deformation transfer: each template triangle's change of shape
    /// copied to the head's triangles paired with it, the head solved for.
    Transfer,
}

/// Options of [`expressions`].
#[derive(Clone, Debug, Default)]
#[non_exhaustive]
pub struct ExpressionOptions {
    /// How the shapes are carried. Default [`CarryMethod::Displacements`].
    pub method: CarryMethod,
    /// Also carry each shape the other way and report where the two
    /// differ most.
    pub compare: bool,
    /// Keep the template's shapes beyond ARKit's 52 under their own names.
    pub all_shapes: bool,
    /// The fitting's options.
    pub correspond: CorrespondOptions,
}

impl ExpressionOptions {
    /// Sets [`ExpressionOptions::method`].
    pub fn with_method(mut self, method: CarryMethod) -> Self {
        self.method = method;
        self
    }
    /// Sets [`ExpressionOptions::compare`].
    pub fn with_compare(mut self, compare: bool) -> Self {
        self.compare = compare;
        self
    }
    /// Sets [`ExpressionOptions::all_shapes`].
    pub fn with_all_shapes(mut self, all: bool) -> Self {
        self.all_shapes = all;
        self
    }
}

/// The shapes put on a head.
#[derive(Clone, Debug)]
pub struct HeadExpressions {
    /// The shapes' names (ARKit's, then the template's others).
    pub names: Vec<String>,
    /// Each shape's delta of every vertex of the head (zero where it does
    /// not move).
    pub deltas: Vec<Vec<[f64; 3]>>,
    /// ARKit names the template has no shape for.
    pub missing: Vec<String>,
    /// Regions no landmark holds, and other things worth knowing.
    pub warnings: Vec<String>,
    /// One line per shape: how many vertices move, the largest delta, and
    /// with [`ExpressionOptions::compare`] how far the two ways differ.
    pub report: Vec<ShapeReport>,
    /// The head's separate parts and the template part each follows.
    pub parts: Vec<FoundPart>,
}

/// What happened to one shape.
#[derive(Clone, Debug, PartialEq)]
pub struct ShapeReport {
    /// The shape's name.
    pub name: String,
    /// Vertices with a delta that is not zero.
    pub moved: usize,
    /// The largest delta's length, over the head's bounding-box diagonal.
    pub largest: f64,
    /// With [`ExpressionOptions::compare`], the largest distance between
    /// the two ways over the diagonal, and the vertex where it is.
    pub methods_differ: Option<(f64, u32)>,
}

/// A separate part of the head and the template part it follows.
#[derive(Clone, Debug, PartialEq)]
pub struct FoundPart {
    /// The part's number among the head's connected components.
    pub component: u32,
    /// Its vertices.
    pub vertices: usize,
    /// The template part it follows (`None`: none is near, it stays still).
    pub follows: Option<String>,
}

/// Puts `template`'s shapes on `head` from `points`: `(landmark name,
/// position on the head)`.
///
/// # Errors
/// - [`Error::InvalidArgument`] for an unknown landmark name, fewer than
///   [`MIN_LANDMARKS`](super::landmarks::MIN_LANDMARKS), or a landmark the
///   template lacks;
/// - the errors of [`correspond`] and [`Transfer::new`].
pub fn expressions(
    template: &ExpressionTemplate,
    head: &Mesh3,
    points: &[(String, [f64; 3])],
    options: &ExpressionOptions,
) -> Result<HeadExpressions> {
    // Copies of a vertex at seams (texture, normals) are one vertex here.
    let seams = Seams::find(&[head]);
    if seams.is_empty() {
        return expressions_welded(template, head, points, options);
    }
    let mut out = expressions_welded(template, &seams.weld(head), points, options)?;
    for d in &mut out.deltas {
        *d = seams.unweld(d);
    }
    Ok(out)
}

/// [`expressions`] on a head without seams.
fn expressions_welded(
    template: &ExpressionTemplate,
    head: &Mesh3,
    points: &[(String, [f64; 3])],
    options: &ExpressionOptions,
) -> Result<HeadExpressions> {
    let (_, mut warnings) = landmark_markers(template, &template.head, points)?;
    let (recipes, missing) = arkit_recipes(&template.shape_names, options.all_shapes);

    // The head's main surface, apart from its separate parts.
    let comps = connected_components(head.num_vertices(), head.triangles());
    let main = largest_component(head, &comps.of_triangle, comps.count);
    let (surface, surface_vertices) = sub_mesh(head, |t| comps.of_triangle[t] == main)?;
    let surface_index = SurfaceIndex::new(surface.positions(), surface.triangles());

    // The template's head given the head's proportions, where it has a
    // model of heads.
    let fitted = (!template.identity.is_empty())
        .then(|| {
            fit_identity(
                &template.head,
                &template.identity,
                &template.outer.clone().collect::<Vec<_>>(),
                (&surface, &surface_index),
                &landmark_vertices(template, points),
            )
        })
        .flatten()
        .map(|positions| template.head.with_positions(positions))
        .transpose()?;
    let reference = fitted.as_ref().unwrap_or(&template.head);
    let (markers, _) = landmark_markers(template, reference, points)?;
    let (markers, _) = markers.snap(reference, &surface)?;

    // Displacements need only the template's head laid onto the head;
    // transfer (and the comparison) the pairs of triangles too.
    let needs_pairs = options.compare || options.method == CarryMethod::Transfer;
    let (similarity, deformed, correspondence) = if needs_pairs {
        let fit = correspond(reference, &surface, &markers, &options.correspond)?;
        (
            fit.marker_fit,
            fit.deformed_source,
            Some(fit.correspondence),
        )
    } else {
        let (similarity, deformed) = deform_onto(
            reference,
            &surface,
            &surface_index,
            &markers,
            &options.correspond,
        )?;
        (similarity, deformed, None)
    };
    let smooth = similarity.apply_all(reference.positions());
    let found = find_places(&deformed, &smooth, &surface);
    warnings.extend(joined_openings(
        template,
        |v| deformed.positions()[v as usize],
        surface.positions(),
        &found.cut,
    ));
    let places = found.places;
    let diagonal = head.bounding_box_diagonal();

    let by_method = |method: CarryMethod| -> Result<Vec<Vec<[f64; 3]>>> {
        match method {
            CarryMethod::Displacements => Ok(recipes
                .par_iter()
                .map(|r| displaced(template, r, &places, &similarity))
                .collect()),
            CarryMethod::Transfer => {
                let Some(correspondence) = &correspondence else {
                    return Err(Error::InvalidArgument(
                        "transfer needs the pairs of triangles".into(),
                    ));
                };
                let transfer = Transfer::new(
                    reference,
                    &surface,
                    correspondence,
                    &TransferOptions::default(),
                )?;
                recipes
                    .par_iter()
                    .map(|r| {
                        let pose = reference.with_positions(recipe_pose(template, reference, r))?;
                        let out = transfer.apply(&pose)?;
                        Ok(out
                            .iter()
                            .zip(surface.positions())
                            .zip(&places)
                            .map(|((o, p), place)| {
                                if still(template, r, place) {
                                    [0.0; 3]
                                } else {
                                    sub(*o, *p)
                                }
                            })
                            .collect())
                    })
                    .collect()
            }
        }
    };
    let surface_deltas = by_method(options.method)?;
    let other = match (options.compare, options.method) {
        (false, _) => None,
        (true, CarryMethod::Displacements) => Some(by_method(CarryMethod::Transfer)?),
        (true, CarryMethod::Transfer) => Some(by_method(CarryMethod::Displacements)?),
    };

    // Where the two ways differ most, before the deltas go onto the head.
    let methods_differ: Vec<Option<(f64, u32)>> = surface_deltas
        .par_iter()
        .enumerate()
        .map(|(k, d)| {
            other.as_ref().map(|o| {
                let (i, dist) = d
                    .iter()
                    .zip(&o[k])
                    .map(|(a, b)| norm(sub(*a, *b)))
                    .enumerate()
                    .fold(
                        (0, 0.0),
                        |best, (i, x)| if x > best.1 { (i, x) } else { best },
                    );
                (dist / diagonal, surface_vertices[i])
            })
        })
        .collect();

    // Onto the whole head (as they are where the surface is the whole head,
    // in its order), parts following the template's parts.
    let whole_head = surface_vertices.len() == head.num_vertices()
        && surface_vertices
            .iter()
            .enumerate()
            .all(|(i, &v)| v as usize == i);
    let mut deltas: Vec<Vec<[f64; 3]>> = surface_deltas
        .into_par_iter()
        .map(|d| {
            if whole_head {
                return d;
            }
            let mut on_head = vec![[0.0; 3]; head.num_vertices()];
            for (&v, x) in surface_vertices.iter().zip(d) {
                on_head[v as usize] = x;
            }
            on_head
        })
        .collect();
    let parts = follow_parts(
        template,
        head,
        &comps,
        main,
        &recipes,
        &similarity,
        &mut deltas,
    );

    let report = recipes
        .par_iter()
        .zip(&deltas)
        .zip(methods_differ)
        .map(|((r, d), methods_differ)| ShapeReport {
            name: r.name.clone(),
            moved: d.iter().filter(|x| **x != [0.0; 3]).count(),
            largest: d.iter().map(|x| norm(*x)).fold(0.0, f64::max) / diagonal,
            methods_differ,
        })
        .collect();
    Ok(HeadExpressions {
        names: recipes.into_iter().map(|r| r.name).collect(),
        deltas,
        missing,
        warnings,
        report,
        parts,
    })
}

/// Each named point's template vertex (the points that name none left
/// out: [`landmark_markers`] refuses them).
fn landmark_vertices(
    template: &ExpressionTemplate,
    points: &[(String, [f64; 3])],
) -> Vec<(u32, [f64; 3])> {
    points
        .iter()
        .filter_map(|(name, p)| Some((template.landmark(&landmark_number(name)?.to_string())?, *p)))
        .collect()
}

/// The markers from named points, and the warnings about regions none holds.
fn landmark_markers(
    template: &ExpressionTemplate,
    reference: &Mesh3,
    points: &[(String, [f64; 3])],
) -> Result<(Markers, Vec<String>)> {
    let mut numbers = Vec::with_capacity(points.len());
    let mut pairs = Vec::with_capacity(points.len());
    let mut names = Vec::with_capacity(points.len());
    for (name, p) in points {
        let n = landmark_number(name).ok_or_else(|| {
            Error::InvalidArgument(format!(
                "landmark `{name}` is not a template landmark: name one by its iBUG number (1 to 68) or an alias such as noseTip, eyeOuterLeft, mouthCornerRight, chin"
            ))
        })?;
        let v = template.landmark(&n.to_string()).ok_or_else(|| {
            Error::InvalidArgument(format!(
                "the template has no landmark {n} ({})",
                landmark_name(n)
            ))
        })?;
        numbers.push(n);
        pairs.push([reference.positions()[v as usize], *p]);
        names.push(Some(landmark_name(n)));
    }
    let mut warnings = check_landmarks(&numbers)?;
    let (on_template, on_head): (Vec<[f64; 3]>, Vec<[f64; 3]>) =
        pairs.iter().map(|p| (p[0], p[1])).unzip();
    let labels: Vec<String> = points.iter().map(|(name, _)| format!("`{name}`")).collect();
    warnings.extend(misplaced_landmarks(&on_template, &on_head, &labels)?);
    Ok((Markers::from_points(pairs).with_names(names), warnings))
}

pub fn norm(v: [f64; 3]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

/// The component of largest area.
fn largest_component(mesh: &Mesh3, of_triangle: &[u32], count: usize) -> u32 {
    let mut area = vec![0.0; count];
    for (t, a) in mesh.triangle_areas().into_iter().enumerate() {
        area[of_triangle[t] as usize] += a;
    }
    (0..count)
        .max_by(|&a, &b| area[a].total_cmp(&area[b]))
        .unwrap_or(0) as u32
}

/// The triangles `keep` takes, with their vertices renumbered in order,
/// and the original number of each vertex.
fn sub_mesh(mesh: &Mesh3, keep: impl Fn(usize) -> bool) -> Result<(Mesh3, Vec<u32>)> {
    let mut new_of = vec![u32::MAX; mesh.num_vertices()];
    let mut kept = Vec::new();
    let mut triangles = Vec::new();
    for (t, tri) in mesh.triangles().iter().enumerate() {
        if keep(t) {
            triangles.push(tri.map(|v| {
                if new_of[v as usize] == u32::MAX {
                    new_of[v as usize] = kept.len() as u32;
                    kept.push(v);
                }
                new_of[v as usize]
            }));
        }
    }
    let positions = kept.iter().map(|&v| mesh.positions()[v as usize]).collect();
    Ok((Mesh3::new(positions, triangles)?, kept))
}

/// Whether every corner of `place`'s triangle is still in recipe `r`.
fn still(template: &ExpressionTemplate, r: &ShapeRecipe, place: &Place) -> bool {
    let tri = template.head.triangles()[place.triangle as usize];
    r.sources.iter().all(|&k| {
        tri.iter()
            .all(|&v| template.head_deltas[k][v as usize] == [0.0; 3])
    })
}

/// The template's head `reference` (as fitted to the head) in recipe `r`.
fn recipe_pose(template: &ExpressionTemplate, reference: &Mesh3, r: &ShapeRecipe) -> Vec<[f64; 3]> {
    reference
        .positions()
        .iter()
        .enumerate()
        .map(|(v, &p)| add(p, template.recipe_delta(r, v)))
        .collect()
}

/// The template's displacements at each place, turned and scaled by the
/// landmarks' similarity.
fn displaced(
    template: &ExpressionTemplate,
    r: &ShapeRecipe,
    places: &[Place],
    similarity: &Similarity,
) -> Vec<[f64; 3]> {
    let tris = template.head.triangles();
    places
        .iter()
        .map(|place| {
            let tri = tris[place.triangle as usize];
            let d = (0..3).fold([0.0; 3], |acc, i| {
                add(
                    acc,
                    scale(template.recipe_delta(r, tri[i] as usize), place.weights[i]),
                )
            });
            if d == [0.0; 3] {
                d
            } else {
                scale(mul_vec(&similarity.rotation, d), similarity.scale)
            }
        })
        .collect()
}

/// Moves each separate part of the head (a connected component other
/// than `main`) rigidly with the template's parts where it lies: each of
/// its vertices, taken into the template's space by the landmarks' fit,
/// finds the closest point of the template's parts, whose motion in the
/// shape it would follow; the part takes the rigid motion (turn and shift)
/// that best fits those motions. A lower tooth thus moves with the lower
/// teeth and gums whatever the pieces the two are split into, an eyeball
/// turns with the template's eyeball, and a part farther than a tenth of
/// the head's diagonal from every template part stays still.
fn follow_parts(
    template: &ExpressionTemplate,
    head: &Mesh3,
    comps: &crate::mesh::topology::Components,
    main: u32,
    recipes: &[ShapeRecipe],
    similarity: &Similarity,
    deltas: &mut [Vec<[f64; 3]>],
) -> Vec<FoundPart> {
    // The template's parts as one surface; each vertex's part and its
    // number in it.
    let mut positions = Vec::new();
    let mut triangles = Vec::new();
    let mut owner: Vec<(usize, usize)> = Vec::new();
    for (k, part) in template.parts.iter().enumerate() {
        let first = positions.len() as u32;
        positions.extend_from_slice(part.mesh.positions());
        triangles.extend(part.mesh.triangles().iter().map(|t| t.map(|v| v + first)));
        owner.extend((0..part.mesh.num_vertices()).map(|v| (k, v)));
    }
    let index = SurfaceIndex::new(&positions, &triangles);
    let reach = 0.1 * head.bounding_box_diagonal() / similarity.scale;
    let mut found = Vec::new();
    for c in (0..comps.count as u32).filter(|&c| c != main) {
        let vertices: Vec<usize> = (0..head.num_vertices())
            .filter(|&v| comps.of_vertex[v] == Some(c))
            .collect();
        // Where each vertex lies among the template's parts.
        let rest: Vec<[f64; 3]> = vertices
            .iter()
            .map(|&v| inverse_apply(similarity, head.positions()[v]))
            .collect();
        let hits: Vec<([u32; 3], [f64; 3], f64)> = rest
            .iter()
            .filter_map(|&p| {
                let hit = index.closest(p)?;
                let tri = triangles[hit.triangle as usize];
                let corners = tri.map(|v| positions[v as usize]);
                Some((tri, closest_region(p, corners).barycentric(), hit.distance))
            })
            .collect();
        let mean_distance = hits.iter().map(|h| h.2).sum::<f64>() / hits.len().max(1) as f64;
        let near = hits.len() == rest.len() && !hits.is_empty() && mean_distance < reach;
        let follows = near.then(|| {
            let mut count = vec![0usize; template.parts.len()];
            for (tri, _, _) in &hits {
                count[owner[tri[0] as usize].0] += 1;
            }
            let k = (0..count.len()).max_by_key(|&k| count[k]).unwrap_or(0);
            template.parts[k].name.clone()
        });
        if near {
            for (s, r) in recipes.iter().enumerate() {
                let delta_at = |v: u32| {
                    let (k, i) = owner[v as usize];
                    r.sources.iter().fold([0.0; 3], |acc, &src| {
                        add(acc, template.parts[k].deltas[src][i])
                    })
                };
                let moved: Vec<[f64; 3]> = hits
                    .iter()
                    .map(|(tri, w, _)| {
                        tri.iter()
                            .zip(w)
                            .fold([0.0; 3], |acc, (&v, &w)| add(acc, scale(delta_at(v), w)))
                    })
                    .collect();
                if moved.iter().all(|d| *d == [0.0; 3]) {
                    continue;
                }
                let targets: Vec<[f64; 3]> =
                    rest.iter().zip(&moved).map(|(p, d)| add(*p, *d)).collect();
                let Some(motion) = rigid_fit(&rest, &targets) else {
                    continue;
                };
                for (&v, &p) in vertices.iter().zip(&rest) {
                    let q = similarity.apply(motion.apply(p));
                    deltas[s][v] = sub(q, head.positions()[v]);
                }
            }
        }
        found.push(FoundPart {
            component: c,
            vertices: vertices.len(),
            follows,
        });
    }
    found
}

/// The rigid motion (a similarity of scale 1) that best takes `rest` to
/// `posed`.
fn rigid_fit(rest: &[[f64; 3]], posed: &[[f64; 3]]) -> Option<Similarity> {
    let mut fit = Similarity::fit(rest, posed).ok()?;
    // Rigid: the part keeps its size (the fit's own centroid rule places it).
    fit.scale = 1.0;
    fit.translation = sub(mean_of(posed), mul_vec(&fit.rotation, mean_of(rest)));
    Some(fit)
}

/// `s⁻¹(p)` for a similarity `s`.
fn inverse_apply(s: &Similarity, p: [f64; 3]) -> [f64; 3] {
    s.inverse().apply(p)
}
