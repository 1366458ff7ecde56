//! The GLB writer, read back with the `gltf` crate: every frame's positions
//! to `f32` precision, texture coordinates across seams, target names, the
//! animation, and clear refusals of bad input.

use std::f64::consts::PI;
use std::path::Path;

use meshmorph::io::gltf::{
    estimate_glb_bytes, write_glb, write_glb_frames, write_glb_to, GltfBase, GltfOptions,
};
use meshmorph::shapes::{bend, curl, strip, tube};
use meshmorph::{Error, FrameSource, Interpolator, InterpolatorOptions};

/// A morph target's position and normal deltas.
type Deltas = (Vec<[f32; 3]>, Vec<[f32; 3]>);

/// What a GLB holds, as the `gltf` crate reads it.
struct ReadBack {
    /// Base positions per glTF vertex.
    positions: Vec<[f32; 3]>,
    normals: Vec<[f32; 3]>,
    uvs: Option<Vec<[f32; 2]>>,
    indices: Vec<u32>,
    /// Per morph target, the position and normal deltas.
    targets: Vec<Deltas>,
    target_names: Vec<String>,
    /// Keyframe times and weights of the animation, if any.
    animation: Option<(Vec<f32>, Vec<f32>)>,
    weights: Vec<f32>,
}

fn read_back(bytes: &[u8]) -> ReadBack {
    let glb = gltf::Gltf::from_slice(bytes).expect("the gltf crate reads the GLB");
    let blob = glb.blob.as_deref().expect("a binary chunk");
    let doc = &glb.document;
    assert_eq!(doc.meshes().count(), 1);
    let mesh = doc.meshes().next().unwrap();
    let prim = mesh.primitives().next().unwrap();
    let reader = prim.reader(|_| Some(blob));
    let extras: serde_json::Value =
        serde_json::from_str(mesh.extras().as_ref().expect("mesh extras").get()).unwrap();
    let target_names = extras["targetNames"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_str().unwrap().to_string())
        .collect();
    let animation = doc.animations().next().map(|a| {
        let channel = a.channels().next().unwrap();
        assert_eq!(
            channel.target().property(),
            gltf::animation::Property::MorphTargetWeights
        );
        let r = channel.reader(|_| Some(blob));
        let times: Vec<f32> = r.read_inputs().unwrap().collect();
        let weights = match r.read_outputs().unwrap() {
            gltf::animation::util::ReadOutputs::MorphTargetWeights(w) => w.into_f32().collect(),
            _ => panic!("weights expected"),
        };
        (times, weights)
    });
    ReadBack {
        positions: reader.read_positions().unwrap().collect(),
        normals: reader.read_normals().unwrap().collect(),
        uvs: reader.read_tex_coords(0).map(|t| t.into_f32().collect()),
        indices: reader.read_indices().unwrap().into_u32().collect(),
        targets: reader
            .read_morph_targets()
            .map(|(p, n, _)| (p.unwrap().collect(), n.unwrap().collect()))
            .collect(),
        target_names,
        animation,
        weights: mesh.weights().unwrap_or(&[]).to_vec(),
    }
}

fn glb<const D: usize>(
    base: &GltfBase<'_, D>,
    frames: &[Vec<[f64; D]>],
    names: &[String],
    options: &GltfOptions,
) -> meshmorph::Result<Vec<u8>> {
    let mut bytes = Vec::new();
    write_glb_to(
        &mut bytes,
        Path::new("test.glb"),
        base,
        frames,
        names,
        options,
    )?;
    Ok(bytes)
}

fn names(n: usize) -> Vec<String> {
    (0..n).map(|k| format!("frame_{k:04}")).collect()
}

/// `|a - b|` within `f32` rounding of numbers of size `scale`.
fn close(a: f32, b: f64, scale: f64) -> bool {
    (f64::from(a) - b).abs() <= 4.0 * f64::from(f32::EPSILON) * scale.max(1.0)
}

/// Asserts that base + delta of target `k` reproduces `frame` at every glTF
/// vertex, with `original[i]` the frame vertex of glTF vertex `i`.
fn assert_frames<const D: usize>(back: &ReadBack, frames: &[Vec<[f64; D]>], original: &[usize]) {
    let scale = frames
        .iter()
        .flatten()
        .flatten()
        .fold(0.0f64, |m, x| m.max(x.abs()));
    assert_eq!(back.targets.len(), frames.len());
    for (k, frame) in frames.iter().enumerate() {
        let deltas = &back.targets[k].0;
        for (i, &v) in original.iter().enumerate() {
            for c in 0..3 {
                let want = if c < D { frame[v][c] } else { 0.0 };
                let got = back.positions[i][c] + deltas[i][c];
                assert!(
                    close(got, want, scale),
                    "frame {k}, vertex {v}, coordinate {c}: {got} vs {want}"
                );
            }
        }
    }
}

