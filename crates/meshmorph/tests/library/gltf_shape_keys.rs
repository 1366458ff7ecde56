//! Shape keys written into a user's own glTF file: read back as the shapes
//! given after the file's own, in every storage of the sample character
//! (skinned, quantised, VRM 0.x and 1.0, text glTF); the rest of the file
//! unchanged; weights and their animations padded; VRM expressions; and
//! refusals naming the file, the mesh and the shape.

use std::path::{Path, PathBuf};

use meshmorph::io::gltf::{
    add_shape_keys, read, GltfMesh, NewShape, SampleCharacter, SampleVrm, ShapeKeyOptions,
};
use serde_json::{json, Value};

use super::gltf_read::{join_glb, split_glb};

fn write(dir: &Path, name: &str, bytes: &[u8]) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

/// Three shapes of a mesh: the lower body pushed out (most vertices
/// still), everything moved, nothing moved.
fn shapes_of(mesh: &GltfMesh) -> Vec<(String, Vec<[f64; 3]>)> {
    let base = mesh.surface.positions();
    let jaw = base
        .iter()
        .map(|&[x, y, z]| {
            if y < 0.2 {
                [x * 1.1, y, z * 1.1]
            } else {
                [x, y, z]
            }
        })
        .collect();
    let wide = base
        .iter()
        .map(|&[x, y, z]| [x * 1.2, y - 0.01, z])
        .collect();
    vec![
        ("jawOpen".to_string(), jaw),
        ("wide".to_string(), wide),
        ("still".to_string(), base.to_vec()),
    ]
}

fn new_shapes(shapes: &[(String, Vec<[f64; 3]>)]) -> Vec<NewShape<'_>> {
    shapes
        .iter()
        .map(|(name, positions)| NewShape { name, positions })
        .collect()
}

fn max_distance(a: &[[f64; 3]], b: &[[f64; 3]]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(p, q)| (0..3).map(|c| (p[c] - q[c]).abs()).fold(0.0, f64::max))
        .fold(0.0, f64::max)
}

/// `json` without the members a write back may change.
fn unchanged_part(json: &Value, mesh: usize) -> Value {
    let mut json = json.clone();
    for name in ["accessors", "bufferViews", "buffers"] {
        json.as_object_mut().unwrap().remove(name);
    }
    json["meshes"][mesh] = Value::Null;
    json
}

fn samples() -> Vec<(&'static str, SampleCharacter)> {
    let mut out = Vec::new();
    for (name, vrm, sparse, quantized, skinned) in [
        ("skinned.glb", SampleVrm::None, true, false, true),
        ("dense.glb", SampleVrm::None, false, false, true),
        ("quantised.glb", SampleVrm::None, true, true, false),
        ("vrm0.vrm", SampleVrm::V0, true, false, true),
        ("vrm1.vrm", SampleVrm::V1, true, false, true),
    ] {
        let mut s = SampleCharacter::default();
        s.vrm = vrm;
        s.sparse = sparse;
        s.quantized = quantized;
        s.skinned = skinned;
        s.rings = 9;
        s.segments = 10;
        out.push((name, s));
    }
    out
}

