//! One mesh of a glTF file read for a transfer: every triangle primitive's
//! vertices side by side (one block per `POSITION` accessor), its morph
//! targets as poses, the node that places it, and the other meshes named
//! when none was asked for.

use std::collections::HashMap;
use std::ops::Range;

use serde_json::Value;

use super::accessor::{read_floats, read_indices};
use super::document::GltfDocument;
use crate::error::Result;
use crate::mesh::seams::Seams;
use crate::mesh::Mesh3;

/// A mesh of a glTF file: its surface in the mesh's own space (the bind
/// pose of a skinned mesh), how the surface's vertices map to its
/// primitives', its morph targets and where its node places it.
#[derive(Clone, Debug)]
#[non_exhaustive]
pub struct GltfMesh {
    /// The mesh's index in the file's `meshes`.
    pub index: usize,
    /// Its name (`mesh N` when it has none).
    pub name: String,
    /// The nodes that show it, in order.
    pub nodes: Vec<usize>,
    /// Whether its (first) node has a skin: then the positions are the
    /// bind pose and [`GltfMesh::transform`] is the identity, as glTF
    /// ignores a skinned mesh's node transform.
    pub skinned: bool,
    /// The column-major 4 × 4 matrix from the mesh's space to the scene's
    /// (its first node's, parents included): for markers and pictures,
    /// never for deltas.
    pub transform: [f64; 16],
    /// Every vertex of the mesh's triangle primitives (block after block),
    /// and the triangles of every triangle primitive, primitive after
    /// primitive. Vertices are not welded: [`GltfMesh::welded`] welds
    /// copies at seams and between primitives.
    pub surface: Mesh3,
    /// The vertex blocks: one per distinct `POSITION` accessor of the
    /// triangle primitives.
    pub blocks: Vec<VertexBlock>,
    /// Each primitive of the mesh, in the file's order.
    pub primitives: Vec<GltfPrimitive>,
    /// The mesh's morph targets, in order: each a pose of
    /// [`GltfMesh::surface`].
    pub targets: Vec<MorphTarget>,
    /// What the reader chose and says (the other meshes when it chose
    /// one).
    pub notes: Vec<String>,
}

/// The vertices of one `POSITION` accessor within [`GltfMesh::surface`].
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub struct VertexBlock {
    /// The accessor.
    pub accessor: usize,
    /// The surface's vertices of this block: the accessor's element `i` is
    /// vertex `vertices.start + i`.
    pub vertices: Range<u32>,
}

/// One primitive of a mesh.
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub struct GltfPrimitive {
    /// The primitive's `mode` (4: triangles, 5: strip, 6: fan; others are
    /// points and lines, not part of the surface).
    pub mode: u64,
    /// Its vertex block, when it has a `POSITION` accessor that a triangle
    /// primitive has.
    pub block: Option<usize>,
    /// Its triangles within [`GltfMesh::surface`]'s (empty for points
    /// and lines).
    pub triangles: Range<usize>,
}

/// A morph target of a mesh, as a pose.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct MorphTarget {
    /// Its name (`mesh.extras.targetNames`, else `target_K`).
    pub name: String,
    /// The surface's positions at weight 1 (base plus the target's
    /// `POSITION` deltas), one per vertex of [`GltfMesh::surface`].
    pub positions: Vec<[f64; 3]>,
}

/// Reads `path` and the mesh `choice` names (a mesh's name or a node's),
/// else the only mesh, else the one with the most vertices (the others
/// named in [`GltfMesh::notes`]).
///
/// # Errors
/// As [`GltfDocument::read`] and [`GltfDocument::mesh`].
pub fn read(path: &std::path::Path, choice: Option<&str>) -> Result<(GltfDocument, GltfMesh)> {
    let doc = GltfDocument::read(path)?;
    let mesh = doc.mesh(choice)?;
    Ok((doc, mesh))
}

impl GltfMesh {
    /// The surface with copies at seams and between primitives welded
    /// ([`Seams::find`]), and the seams that map it back.
    pub fn welded(&self) -> (Seams, Mesh3) {
        let seams = Seams::find(&[&self.surface]);
        let mesh = seams.weld(&self.surface);
        (seams, mesh)
    }

