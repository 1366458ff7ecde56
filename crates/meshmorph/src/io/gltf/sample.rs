//! A small glTF character made in code, for the demo, the tests and the
//! benchmarks: a skinned, textured body of two primitives (skin and
//! cloth, meeting at a seam), an existing shape key, a separate eye mesh
//! on the head joint, an animation, a camera and, when asked, the
//! extension data of a VRM 0.x or 1.0 avatar.

use serde_json::{json, Value};

use super::glb::{glb_bytes, Appender, Pieces, ARRAY_BUFFER, ELEMENT_ARRAY_BUFFER};
use crate::linalg::vector::angle_weighted_vertex_normals;
use crate::mesh::{shapes, Mesh3};

/// Which avatar format's data the sample carries.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[non_exhaustive]
pub enum SampleVrm {
    /// Plain glTF.
    #[default]
    None,
    /// VRM 0.x: the `VRM` extension (meta, humanoid, blend shape groups,
    /// spring bones, material properties).
    V0,
    /// VRM 1.0: `VRMC_vrm` (meta, humanoid, expressions) and
    /// `VRMC_springBone`.
    V1,
}

/// How the sample character is made.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct SampleCharacter {
    /// Rings along the body (at least 4); the body has `rings × segments
    /// + 2` vertices before the seam splits one ring in two.
    pub rings: usize,
    /// Vertices around the body (at least 3).
    pub segments: usize,
    /// Avatar data. Default none.
    pub vrm: SampleVrm,
    /// A skin of two joints (hips, head) with an animation nodding the
    /// head. Default `true`; without it the body node places the body.
    pub skinned: bool,
    /// The body's positions as normalised 16-bit integers
    /// (KHR_mesh_quantization, decoded by the body node's translation and
    /// scale; only without a skin). Default `false`.
    pub quantized: bool,
    /// The existing shape key (`Smile`) stored sparsely. Default `true`.
    pub sparse: bool,
    /// Extra morph targets of the body (`Extra_K`, each a small bulge),
    /// for benchmarks. Default 0.
    pub extra_targets: usize,
}

impl Default for SampleCharacter {
    fn default() -> Self {
        SampleCharacter {
            rings: 12,
            segments: 16,
            vrm: SampleVrm::None,
            skinned: true,
            quantized: false,
            sparse: true,
            extra_targets: 0,
        }
    }
}

/// A 2 × 2 RGBA PNG of skin colour (the body's texture).
const SKIN_PNG: [u8; 74] = [
    137, 80, 78, 71, 13, 10, 26, 10, 0, 0, 0, 13, 73, 72, 68, 82, 0, 0, 0, 2, 0, 0, 0, 2, 8, 6, 0,
    0, 0, 114, 182, 13, 36, 0, 0, 0, 17, 73, 68, 65, 84, 120, 156, 99, 56, 49, 173, 226, 63, 8, 51,
    192, 24, 0, 100, 248, 11, 85, 155, 87, 191, 124, 0, 0, 0, 0, 73, 69, 78, 68, 174, 66, 96, 130,
];

/// The height of the body.
const HEIGHT: f64 = 1.6;

impl SampleCharacter {
    /// The body as one mesh, standing along +y from 0 to 1.6 (a capped
    /// tube): the surface the file's two primitives make once welded.
    ///
    /// # Panics
    /// If `rings < 4` or `segments < 3`.
    pub fn body(&self) -> Mesh3 {
        assert!(self.rings >= 4 && self.segments >= 3, "sample too coarse");
        let tube = shapes::tube(HEIGHT, 0.25, self.rings, self.segments);
        let positions = tube
            .positions()
            .iter()
            .map(|&[x, y, z]| [y, x, -z])
            .collect();
        Mesh3::new(positions, tube.triangles().to_vec()).expect("a tube turned is a mesh")
    }

    /// The body's `Smile` shape: the upper half's front pushed forwards.
    pub fn smile(&self, positions: &[[f64; 3]]) -> Vec<[f64; 3]> {
        positions
            .iter()
            .map(|&[x, y, z]| {
                let near = (y > 0.7 * HEIGHT && z > 0.1) as u8 as f64;
                [x, y, z + 0.05 * near]
            })
            .collect()
    }