#[test]
fn planar_interpolation_reads_back_frame_by_frame() {
    let bar = strip(6.0, 0.5, 24, 2);
    let spiral = curl(&bar, 2.0 * PI);
    let morph = Interpolator::new(&bar, &spiral, &InterpolatorOptions::default()).unwrap();
    let times = [0.0, 0.25, 0.5, 0.75, 1.0];
    let frames = morph.frames(&times);
    let options = GltfOptions::default().with_fps(10.0);
    let base = GltfBase::new(bar.positions(), bar.triangles());
    let bytes = glb(&base, &frames, &names(5), &options).unwrap();
    let back = read_back(&bytes);
    let identity: Vec<usize> = (0..bar.num_vertices()).collect();
    assert_eq!(back.positions.len(), bar.num_vertices());
    assert_frames(&back, &frames, &identity);
    assert!(back.positions.iter().all(|p| p[2] == 0.0), "planar: z = 0");
    assert!(
        back.normals.iter().all(|n| *n == [0.0, 0.0, 1.0]),
        "+z normals"
    );
    assert!(back
        .targets
        .iter()
        .all(|t| t.1.iter().all(|n| *n == [0.0; 3])));
    let want: Vec<u32> = bar.triangles().iter().flatten().copied().collect();
    assert_eq!(back.indices, want);
    assert_eq!(back.target_names, names(5));
    let (t, w) = back.animation.expect("an animation");
    assert_eq!(t, vec![0.0, 0.1, 0.2, 0.3, 0.4]);
    for k in 0..5 {
        for j in 0..5 {
            assert_eq!(w[5 * k + j], if j == k { 1.0 } else { 0.0 }, "one-hot");
        }
    }
    // The estimate is close to what was written.
    let estimate = estimate_glb_bytes::<2>(bar.num_vertices(), bar.num_triangles(), 5, false);
    let ratio = estimate as f64 / bytes.len() as f64;
    assert!((0.7..1.5).contains(&ratio), "{estimate} vs {}", bytes.len());
}

/// Texture coordinates of a tube unrolled: u around (0 to 1, so the seam
/// vertices carry both 0 and 1), v along.
fn tube_uvs(mesh: &meshmorph::Mesh3) -> Vec<[[f32; 2]; 3]> {
    let p = mesh.positions();
    mesh.triangles()
        .iter()
        .map(|t| {
            let angle = |v: u32| {
                let q = p[v as usize];
                q[2].atan2(q[1]).rem_euclid(2.0 * PI) / (2.0 * PI)
            };
            let mut u = t.map(angle);
            // Corners past the seam read 1 rather than 0.
            if u.iter().any(|&x| x > 0.75) {
                for x in &mut u {
                    if *x < 0.25 {
                        *x += 1.0;
                    }
                }
            }
            std::array::from_fn(|k| [u[k] as f32, (p[t[k] as usize][0] / 4.0) as f32])
        })
        .collect()
}

#[test]
fn poses_in_space_with_texture_seams_read_back() {
    let rest = tube(4.0, 0.5, 9, 12);
    let uvs = tube_uvs(&rest);
    let poses: Vec<Vec<[f64; 3]>> = [0.3, 0.9, 1.6]
        .iter()
        .map(|&a| bend(&rest, 4.0, a).positions().to_vec())
        .collect();
    let base = GltfBase::new(rest.positions(), rest.triangles()).with_corner_uvs(&uvs);
    let pose_names = vec!["a".to_string(), "b".into(), "c".into()];
    let bytes = glb(&base, &poses, &pose_names, &GltfOptions::default()).unwrap();
    let back = read_back(&bytes);
    // The seam splits its vertices: one more ring of 9, and both caps'
    // centres.
    assert_eq!(back.positions.len(), rest.num_vertices() + 9 + 2);
    let uv_back = back.uvs.as_ref().expect("TEXCOORD_0");
    // Every triangle corner: the original position and the given (u, 1 - v).
    let mut original = vec![usize::MAX; back.positions.len()];
    for (t, (tri, corners)) in rest.triangles().iter().zip(&uvs).enumerate() {
        for k in 0..3 {
            let i = back.indices[3 * t + k] as usize;
            let v = tri[k] as usize;
            original[i] = v;
            for c in 0..3 {
                assert!(close(back.positions[i][c], rest.positions()[v][c], 1.0));
            }
            assert_eq!(uv_back[i], [corners[k][0], 1.0 - corners[k][1]]);
        }
    }
    assert_frames(&back, &poses, &original);
    // Normals: unit, and base + delta is the pose's normal (unit again).
    for n in &back.normals {
        let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
        assert!((len - 1.0).abs() < 1e-5);
    }
    for (_, dn) in &back.targets {
        for (n, d) in back.normals.iter().zip(dn) {
            let m: [f32; 3] = std::array::from_fn(|c| n[c] + d[c]);
            let len = (m[0] * m[0] + m[1] * m[1] + m[2] * m[2]).sqrt();
            assert!((len - 1.0).abs() < 1e-4, "{len}");
        }
    }
    assert_eq!(back.target_names, pose_names);
}