    /// `positions` (of [`GltfMesh::surface`]) placed in the scene by
    /// [`GltfMesh::transform`].
    pub fn placed(&self, positions: &[[f64; 3]]) -> Vec<[f64; 3]> {
        let m = &self.transform;
        positions
            .iter()
            .map(|p| {
                std::array::from_fn(|r| m[r] * p[0] + m[4 + r] * p[1] + m[8 + r] * p[2] + m[12 + r])
            })
            .collect()
    }

    /// `positions` in the scene taken back to the mesh's own space (the
    /// inverse of [`GltfMesh::placed`]); `None` when the node's matrix
    /// cannot be inverted (a scale of 0).
    pub fn unplaced(&self, positions: &[[f64; 3]]) -> Option<Vec<[f64; 3]>> {
        let m = &self.transform;
        let a = |r: usize, c: usize| m[4 * c + r];
        let det = a(0, 0) * (a(1, 1) * a(2, 2) - a(1, 2) * a(2, 1))
            - a(0, 1) * (a(1, 0) * a(2, 2) - a(1, 2) * a(2, 0))
            + a(0, 2) * (a(1, 0) * a(2, 1) - a(1, 1) * a(2, 0));
        if !det.is_finite() || det.abs() < 1e-300 {
            return None;
        }
        // The inverse of the linear part by cofactors.
        let inv = |r: usize, c: usize| {
            let (r1, r2) = ((c + 1) % 3, (c + 2) % 3);
            let (c1, c2) = ((r + 1) % 3, (r + 2) % 3);
            (a(r1, c1) * a(r2, c2) - a(r1, c2) * a(r2, c1)) / det
        };
        Some(
            positions
                .iter()
                .map(|p| {
                    let d = [p[0] - m[12], p[1] - m[13], p[2] - m[14]];
                    std::array::from_fn(|r| (0..3).map(|c| inv(r, c) * d[c]).sum())
                })
                .collect(),
        )
    }

    /// The target names, in order.
    pub fn target_names(&self) -> Vec<&str> {
        self.targets.iter().map(|t| t.name.as_str()).collect()
    }
}

/// The name of mesh `index` (`mesh N` when it has none).
pub(crate) fn mesh_name(doc: &GltfDocument, index: usize) -> String {
    doc.item("meshes", index)
        .ok()
        .and_then(|m| m.get("name"))
        .and_then(Value::as_str)
        .map_or_else(|| format!("mesh {index}"), str::to_string)
}

impl GltfDocument {
    /// The names of the file's meshes, in order (`mesh N` for one without).
    pub fn mesh_names(&self) -> Vec<String> {
        (0..self.count("meshes"))
            .map(|i| mesh_name(self, i))
            .collect()
    }

    /// The mesh `choice` names (a mesh's name, else a node's), else the
    /// only mesh with triangles, else the one with the most vertices.
    ///
    /// # Errors
    /// [`Error::Parse`](crate::Error::Parse) naming the file and the mesh: no mesh of that name,
    /// no mesh with triangles, a mesh compressed with Draco or meshopt, a
    /// bad accessor.
    pub fn mesh(&self, choice: Option<&str>) -> Result<GltfMesh> {
        let names = self.mesh_names();
        let mut notes = Vec::new();
        let index = match choice {
            Some(name) => self.mesh_named(name, &names)?,
            None => {
                let sizes: Vec<usize> = (0..names.len()).map(|i| self.vertex_count(i)).collect();
                let with_triangles: Vec<usize> =
                    (0..names.len()).filter(|&i| sizes[i] > 0).collect();
                match with_triangles.as_slice() {
                    [] => {
                        return Err(self.error(if names.is_empty() {
                            "the file has no mesh".to_string()
                        } else {
                            format!("none of its meshes ({}) has triangles", quoted(&names))
                        }))
                    }
                    [only] => *only,
                    many => {
                        let best = *many
                            .iter()
                            .max_by_key(|&&i| (sizes[i], std::cmp::Reverse(i)))
                            .expect("not empty");
                        let others: Vec<String> = many
                            .iter()
                            .filter(|&&i| i != best)
                            .map(|&i| names[i].clone())
                            .collect();
                        notes.push(format!(
                            "`{}`: mesh `{}` taken ({} vertices, the most); the others are {} (choose one with --source-mesh or --target-mesh)",
                            self.path().display(),
                            names[best],
                            sizes[best],
                            quoted(&others)
                        ));
                        best
                    }
                }
            }
        };
        let mut mesh = self.read_mesh(index, &names[index])?;
        mesh.notes = notes;
        Ok(mesh)
    }