#[test]
fn added_shapes_read_back_after_the_files_own_and_the_rest_is_unchanged() {
    let dir = tempfile::tempdir().unwrap();
    for (name, sample) in samples() {
        let input = sample.glb();
        let path = write(dir.path(), name, &input);
        let (doc, mesh) = read(&path, Some("Body")).unwrap();
        let shapes = shapes_of(&mesh);
        let bytes = add_shape_keys(
            &doc,
            &mesh,
            &new_shapes(&shapes),
            &ShapeKeyOptions::default(),
        )
        .unwrap();
        let out = write(dir.path(), &format!("out-{name}"), &bytes);
        let (_, back) = read(&out, Some("Body")).unwrap();
        assert_eq!(
            back.target_names(),
            ["Smile", "jawOpen", "wide", "still"],
            "{name}"
        );
        assert_eq!(back.surface.positions(), mesh.surface.positions(), "{name}");
        assert_eq!(back.targets[0], mesh.targets[0], "{name}");
        for ((_, want), got) in shapes.iter().zip(&back.targets[1..]) {
            assert!(
                max_distance(want, &got.positions) < 1e-6,
                "{name} {}",
                got.name
            );
        }
        // Lossless: the same JSON but for the mesh, accessors, views and
        // buffers; those of the input are kept as they were, and so are
        // the bytes of its binary chunk.
        let (before, before_bin) = split_glb(&input);
        let (after, after_bin) = split_glb(&bytes);
        assert_eq!(
            unchanged_part(&before, 0),
            unchanged_part(&after, 0),
            "{name}"
        );
        for part in ["accessors", "bufferViews"] {
            let old = before[part].as_array().unwrap();
            assert_eq!(
                old[..],
                after[part].as_array().unwrap()[..old.len()],
                "{name}"
            );
        }
        assert_eq!(after_bin[..before_bin.len()], before_bin[..], "{name}");
        let (old_mesh, new_mesh) = (&before["meshes"][0], &after["meshes"][0]);
        assert_eq!(old_mesh["name"], new_mesh["name"]);
        assert_eq!(new_mesh["weights"], json!([0.0, 0.0, 0.0, 0.0]));
        for (p, q) in old_mesh["primitives"]
            .as_array()
            .unwrap()
            .iter()
            .zip(new_mesh["primitives"].as_array().unwrap())
        {
            assert_eq!(p["attributes"], q["attributes"]);
            assert_eq!(p["material"], q["material"]);
            assert_eq!(q["targets"].as_array().unwrap().len(), 4);
            assert_eq!(p["targets"][0], q["targets"][0]);
        }
        // The still shape takes no bytes; jawOpen is sparse.
        let still = new_mesh["primitives"][0]["targets"][3]["POSITION"]
            .as_u64()
            .unwrap();
        assert!(after["accessors"][still as usize]
            .get("bufferView")
            .is_none());
        let jaw = new_mesh["primitives"][1]["targets"][1]["POSITION"]
            .as_u64()
            .unwrap();
        assert!(
            after["accessors"][jaw as usize].get("sparse").is_some(),
            "{name}"
        );
    }
}

#[test]
fn existing_names_are_refused_unless_replaced_and_bad_shapes_named() {
    let dir = tempfile::tempdir().unwrap();
    let path = write(dir.path(), "rig.glb", &SampleCharacter::default().glb());
    let (doc, mesh) = read(&path, None).unwrap();
    let smile: Vec<[f64; 3]> = mesh
        .surface
        .positions()
        .iter()
        .map(|&[x, y, z]| [x, y + 0.1, z])
        .collect();
    let shapes = [NewShape {
        name: "Smile",
        positions: &smile,
    }];
    let error = add_shape_keys(&doc, &mesh, &shapes, &ShapeKeyOptions::default())
        .unwrap_err()
        .to_string();
    for part in ["rig.glb", "`Body`", "`Smile`", "--replace-shapes"] {
        assert!(error.contains(part), "{error}");
    }
    let bytes = add_shape_keys(
        &doc,
        &mesh,
        &shapes,
        &ShapeKeyOptions::default().with_replace(true),
    )
    .unwrap();
    let out = write(dir.path(), "replaced.glb", &bytes);
    let (_, back) = read(&out, None).unwrap();
    assert_eq!(back.target_names(), ["Smile"]);
    assert!(max_distance(&back.targets[0].positions, &smile) < 1e-6);

    let short = vec![[0.0; 3]; 3];
    let nan = vec![[f64::NAN; 3]; mesh.surface.num_vertices()];
    for (shapes, parts, options) in [
        (
            vec![NewShape {
                name: "a",
                positions: &short,
            }],
            vec!["`a`", "3 positions"],
            ShapeKeyOptions::default(),
        ),
        (
            vec![NewShape {
                name: "b",
                positions: &nan,
            }],
            vec!["`b`", "vertex 0", "finite"],
            ShapeKeyOptions::default(),
        ),
        (
            vec![
                NewShape {
                    name: "c",
                    positions: &smile,
                },
                NewShape {
                    name: "c",
                    positions: &smile,
                },
            ],
            vec!["two shapes", "`c`"],
            ShapeKeyOptions::default(),
        ),
        (
            vec![NewShape {
                name: "d",
                positions: &smile,
            }],
            vec!["VRM"],
            ShapeKeyOptions::default().with_vrm_expressions(true),
        ),
    ] {
        let error = add_shape_keys(&doc, &mesh, &shapes, &options)
            .unwrap_err()
            .to_string();
        assert!(
            error.contains("rig.glb") && error.contains("`Body`"),
            "{error}"
        );
        for part in parts {
            assert!(error.contains(part), "{error}");
        }
    }
}

