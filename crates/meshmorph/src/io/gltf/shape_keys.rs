//! New shape keys written into a user's own glTF file: each shape a morph
//! target of the chosen mesh (every primitive of it), named in
//! `mesh.extras.targetNames`, sparse where most vertices do not move. The
//! JSON is edited as it was read (every member meshmorph does not know is
//! kept) and the new data appended to the file's binary chunk, so that
//! everything else keeps its meaning: nodes, materials, textures, skins,
//! animations, cameras, other meshes, extensions (VRM's included),
//! `extras` and the asset's copyright.
//!
//! What changes besides the mesh's targets: its `weights` and those of its
//! nodes get a 0 for each new target; animations of those nodes' weights
//! get a 0 track for each (glTF needs one value per target and key); with
//! [`ShapeKeyOptions::vrm_expressions`], the VRM's custom expressions
//! (VRM 0.x blend shape groups, VRM 1.0 `expressions.custom`) gain one per
//! shape.

use std::io::Write;
use std::path::Path;

use rayon::prelude::*;
use serde_json::{json, Map, Value};

use super::accessor::read_floats;
use super::base64;
use super::document::{Container, GltfDocument};
use super::glb::{glb_length, write_glb, Appender, DeltaSummary, Pieces};
use super::mesh::{target_names, GltfMesh};
use crate::error::{Error, Result};
use crate::io::write_atomic;

/// A shape to add: its name and the positions of every vertex of
/// [`GltfMesh::surface`] in it.
#[derive(Clone, Copy, Debug)]
pub struct NewShape<'a> {
    /// The morph target's name.
    pub name: &'a str,
    /// `#V` positions, one per vertex of the mesh's surface (not welded:
    /// [`Seams::unweld`](crate::Seams::unweld) gives them from welded
    /// ones).
    pub positions: &'a [[f64; 3]],
}

/// How shape keys are added.
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub struct ShapeKeyOptions {
    /// A shape whose name the mesh already has replaces that target (same
    /// index); else such a shape is refused. Default `false`.
    pub replace: bool,
    /// Also add each shape as a VRM custom expression of the same name
    /// (the file must be a VRM 0.x or 1.0). Default `false`.
    pub vrm_expressions: bool,
    /// Store a target sparsely when that is smaller. Default `true`.
    pub sparse: bool,
}

impl Default for ShapeKeyOptions {
    fn default() -> Self {
        ShapeKeyOptions {
            replace: false,
            vrm_expressions: false,
            sparse: true,
        }
    }
}

impl ShapeKeyOptions {
    /// Sets [`replace`](Self::replace).
    pub fn with_replace(mut self, replace: bool) -> Self {
        self.replace = replace;
        self
    }

    /// Sets [`vrm_expressions`](Self::vrm_expressions).
    pub fn with_vrm_expressions(mut self, vrm_expressions: bool) -> Self {
        self.vrm_expressions = vrm_expressions;
        self
    }

    /// Sets [`sparse`](Self::sparse).
    pub fn with_sparse(mut self, sparse: bool) -> Self {
        self.sparse = sparse;
        self
    }
}

/// Writes `doc` with `shapes` added to `mesh` to `path` (atomically: a
/// failed write leaves nothing), in the document's own container: a GLB
/// (`.glb`, `.vrm`) stays binary, a `.gltf` stays text with its new data
/// in a `data:` URI (its other files are referred to as before, so it
/// belongs beside them).
///
/// # Errors
/// As [`add_shape_keys`]; [`Error::Io`] when the file cannot be written.
pub fn write_shape_keys(
    path: &Path,
    doc: &GltfDocument,
    mesh: &GltfMesh,
    shapes: &[NewShape<'_>],
    options: &ShapeKeyOptions,
) -> Result<()> {
    let edited = edit(doc, mesh, shapes, options)?;
    write_atomic(path, |w| edited.write_to(w))
}

/// The bytes of `doc` with `shapes` added to `mesh` (read from `doc`) as
/// morph targets after its own (see the [module documentation](self)).
///
/// # Errors
/// [`Error::InvalidMesh`] naming the file, the mesh and the shape: a shape
/// with another vertex count or a coordinate that is not finite, two
/// shapes of one name, a name the mesh has (unless
/// [`ShapeKeyOptions::replace`]), `vrm_expressions` for a file that is not
/// a VRM; [`Error::Parse`] when an animation of the mesh's weights cannot
/// be read.
///
/// # Performance
/// One pass over each shape's positions encodes its deltas (checking them
/// finite as it goes); the file's bytes are then copied once, followed by
/// the new ones ([`write_shape_keys`] writes them to the file from where
/// they are, without assembling them first).
pub fn add_shape_keys(
    doc: &GltfDocument,
    mesh: &GltfMesh,
    shapes: &[NewShape<'_>],
    options: &ShapeKeyOptions,
) -> Result<Vec<u8>> {
    let edited = edit(doc, mesh, shapes, options)?;
    let mut bytes = Vec::with_capacity(edited.len());
    edited
        .write_to(&mut bytes)
        .expect("writing to memory does not fail");
    Ok(bytes)
}

/// A document with shape keys added, in parts: its new JSON, and for a GLB
/// its binary chunk as the file's own bytes followed by the new ones (made
/// as they are written).
struct Edited<'d> {
    /// The new JSON.
    json: Vec<u8>,
    /// For a GLB: its binary chunk, as the file's own bytes and the new
    /// ones after them.
    bin: Option<(&'d [u8], Pieces<'d>)>,
}

impl Edited<'_> {
    /// The length of the file.
    fn len(&self) -> usize {
        match &self.bin {
            Some((old, new)) => glb_length(self.json.len(), Some(old.len() + new.len())),
            None => self.json.len(),
        }
    }

    /// Writes the file: a GLB from its parts, or the JSON of a `.gltf`.
    fn write_to(&self, w: &mut dyn Write) -> std::io::Result<()> {
        match &self.bin {
            Some((old, new)) => {
                let mut write_bin = |w: &mut dyn Write| {
                    w.write_all(old)?;
                    new.write_to(w)
                };
                write_glb(w, &self.json, Some((old.len() + new.len(), &mut write_bin)))
            }
            None => w.write_all(&self.json),
        }
    }
}

