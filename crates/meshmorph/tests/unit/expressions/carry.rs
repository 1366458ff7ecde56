use meshmorph::expressions::arkit_names::arkit_recipes;
use meshmorph::expressions::landmarks::landmark_name;
use meshmorph::expressions::template::ExpressionTemplate;
use meshmorph::linalg::matrix::mul_vec;
use meshmorph::linalg::similarity::Similarity;
use meshmorph::linalg::vector::{add, scale, sub};
use meshmorph::mesh::closest::SurfaceIndex;
use meshmorph::mesh::Mesh3;

use meshmorph::expressions::carry::*;
use meshmorph::expressions::landmarks::RECOMMENDED;
use meshmorph::mesh::shapes::rotation_matrix;

/// The template's own head, turned, scaled by 1.3 and moved, with the
/// recommended landmarks where its vertices went.
fn moved_template() -> (
    ExpressionTemplate,
    Mesh3,
    Vec<(String, [f64; 3])>,
    Similarity,
) {
    let t = ExpressionTemplate::arkit();
    let s = Similarity {
        rotation: rotation_matrix([0.1, 0.5, -0.05]),
        scale: 1.3,
        translation: [0.2, -1.0, 3.0],
    };
    let head = t
        .head
        .with_positions(s.apply_all(t.head.positions()))
        .unwrap();
    let points = RECOMMENDED
        .iter()
        .map(|&n| {
            let v = t.landmark(&n.to_string()).unwrap();
            (landmark_name(n), head.positions()[v as usize])
        })
        .collect();
    (t, head, points, s)
}

fn distance(a: [f64; 3], b: [f64; 3]) -> f64 {
    norm(sub(a, b))
}

#[test]
fn the_template_onto_itself_gets_its_own_shapes_with_still_regions_exactly_zero() {
    let (t, head, points, s) = moved_template();
    let out = expressions(&t, &head, &points, &ExpressionOptions::default()).unwrap();
    assert_eq!(out.missing, ["tongueOut"]);
    assert_eq!(out.names.len(), 51);
    assert!(out.warnings.is_empty(), "{:?}", out.warnings);
    let diagonal = head.bounding_box_diagonal();
    let (recipes, _) = arkit_recipes(&t.shape_names, false);
    for (k, r) in recipes.iter().enumerate() {
        let mut worst = 0.0f64;
        for v in t.face.clone() {
            let truth = scale(mul_vec(&s.rotation, t.recipe_delta(r, v)), s.scale);
            worst = worst.max(distance(out.deltas[k][v], truth));
        }
        assert!(worst < 0.002 * diagonal, "{}: {worst}", r.name);
        // Where the template is still, so is the head, exactly: every
        // vertex whose triangles all keep still in the recipe.
        let mut near_motion = vec![false; head.num_vertices()];
        for tri in t.head.triangles() {
            if tri
                .iter()
                .any(|&c| t.recipe_delta(r, c as usize) != [0.0; 3])
            {
                tri.iter().for_each(|&c| near_motion[c as usize] = true);
            }
        }
        for (v, near) in near_motion.iter().enumerate() {
            if !near && t.recipe_delta(r, v) == [0.0; 3] {
                assert_eq!(out.deltas[k][v], [0.0; 3], "{} vertex {v}", r.name);
            }
        }
    }
}