#[test]
fn shapes_only_has_no_animation_and_zero_weights() {
    let rest = tube(4.0, 0.5, 5, 8);
    let poses = vec![bend(&rest, 4.0, 1.0).positions().to_vec()];
    let base = GltfBase::new(rest.positions(), rest.triangles());
    let options = GltfOptions::default().with_animation(false);
    let back = read_back(&glb(&base, &poses, &["smile".into()], &options).unwrap());
    assert!(back.animation.is_none());
    assert_eq!(back.weights, vec![0.0]);
    assert_eq!(back.target_names, vec!["smile".to_string()]);
}

#[test]
fn unused_vertices_are_left_out() {
    let positions = vec![[0.0, 0.0], [9.0, 9.0], [1.0, 0.0], [0.0, 1.0]];
    let triangles = vec![[0, 2, 3]];
    let frames = vec![vec![[0.0, 0.0], [5.0, 5.0], [2.0, 0.0], [0.0, 2.0]]];
    let base = GltfBase::new(&positions, &triangles);
    let back = read_back(&glb(&base, &frames, &names(1), &GltfOptions::default()).unwrap());
    assert_eq!(back.positions.len(), 3);
    assert_eq!(back.indices, vec![0, 1, 2]);
    assert_frames(&back, &frames, &[0, 2, 3]);
}

#[test]
fn bad_input_is_refused_and_leaves_no_file() {
    let positions = vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
    let triangles = vec![[0, 1, 2]];
    let base = GltfBase::new(&positions, &triangles);
    let good = vec![positions.clone()];
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("out.glb");
    let opts = GltfOptions::default();
    let expect = |r: meshmorph::Result<()>, parts: &[&str]| {
        let e = r.expect_err("refused").to_string();
        for p in parts {
            assert!(e.contains(p), "`{p}` not in: {e}");
        }
        assert!(!path.exists());
        assert_eq!(
            std::fs::read_dir(dir.path()).unwrap().count(),
            0,
            "no leftovers"
        );
    };
    let nan = vec![
        positions.clone(),
        vec![[0.0, 0.0], [f64::NAN, 0.0], [0.0, 1.0]],
    ];
    expect(
        write_glb(&path, &base, &nan, &names(2), &opts),
        &[
            "out.glb",
            "frame 1",
            "frame_0001",
            "vertex 1",
            "not a finite number",
        ],
    );
    let short = vec![vec![[0.0, 0.0]]];
    expect(
        write_glb(&path, &base, &short, &names(1), &opts),
        &["frame 0", "1 vertices", "3"],
    );
    expect(
        write_glb(&path, &base, &good, &names(1), &opts.clone().with_fps(0.0)),
        &["frame rate"],
    );
    expect(
        write_glb(
            &path,
            &base,
            &good,
            &names(1),
            &opts.clone().with_fps(f64::INFINITY),
        ),
        &["frame rate"],
    );
    // Rates whose `float` times would overflow or all round to 0.
    for fps in [1e-20, 1e50] {
        expect(
            write_glb(&path, &base, &good, &names(1), &opts.clone().with_fps(fps)),
            &["frame rate must be from 0.01 to 1000"],
        );
    }
    expect(
        write_glb(&path, &base, &good, &names(2), &opts),
        &["1 frames but 2 names"],
    );
    let none: Vec<Vec<[f64; 2]>> = Vec::new();
    expect(write_glb(&path, &base, &none, &[], &opts), &["no frames"]);
    let bad_uvs = [[[0.0, 0.0], [f32::NAN, 0.0], [0.0, 1.0]]];
    expect(
        write_glb(
            &path,
            &base.with_corner_uvs(&bad_uvs),
            &good,
            &names(1),
            &opts,
        ),
        &["triangle 0", "texture coordinates"],
    );
    let missing = dir.path().join("no/such/folder/out.glb");
    let e = write_glb(&missing, &base, &good, &names(1), &opts).unwrap_err();
    assert!(matches!(e, Error::Io { .. }), "{e}");
    assert!(e.to_string().contains("no/such/folder/out.glb"), "{e}");
    assert!(!missing.exists());
}

/// An interpolation's frames, computed each time they are asked for,
/// counting the requests.
struct OnDemand<'a> {
    morph: &'a Interpolator<2>,
    times: &'a [f64],
    asked: std::sync::atomic::AtomicUsize,
}

impl FrameSource<2> for OnDemand<'_> {
    fn num_frames(&self) -> usize {
        self.times.len()
    }
    fn with_frame(&self, k: usize, use_frame: &mut dyn FnMut(&[[f64; 2]])) {
        self.asked
            .fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        use_frame(&self.morph.at(self.times[k]))
    }
}