/// The edit behind [`add_shape_keys`] and [`write_shape_keys`]: the new
/// JSON and the new bytes of the binary chunk, the file's own left where
/// they are.
fn edit<'d>(
    doc: &'d GltfDocument,
    mesh: &'d GltfMesh,
    shapes: &'d [NewShape<'d>],
    options: &ShapeKeyOptions,
) -> Result<Edited<'d>> {
    let invalid = |message: String| {
        Error::InvalidMesh(format!(
            "`{}`, mesh `{}`: {message}",
            doc.path().display(),
            mesh.name
        ))
    };
    let n = mesh.surface.num_vertices();
    let mut json = doc.json().clone();
    let mesh_json = &json["meshes"][mesh.index];
    let primitive_count = mesh.primitives.len();
    let old_count = (0..primitive_count)
        .map(|k| {
            mesh_json["primitives"][k]["targets"]
                .as_array()
                .map_or(0, Vec::len)
        })
        .max()
        .unwrap_or(0);
    let mut names = target_names(mesh_json);
    names.resize(old_count.max(names.len()), String::new());
    for (t, name) in names.iter_mut().enumerate().take(old_count) {
        if name.is_empty() {
            *name = format!("target_{t}");
        }
    }
    names.truncate(old_count);
    // Where each shape goes.
    let mut slots = Vec::with_capacity(shapes.len());
    for (s, shape) in shapes.iter().enumerate() {
        if shape.positions.len() != n {
            return Err(invalid(format!(
                "shape `{}` has {} positions, the mesh {n} vertices",
                shape.name,
                shape.positions.len()
            )));
        }
        if shapes[..s].iter().any(|o| o.name == shape.name) {
            return Err(invalid(format!("two shapes are named `{}`", shape.name)));
        }
        match names.iter().position(|m| m == shape.name) {
            Some(t) if options.replace => slots.push(t),
            Some(_) => {
                return Err(invalid(format!(
                    "it already has a shape key `{}`: pass --replace-shapes to replace it, or give the shape another name",
                    shape.name
                )))
            }
            None => {
                slots.push(names.len());
                names.push(shape.name.to_string());
            }
        }
    }
    let new_count = names.len();
    // The buffer the new data goes into: a GLB's binary chunk, else a new
    // buffer of its own written as a `data:` URI.
    let glb_buffer = (doc.container() == Container::Glb && doc.bin().is_some())
        .then(|| {
            json["buffers"]
                .as_array()
                .and_then(|b| b.iter().position(|b| b.get("uri").is_none()))
        })
        .flatten();
    // The new bytes follow the buffer's own, which stay where they are.
    let (buffer, old): (usize, &[u8]) = match glb_buffer {
        Some(b) => {
            let length = json["buffers"][b]["byteLength"].as_u64().unwrap_or(0) as usize;
            let old = doc.bin().expect("checked");
            (b, &old[..length.min(old.len())])
        }
        None => (json["buffers"].as_array().map_or(0, Vec::len), &[]),
    };
    let mut bin = Pieces::default();
    if glb_buffer.is_none() {
        let buffers = json
            .as_object_mut()
            .expect("an object")
            .entry("buffers")
            .or_insert_with(|| json!([]));
        buffers
            .as_array_mut()
            .expect("an array")
            .push(json!({"byteLength": 0}));
    }
    let mut add = Appender {
        json: &mut json,
        buffer,
        base: old.len(),
        bin: &mut bin,
    };
    for (k, primitive) in mesh.primitives.iter().enumerate() {
        let block = primitive.block.map(|b| mesh.blocks[b].vertices.clone());
        let position =
            add.json["meshes"][mesh.index]["primitives"][k]["attributes"]["POSITION"].as_u64();
        let count = match (&block, position) {
            (Some(r), _) => (r.end - r.start) as usize,
            (None, Some(a)) => add.json["accessors"][a as usize]["count"]
                .as_u64()
                .unwrap_or(0) as usize,
            (None, None) => 0,
        };
        let mut targets: Vec<Value> = add.json["meshes"][mesh.index]["primitives"][k]["targets"]
            .as_array()
            .cloned()
            .unwrap_or_default();
        while targets.len() < new_count {
            targets.push(Value::Null);
        }
        for t in 0..new_count {
            if targets[t].is_null() {
                targets[t] = zero_target(&mut add, count);
            }
        }
        // A replaced target loses its other attributes (normals and
        // tangents of the old shape). One pass over each shape (on every
        // thread) finds its bounds and what moves; its bytes are made as
        // the file is written.
        let Some(range) = block else {
            for &slot in &slots {
                targets[slot] = zero_target(&mut add, count);
            }
            add.json["meshes"][mesh.index]["primitives"][k]["targets"] = Value::Array(targets);
            continue;
        };
        let range = range.start as usize..range.end as usize;
        let rest = &mesh.surface.positions()[range.clone()];
        let deltas: Vec<_> = shapes
            .iter()
            .map(|shape| {
                let moved = &shape.positions[range.clone()];
                move |v: usize| -> [f32; 3] {
                    std::array::from_fn(|c| (moved[v][c] - rest[v][c]) as f32)
                }
            })
            .collect();
        let summaries: Vec<DeltaSummary> = deltas
            .par_iter()
            .map(|delta| DeltaSummary::of(rest.len(), delta))
            .collect();
        for (((summary, delta), &slot), shape) in
            summaries.iter().zip(deltas).zip(&slots).zip(shapes)
        {
            if !summary.finite {
                return Err(invalid(not_finite(shape)));
            }
            let accessor = add.deltas_later(summary, options.sparse, delta);
            targets[slot] = json!({ "POSITION": accessor });
        }
        add.json["meshes"][mesh.index]["primitives"][k]["targets"] = Value::Array(targets);
    }
    let mesh_json = &mut add.json["meshes"][mesh.index];
    set_extra(mesh_json, "targetNames", json!(names));
    extend_weights(mesh_json, new_count);
    for &node in &mesh.nodes {
        extend_weights(&mut add.json["nodes"][node], new_count);
    }
    extend_animations(doc, &mut add, &mesh.nodes, old_count, new_count)?;
    if options.vrm_expressions {
        add_vrm_expressions(add.json, mesh, shapes, &slots, options.replace).map_err(invalid)?;
    }
    // The buffer's new length, and the new buffer's data.
    match glb_buffer {
        Some(_) => json["buffers"][buffer]["byteLength"] = json!(old.len() + bin.len()),
        None => {
            json["buffers"][buffer] = json!({
                "byteLength": bin.len(),
                "uri": format!("data:application/octet-stream;base64,{}", base64::encode(&bin.concat())),
            });
        }
    }
    let json = serde_json::to_vec(&json).expect("JSON serialises");
    let bin = match (doc.container(), glb_buffer) {
        (Container::Json, _) => None,
        (Container::Glb, Some(_)) => Some((old, bin)),
        (Container::Glb, None) => doc.bin().map(|b| (b, Pieces::default())),
    };
    Ok(Edited { json, bin })
}

