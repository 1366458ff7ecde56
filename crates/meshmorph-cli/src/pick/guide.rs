//! `meshmorph pick --template`: landmarks placed on a head, guided by an
//! expression template. The template's head is the source of every pair,
//! each pair named by the landmark it places and its source point fixed at
//! the template's landmark vertex; the page lights the next one on the
//! template, a click on the head places it. Each fit also puts two of the
//! template's shapes on the head ([`Guide::preview`]), and a save writes
//! the head's points as a landmark file (`meshmorph expressions
//! --markers`).

use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};
use meshmorph::{
    expressions, landmark_name, ExpressionOptions, ExpressionTemplate, Markers, Mesh3,
    SurfacePoint, MIN_LANDMARKS, RECOMMENDED_LANDMARKS,
};
use serde_json::{json, Value};

use crate::output::WeldedFile;
use crate::transfer::Reference;

/// The shapes the preview puts on the head together.
pub const PREVIEW: [&str; 2] = ["jawOpen", "eyeBlinkLeft"];

/// A template and the landmarks the page asks for, in order.
pub struct Guide {
    pub template: ExpressionTemplate,
    /// What the page calls the template (`arkit`, or its file).
    pub name: String,
    /// `(name, template vertex)`: the recommended landmarks first, then
    /// the template's others by iBUG number.
    pub landmarks: Vec<(String, u32)>,
}

impl Guide {
    /// `arkit` (built in) or a rig's GLB.
    pub fn read(template: &str) -> Result<Self> {
        let (template, name) = if template == "arkit" {
            (ExpressionTemplate::arkit(), "arkit".to_string())
        } else {
            let path = Path::new(template);
            let bytes = std::fs::read(path)
                .with_context(|| format!("reading the template `{}`", path.display()))?;
            let name = path.display().to_string();
            let template = ExpressionTemplate::from_glb(&bytes, &name)?;
            (template, format!("the template `{name}`"))
        };
        let numbered = |n: u8| {
            template
                .landmark(&n.to_string())
                .map(|v| (landmark_name(n), v))
        };
        let mut landmarks: Vec<(String, u32)> = RECOMMENDED_LANDMARKS
            .iter()
            .filter_map(|&n| numbered(n))
            .collect();
        landmarks.extend(
            (1..=68)
                .filter(|n| !RECOMMENDED_LANDMARKS.contains(n))
                .filter_map(numbered),
        );
        if landmarks.len() < MIN_LANDMARKS {
            bail!(
                "{name} has {} of the iBUG landmarks (1 to 68) by number: at least {MIN_LANDMARKS} are needed to place",
                landmarks.len()
            );
        }
        Ok(Guide {
            template,
            name,
            landmarks,
        })
    }

    /// The template's head as the source reference of the pairs.
    pub fn source(&self) -> Result<Reference> {
        let head = &self.template.head;
        let path = PathBuf::from(&self.name);
        let mut text = Vec::new();
        meshmorph::io::write_positions_to(
            &mut text,
            &path,
            head.positions(),
            head.triangles(),
            meshmorph::io::Format::Obj,
        )?;
        let file = meshmorph::io::MeshFile::parse(text, meshmorph::io::Format::Obj, &path)?;
        let (file, mesh) = WeldedFile::new(file, false);
        Ok(Reference {
            file,
            mesh,
            rig: None,
        })
    }

    /// The landmarks for the page: `[{name, vertex}]`.
    pub fn describe(&self) -> Value {
        let list: Vec<Value> = self
            .landmarks
            .iter()
            .map(|(name, vertex)| json!({ "name": name, "vertex": vertex }))
            .collect();
        json!({ "template": self.name, "landmarks": list, "needed": MIN_LANDMARKS, "preview": PREVIEW })
    }

    /// The head's points of `markers`, each named by its landmark: refused
    /// when a pair has no name, or one that is not a landmark the guide
    /// asks for, or when its template point is not that landmark's vertex.
    pub fn points(&self, markers: &Markers) -> Result<Vec<(String, SurfacePoint)>> {
        (0..markers.pairs().len())
            .map(|k| {
                let Some(name) = markers.name(k) else {
                    bail!("pair {}: without a landmark's name", k + 1);
                };
                let Some(&(_, vertex)) = self.landmarks.iter().find(|(n, _)| n == name) else {
                    bail!(
                        "pair {} is named `{name}`, which is not a landmark of {}",
                        k + 1,
                        self.name
                    );
                };
                let [source, target] = markers.pairs()[k];
                if source != SurfacePoint::Vertex(vertex) {
                    bail!(
                        "pair {} ({name}): its template point is not the landmark's vertex {vertex}",
                        k + 1
                    );
                }
                Ok((name.to_string(), target))
            })
            .collect()
    }

    /// The head posed by the [`PREVIEW`] shapes at once, carried by the
    /// placed landmarks; `None` while fewer than [`MIN_LANDMARKS`] are
    /// placed.
    pub fn preview(&self, markers: &Markers, head: &Mesh3) -> Result<Option<Vec<[f64; 3]>>> {
        let points = self.points(markers)?;
        if points.len() < MIN_LANDMARKS {
            return Ok(None);
        }
        let placed: Vec<(String, [f64; 3])> = points
            .into_iter()
            .map(|(name, p)| (name, p.position(head)))
            .collect();
        let made = expressions(&self.template, head, &placed, &ExpressionOptions::default())?;
        let mut posed = head.positions().to_vec();
        for shape in PREVIEW {
            if let Some(k) = made.names.iter().position(|n| n == shape) {
                for (p, d) in posed.iter_mut().zip(&made.deltas[k]) {
                    *p = std::array::from_fn(|i| p[i] + d[i]);
                }
            }
        }
        Ok(Some(posed))
    }

    /// The landmark file of `markers`: one line a landmark, `name v VERTEX`
    /// or `name t TRIANGLE b0 b1 b2` on the head, as `expressions --markers`
    /// reads it.
    pub fn landmark_file(&self, markers: &Markers) -> Result<String> {
        let mut text = format!(
            "# landmarks on the head for `meshmorph expressions --markers` (template {}): name, then the point\n",
            self.name
        );
        for (name, point) in self.points(markers)? {
            text += &match point {
                SurfacePoint::Vertex(v) => format!("{name} v {v}\n"),
                SurfacePoint::Triangle {
                    triangle,
                    barycentric: [a, b, c],
                } => format!("{name} t {triangle} {a} {b} {c}\n"),
            };
        }
        Ok(text)
    }
}