/// A head that is its own mirror image (the template's, a symmetric
/// head, widened towards the jaw and its face lengthened) gets left and
/// right shapes that are each other's mirror images as closely as the
/// template's own are: every ARKit pair (`...Left`, `...Right`), at
/// every vertex, within the template's own difference plus 0.1 % of the
/// diagonal.
#[test]
fn left_and_right_shapes_stay_mirror_images_on_a_symmetric_head() {
    let t = ExpressionTemplate::arkit();
    let d0 = t.head.bounding_box_diagonal();
    let warp = |[x, y, z]: [f64; 3]| {
        let v = y / d0;
        [
            x * (1.08 - 0.4 * v),
            y * 1.06,
            z + 0.03 * (x / d0).powi(2) * d0,
        ]
    };
    let head = t
        .head
        .with_positions(t.head.positions().iter().map(|&p| warp(p)).collect())
        .unwrap();
    let points: Vec<(String, [f64; 3])> = RECOMMENDED
        .iter()
        .map(|&n| {
            let v = t.landmark(&n.to_string()).unwrap();
            (landmark_name(n), head.positions()[v as usize])
        })
        .collect();
    // Each vertex's mirror image: the nearest corner of the nearest
    // triangle to its reflection (the template is symmetric to 0.05 mm).
    let reflect = |p: [f64; 3]| [-p[0], p[1], p[2]];
    let index = SurfaceIndex::new(head.positions(), head.triangles());
    let mirror: Vec<usize> = head
        .positions()
        .iter()
        .map(|&p| {
            let q = reflect(p);
            let hit = index.closest(q).unwrap();
            let tri = head.triangles()[hit.triangle as usize];
            tri.iter()
                .map(|&c| c as usize)
                .min_by(|&a, &b| {
                    distance(head.positions()[a], q).total_cmp(&distance(head.positions()[b], q))
                })
                .unwrap()
        })
        .collect();
    let out = expressions(&t, &head, &points, &ExpressionOptions::default()).unwrap();
    let (recipes, _) = arkit_recipes(&t.shape_names, false);
    let diagonal = head.bounding_box_diagonal();
    let mut pairs = 0;
    for (l, name) in out.names.iter().enumerate() {
        let Some(stem) = name.strip_suffix("Left") else {
            continue;
        };
        let r = out
            .names
            .iter()
            .position(|n| *n == format!("{stem}Right"))
            .unwrap();
        let asymmetry = |delta: &dyn Fn(usize, usize) -> [f64; 3]| {
            t.face
                .clone()
                .map(|v| distance(delta(l, v), reflect(delta(r, mirror[v]))))
                .fold(0.0, f64::max)
        };
        let own = asymmetry(&|k, v| t.recipe_delta(&recipes[k], v)) / d0;
        let carried = asymmetry(&|k, v| out.deltas[k][v]) / diagonal;
        assert!(
            carried <= own + 1e-3,
            "{name}: left and right differ by {:.3} % of the diagonal, the template's by {:.3} %",
            100.0 * carried,
            100.0 * own
        );
        pairs += 1;
    }
    assert!(pairs >= 20, "{pairs} left and right pairs");
}

#[test]
fn eyelids_meet_in_eye_blink_and_lips_in_mouth_close_with_jaw_open() {
    let (t, head, points, _) = moved_template();
    let out = expressions(&t, &head, &points, &ExpressionOptions::default()).unwrap();
    let posed = |name: &str, v: u32| {
        let k = out.names.iter().position(|n| n == name).unwrap();
        add(head.positions()[v as usize], out.deltas[k][v as usize])
    };
    let lm = |n: u8| t.landmark(&n.to_string()).unwrap();
    let diagonal = head.bounding_box_diagonal();
    // Upper lid (38, 39 / 44, 45) to lower lid (42, 41 / 48, 47).
    for (shape, pairs) in [
        ("eyeBlinkRight", [(38, 42), (39, 41)]),
        ("eyeBlinkLeft", [(44, 48), (45, 47)]),
    ] {
        for (up, low) in pairs {
            let open = distance(
                head.positions()[lm(up) as usize],
                head.positions()[lm(low) as usize],
            );
            let closed = distance(posed(shape, lm(up)), posed(shape, lm(low)));
            assert!(
                closed < 0.2 * open && closed < 0.003 * diagonal,
                "{shape} {up}-{low}: {open} -> {closed}"
            );
        }
    }
    // jawOpen and mouthClose together: the inner lips (63, 67) as close
    // as the template's own shapes bring them (ARKit's mouthClose is
    // made to be added to jawOpen; the FaceKit's leaves them 7 mm
    // apart on its head, against 0.8 mm at rest).
    let jaw = out.names.iter().position(|n| n == "jawOpen").unwrap();
    let close = out.names.iter().position(|n| n == "mouthClose").unwrap();
    let both = |v: u32| {
        let v = v as usize;
        add(
            head.positions()[v],
            add(out.deltas[jaw][v], out.deltas[close][v]),
        )
    };
    let rest = distance(
        head.positions()[lm(63) as usize],
        head.positions()[lm(67) as usize],
    );
    let open = distance(posed("jawOpen", lm(63)), posed("jawOpen", lm(67)));
    let shut = distance(both(lm(63)), both(lm(67)));
    let own = |v: u32| {
        let v = v as usize;
        let d = add(
            t.head_deltas[t.shape("jawOpen").unwrap()][v],
            t.head_deltas[t.shape("mouthClose").unwrap()][v],
        );
        add(t.head.positions()[v], d)
    };
    let template_shut = 1.3 * distance(own(lm(63)), own(lm(67)));
    assert!(open > 4.0 * shut, "{rest} {open} {shut}");
    assert!(
        (shut - template_shut).abs() < 0.001 * diagonal,
        "{template_shut} {shut}"
    );
}