#[test]
fn frames_on_demand_write_the_same_file_as_frames_in_memory() {
    let bar = strip(6.0, 0.5, 24, 2);
    let spiral = curl(&bar, 2.0 * PI);
    let morph = Interpolator::new(&bar, &spiral, &InterpolatorOptions::default()).unwrap();
    let times: Vec<f64> = (0..13).map(|k| k as f64 / 12.0).collect();
    let base = GltfBase::new(bar.positions(), bar.triangles());
    let options = GltfOptions::default();
    let held = glb(&base, &morph.frames(&times), &names(13), &options).unwrap();
    let dir = std::env::temp_dir().join(format!("meshmorph-gltf-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("streamed.glb");
    let source = OnDemand {
        morph: &morph,
        times: &times,
        asked: 0.into(),
    };
    write_glb_frames(&path, &base, &source, &names(13), &options).unwrap();
    let streamed = std::fs::read(&path).unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    assert_eq!(held, streamed);
    // Once for the bounds, once for the data.
    assert_eq!(source.asked.into_inner(), 2 * 13);
}

/// A tube's corner normal groups with the ring at `hard` a hard edge:
/// corners of its vertices in triangles on either side get different
/// groups.
fn hard_ring_groups(mesh: &meshmorph::Mesh3, segments: u32, hard: u32) -> Vec<[u32; 3]> {
    mesh.triangles()
        .iter()
        .map(|t| {
            let ring = |v: u32| v / segments;
            // The triangle's side of the hard ring: its lowest ring.
            let below = t.iter().map(|&v| ring(v)).min().unwrap() < hard;
            t.map(|v| u32::from(ring(v) == hard && below))
        })
        .collect()
}

#[test]
fn hard_edges_of_the_file_stay_hard_in_every_frame() {
    let (rings, segments) = (9, 12);
    let rest = tube(4.0, 0.5, rings, segments);
    let groups = hard_ring_groups(&rest, segments as u32, 4);
    let poses: Vec<Vec<[f64; 3]>> = [0.6, 1.5]
        .iter()
        .map(|&a| bend(&rest, 4.0, a).positions().to_vec())
        .collect();
    let smooth = read_back(
        &glb(
            &GltfBase::new(rest.positions(), rest.triangles()),
            &poses,
            &names(2),
            &GltfOptions::default(),
        )
        .unwrap(),
    );
    let base = GltfBase::new(rest.positions(), rest.triangles()).with_corner_normal_groups(&groups);
    let hard = read_back(&glb(&base, &poses, &names(2), &GltfOptions::default()).unwrap());
    // The hard ring's vertices are split in two.
    assert_eq!(smooth.positions.len(), rest.num_vertices());
    assert_eq!(hard.positions.len(), rest.num_vertices() + segments);
    // At the hard ring (x = 2, the tube's middle), the two sides' normals
    // are the normals of their own faces: in the straight tube both point
    // away from the axis but lean apart along it (each side's faces alone),
    // while the smooth vertex's normal has no x component.
    let at_ring = |back: &ReadBack| -> Vec<[f32; 3]> {
        (0..back.positions.len())
            .filter(|&i| (back.positions[i][0] - 2.0).abs() < 1e-6)
            .map(|i| back.normals[i])
            .collect()
    };
    for n in at_ring(&smooth) {
        assert!(n[0].abs() < 1e-6, "{n:?}");
    }
    // On a straight tube both sides' faces are parallel to the axis: the
    // hard ring's normals equal the smooth ones there; bent, they differ.
    let bent = |back: &ReadBack, k: usize| -> Vec<[f32; 3]> {
        (0..back.positions.len())
            .filter(|&i| (back.positions[i][0] - 2.0).abs() < 1e-6)
            .map(|i| std::array::from_fn(|c| back.normals[i][c] + back.targets[k].1[i][c]))
            .collect()
    };
    let (hard_bent, smooth_bent) = (bent(&hard, 1), bent(&smooth, 1));
    assert_eq!(hard_bent.len(), 2 * segments);
    assert_eq!(smooth_bent.len(), segments);
    // Each pair of copies (one place) leans apart along the bend, up to
    // about a band's turn (1.5 rad over 8 bands: 0.19 rad) on the inside
    // and outside of the bend (none on its flanks), the smooth normal
    // between them.
    let angle = |a: [f32; 3], b: [f32; 3]| {
        let dot: f32 = (0..3).map(|c| a[c] * b[c]).sum::<f32>()
            / (0..3).map(|c| a[c] * a[c]).sum::<f32>().sqrt()
            / (0..3).map(|c| b[c] * b[c]).sum::<f32>().sqrt();
        dot.clamp(-1.0, 1.0).acos()
    };
    let places = |back: &ReadBack| -> Vec<[f32; 3]> {
        (0..back.positions.len())
            .filter(|&i| (back.positions[i][0] - 2.0).abs() < 1e-6)
            .map(|i| back.positions[i])
            .collect()
    };
    let (hard_places, smooth_places) = (places(&hard), places(&smooth));
    let mut widest: f32 = 0.0;
    for (k, p) in hard_places.iter().enumerate().take(segments) {
        let twin = (segments..2 * segments)
            .find(|&m| hard_places[m] == *p)
            .expect("a copy");
        let s = smooth_places
            .iter()
            .position(|q| q == p)
            .expect("the smooth vertex");
        let apart = angle(hard_bent[k], hard_bent[twin]);
        widest = widest.max(apart);
        let (a, b) = (
            angle(hard_bent[k], smooth_bent[s]),
            angle(hard_bent[twin], smooth_bent[s]),
        );
        assert!(
            a < apart && b < apart && (a + b - apart).abs() < 0.01,
            "vertex {k}: {a} {b} {apart}"
        );
    }
}

/// A 2 x 2 RGBA PNG.
fn tiny_png() -> Vec<u8> {
    let mut bytes = Vec::new();
    let mut encoder = png::Encoder::new(&mut bytes, 2, 2);
    encoder.set_color(png::ColorType::Rgba);
    encoder.set_depth(png::BitDepth::Eight);
    let mut writer = encoder.write_header().unwrap();
    writer
        .write_image_data(&[
            255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 255, 255, 255, 255,
        ])
        .unwrap();
    writer.finish().unwrap();
    bytes
}

/// An OBJ of three faces: one before any `usemtl`, a textured quad and a
/// translucent triangle, with its material library and texture.
fn write_looks(dir: &Path, with_texture: bool) -> std::path::PathBuf {
    std::fs::create_dir_all(dir.join("tex")).unwrap();
    if with_texture {
        std::fs::write(dir.join("tex/skin.png"), tiny_png()).unwrap();
    }
    std::fs::write(
        dir.join("looks.mtl"),
        "newmtl Skin\nNs 250\nKd 0.8 0.5 0.4\nmap_Kd -bm 1 tex/skin.png\n\nnewmtl Glass\nKd 0.2 0.4 0.9\nd 0.5\nPr 0.1\n",
    )
    .unwrap();
    let obj = dir.join("looks.obj");
    std::fs::write(
        &obj,
        "mtllib looks.mtl\n\
         v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nv 1 1 0.2\nv 2 1 0\nv 3 0 0\n\
         vt 0 0\nvt 0.5 0\nvt 1 0\nvt 0 1\nvt 0.5 1\nvt 1 1\nvt 1 0.5\n\
         f 1/1 2/2 5/5 4/4\nusemtl Skin\nf 2/2 3/3 6/6 5/5\nusemtl Glass\nf 3/3 7/7 6/6\nusemtl Unused\n",
    )
    .unwrap();
    obj
}

#[test]
fn obj_materials_and_textures_are_carried() {
    use meshmorph::io::{Appearance, MeshFile};
    let dir = tempfile::tempdir().unwrap();
    let obj = write_looks(dir.path(), true);
    let file = MeshFile::read(&obj).unwrap();
    let look = Appearance::of_file(&file, u64::MAX).unwrap();
    assert!(look.warnings.is_empty(), "{:?}", look.warnings);
    let positions = file.mesh().positions();
    let frame: Vec<[f64; 3]> = positions
        .iter()
        .map(|p| [p[0], p[1], p[2] + p[0]])
        .collect();
    let base = look.base(positions, file.mesh().triangles());
    let bytes = glb(&base, &[frame], &names(1), &GltfOptions::default()).unwrap();

    let glb = gltf::Gltf::from_slice(&bytes).unwrap();
    let blob = glb.blob.as_deref().unwrap();
    let mesh = glb.document.meshes().next().unwrap();
    let mut seen = Vec::new();
    for prim in mesh.primitives() {
        let material = prim.material();
        let pbr = material.pbr_metallic_roughness();
        let reader = prim.reader(|_| Some(blob));
        let triangles = reader.read_indices().unwrap().into_u32().count() / 3;
        let image = pbr.base_color_texture().map(|info| {
            let source = info.texture().source();
            let gltf::image::Source::View { view, mime_type } = source.source() else {
                panic!("an embedded image");
            };
            assert_eq!(mime_type, "image/png");
            blob[view.offset()..view.offset() + view.length()].to_vec()
        });
        // Every primitive shares the morph target: the frame reads back.
        let base: Vec<[f32; 3]> = reader.read_positions().unwrap().collect();
        let (delta, _, _) = reader.read_morph_targets().next().unwrap();
        for (b, d) in base.iter().zip(delta.unwrap()) {
            assert!((b[2] + d[2] - (b[2] + b[0])).abs() < 1e-6);
        }
        seen.push((
            material.name().unwrap().to_string(),
            triangles,
            pbr.base_color_factor(),
            material.alpha_mode(),
            pbr.roughness_factor(),
            image,
        ));
    }
    assert_eq!(seen.len(), 3);
    // A material no face uses is left out.
    assert_eq!(glb.document.materials().count(), 3);
    let (skin, glass, none) = (&seen[0], &seen[1], &seen[2]);
    assert_eq!((skin.0.as_str(), skin.1), ("Skin", 2));
    assert_eq!(skin.2, [1.0; 4], "the texture is the colour");
    assert_eq!(skin.5.as_deref(), Some(&tiny_png()[..]));
    assert!((skin.4 - 0.5).abs() < 1e-6, "roughness from Ns 250");
    assert_eq!((glass.0.as_str(), glass.1), ("Glass", 1));
    assert_eq!(glass.2, [0.2, 0.4, 0.9, 0.5]);
    assert_eq!(glass.3, gltf::material::AlphaMode::Blend);
    assert!((glass.4 - 0.1).abs() < 1e-6);
    assert_eq!(glass.5, None);
    assert_eq!((none.1, none.2), (2, [0.8, 0.8, 0.8, 1.0]));
}

#[test]
fn missing_textures_and_undefined_materials_are_warned_of() {
    use meshmorph::io::{Appearance, MeshFile};
    let dir = tempfile::tempdir().unwrap();
    let obj = write_looks(dir.path(), false);
    let text = std::fs::read_to_string(&obj)
        .unwrap()
        .replace("usemtl Glass", "usemtl Gold");
    std::fs::write(&obj, text).unwrap();
    let file = MeshFile::read(&obj).unwrap();
    let look = Appearance::of_file(&file, u64::MAX).unwrap();
    let all = look.warnings.join("\n");
    assert!(all.contains("skin.png") && all.contains("`Skin`"), "{all}");
    assert!(all.contains("`Gold`") && all.contains("grey"), "{all}");
    let base = look.base(file.mesh().positions(), file.mesh().triangles());
    let bytes = glb(
        &base,
        &[file.mesh().positions().to_vec()],
        &names(1),
        &GltfOptions::default(),
    )
    .unwrap();
    let glb = gltf::Gltf::from_slice(&bytes).unwrap();
    assert_eq!(glb.document.images().count(), 0);
    assert_eq!(
        glb.document.meshes().next().unwrap().primitives().count(),
        3
    );
}

#[test]
fn vertex_colours_of_ply_obj_and_off_become_color_0() {
    use meshmorph::io::{Appearance, MeshFile};
    let dir = tempfile::tempdir().unwrap();
    let ply = dir.path().join("c.ply");
    std::fs::write(
        &ply,
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n\
         property uchar red\nproperty uchar green\nproperty uchar blue\nproperty uchar alpha\n\
         element face 1\nproperty list uchar int vertex_indices\nend_header\n\
         0 0 0 255 0 0 255\n1 0 0 0 255 0 128\n0 1 0 0 0 51 255\n3 0 1 2\n",
    )
    .unwrap();
    let obj = dir.path().join("c.obj");
    std::fs::write(
        &obj,
        "v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 0 1 0 0 0 0.2\nf 1 2 3\n",
    )
    .unwrap();
    let off = dir.path().join("c.off");
    std::fs::write(
        &off,
        "COFF\n3 1 0\n0 0 0 255 0 0 255\n1 0 0 0 255 0 255\n0 1 0 0 0 51 255\n3 0 1 2\n",
    )
    .unwrap();
    let srgb = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 0.2]];
    for path in [&ply, &obj, &off] {
        let file = MeshFile::read(path).unwrap();
        let colors = file.vertex_colors().expect("vertex colours");
        for (c, want) in colors.iter().zip(&srgb) {
            for k in 0..3 {
                assert!((c[k] - want[k]).abs() < 1e-6, "{}: {c:?}", path.display());
            }
        }
        let look = Appearance::of_file(&file, u64::MAX).unwrap();
        assert!(look.warnings.is_empty(), "{:?}", look.warnings);
        let base = look.base(file.mesh().positions(), file.mesh().triangles());
        let bytes = glb(
            &base,
            &[file.mesh().positions().to_vec()],
            &names(1),
            &GltfOptions::default(),
        )
        .unwrap();
        let glb = gltf::Gltf::from_slice(&bytes).unwrap();
        let blob = glb.blob.as_deref().unwrap();
        let prim = glb
            .document
            .meshes()
            .next()
            .unwrap()
            .primitives()
            .next()
            .unwrap();
        assert_eq!(
            prim.material().pbr_metallic_roughness().base_color_factor(),
            [1.0; 4]
        );
        let got: Vec<[f32; 4]> = prim
            .reader(|_| Some(blob))
            .read_colors(0)
            .expect("COLOR_0")
            .into_rgba_f32()
            .collect();
        // 0.2 in sRGB is 0.0331 linear; alpha stays as stored.
        assert!((got[2][2] - 0.033_105).abs() < 1e-4, "{got:?}");
        assert_eq!(got[0][0], 1.0);
        // A translucent vertex makes the material blended.
        let blended = prim.material().alpha_mode() == gltf::material::AlphaMode::Blend;
        if path == &ply {
            assert!((got[1][3] - 128.0 / 255.0).abs() < 1e-6);
            assert!(blended);
        } else {
            assert!(!blended);
        }
    }
}