    fn mesh_named(&self, name: &str, names: &[String]) -> Result<usize> {
        if let Some(i) = names.iter().position(|n| n == name) {
            return Ok(i);
        }
        let nodes = self.json().get("nodes").and_then(Value::as_array);
        let by_node = nodes.and_then(|nodes| {
            nodes.iter().find_map(|n| {
                (n.get("name").and_then(Value::as_str) == Some(name))
                    .then(|| n.get("mesh").and_then(Value::as_u64))
                    .flatten()
            })
        });
        match by_node {
            Some(i) if (i as usize) < names.len() => Ok(i as usize),
            _ => Err(self.error(format!(
                "no mesh or node with a mesh is named `{name}`; its meshes are {}",
                quoted(names)
            ))),
        }
    }

    /// The vertices of mesh `index`'s triangle primitives (0 when it has
    /// none or is malformed).
    fn vertex_count(&self, index: usize) -> usize {
        let Ok(mesh) = self.item("meshes", index) else {
            return 0;
        };
        let mut seen = Vec::new();
        for p in primitives(mesh) {
            if !is_triangles(p) {
                continue;
            }
            if let Some(a) = p.pointer("/attributes/POSITION").and_then(Value::as_u64) {
                if !seen.contains(&a) {
                    seen.push(a);
                }
            }
        }
        seen.iter()
            .filter_map(|&a| self.item("accessors", a as usize).ok())
            .filter_map(|a| a.get("count").and_then(Value::as_u64))
            .sum::<u64>() as usize
    }

    fn read_mesh(&self, index: usize, name: &str) -> Result<GltfMesh> {
        let json = self.item("meshes", index)?;
        let prims = primitives(json);
        for (k, p) in prims.iter().enumerate() {
            if p.pointer("/extensions/KHR_draco_mesh_compression")
                .is_some()
            {
                return Err(self.error(format!(
                    "mesh `{name}` (primitive {k}) is compressed with KHR_draco_mesh_compression, which meshmorph does not decode: export it without Draco compression (in Blender: glTF export, Data > Compression off)"
                )));
            }
        }
        let what =
            |k: usize, attribute: &str| format!("{attribute} of primitive {k} of mesh `{name}`");
        // Vertex blocks: the distinct POSITION accessors of the triangle
        // primitives.
        let mut blocks: Vec<VertexBlock> = Vec::new();
        let mut block_of: HashMap<u64, usize> = HashMap::new();
        let mut positions: Vec<[f64; 3]> = Vec::new();
        let mut first_primitive_of_block: Vec<usize> = Vec::new();
        for (k, p) in prims.iter().enumerate() {
            if !is_triangles(p) {
                continue;
            }
            let Some(accessor) = p.pointer("/attributes/POSITION").and_then(Value::as_u64) else {
                return Err(self.error(format!("primitive {k} of mesh `{name}` has no POSITION")));
            };
            if block_of.contains_key(&accessor) {
                continue;
            }
            let values = read_floats(self, accessor as usize, 3, &what(k, "POSITION"))?;
            let start = positions.len() as u32;
            positions.extend(values.chunks_exact(3).map(|c| [c[0], c[1], c[2]]));
            block_of.insert(accessor, blocks.len());
            blocks.push(VertexBlock {
                accessor: accessor as usize,
                vertices: start..positions.len() as u32,
            });
            first_primitive_of_block.push(k);
        }
        if blocks.is_empty() {
            return Err(self.error(format!("mesh `{name}` has no triangles")));
        }
        let mut triangles: Vec<[u32; 3]> = Vec::new();
        let mut primitives_out = Vec::with_capacity(prims.len());
        for (k, p) in prims.iter().enumerate() {
            let block = p
                .pointer("/attributes/POSITION")
                .and_then(Value::as_u64)
                .and_then(|a| block_of.get(&a).copied());
            let start = triangles.len();
            let mode = p.get("mode").and_then(Value::as_u64).unwrap_or(4);
            if let (true, Some(b)) = (is_triangles(p), block) {
                let range = &blocks[b].vertices;
                let n = range.end - range.start;
                let indices = match p.get("indices").and_then(Value::as_u64) {
                    Some(i) => read_indices(self, i as usize, &what(k, "indices"))?,
                    None => (0..n).collect(),
                };
                if let Some(&bad) = indices.iter().find(|&&i| i >= n) {
                    return Err(self.error(format!(
                        "primitive {k} of mesh `{name}` uses vertex {bad}, but its POSITION has {n}"
                    )));
                }
                for t in triangles_of(mode, &indices) {
                    if t[0] != t[1] && t[1] != t[2] && t[0] != t[2] {
                        triangles.push(t.map(|i| i + range.start));
                    }
                }
            }
            primitives_out.push(GltfPrimitive {
                mode,
                block,
                triangles: start..triangles.len(),
            });
        }
        let targets = self.read_targets(
            json,
            name,
            &prims,
            &blocks,
            &first_primitive_of_block,
            &positions,
        )?;
        let surface = Mesh3::new(positions, triangles)
            .map_err(|e| self.error(format!("mesh `{name}`: {e}")))?;
        let nodes = self.nodes_of(index);
        let skinned = nodes
            .first()
            .and_then(|&n| self.item("nodes", n).ok())
            .is_some_and(|n| n.get("skin").is_some());
        let transform = match nodes.first() {
            Some(&n) if !skinned => self.world_matrix(n)?,
            _ => IDENTITY,
        };
        Ok(GltfMesh {
            index,
            name: name.to_string(),
            nodes,
            skinned,
            transform,
            surface,
            blocks,
            primitives: primitives_out,
            targets,
            notes: Vec::new(),
        })
    }

