//! The glTF reader: GLBs of the project's own writer and its sample
//! character read back as the meshes and poses they were made of, every
//! storage (dense, sparse, quantised, interleaved), mesh choice, and
//! refusals naming the file and the mesh.

use std::collections::HashMap;
use std::path::Path;

use meshmorph::io::gltf::{
    read, write_glb_to, GltfBase, GltfDocument, GltfOptions, SampleCharacter, SampleVrm,
};
use meshmorph::shapes::{bend, tube, twist};
use serde_json::{json, Value};

/// The JSON and binary chunk of a GLB.
pub fn split_glb(bytes: &[u8]) -> (Value, Vec<u8>) {
    let word = |at: usize| u32::from_le_bytes(bytes[at..at + 4].try_into().unwrap()) as usize;
    let json_len = word(12);
    let json = serde_json::from_slice(&bytes[20..20 + json_len]).unwrap();
    let at = 20 + json_len;
    let bin = if at + 8 <= bytes.len() {
        bytes[at + 8..at + 8 + word(at)].to_vec()
    } else {
        Vec::new()
    };
    (json, bin)
}

/// A GLB of `json` and `bin`.
pub fn join_glb(json: &Value, bin: &[u8]) -> Vec<u8> {
    let mut text = serde_json::to_vec(json).unwrap();
    text.resize(text.len().next_multiple_of(4), b' ');
    let mut bin = bin.to_vec();
    bin.resize(bin.len().next_multiple_of(4), 0);
    let mut out = b"glTF".to_vec();
    out.extend(2u32.to_le_bytes());
    out.extend(((28 + text.len() + bin.len()) as u32).to_le_bytes());
    out.extend((text.len() as u32).to_le_bytes());
    out.extend(b"JSON");
    out.extend(text);
    out.extend((bin.len() as u32).to_le_bytes());
    out.extend(b"BIN\0");
    out.extend(bin);
    out
}

/// `bytes` with its JSON changed by `edit`.
pub fn edit_glb(bytes: &[u8], edit: impl FnOnce(&mut Value)) -> Vec<u8> {
    let (mut json, bin) = split_glb(bytes);
    edit(&mut json);
    join_glb(&json, &bin)
}

fn write(dir: &Path, name: &str, bytes: &[u8]) -> std::path::PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

fn max_distance(a: &[[f64; 3]], b: &[[f64; 3]]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .map(|(p, q)| (0..3).map(|c| (p[c] - q[c]).abs()).fold(0.0, f64::max))
        .fold(0.0, f64::max)
}

#[test]
fn glbs_of_the_writer_read_back_as_their_base_and_frames() {
    let dir = tempfile::tempdir().unwrap();
    for (rings, segments) in [(4, 5), (9, 12)] {
        let base = tube(3.0, 0.4, rings, segments);
        let frames = vec![
            bend(&base, 3.0, 1.2).positions().to_vec(),
            twist(&base, 3.0, 0.8).positions().to_vec(),
            base.positions().to_vec(),
        ];
        let names: Vec<String> = ["bend", "twist", "rest"].map(String::from).to_vec();
        for (sparse, quantize) in [(true, false), (false, false), (true, true)] {
            let options = GltfOptions::default()
                .with_sparse(sparse)
                .with_quantize(quantize)
                .with_name("Tube");
            let mut bytes = Vec::new();
            let glb_base = GltfBase::new(base.positions(), base.triangles());
            write_glb_to(
                &mut bytes,
                Path::new("t.glb"),
                &glb_base,
                &frames,
                &names,
                &options,
            )
            .unwrap();
            let path = write(dir.path(), "t.glb", &bytes);
            let (_, mesh) = read(&path, None).unwrap();
            assert_eq!(mesh.name, "Tube");
            assert!(mesh.notes.is_empty());
            assert_eq!(mesh.surface.triangles(), base.triangles());
            assert_eq!(mesh.target_names(), ["bend", "twist", "rest"]);
            // Quantised positions are decoded by the node: the mesh's own
            // space is the integers'.
            let tolerance = if quantize { 4.0 * 3.5 / 32767.0 } else { 1e-6 };
            let placed = mesh.placed(mesh.surface.positions());
            assert!(
                max_distance(&placed, base.positions()) < tolerance,
                "{sparse} {quantize}"
            );
            for (target, frame) in mesh.targets.iter().zip(&frames) {
                let placed = mesh.placed(&target.positions);
                assert!(max_distance(&placed, frame) < tolerance, "{}", target.name);
            }
        }
    }
}