#[test]
fn flat_shaded_faces_keep_their_own_normals_even_when_they_share_one_vn() {
    use meshmorph::io::{Appearance, MeshFile};
    let dir = tempfile::tempdir().unwrap();
    // Two coplanar quads naming one normal, as exporters write flat faces.
    let body = "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nv 1 1 0\nv 2 1 0\nvn 0 0 1\n";
    let faces = "f 1//1 2//1 5//1 4//1\nf 2//1 3//1 6//1 5//1\n";
    let count = |shading: &str| {
        let path = dir
            .path()
            .join(format!("{}.obj", shading.replace(' ', "_")));
        std::fs::write(&path, format!("{body}{shading}\n{faces}")).unwrap();
        let file = MeshFile::read(&path).unwrap();
        let look = Appearance::of_file(&file, u64::MAX).unwrap();
        // The second quad folded up about x = 1.
        let folded: Vec<[f64; 3]> = file
            .mesh()
            .positions()
            .iter()
            .map(|p| if p[0] > 1.5 { [1.0, p[1], 1.0] } else { *p })
            .collect();
        let base = look.base(file.mesh().positions(), file.mesh().triangles());
        let back = read_back(&glb(&base, &[folded], &names(1), &GltfOptions::default()).unwrap());
        // The normals of the vertices on the fold (x = 1) in the folded frame.
        let mut at_fold: Vec<[f32; 3]> = (0..back.positions.len())
            .filter(|&i| back.positions[i][0] == 1.0)
            .map(|i| std::array::from_fn(|c| back.normals[i][c] + back.targets[0].1[i][c]))
            .collect();
        at_fold.sort_by(|a, b| a.partial_cmp(b).unwrap());
        (back.positions.len(), at_fold)
    };
    // Flat: each quad its own vertices, and on the fold one normal per face
    // (+z and -x).
    let (vertices, normals) = count("s off");
    assert_eq!(vertices, 8);
    assert_eq!(normals.len(), 4);
    for n in &normals {
        let axis = [n[0].abs(), n[1].abs(), n[2].abs()];
        assert!(axis.iter().any(|&x| (x - 1.0).abs() < 1e-5), "{normals:?}");
    }
    // Smooth: one vertex per position, the fold's normal between the two.
    let (vertices, normals) = count("s 1");
    assert_eq!(vertices, 6);
    assert!(
        normals.iter().all(|n| n[0].abs() > 0.5 && n[2].abs() > 0.5),
        "{normals:?}"
    );
}

