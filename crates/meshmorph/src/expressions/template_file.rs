//! Reading an expression template's GLB (the layout `tools/arkit-template/
//! build.py` writes) through the library's glTF reader: the meshes'
//! positions, triangles and morph-target deltas (any storage glTF allows:
//! `f32` or quantised, dense or sparse), `extras.targetNames`,
//! `extras.landmarks` and `extras.regions`.

use std::path::Path;

use crate::error::Result;
use crate::expressions::template::{ExpressionTemplate, TemplatePart};
use crate::io::gltf::accessor::{read_floats, read_indices};
use crate::io::gltf::GltfDocument;
use crate::mesh::Mesh3;

/// Reads a template GLB; `name` names it in errors.
pub fn read_template_glb(bytes: &[u8], name: &str) -> Result<ExpressionTemplate> {
    let doc = GltfDocument::parse(bytes.to_vec(), Path::new(name))?;
    let bad = |m: &str| doc.error(m);
    let meshes = doc
        .json()
        .get("meshes")
        .and_then(|m| m.as_array())
        .ok_or_else(|| bad("no meshes"))?;
    let mut head = None;
    let mut parts = Vec::new();
    for (m, mesh) in meshes.iter().enumerate() {
        let name = mesh["name"]
            .as_str()
            .map_or_else(|| format!("mesh {m}"), String::from);
        let read = read_mesh(&doc, m, &name)?;
        if name == "head" {
            head = Some((mesh, read));
        } else {
            parts.push((name, read));
        }
    }
    let (head_json, (head_mesh, head_deltas)) = head.ok_or_else(|| bad("no mesh named `head`"))?;
    let extras = &head_json["extras"];
    let shape_names: Vec<String> = extras["targetNames"]
        .as_array()
        .map(|a| {
            a.iter()
                .filter_map(|n| n.as_str().map(String::from))
                .collect()
        })
        .unwrap_or_else(|| {
            (0..head_deltas.len())
                .map(|k| format!("target_{k}"))
                .collect()
        });
    let landmarks = extras["landmarks"]
        .as_array()
        .ok_or_else(|| bad("the head has no `extras.landmarks`"))?
        .iter()
        .map(|l| {
            Some((
                l["name"].as_str()?.to_string(),
                u32::try_from(l["vertex"].as_u64()?).ok()?,
            ))
        })
        .collect::<Option<Vec<_>>>()
        .ok_or_else(|| bad("a landmark without a `name` and a `vertex`"))?;
    let region = |name: &str| {
        extras["regions"][name]
            .as_array()
            .and_then(|r| Some(r.first()?.as_u64()? as usize..r.get(1)?.as_u64()? as usize + 1))
    };
    let face = region("face").unwrap_or(0..head_mesh.num_vertices());
    let outer = match (region("face"), region("headNeck")) {
        (Some(f), Some(h)) => f.start.min(h.start)..f.end.max(h.end),
        _ => 0..head_mesh.num_vertices(),
    };
    // The identity bases are the head's targets that `extras.identityBases`
    // names, after its shapes.
    let bases = extras["identityBases"].as_array().map_or(0, Vec::len);
    if bases > head_deltas.len() {
        return Err(bad(
            "`extras.identityBases` names more targets than the head has",
        ));
    }
    let mut head_deltas = head_deltas;
    let mut identity = head_deltas.split_off(head_deltas.len() - bases);
    // Each basis may be stored stretched, its unit beside it.
    if let Some(units) = extras["identityUnits"].as_array() {
        if units.len() != bases {
            return Err(bad(
                "`extras.identityUnits` does not give one unit per identity basis",
            ));
        }
        for (basis, unit) in identity.iter_mut().zip(units) {
            let unit = unit
                .as_f64()
                .filter(|u| u.is_finite() && *u > 0.0)
                .ok_or_else(|| bad("an identity basis's unit is not a positive number"))?;
            basis.iter_mut().flatten().for_each(|x| *x *= unit);
        }
    }
    let mut shape_names = shape_names;
    shape_names.truncate(head_deltas.len());
    let template = ExpressionTemplate {
        head: head_mesh,
        face,
        shape_names,
        head_deltas,
        landmarks,
        identity,
        outer,
        parts: parts
            .into_iter()
            .map(|(name, (mesh, deltas))| TemplatePart { name, mesh, deltas })
            .collect(),
    };
    template.check(name)?;
    Ok(template)
}

/// Mesh `m` (named `name`)'s first primitive: its positions and triangles,
/// and each morph target's position deltas.
fn read_mesh(doc: &GltfDocument, m: usize, name: &str) -> Result<(Mesh3, Vec<Vec<[f64; 3]>>)> {
    let prim = &doc.json()["meshes"][m]["primitives"][0];
    let accessor = |value: &serde_json::Value, what: &str| {
        value
            .as_u64()
            .map(|a| a as usize)
            .ok_or_else(|| doc.error(format!("mesh `{name}` has no {what}")))
    };
    let vectors = |index: usize, what: &str| -> Result<Vec<[f64; 3]>> {
        let floats = read_floats(doc, index, 3, &format!("{what} of mesh `{name}`"))?;
        Ok(floats.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect())
    };
    let positions = vectors(
        accessor(&prim["attributes"]["POSITION"], "POSITION")?,
        "POSITION",
    )?;
    let indices = read_indices(
        doc,
        accessor(&prim["indices"], "indices")?,
        &format!("the indices of mesh `{name}`"),
    )?;
    if indices.len() % 3 != 0 {
        return Err(doc.error(format!(
            "mesh `{name}` has an index count that is not a multiple of 3"
        )));
    }
    let triangles = indices
        .chunks_exact(3)
        .map(|t| [t[0], t[1], t[2]])
        .collect();
    let deltas = match prim["targets"].as_array() {
        Some(targets) => targets
            .iter()
            .enumerate()
            .map(|(t, target)| {
                let what = format!("target {t}'s POSITION");
                vectors(accessor(&target["POSITION"], &what)?, &what)
            })
            .collect::<Result<Vec<_>>>()?,
        None => Vec::new(),
    };
    let mesh =
        Mesh3::new(positions, triangles).map_err(|e| doc.error(format!("mesh `{name}`: {e}")))?;
    Ok((mesh, deltas))
}