/// The body vertex at each surface vertex (by position).
fn body_vertex_of(surface: &[[f64; 3]], body: &[[f64; 3]]) -> Vec<usize> {
    let key = |p: &[f64; 3]| p.map(|x| (x as f32).to_bits());
    let of: HashMap<[u32; 3], usize> = body.iter().enumerate().map(|(i, p)| (key(p), i)).collect();
    surface.iter().map(|p| of[&key(p)]).collect()
}

#[test]
fn the_sample_character_reads_as_its_body_and_shape_key_in_every_storage() {
    let dir = tempfile::tempdir().unwrap();
    for (rings, segments) in [(4, 3), (12, 16), (7, 9)] {
        for (vrm, sparse, quantized, skinned) in [
            (SampleVrm::None, true, false, true),
            (SampleVrm::None, false, false, true),
            (SampleVrm::None, true, true, false),
            (SampleVrm::V0, true, false, true),
            (SampleVrm::V1, false, false, false),
        ] {
            let mut sample = SampleCharacter::default();
            sample.rings = rings;
            sample.segments = segments;
            sample.vrm = vrm;
            sample.sparse = sparse;
            sample.quantized = quantized;
            sample.skinned = skinned;
            let path = write(dir.path(), "c.vrm", &sample.glb());
            let (doc, mesh) = read(&path, None).unwrap();
            let case = format!("{rings}x{segments} {vrm:?} sparse {sparse} quantized {quantized}");
            assert_eq!(mesh.name, "Body", "{case}");
            assert_eq!(mesh.blocks.len(), 2, "{case}");
            assert_eq!(mesh.primitives.len(), 2, "{case}");
            assert_eq!(mesh.skinned, skinned && !quantized, "{case}");
            assert_eq!(mesh.nodes, [3]);
            assert_eq!(doc.mesh_names(), ["Body", "Eye"]);
            assert!(mesh.notes[0].contains("`Eye`"), "{case}: {:?}", mesh.notes);
            let body = sample.body();
            // The seam between the primitives is welded: one ring apart.
            let (seams, welded) = mesh.welded();
            assert_eq!(welded.num_vertices(), body.num_vertices(), "{case}");
            assert!(
                mesh.surface.num_vertices() >= body.num_vertices() + segments,
                "{case}"
            );
            assert_eq!(welded.num_triangles(), body.num_triangles());
            let tolerance = if quantized { 2.0 / 32767.0 } else { 1e-6 };
            let placed = mesh.placed(mesh.surface.positions());
            let of = if quantized {
                // Nearest body vertex.
                placed
                    .iter()
                    .map(|p| {
                        (0..body.num_vertices())
                            .min_by(|&a, &b| {
                                let d = |v: usize| max_distance(&[body.positions()[v]], &[*p]);
                                d(a).total_cmp(&d(b))
                            })
                            .unwrap()
                    })
                    .collect()
            } else {
                body_vertex_of(mesh.surface.positions(), body.positions())
            };
            let smile = sample.smile(body.positions());
            assert_eq!(mesh.target_names(), ["Smile"]);
            let want: Vec<[f64; 3]> = of.iter().map(|&v| smile[v]).collect();
            let got = mesh.placed(&mesh.targets[0].positions);
            assert!(max_distance(&got, &want) < tolerance, "{case}");
            assert_eq!(seams.num_apart(&mesh.targets[0].positions), 0, "{case}");
        }
    }
}