#[test]
fn vrm_expressions_are_added_as_custom_expressions() {
    let dir = tempfile::tempdir().unwrap();
    for (name, sample) in samples().into_iter().filter(|(n, _)| n.ends_with(".vrm")) {
        let input = sample.glb();
        let path = write(dir.path(), name, &input);
        let (doc, mesh) = read(&path, None).unwrap();
        let shapes = shapes_of(&mesh);
        let options = ShapeKeyOptions::default().with_vrm_expressions(true);
        let bytes = add_shape_keys(&doc, &mesh, &new_shapes(&shapes), &options).unwrap();
        let (before, _) = split_glb(&input);
        let (after, _) = split_glb(&bytes);
        if name == "vrm1.vrm" {
            let custom = &after["extensions"]["VRMC_vrm"]["expressions"]["custom"];
            assert_eq!(
                custom["wide"]["morphTargetBinds"],
                json!([{"node": 3, "index": 2, "weight": 1.0}])
            );
            let mut rest = after["extensions"].clone();
            rest["VRMC_vrm"]["expressions"]
                .as_object_mut()
                .unwrap()
                .remove("custom");
            assert_eq!(rest, before["extensions"]);
        } else {
            let groups = after["extensions"]["VRM"]["blendShapeMaster"]["blendShapeGroups"]
                .as_array()
                .unwrap();
            assert_eq!(groups.len(), 4);
            assert_eq!(
                groups[0],
                before["extensions"]["VRM"]["blendShapeMaster"]["blendShapeGroups"][0]
            );
            assert_eq!(groups[3]["name"], "still");
            assert_eq!(
                groups[3]["binds"],
                json!([{"mesh": 0, "index": 3, "weight": 100}])
            );
        }
        // Once there, an expression of that name is refused unless replaced.
        let out = write(dir.path(), &format!("out-{name}"), &bytes);
        let (doc, mesh) = read(&out, None).unwrap();
        let again = [NewShape {
            name: "other",
            positions: mesh.surface.positions(),
        }];
        assert!(add_shape_keys(&doc, &mesh, &again, &options).is_ok());
        let replaced = [NewShape {
            name: "wide",
            positions: mesh.surface.positions(),
        }];
        let error = add_shape_keys(&doc, &mesh, &replaced, &options)
            .unwrap_err()
            .to_string();
        assert!(error.contains("`wide`"), "{error}");
        add_shape_keys(&doc, &mesh, &replaced, &options.clone().with_replace(true)).unwrap();
    }
}

/// Little-endian `f32`s of a dense accessor of a GLB.
fn floats(json: &Value, bin: &[u8], accessor: usize) -> Vec<f32> {
    let a = &json["accessors"][accessor];
    let view = &json["bufferViews"][a["bufferView"].as_u64().unwrap() as usize];
    let start = view["byteOffset"].as_u64().unwrap_or(0) as usize
        + a["byteOffset"].as_u64().unwrap_or(0) as usize;
    let count = a["count"].as_u64().unwrap() as usize;
    bin[start..start + 4 * count]
        .chunks_exact(4)
        .map(|b| f32::from_le_bytes(b.try_into().unwrap()))
        .collect()
}