#[test]
fn one_vn_per_corner_with_equal_values_stays_smooth() {
    use meshmorph::io::{Appearance, MeshFile};
    let dir = tempfile::tempdir().unwrap();
    // Two triangles meeting along an edge, their corners naming normals of
    // equal values one by one, as exporters that list a `vn` per corner do.
    let path = dir.path().join("per_corner.obj");
    std::fs::write(
        &path,
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0.3\n\
         vn 0 0 1\nvn 0 0 1\nvn 0 0 1\nvn 0 0 1\nvn 0 0 1\nvn 0 0 1\n\
         f 1//1 2//2 3//3\nf 2//4 4//5 3//6\n",
    )
    .unwrap();
    let file = MeshFile::read(&path).unwrap();
    let look = Appearance::of_file(&file, u64::MAX).unwrap();
    let base = look.base(file.mesh().positions(), file.mesh().triangles());
    let back = read_back(
        &glb(
            &base,
            &[file.mesh().positions().to_vec()],
            &names(1),
            &GltfOptions::default(),
        )
        .unwrap(),
    );
    assert_eq!(back.positions.len(), 4);
}

/// Every frame's positions as a viewer decodes the GLB, per glTF vertex:
/// base plus delta, through dense or sparse accessors, `f32` or normalised
/// `i16` (KHR_mesh_quantization), then the node's scale and translation.
/// Also the document and the size of the binary chunk.
fn decode_frames(bytes: &[u8]) -> (Vec<Vec<[f64; 3]>>, serde_json::Value) {
    let u32_at = |o: usize| u32::from_le_bytes(bytes[o..o + 4].try_into().unwrap()) as usize;
    let json_length = u32_at(12);
    let doc: serde_json::Value = serde_json::from_slice(&bytes[20..20 + json_length]).unwrap();
    let bin = &bytes[28 + json_length..];
    let number = |v: &serde_json::Value, key: &str| v[key].as_u64().map(|x| x as usize);
    let component = |ty: usize, normalized: bool, at: &[u8]| -> f64 {
        match ty {
            5126 => f64::from(f32::from_le_bytes(at[..4].try_into().unwrap())),
            5122 => {
                let x = f64::from(i16::from_le_bytes(at[..2].try_into().unwrap()));
                if normalized {
                    (x / 32767.0).max(-1.0)
                } else {
                    x
                }
            }
            other => panic!("component type {other}"),
        }
    };
    let accessor = |index: usize| -> Vec<[f64; 3]> {
        let a = &doc["accessors"][index];
        let (n, ty) = (
            number(a, "count").unwrap(),
            number(a, "componentType").unwrap(),
        );
        let normalized = a["normalized"].as_bool().unwrap_or(false);
        let size = if ty == 5126 { 4 } else { 2 };
        let read =
            |view: usize, offset: usize, stride: Option<usize>, count: usize| -> Vec<[f64; 3]> {
                let v = &doc["bufferViews"][view];
                let start = number(v, "byteOffset").unwrap_or(0) + offset;
                let stride = stride.or(number(v, "byteStride")).unwrap_or(3 * size);
                (0..count)
                    .map(|i| {
                        std::array::from_fn(|k| {
                            component(ty, normalized, &bin[start + i * stride + k * size..])
                        })
                    })
                    .collect()
            };
        let mut values = match number(a, "bufferView") {
            Some(view) => read(view, number(a, "byteOffset").unwrap_or(0), None, n),
            None => vec![[0.0; 3]; n],
        };
        if let Some(sparse) = a.get("sparse") {
            let k = number(sparse, "count").unwrap();
            let iv = &doc["bufferViews"][number(&sparse["indices"], "bufferView").unwrap()];
            let index_type = number(&sparse["indices"], "componentType").unwrap();
            let start = number(iv, "byteOffset").unwrap_or(0);
            let given = read(
                number(&sparse["values"], "bufferView").unwrap(),
                0,
                Some(3 * size),
                k,
            );
            for (j, value) in given.into_iter().enumerate() {
                let i = match index_type {
                    5123 => u16::from_le_bytes(
                        bin[start + 2 * j..start + 2 * j + 2].try_into().unwrap(),
                    ) as usize,
                    5125 => u32_at(28 + json_length + start + 4 * j),
                    other => panic!("index type {other}"),
                };
                values[i] = value;
            }
        }
        values
    };
    let node = &doc["nodes"][0];
    let get3 = |key: &str, default: f64| -> [f64; 3] {
        node.get(key)
            .map(|v| std::array::from_fn(|k| v[k].as_f64().unwrap()))
            .unwrap_or([default; 3])
    };
    let (t, s) = (get3("translation", 0.0), get3("scale", 1.0));
    let primitive = &doc["meshes"][0]["primitives"][0];
    let base = accessor(number(&primitive["attributes"], "POSITION").unwrap());
    let frames = primitive["targets"]
        .as_array()
        .unwrap()
        .iter()
        .map(|target| {
            let delta = accessor(number(target, "POSITION").unwrap());
            base.iter()
                .zip(&delta)
                .map(|(b, d)| std::array::from_fn(|k| t[k] + s[k] * (b[k] + d[k])))
                .collect()
        })
        .collect();
    (frames, doc)
}