#[test]
fn meshes_are_chosen_by_mesh_or_node_name() {
    let dir = tempfile::tempdir().unwrap();
    let path = write(dir.path(), "c.glb", &SampleCharacter::default().glb());
    let doc = GltfDocument::read(&path).unwrap();
    let eye = doc.mesh(Some("Eye")).unwrap();
    assert_eq!((eye.index, eye.surface.num_vertices()), (1, 6));
    assert!(eye.targets.is_empty() && eye.notes.is_empty());
    // The eye's node sits on the head joint: its matrix places it there.
    let placed = eye.placed(&[[0.0; 3]]);
    assert!(
        max_distance(&placed, &[[0.08, 1.45, 0.24]]) < 1e-9,
        "{placed:?}"
    );
    let renamed = edit_glb(&SampleCharacter::default().glb(), |j| {
        j["meshes"][0]["name"] = json!("BodyMesh");
    });
    let path = write(dir.path(), "r.glb", &renamed);
    let doc = GltfDocument::read(&path).unwrap();
    assert_eq!(doc.mesh(Some("Body")).unwrap().index, 0);
    let error = doc.mesh(Some("Face")).unwrap_err().to_string();
    for part in ["r.glb", "`Face`", "`BodyMesh`", "`Eye`"] {
        assert!(error.contains(part), "{error}");
    }
}

#[test]
fn compressed_and_broken_meshes_are_refused_naming_file_mesh_and_extension() {
    let dir = tempfile::tempdir().unwrap();
    let sample = SampleCharacter::default().glb();
    let draco = edit_glb(&sample, |j| {
        j["meshes"][0]["primitives"][1]["extensions"] =
            json!({"KHR_draco_mesh_compression": {"bufferView": 0, "attributes": {"POSITION": 0}}});
    });
    let meshopt = edit_glb(&sample, |j| {
        let position = j["meshes"][0]["primitives"][0]["attributes"]["POSITION"]
            .as_u64()
            .unwrap();
        let view = j["accessors"][position as usize]["bufferView"]
            .as_u64()
            .unwrap();
        j["bufferViews"][view as usize]["extensions"] = json!({"EXT_meshopt_compression": {
            "buffer": 0, "byteLength": 4, "byteStride": 12, "count": 1, "mode": "ATTRIBUTES"}});
    });
    let out_of_range = edit_glb(&sample, |j| {
        let position = j["meshes"][0]["primitives"][0]["attributes"]["POSITION"]
            .as_u64()
            .unwrap();
        j["accessors"][position as usize]["count"] = json!(1_000_000);
    });
    let no_triangles = edit_glb(&sample, |j| {
        j["meshes"][0]["primitives"][0]["mode"] = json!(0);
        j["meshes"][0]["primitives"][1]["mode"] = json!(1);
        j["meshes"][1]["primitives"][0]["mode"] = json!(0);
    });
    for (name, bytes, parts) in [
        (
            "draco.glb",
            draco,
            vec!["`Body`", "KHR_draco_mesh_compression", "primitive 1"],
        ),
        (
            "meshopt.glb",
            meshopt,
            vec!["`Body`", "EXT_meshopt_compression", "POSITION"],
        ),
        (
            "range.glb",
            out_of_range,
            vec!["`Body`", "POSITION", "bytes"],
        ),
        (
            "lines.glb",
            no_triangles,
            vec!["`Body`", "`Eye`", "triangles"],
        ),
        ("text.glb", b"hello".to_vec(), vec!["not glTF"]),
        (
            "v1.gltf",
            br#"{"asset": {"version": "1.0"}}"#.to_vec(),
            vec!["glTF version 1.0"],
        ),
    ] {
        let path = write(dir.path(), name, &bytes);
        let error = read(&path, None).unwrap_err().to_string();
        assert!(error.contains(name), "{error}");
        for part in parts {
            assert!(error.contains(part), "{name}: {error}");
        }
    }
    // The Eye is still read from the file whose Body is compressed.
    let path = dir.path().join("draco.glb");
    assert_eq!(
        read(&path, Some("Eye")).unwrap().1.surface.num_vertices(),
        6
    );
}