    fn read_targets(
        &self,
        json: &Value,
        name: &str,
        prims: &[&Value],
        blocks: &[VertexBlock],
        first_primitive_of_block: &[usize],
        base: &[[f64; 3]],
    ) -> Result<Vec<MorphTarget>> {
        let count = first_primitive_of_block
            .iter()
            .map(|&k| targets_of(prims[k]).len())
            .max()
            .unwrap_or(0);
        let names = target_names(json);
        let mut targets: Vec<MorphTarget> = (0..count)
            .map(|t| MorphTarget {
                name: names
                    .get(t)
                    .cloned()
                    .unwrap_or_else(|| format!("target_{t}")),
                positions: base.to_vec(),
            })
            .collect();
        for (b, &k) in first_primitive_of_block.iter().enumerate() {
            for (t, target) in targets_of(prims[k]).iter().enumerate() {
                let Some(a) = target.get("POSITION").and_then(Value::as_u64) else {
                    continue;
                };
                let what = format!(
                    "POSITION of morph target {t} (`{}`) of primitive {k} of mesh `{name}`",
                    targets[t].name
                );
                let deltas = read_floats(self, a as usize, 3, &what)?;
                let range = blocks[b].vertices.clone();
                if deltas.len() != 3 * (range.end - range.start) as usize {
                    return Err(self.error(format!(
                        "{what} has {} elements, its primitive's POSITION {}",
                        deltas.len() / 3,
                        range.end - range.start
                    )));
                }
                for (p, d) in targets[t].positions[range.start as usize..range.end as usize]
                    .iter_mut()
                    .zip(deltas.chunks_exact(3))
                {
                    for c in 0..3 {
                        p[c] += d[c];
                    }
                }
            }
        }
        Ok(targets)
    }

    /// The nodes whose `mesh` is `index`.
    pub(crate) fn nodes_of(&self, index: usize) -> Vec<usize> {
        self.json()
            .get("nodes")
            .and_then(Value::as_array)
            .map(|nodes| {
                nodes
                    .iter()
                    .enumerate()
                    .filter(|(_, n)| n.get("mesh").and_then(Value::as_u64) == Some(index as u64))
                    .map(|(i, _)| i)
                    .collect()
            })
            .unwrap_or_default()
    }

    /// Node `node`'s matrix in the scene: its parents' matrices times its own.
    fn world_matrix(&self, node: usize) -> Result<[f64; 16]> {
        let nodes = self.json().get("nodes").and_then(Value::as_array);
        let nodes: &[Value] = nodes.map_or(&[], Vec::as_slice);
        let mut parent = vec![None; nodes.len()];
        for (i, n) in nodes.iter().enumerate() {
            for c in n
                .get("children")
                .and_then(Value::as_array)
                .into_iter()
                .flatten()
            {
                if let Some(c) = c.as_u64().filter(|&c| (c as usize) < nodes.len()) {
                    parent[c as usize] = Some(i);
                }
            }
        }
        let mut m = IDENTITY;
        let mut at = Some(node);
        let mut steps = 0;
        while let Some(n) = at {
            m = multiply(&local_matrix(&nodes[n]), &m);
            at = parent[n];
            steps += 1;
            if steps > nodes.len() {
                return Err(self.error(format!("node {node}'s parents form a cycle")));
            }
        }
        Ok(m)
    }
}