#[test]
fn node_weights_their_animation_and_other_primitives_get_the_new_targets() {
    let dir = tempfile::tempdir().unwrap();
    let (mut json, mut bin) = split_glb(&SampleCharacter::default().glb());
    // The body's node has weights, animated: Smile 0 → 1; and the body has
    // a points primitive of the eye's vertices.
    json["nodes"][3]["weights"] = json!([0.5]);
    let offset = bin.len();
    for x in [0.0f32, 1.0, 0.0, 1.0] {
        bin.extend(x.to_le_bytes());
    }
    let views = json["bufferViews"].as_array_mut().unwrap();
    views.push(json!({"buffer": 0, "byteOffset": offset, "byteLength": 16}));
    let view = views.len() - 1;
    let accessors = json["accessors"].as_array_mut().unwrap();
    accessors.push(json!({"bufferView": view, "componentType": 5126, "count": 2, "type": "SCALAR", "min": [0.0], "max": [1.0]}));
    accessors.push(json!({"bufferView": view, "byteOffset": 8, "componentType": 5126, "count": 2, "type": "SCALAR"}));
    let times = accessors.len() - 2;
    json["buffers"][0]["byteLength"] = json!(bin.len());
    json["animations"]
        .as_array_mut()
        .unwrap()
        .push(json!({"name": "Smiling",
        "samplers": [{"input": times, "output": times + 1}],
        "channels": [{"sampler": 0, "target": {"node": 3, "path": "weights"}}]}));
    let eye_positions = json["meshes"][1]["primitives"][0]["attributes"]["POSITION"].clone();
    json["meshes"][0]["primitives"]
        .as_array_mut()
        .unwrap()
        .push(json!({
        "attributes": {"POSITION": eye_positions}, "mode": 0,
        "targets": [{"POSITION": eye_positions}]}));
    let path = write(dir.path(), "animated.glb", &join_glb(&json, &bin));
    let (doc, mesh) = read(&path, None).unwrap();
    assert_eq!(mesh.primitives[2].block, None);
    let shapes = shapes_of(&mesh);
    let bytes = add_shape_keys(
        &doc,
        &mesh,
        &new_shapes(&shapes[..2]),
        &ShapeKeyOptions::default(),
    )
    .unwrap();
    let (after, after_bin) = split_glb(&bytes);
    assert_eq!(after["nodes"][3]["weights"], json!([0.5, 0.0, 0.0]));
    let output = after["animations"][1]["samplers"][0]["output"]
        .as_u64()
        .unwrap() as usize;
    assert_eq!(
        floats(&after, &after_bin, output),
        [0.0, 0.0, 0.0, 1.0, 0.0, 0.0]
    );
    let points = &after["meshes"][0]["primitives"][2]["targets"];
    assert_eq!(points.as_array().unwrap().len(), 3);
    let zeros = &after["accessors"][points[2]["POSITION"].as_u64().unwrap() as usize];
    assert_eq!(
        (zeros["count"].as_u64(), zeros.get("bufferView")),
        (Some(6), None)
    );
    assert_eq!(
        unchanged_part(&json, 0)["nodes"][0],
        unchanged_part(&after, 0)["nodes"][0]
    );
}

#[test]
fn a_text_gltf_stays_text_with_its_new_data_inline() {
    let dir = tempfile::tempdir().unwrap();
    let (mut json, bin) = split_glb(&SampleCharacter::default().glb());
    std::fs::write(dir.path().join("body.bin"), &bin).unwrap();
    json["buffers"][0]["uri"] = json!("body.bin");
    let path = write(dir.path(), "rig.gltf", json.to_string().as_bytes());
    let (doc, mesh) = read(&path, None).unwrap();
    let shapes = shapes_of(&mesh);
    let bytes = add_shape_keys(
        &doc,
        &mesh,
        &new_shapes(&shapes),
        &ShapeKeyOptions::default(),
    )
    .unwrap();
    let after: Value = serde_json::from_slice(&bytes).unwrap();
    assert_eq!(after["buffers"][0], json["buffers"][0]);
    assert!(after["buffers"][1]["uri"]
        .as_str()
        .unwrap()
        .starts_with("data:application/octet-stream;base64,"));
    let out = write(dir.path(), "out.gltf", &bytes);
    let (_, back) = read(&out, None).unwrap();
    assert_eq!(back.target_names(), ["Smile", "jawOpen", "wide", "still"]);
    assert!(max_distance(&back.targets[2].positions, &shapes[1].1) < 1e-6);
}