/// A `.gltf` of a quad as a strip, its fan twin and a line, with its
/// buffer in a file beside it or in a `data:` URI.
fn strip_gltf(uri: &str) -> Value {
    json!({
        "asset": {"version": "2.0"},
        "buffers": [{"uri": uri, "byteLength": 48 + 12}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 48, "byteStride": 12},
            {"buffer": 0, "byteOffset": 48, "byteLength": 12}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
             "min": [0, 0, 0], "max": [1, 1, 0]},
            {"bufferView": 1, "componentType": 5121, "count": 4, "type": "SCALAR"}],
        "meshes": [{"name": "Quad", "primitives": [
            {"attributes": {"POSITION": 0}, "mode": 5},
            {"attributes": {"POSITION": 0}, "mode": 6, "indices": 1},
            {"attributes": {"POSITION": 0}, "mode": 1}]}],
        "nodes": [{"mesh": 0, "name": "QuadNode", "translation": [0, 0, 2]}],
    })
}

fn strip_bytes() -> Vec<u8> {
    let mut bytes: Vec<u8> = [
        [0.0f32, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [1.0, 1.0, 0.0],
    ]
    .iter()
    .flatten()
    .flat_map(|x| x.to_le_bytes())
    .collect();
    bytes.extend([0u8, 1, 3, 2, 0, 0, 0, 0, 0, 0, 0, 0]);
    bytes
}

#[test]
fn gltf_text_with_buffers_beside_it_or_inline_strips_and_fans() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("quad data.bin"), strip_bytes()).unwrap();
    let beside = strip_gltf("quad%20data.bin");
    let inline = strip_gltf(&format!(
        "data:application/octet-stream;base64,{}",
        base64_of(&strip_bytes())
    ));
    for (name, json) in [("beside.gltf", beside), ("inline.gltf", inline)] {
        let path = write(dir.path(), name, json.to_string().as_bytes());
        let (_, mesh) = read(&path, Some("QuadNode")).unwrap();
        assert_eq!(mesh.blocks.len(), 1, "{name}");
        assert_eq!(mesh.surface.num_vertices(), 4);
        // Two triangles of the strip, two of the fan, none of the line.
        assert_eq!(mesh.surface.num_triangles(), 4, "{name}");
        assert_eq!(mesh.primitives[2].triangles, 4..4);
        assert_eq!(mesh.primitives[2].block, Some(0));
        assert_eq!(mesh.placed(&[[1.0, 1.0, 0.0]]), [[1.0, 1.0, 2.0]]);
        // Every triangle faces +z, as the strip's alternating order means.
        for t in mesh.surface.triangles() {
            let p = t.map(|v| mesh.surface.positions()[v as usize]);
            let cross = (p[1][0] - p[0][0]) * (p[2][1] - p[0][1])
                - (p[1][1] - p[0][1]) * (p[2][0] - p[0][0]);
            assert!(cross > 0.0, "{name}: {t:?}");
        }
    }
    std::fs::remove_file(dir.path().join("quad data.bin")).unwrap();
    let error = read(&dir.path().join("beside.gltf"), None)
        .unwrap_err()
        .to_string();
    assert!(
        error.contains("beside.gltf") && error.contains("quad data.bin"),
        "{error}"
    );
}

fn base64_of(bytes: &[u8]) -> String {
    const A: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::new();
    for c in bytes.chunks(3) {
        let n = (u32::from(c[0]) << 16)
            | (u32::from(*c.get(1).unwrap_or(&0)) << 8)
            | u32::from(*c.get(2).unwrap_or(&0));
        for k in 0..4 {
            out.push(if k <= c.len() {
                A[(n >> (18 - 6 * k) & 63) as usize] as char
            } else {
                '='
            });
        }
    }
    out
}