#[test]
fn too_few_or_unknown_landmarks_are_refused() {
    let (t, head, points, _) = moved_template();
    let err = expressions(&t, &head, &points[..8], &ExpressionOptions::default())
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("8 landmarks given") && err.contains("mouthCornerLeft"),
        "{err}"
    );
    let mut bad = points.clone();
    bad[0].0 = "elbow".into();
    let err = expressions(&t, &head, &bad, &ExpressionOptions::default())
        .unwrap_err()
        .to_string();
    assert!(err.contains("`elbow`"), "{err}");
}

#[test]
fn separate_parts_follow_their_template_part_rigidly() {
    let t = ExpressionTemplate::arkit();
    // The head with the template's lower teeth and left eye as parts of
    // the same mesh.
    let mut positions = t.head.positions().to_vec();
    let mut triangles = t.head.triangles().to_vec();
    let mut ranges = Vec::new();
    for name in ["teethLower", "eyeLeft"] {
        let p = t.parts.iter().find(|p| p.name == name).unwrap();
        let first = positions.len() as u32;
        positions.extend_from_slice(p.mesh.positions());
        triangles.extend(p.mesh.triangles().iter().map(|tri| tri.map(|v| v + first)));
        ranges.push((name, first as usize..positions.len()));
    }
    let head = Mesh3::new(positions, triangles).unwrap();
    let points: Vec<(String, [f64; 3])> = RECOMMENDED
        .iter()
        .map(|&n| {
            (
                n.to_string(),
                head.positions()[t.landmark(&n.to_string()).unwrap() as usize],
            )
        })
        .collect();
    let out = expressions(&t, &head, &points, &ExpressionOptions::default()).unwrap();
    // The lower teeth are many pieces, the eye two: each follows its
    // own template part, every vertex of them accounted for.
    let following = |name: &str| -> usize {
        out.parts
            .iter()
            .filter(|p| p.follows.as_deref() == Some(name))
            .map(|p| p.vertices)
            .sum()
    };
    assert_eq!(
        following("teethLower"),
        ranges[0].1.len(),
        "{:?}",
        out.parts
    );
    assert_eq!(following("eyeLeft"), ranges[1].1.len(), "{:?}", out.parts);
    for (shape, part, moves) in [
        ("jawOpen", 0, true),
        ("eyeLookUpLeft", 1, true),
        ("eyeBlinkLeft", 0, false),
    ] {
        let k = out.names.iter().position(|n| n == shape).unwrap();
        let range = ranges[part].1.clone();
        let d = &out.deltas[k];
        assert_eq!(range.clone().any(|v| d[v] != [0.0; 3]), moves, "{shape}");
        // Rigid: edge lengths kept.
        for tri in head
            .triangles()
            .iter()
            .filter(|tri| range.contains(&(tri[0] as usize)))
        {
            let [a, b, _] = tri.map(|v| v as usize);
            let before = distance(head.positions()[a], head.positions()[b]);
            let after = distance(
                add(head.positions()[a], d[a]),
                add(head.positions()[b], d[b]),
            );
            assert!((after - before).abs() < 1e-9, "{shape}");
        }
    }
}