const IDENTITY: [f64; 16] = [
    1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0,
];

/// Column-major `a × b`.
fn multiply(a: &[f64; 16], b: &[f64; 16]) -> [f64; 16] {
    std::array::from_fn(|i| {
        let (col, row) = (i / 4, i % 4);
        (0..4).map(|k| a[k * 4 + row] * b[col * 4 + k]).sum()
    })
}

/// A node's own matrix: `matrix`, else translation × rotation × scale.
fn local_matrix(node: &Value) -> [f64; 16] {
    let numbers = |name: &str| -> Option<Vec<f64>> {
        node.get(name)?
            .as_array()?
            .iter()
            .map(Value::as_f64)
            .collect()
    };
    if let Some(m) = numbers("matrix").filter(|m| m.len() == 16) {
        return m.try_into().expect("16 numbers");
    }
    let t = numbers("translation")
        .filter(|v| v.len() == 3)
        .unwrap_or(vec![0.0; 3]);
    let q = numbers("rotation")
        .filter(|v| v.len() == 4)
        .unwrap_or(vec![0.0, 0.0, 0.0, 1.0]);
    let s = numbers("scale")
        .filter(|v| v.len() == 3)
        .unwrap_or(vec![1.0; 3]);
    let (x, y, z, w) = (q[0], q[1], q[2], q[3]);
    let r = [
        1.0 - 2.0 * (y * y + z * z),
        2.0 * (x * y + z * w),
        2.0 * (x * z - y * w),
        2.0 * (x * y - z * w),
        1.0 - 2.0 * (x * x + z * z),
        2.0 * (y * z + x * w),
        2.0 * (x * z + y * w),
        2.0 * (y * z - x * w),
        1.0 - 2.0 * (x * x + y * y),
    ];
    let mut m = [0.0; 16];
    for col in 0..3 {
        for row in 0..3 {
            m[col * 4 + row] = r[col * 3 + row] * s[col];
        }
    }
    m[12..15].copy_from_slice(&t);
    m[15] = 1.0;
    m
}

/// A mesh's primitives.
pub(crate) fn primitives(mesh: &Value) -> Vec<&Value> {
    mesh.get("primitives")
        .and_then(Value::as_array)
        .map(|a| a.iter().collect())
        .unwrap_or_default()
}

/// A primitive's morph targets.
pub(crate) fn targets_of(primitive: &Value) -> &[Value] {
    primitive
        .get("targets")
        .and_then(Value::as_array)
        .map_or(&[], Vec::as_slice)
}

/// `mesh.extras.targetNames`.
pub(crate) fn target_names(mesh: &Value) -> Vec<String> {
    mesh.pointer("/extras/targetNames")
        .and_then(Value::as_array)
        .map(|a| {
            a.iter()
                .map(|n| n.as_str().unwrap_or_default().to_string())
                .collect()
        })
        .unwrap_or_default()
}

/// Whether a primitive's mode makes triangles (4, 5, 6; 4 when absent).
fn is_triangles(primitive: &Value) -> bool {
    matches!(
        primitive.get("mode").and_then(Value::as_u64).unwrap_or(4),
        4..=6
    )
}

/// The triangles of a triangle list, strip or fan.
fn triangles_of(mode: u64, indices: &[u32]) -> Vec<[u32; 3]> {
    match mode {
        5 => indices
            .windows(3)
            .enumerate()
            .map(|(i, w)| {
                if i % 2 == 0 {
                    [w[0], w[1], w[2]]
                } else {
                    [w[1], w[0], w[2]]
                }
            })
            .collect(),
        6 => indices
            .get(1..)
            .unwrap_or(&[])
            .windows(2)
            .map(|w| [indices[0], w[0], w[1]])
            .collect(),
        _ => indices
            .chunks_exact(3)
            .map(|c| [c[0], c[1], c[2]])
            .collect(),
    }
}

/// `` `a`, `b` and `c` ``.
fn quoted(names: &[String]) -> String {
    let q: Vec<String> = names.iter().map(|n| format!("`{n}`")).collect();
    match q.as_slice() {
        [] => "none".to_string(),
        [one] => one.clone(),
        [rest @ .., last] => format!("{} and {last}", rest.join(", ")),
    }
}