    /// The GLB's bytes.
    pub fn glb(&self) -> Vec<u8> {
        let (json, bin) = self.build();
        let text = serde_json::to_vec(&json).expect("JSON serialises");
        glb_bytes(&text, Some(&bin))
    }

    /// The document and its binary chunk.
    fn build(&self) -> (Value, Vec<u8>) {
        let body = self.body();
        let skinned = self.skinned && !self.quantized;
        let mut json = json!({
            "asset": {
                "version": "2.0",
                "generator": "meshmorph sample character",
                "copyright": "(c) the meshmorph sample character's makers, CC0",
            },
            "extras": { "note": "made in code for tests" },
        });
        let mut bin = Pieces::default();
        let mut add = Appender {
            json: &mut json,
            buffer: 0,
            base: 0,
            bin: &mut bin,
        };
        // The seam: triangles of the lower half are cloth, of the upper half
        // skin; each primitive has its own vertices.
        let mid = 0.5 * HEIGHT;
        let (mut lower, mut upper) = (Vec::new(), Vec::new());
        for t in body.triangles() {
            let y = t
                .iter()
                .map(|&v| body.positions()[v as usize][1])
                .sum::<f64>()
                / 3.0;
            if y < mid { &mut lower } else { &mut upper }.push(*t);
        }
        let smile = self.smile(body.positions());
        let image_view = add.view(SKIN_PNG.to_vec(), None);
        let mut primitives = Vec::new();
        let mut node_scale = None;
        for (k, triangles) in [upper, lower].iter().enumerate() {
            let mut local = vec![u32::MAX; body.num_vertices()];
            let mut used = Vec::new();
            let tris: Vec<u32> = triangles
                .iter()
                .flatten()
                .map(|&v| {
                    if local[v as usize] == u32::MAX {
                        local[v as usize] = used.len() as u32;
                        used.push(v);
                    }
                    local[v as usize]
                })
                .collect();
            let positions: Vec<[f64; 3]> =
                used.iter().map(|&v| body.positions()[v as usize]).collect();
            let local_tris: Vec<[u32; 3]> =
                tris.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
            let normals = angle_weighted_vertex_normals(&positions, &local_tris);
            let mut attributes = serde_json::Map::new();
            if self.quantized {
                let scale = 2.0f32;
                let q: Vec<u32> = positions
                    .iter()
                    .flatten()
                    .map(|&x| ((x / f64::from(scale) * 32767.0).round() as i16) as u16 as u32)
                    .collect();
                let bytes: Vec<u8> = q
                    .chunks_exact(3)
                    .flat_map(|c| {
                        let mut b: Vec<u8> =
                            c.iter().flat_map(|&v| (v as u16).to_le_bytes()).collect();
                        b.extend([0, 0]);
                        b
                    })
                    .collect();
                let view = add.view(bytes, Some(ARRAY_BUFFER));
                add.array("bufferViews")[view]["byteStride"] = json!(8);
                let decoded: Vec<f32> = q.iter().map(|&v| (v as u16 as i16) as f32).collect();
                let (min, max) = super::glb::bounds_of(&decoded, 3);
                let a = add.push(
                    "accessors",
                    json!({"bufferView": view, "componentType": 5122, "normalized": true,
                        "count": positions.len(), "type": "VEC3",
                        "min": min, "max": max}),
                );
                attributes.insert("POSITION".into(), json!(a));
                node_scale = Some(scale);
            } else {
                let values: Vec<f32> = positions.iter().flatten().map(|&x| x as f32).collect();
                let a = add.floats(&values, 3, Some(ARRAY_BUFFER), true);
                attributes.insert("POSITION".into(), json!(a));
            }
            let n: Vec<f32> = normals.iter().flatten().map(|&x| x as f32).collect();
            attributes.insert(
                "NORMAL".into(),
                json!(add.floats(&n, 3, Some(ARRAY_BUFFER), false)),
            );
            let uv: Vec<f32> = positions
                .iter()
                .flat_map(|p| {
                    [
                        (p[0].atan2(p[2]) / std::f64::consts::TAU + 0.5) as f32,
                        (1.0 - p[1] / HEIGHT) as f32,
                    ]
                })
                .collect();
            attributes.insert(
                "TEXCOORD_0".into(),
                json!(add.floats(&uv, 2, Some(ARRAY_BUFFER), false)),
            );
            if skinned {
                let joints: Vec<u32> = positions.iter().flat_map(|_| [0, 1, 0, 0]).collect();
                let weights: Vec<f32> = positions
                    .iter()
                    .flat_map(|p| {
                        let w = (p[1] / HEIGHT).clamp(0.0, 1.0) as f32;
                        [1.0 - w, w, 0.0, 0.0]
                    })
                    .collect();
                attributes.insert(
                    "JOINTS_0".into(),
                    json!(add.integers(&joints, 4, Some(5121), Some(ARRAY_BUFFER))),
                );
                attributes.insert(
                    "WEIGHTS_0".into(),
                    json!(add.floats(&weights, 4, Some(ARRAY_BUFFER), false)),
                );
            }
            let indices = add.integers(&tris, 1, None, Some(ELEMENT_ARRAY_BUFFER));
            // The existing shape key: `Smile`, moving only the upper half.
            let deltas: Vec<[f32; 3]> = used
                .iter()
                .map(|&v| {
                    let (a, b) = (body.positions()[v as usize], smile[v as usize]);
                    std::array::from_fn(|c| (b[c] - a[c]) as f32)
                })
                .collect();
            let mut targets =
                vec![json!({ "POSITION": self.target(&mut add, &deltas, node_scale) })];
            for e in 0..self.extra_targets {
                let bulge: Vec<[f32; 3]> = used
                    .iter()
                    .map(|&v| {
                        let p = body.positions()[v as usize];
                        let centre = HEIGHT * (e as f64 + 0.5) / self.extra_targets as f64;
                        let w = (1.0 - ((p[1] - centre) / 0.1).powi(2)).max(0.0);
                        [(0.02 * w * p[0]) as f32, 0.0, (0.02 * w * p[2]) as f32]
                    })
                    .collect();
                targets.push(json!({ "POSITION": self.target(&mut add, &bulge, node_scale) }));
            }
            primitives.push(json!({
                "attributes": attributes,
                "indices": indices,
                "material": k,
                "targets": targets,
            }));
        }
        let mut target_names = vec![json!("Smile")];
        target_names.extend((0..self.extra_targets).map(|e| json!(format!("Extra_{e}"))));
        let weights = vec![json!(0.0); target_names.len()];
        add.push(
            "meshes",
            json!({"name": "Body", "primitives": primitives, "weights": weights,
                "extras": {"targetNames": target_names}}),
        );
        // The eye: an octahedron in front of the head.
        let eye = shapes::octahedron([0.0, 0.0, 0.0], 0.04);
        let p: Vec<f32> = eye
            .positions()
            .iter()
            .flatten()
            .map(|&x| x as f32)
            .collect();
        let eye_positions = add.floats(&p, 3, Some(ARRAY_BUFFER), true);
        let eye_indices: Vec<u32> = eye.triangles().iter().flatten().copied().collect();
        let eye_indices = add.integers(&eye_indices, 1, None, Some(ELEMENT_ARRAY_BUFFER));
        add.push(
            "meshes",
            json!({"name": "Eye", "primitives": [{"attributes": {"POSITION": eye_positions},
                "indices": eye_indices, "material": 2}]}),
        );
        add.push(
            "images",
            json!({"name": "skin", "bufferView": image_view, "mimeType": "image/png"}),
        );
        add.push(
            "samplers",
            json!({"magFilter": 9729, "minFilter": 9987, "wrapS": 10497, "wrapT": 10497}),
        );
        add.push("textures", json!({"sampler": 0, "source": 0}));
        for material in [
            json!({"name": "Skin", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0},
                "metallicFactor": 0.0, "roughnessFactor": 0.8}}),
            json!({"name": "Cloth", "pbrMetallicRoughness": {"baseColorFactor": [0.2, 0.3, 0.7, 1.0],
                "metallicFactor": 0.0}, "doubleSided": true}),
            json!({"name": "Eye", "pbrMetallicRoughness": {"baseColorFactor": [0.05, 0.05, 0.05, 1.0]}}),
        ] {
            add.push("materials", material);
        }
        add.push(
            "cameras",
            json!({"name": "Front", "type": "perspective",
            "perspective": {"yfov": 0.6, "znear": 0.05, "zfar": 100.0, "aspectRatio": 1.5}}),
        );
        // Nodes: 0 Armature (1 Hips → 2 Head → 4 Eye), 3 Body, 5 Camera.
        let body_node = match (skinned, node_scale) {
            (true, _) => json!({"name": "Body", "mesh": 0, "skin": 0}),
            (false, Some(s)) => json!({"name": "Body", "mesh": 0, "scale": [s, s, s]}),
            (false, None) => json!({"name": "Body", "mesh": 0}),
        };
        for node in [
            json!({"name": "Armature", "children": [1, 3]}),
            json!({"name": "Hips", "translation": [0.0, 0.0, 0.0], "children": [2]}),
            json!({"name": "Head", "translation": [0.0, 1.2, 0.0], "children": [4]}),
            body_node,
            json!({"name": "Eye", "mesh": 1, "translation": [0.08, 0.25, 0.24]}),
            json!({"name": "Camera", "camera": 0, "translation": [0.0, 1.0, 4.0]}),
        ] {
            add.push("nodes", node);
        }
        add.push("scenes", json!({"name": "Scene", "nodes": [0, 5]}));
        add.json["scene"] = json!(0);
        if skinned {
            let ibm: Vec<f32> = [[0.0f32; 3], [0.0, -1.2, 0.0]]
                .iter()
                .flat_map(|t| {
                    [
                        1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, t[0], t[1],
                        t[2], 1.0,
                    ]
                })
                .collect();
            let bytes: Vec<u8> = ibm.iter().flat_map(|x| x.to_le_bytes()).collect();
            let view = add.view(bytes, None);
            let a = add.push(
                "accessors",
                json!({"bufferView": view, "componentType": 5126, "count": 2, "type": "MAT4"}),
            );
            add.push("skins", json!({"name": "Armature", "joints": [1, 2], "skeleton": 1, "inverseBindMatrices": a}));
            let times = add.floats(&[0.0, 1.0], 1, None, true);
            let s = (0.1f32).sin();
            let c = (0.1f32).cos();
            let rotations = add.floats(&[0.0, 0.0, 0.0, 1.0, s, 0.0, 0.0, c], 4, None, false);
            add.push(
                "animations",
                json!({"name": "Nod",
                "samplers": [{"input": times, "output": rotations, "interpolation": "LINEAR"}],
                "channels": [{"sampler": 0, "target": {"node": 2, "path": "rotation"}}]}),
            );
        }
        let length = add.bin.len().next_multiple_of(4);
        add.push("buffers", json!({"byteLength": length}));
        let mut used = Vec::new();
        if self.quantized {
            used.push(json!("KHR_mesh_quantization"));
            json["extensionsRequired"] = json!(["KHR_mesh_quantization"]);
        }
        match self.vrm {
            SampleVrm::None => {}
            SampleVrm::V0 => {
                used.push(json!("VRM"));
                json["extensions"] = json!({"VRM": vrm0()});
            }
            SampleVrm::V1 => {
                used.push(json!("VRMC_vrm"));
                used.push(json!("VRMC_springBone"));
                json["extensions"] = json!({"VRMC_vrm": vrm1(), "VRMC_springBone": spring_bones()});
            }
        }
        if !used.is_empty() {
            json["extensionsUsed"] = Value::Array(used);
        }
        bin.push(vec![0; bin.len().next_multiple_of(4) - bin.len()]);
        (json, bin.concat())
    }

    /// A `POSITION` target accessor of `deltas`: sparse when
    /// [`sparse`](Self::sparse) and most are zero; normalised 16-bit when
    /// quantised.
    fn target(&self, add: &mut Appender<'_, '_>, deltas: &[[f32; 3]], scale: Option<f32>) -> usize {
        if let Some(scale) = scale {
            let q: Vec<i16> = deltas
                .iter()
                .flatten()
                .map(|&d| (d / scale * 32767.0).round() as i16)
                .collect();
            let mut bytes = Vec::new();
            for c in q.chunks_exact(3) {
                for v in c {
                    bytes.extend(v.to_le_bytes());
                }
                bytes.extend([0, 0]);
            }
            let view = add.view(bytes, Some(ARRAY_BUFFER));
            add.array("bufferViews")[view]["byteStride"] = json!(8);
            let decoded: Vec<f32> = q.iter().map(|&v| f32::from(v)).collect();
            let (min, max) = super::glb::bounds_of(&decoded, 3);
            return add.push(
                "accessors",
                json!({"bufferView": view, "componentType": 5122,
                "normalized": true, "count": deltas.len(), "type": "VEC3", "min": min, "max": max}),
            );
        }
        add.deltas(deltas, self.sparse)
    }
}

