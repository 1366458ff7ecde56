use meshmorph::mesh::topology::Components;
use meshmorph::mesh::Mesh3;

use meshmorph::mesh::shapes::tube;
use meshmorph::mesh::topology::connected_components;
use meshmorph::transfer::partner_parts::*;

/// The `pairs` (source triangle, target triangle) whose parts are partners
/// (see the module documentation), in their order; `source_components`
/// are the source's connected parts.
fn between_partner_parts(
    pairs: Vec<[u32; 2]>,
    source: &Mesh3,
    source_components: &Components,
    target: &Mesh3,
) -> Vec<[u32; 2]> {
    let target_components = connected_components(target.num_vertices(), target.triangles());
    if source_components.count <= 1 && target_components.count <= 1 {
        return pairs;
    }
    Partners::new(
        &pairs,
        source,
        source_components,
        target,
        &target_components,
    )
    .keep(pairs)
}

fn parts(m: &Mesh3) -> Components {
    connected_components(m.num_vertices(), m.triangles())
}

/// `m` with only the triangles whose vertices all `keep` (its vertices
/// all kept).
fn with_triangles_of(m: &Mesh3, keep: &dyn Fn(u32) -> bool) -> Mesh3 {
    let tris: Vec<[u32; 3]> = m
        .triangles()
        .iter()
        .copied()
        .filter(|t| t.iter().all(|&v| keep(v)))
        .collect();
    Mesh3::new(m.positions().to_vec(), tris).unwrap()
}

/// `a` and `b` (moved by `by`) as one mesh.
fn joined(a: &Mesh3, b: &Mesh3, by: [f64; 3]) -> Mesh3 {
    let n = a.num_vertices() as u32;
    let mut positions = a.positions().to_vec();
    positions.extend(
        b.positions()
            .iter()
            .map(|p| [p[0] + by[0], p[1] + by[1], p[2] + by[2]]),
    );
    let mut triangles = a.triangles().to_vec();
    triangles.extend(b.triangles().iter().map(|t| t.map(|v| v + n)));
    Mesh3::new(positions, triangles).unwrap()
}

#[test]
fn an_eye_pairs_with_the_eye_and_a_split_body_with_the_whole() {
    let (head, eye) = (tube(2.0, 0.5, 9, 8), tube(0.2, 0.1, 3, 6));
    let mesh = joined(&head, &eye, [1.0, 0.55, 0.0]);
    let (h, e) = (head.num_triangles() as u32, eye.num_triangles() as u32);
    // Every triangle with itself, and a few of the eye with the head
    // and of the head with the eye, both ways.
    let mut pairs: Vec<[u32; 2]> = (0..h + e).map(|t| [t, t]).collect();
    pairs.extend([[h, 3], [h + 1, 4], [5, h + 2], [6, h + 3]]);
    let kept = between_partner_parts(pairs.clone(), &mesh, &parts(&mesh), &mesh);
    assert_eq!(kept, (0..h + e).map(|t| [t, t]).collect::<Vec<_>>());
    // A target in two pieces (the head cut in half along its rings) and
    // a source in one: every pair is kept.
    let near = with_triangles_of(&head, &|v| v < 4 * 8);
    let far = with_triangles_of(&head, &|v| (4 * 8..9 * 8).contains(&v));
    let split = joined(&near, &far, [0.0; 3]);
    let n = near.num_triangles() as u32;
    let pairs: Vec<[u32; 2]> = (0..split.num_triangles() as u32)
        .map(|t| [if t < n { t } else { t + 2 * 8 }, t])
        .collect();
    assert_eq!(
        between_partner_parts(pairs.clone(), &head, &parts(&head), &split),
        pairs
    );
}

#[test]
fn a_source_eye_gives_nothing_to_skin_its_partner_covers() {
    // Source: a head and an eye; target: the head alone. The eye pairs
    // with two skin triangles the source's head covers too, and with one
    // it alone covers (as a source hand cut off at a seam covers the
    // target's hand): only that pair is kept.
    let (head, eye) = (tube(2.0, 0.5, 9, 8), tube(0.2, 0.1, 3, 6));
    let source = joined(&head, &eye, [1.0, 0.55, 0.0]);
    let h = head.num_triangles() as u32;
    let mut pairs: Vec<[u32; 2]> = (0..h).filter(|&t| t != 7).map(|t| [t, t]).collect();
    pairs.extend([[h, 3], [h + 1, 4], [h + 2, 7]]);
    pairs.sort_unstable();
    let kept = between_partner_parts(pairs.clone(), &source, &parts(&source), &head);
    let mut expected: Vec<[u32; 2]> = (0..h).filter(|&t| t != 7).map(|t| [t, t]).collect();
    expected.push([h + 2, 7]);
    expected.sort_unstable();
    assert_eq!(kept, expected);
}

#[test]
fn a_hand_cut_off_keeps_its_pairs_with_the_body_beside_a_watch() {
    // Source: a long body in one piece and a small watch near its far
    // end. Target: the same body cut into a long piece and its end (a
    // hand), which the watch also pairs with.
    let body = tube(10.0, 0.5, 41, 8);
    let watch = tube(0.3, 0.3, 3, 8);
    let source = joined(&body, &watch, [9.5, 0.0, 0.0]);
    let nv = body.num_vertices() as u32;
    let near = with_triangles_of(&body, &|v| v < 37 * 8 || v == nv - 2);
    let far = with_triangles_of(&body, &|v| (37 * 8..41 * 8).contains(&v) || v == nv - 1);
    let target = joined(&near, &far, [0.0; 3]);
    let mut pairs: Vec<[u32; 2]> = Vec::new();
    for (k, t) in target.triangles().iter().enumerate() {
        let t = t.map(|v| v % nv);
        if let Some(s) = body.triangles().iter().position(|&b| b == t) {
            pairs.push([s as u32, k as u32]);
        }
    }
    let hand = near.num_triangles() as u32;
    let (b, w) = (body.num_triangles() as u32, watch.num_triangles() as u32);
    for i in 0..w {
        pairs.push([b + i, hand + (i % 8)]);
    }
    pairs.sort_unstable();
    let with_body = |pairs: &[[u32; 2]]| pairs.iter().filter(|p| p[1] >= hand && p[0] < b).count();
    let kept = between_partner_parts(pairs.clone(), &source, &parts(&source), &target);
    assert!(with_body(&pairs) > 0);
    assert_eq!(with_body(&kept), with_body(&pairs));
}