/// Why `shape` is refused when a delta of it is not finite: the first
/// vertex with a coordinate that is not finite, or too large for `f32`.
fn not_finite(shape: &NewShape<'_>) -> String {
    match shape
        .positions
        .iter()
        .position(|p| p.iter().any(|x| !x.is_finite()))
    {
        Some(v) => format!(
            "shape `{}`: vertex {v} has a coordinate that is not finite",
            shape.name
        ),
        None => format!(
            "shape `{}` moves a vertex farther than glTF's 32-bit floats hold",
            shape.name
        ),
    }
}

/// `value[extras][name] = item`, making `extras` when missing.
fn set_extra(value: &mut Value, name: &str, item: Value) {
    if !value.get("extras").is_some_and(Value::is_object) {
        value["extras"] = Value::Object(Map::new());
    }
    value["extras"][name] = item;
}

/// `weights` (when present) padded with zeros to `count`.
fn extend_weights(value: &mut Value, count: usize) {
    if let Some(w) = value.get_mut("weights").and_then(Value::as_array_mut) {
        while w.len() < count {
            w.push(json!(0.0));
        }
    }
}

/// A target of zeros: `POSITION` of an accessor without data.
fn zero_target(add: &mut Appender<'_, '_>, count: usize) -> Value {
    json!({ "POSITION": add.zeros(count) })
}