/// VRM 0.x data: meta, humanoid, an empty blend shape master, spring bones
/// and material properties, as VRoid Studio writes them.
fn vrm0() -> Value {
    json!({
        "exporterVersion": "meshmorph sample",
        "specVersion": "0.0",
        "meta": {"title": "Sample", "version": "1", "author": "meshmorph",
            "allowedUserName": "Everyone", "violentUssageName": "Disallow",
            "sexualUssageName": "Disallow", "commercialUssageName": "Allow",
            "licenseName": "CC0", "texture": -1},
        "humanoid": {"humanBones": [
            {"bone": "hips", "node": 1, "useDefaultValues": true},
            {"bone": "head", "node": 2, "useDefaultValues": true}],
            "armStretch": 0.05, "legStretch": 0.05},
        "firstPerson": {"firstPersonBone": 2, "firstPersonBoneOffset": {"x": 0, "y": 0.06, "z": 0},
            "meshAnnotations": [{"mesh": 0, "firstPersonFlag": "Auto"}]},
        "blendShapeMaster": {"blendShapeGroups": [
            {"name": "Joy", "presetName": "joy", "binds": [{"mesh": 0, "index": 0, "weight": 100}],
             "materialValues": [], "isBinary": false}]},
        "secondaryAnimation": {"boneGroups": [{"comment": "hair", "stiffiness": 1.0, "gravityPower": 0,
            "gravityDir": {"x": 0, "y": -1, "z": 0}, "dragForce": 0.4, "center": -1, "hitRadius": 0.02,
            "bones": [2], "colliderGroups": []}], "colliderGroups": []},
        "materialProperties": [{"name": "Skin", "shader": "VRM_USE_GLTFSHADER", "renderQueue": 2000,
            "floatProperties": {}, "vectorProperties": {}, "textureProperties": {}, "keywordMap": {}, "tagMap": {}}],
    })
}