#[test]
fn sparse_dense_and_quantised_glbs_decode_to_the_same_frames() {
    // A tube whose far end bends while the rest stays put: frame 0 is the
    // rest itself, the others move the vertices past x = 2.5 only.
    let rest = tube(4.0, 0.5, 17, 12);
    let bent: Vec<Vec<[f64; 3]>> = [0.0, 0.4, 0.9]
        .iter()
        .map(|&angle: &f64| {
            rest.positions()
                .iter()
                .map(|&[x, y, z]| {
                    if x <= 2.5 {
                        [x, y, z]
                    } else {
                        let a = angle * (x - 2.5);
                        [
                            2.5 + (x - 2.5) * a.cos() - z * a.sin(),
                            y,
                            (x - 2.5) * a.sin() + z * a.cos(),
                        ]
                    }
                })
                .collect()
        })
        .collect();
    let base = GltfBase::new(rest.positions(), rest.triangles());
    let names = names(bent.len());
    let write = |options: GltfOptions| glb(&base, &bent, &names, &options).unwrap();
    let dense = write(GltfOptions::default().with_sparse(false));
    let sparse = write(GltfOptions::default());
    let quantised = write(GltfOptions::default().with_quantize(true));
    let quantised_dense = write(
        GltfOptions::default()
            .with_quantize(true)
            .with_sparse(false),
    );
    assert!(
        sparse.len() < dense.len() * 3 / 4,
        "{} against {}",
        sparse.len(),
        dense.len()
    );
    assert!(quantised.len() < sparse.len() && quantised_dense.len() < dense.len());

    let (from_dense, doc) = decode_frames(&dense);
    assert!(doc["accessors"]
        .as_array()
        .unwrap()
        .iter()
        .all(|a| a.get("sparse").is_none()));
    let (from_sparse, doc) = decode_frames(&sparse);
    assert!(doc["accessors"]
        .as_array()
        .unwrap()
        .iter()
        .any(|a| a.get("sparse").is_some()));
    assert_eq!(doc["meshes"][0]["extras"]["targetNames"][2], "frame_0002");
    // Sparse storage is lossless: the same numbers as dense.
    assert_eq!(from_sparse, from_dense);
    // And dense is each frame to f32 precision.
    for (decoded, frame) in from_dense.iter().zip(&bent) {
        for (p, q) in decoded.iter().zip(frame) {
            for k in 0..3 {
                assert!((p[k] - q[k]).abs() <= 4.0 * f64::from(f32::EPSILON) * 4.0);
            }
        }
    }
    // Quantised: within the stated tolerance, scale / 32767 a coordinate.
    for bytes in [&quantised, &quantised_dense] {
        let (decoded, doc) = decode_frames(bytes);
        assert_eq!(doc["extensionsRequired"][0], "KHR_mesh_quantization");
        let scale = doc["nodes"][0]["scale"][0].as_f64().unwrap();
        let tolerance = scale / 32767.0 * (1.0 + 1e-6) + 1e-6 * scale;
        let mut worst: f64 = 0.0;
        for (decoded, frame) in decoded.iter().zip(&bent) {
            for (p, q) in decoded.iter().zip(frame) {
                for k in 0..3 {
                    worst = worst.max((p[k] - q[k]).abs());
                }
            }
        }
        assert!(worst <= tolerance, "{worst} against {tolerance}");
        assert!(worst > 0.0);
    }
}