/// Animations of the weights of `nodes`: each output's rows of
/// `old_count` values made rows of `new_count` (zeros for the new
/// targets), in a new `f32` accessor.
fn extend_animations(
    doc: &GltfDocument,
    add: &mut Appender<'_, '_>,
    nodes: &[usize],
    old_count: usize,
    new_count: usize,
) -> Result<()> {
    if new_count == old_count || old_count == 0 {
        // Without targets before, no animation of weights can be valid.
        return Ok(());
    }
    let animations = add.json["animations"].as_array().map_or(0, Vec::len);
    for a in 0..animations {
        let channels = add.json["animations"][a]["channels"]
            .as_array()
            .cloned()
            .unwrap_or_default();
        let mut done = Vec::new();
        for channel in channels {
            let target = &channel["target"];
            let of_mesh = target["path"] == "weights"
                && target["node"]
                    .as_u64()
                    .is_some_and(|n| nodes.contains(&(n as usize)));
            let Some(sampler) = channel["sampler"].as_u64().filter(|_| of_mesh) else {
                continue;
            };
            if done.contains(&sampler) {
                continue;
            }
            done.push(sampler);
            let Some(output) =
                add.json["animations"][a]["samplers"][sampler as usize]["output"].as_u64()
            else {
                continue;
            };
            let old = read_floats(
                doc,
                output as usize,
                1,
                &format!("the weights animated by animation {a}"),
            )?;
            let mut new = Vec::with_capacity(old.len() / old_count * new_count);
            for row in old.chunks(old_count) {
                new.extend(row.iter().map(|&x| x as f32));
                new.extend(std::iter::repeat_n(0.0, new_count - row.len()));
            }
            let accessor = add.floats(&new, 1, None, false);
            add.json["animations"][a]["samplers"][sampler as usize]["output"] = json!(accessor);
        }
    }
    Ok(())
}

/// The shapes as VRM custom expressions: VRM 0.x blend shape groups of
/// preset `unknown`, VRM 1.0 `expressions.custom` entries.
fn add_vrm_expressions(
    json: &mut Value,
    mesh: &GltfMesh,
    shapes: &[NewShape<'_>],
    slots: &[usize],
    replace: bool,
) -> std::result::Result<(), String> {
    let clash = |name: &str| {
        format!("the VRM already has an expression `{name}`: pass --replace-shapes to replace it")
    };
    if json.pointer("/extensions/VRMC_vrm").is_some() {
        let node = *mesh
            .nodes
            .first()
            .ok_or("no node shows the mesh, so a VRM 1.0 expression cannot bind it")?;
        let vrm = &mut json["extensions"]["VRMC_vrm"];
        if !vrm["expressions"].is_object() {
            vrm["expressions"] = json!({});
        }
        if !vrm["expressions"]["custom"].is_object() {
            vrm["expressions"]["custom"] = json!({});
        }
        for (shape, &slot) in shapes.iter().zip(slots) {
            let custom = &mut vrm["expressions"]["custom"];
            if custom.get(shape.name).is_some() && !replace {
                return Err(clash(shape.name));
            }
            custom[shape.name] = json!({
                "morphTargetBinds": [{"node": node, "index": slot, "weight": 1.0}],
                "isBinary": false,
                "overrideBlink": "none",
                "overrideLookAt": "none",
                "overrideMouth": "none",
            });
        }
        return Ok(());
    }
    if json.pointer("/extensions/VRM").is_some() {
        let master = &mut json["extensions"]["VRM"]["blendShapeMaster"];
        if !master["blendShapeGroups"].is_array() {
            master["blendShapeGroups"] = json!([]);
        }
        let groups = master["blendShapeGroups"].as_array_mut().expect("an array");
        for (shape, &slot) in shapes.iter().zip(slots) {
            let group = json!({
                "name": shape.name,
                "presetName": "unknown",
                "binds": [{"mesh": mesh.index, "index": slot, "weight": 100}],
                "materialValues": [],
                "isBinary": false,
            });
            match groups.iter().position(|g| g["name"] == shape.name) {
                Some(_) if !replace => return Err(clash(shape.name)),
                Some(g) => groups[g] = group,
                None => groups.push(group),
            }
        }
        return Ok(());
    }
    Err("--vrm-expressions needs a VRM (its `VRM` or `VRMC_vrm` extension), and this file has neither".to_string())
}