/// VRM 1.0 `VRMC_vrm`: meta, humanoid and a preset expression.
fn vrm1() -> Value {
    json!({
        "specVersion": "1.0",
        "meta": {"name": "Sample", "version": "1", "authors": ["meshmorph"],
            "licenseUrl": "https://vrm.dev/licenses/1.0/", "avatarPermission": "everyone",
            "commercialUsage": "personalNonProfit", "allowRedistribution": true},
        "humanoid": {"humanBones": {"hips": {"node": 1}, "head": {"node": 2}}},
        "expressions": {"preset": {"happy": {"morphTargetBinds": [{"node": 3, "index": 0, "weight": 1.0}],
            "isBinary": false, "overrideBlink": "none", "overrideLookAt": "none", "overrideMouth": "none"}}},
        "lookAt": {"type": "bone", "offsetFromHeadBone": [0.0, 0.06, 0.0]},
    })
}

/// VRM 1.0 `VRMC_springBone`: one spring on the head.
fn spring_bones() -> Value {
    json!({
        "specVersion": "1.0",
        "colliders": [{"node": 1, "shape": {"sphere": {"offset": [0.0, 0.0, 0.0], "radius": 0.1}}}],
        "colliderGroups": [{"name": "Hips", "colliders": [0]}],
        "springs": [{"name": "Head", "joints": [{"node": 2, "hitRadius": 0.02, "stiffness": 1.0,
            "gravityPower": 0.0, "gravityDir": [0.0, -1.0, 0.0], "dragForce": 0.5}], "colliderGroups": [0]}],
    })
}
