//! What the page of `meshmorph pick` may ask for: its own files, the two
//! meshes (binary arrays), the session (file names, the starting markers,
//! the mirror planes), a fit of the current markers (the correspondence,
//! its fit report and, with `--pose`, that pose transferred), a pair
//! mirrored across the meshes' planes, a save of the markers to `-o`, and
//! the end of the session. Nothing else is read or written: the files are
//! those named on the command line, read once at the start.

use std::path::PathBuf;
use std::sync::mpsc::Sender;
use std::sync::Mutex;
use std::time::Instant;

use anyhow::{bail, Context, Result};
use meshmorph::{Markers, MirrorPlane, SurfacePoint, Transfer, TransferOptions};
use serde::Deserialize;
use serde_json::{json, Value};

use super::door::{Handler, Request, Response};
use super::guide::Guide;
use super::page;
use crate::outputs::{Output, Plan, Staging};
use crate::transfer::{CorrespondArgs, Reference, References};

/// The most marker pairs a request may hold.
pub const MAX_MARKERS: usize = 10_000;

/// One run of `pick`: the meshes, what the fit needs, and where to save.
pub struct Session {
    pub refs: References,
    pub correspond: CorrespondArgs,
    pub source: Reference,
    pub target: Reference,
    /// The pose shown transferred after each fit (welded like the source).
    pub pose: Option<(PathBuf, meshmorph::Mesh3)>,
    /// Where "save" writes.
    pub save: SaveTarget,
    /// The markers the page starts from.
    pub start: Markers,
    pub planes: [Option<MirrorPlane>; 2],
    /// One fit at a time (each takes the machine's cores).
    pub fitting: Mutex<()>,
    /// Told when the page's "done" has been answered.
    pub done: Mutex<Sender<()>>,
    /// Held by a save for its whole length, and by "done" (which sets it):
    /// "done" waits for a save under way, and no save starts after it.
    pub ended: Mutex<bool>,
    /// With `--template`: the template whose landmarks are placed on the
    /// head (the target); the source is its head.
    pub guide: Option<Guide>,
}

/// Where "save" writes, and every file the run reads: each save (and the
/// check before serving) goes through the output rules against them.
pub struct SaveTarget {
    pub path: PathBuf,
    pub inputs: Vec<(PathBuf, &'static str)>,
}

impl SaveTarget {
    /// The save planned and prepared: refused if it would write over an
    /// input, else staged for [`Staging::write`] and [`Staging::commit`].
    pub fn prepare(&self) -> Result<(Staging, Output)> {
        let mut plan = Plan::new();
        for (path, role) in &self.inputs {
            plan.input(path, role);
        }
        let out = plan.file(&self.path, "marker file");
        Ok((plan.prepare()?, out))
    }
}

/// A marker pair as the page sends it.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct PagePair {
    #[serde(default)]
    name: Option<String>,
    source: PagePoint,
    target: PagePoint,
}

/// A surface point as the page sends it: a vertex, or a triangle's point.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct PagePoint {
    #[serde(default)]
    vertex: Option<u32>,
    #[serde(default)]
    triangle: Option<u32>,
    #[serde(default)]
    barycentric: Option<[f64; 3]>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct PageMarkers {
    pairs: Vec<PagePair>,
}

impl Handler for Session {
    fn handle(&self, request: Request) -> Response {
        let Request { method, path, body } = request;
        if let Some(answer) = serve_file(page::asset(&path), &method) {
            return answer;
        }
        let answer = match (method.as_str(), path.as_str()) {
            ("GET", "/api/session") => Ok(Response::json(&self.describe())),
            ("GET", "/api/mesh/source") => Ok(mesh_bytes(self.source.file_mesh())),
            ("GET", "/api/mesh/target") => Ok(mesh_bytes(self.target.file_mesh())),
            ("POST", "/api/fit") => self.markers(&body).and_then(|m| self.fit(&m)),
            ("POST", "/api/mirror") => self.markers(&body).and_then(|m| self.mirror(&m)),
            ("POST", "/api/save") => self.markers(&body).and_then(|m| self.save(&m)),
            ("POST", "/api/done") => Ok(end(&self.ended)),
            (_, "/api/session" | "/api/mesh/source" | "/api/mesh/target") => {
                return Response::error(405, "use GET")
            }
            (_, "/api/fit" | "/api/mirror" | "/api/save" | "/api/done") => {
                return Response::error(405, "use POST")
            }
            _ => return Response::error(404, "no such page"),
        };
        answer.unwrap_or_else(|e| Response::error(422, &format!("{e:#}")))
    }

    fn ended(&self) {
        let _ = self.done.lock().map(|d| d.send(()));
    }
}

impl Session {
    /// The session as the page starts it.
    fn describe(&self) -> Value {
        let name = |p: &std::path::Path| p.display().to_string();
        let pairs: Vec<Value> = (0..self.start.pairs().len())
            .map(|k| {
                let [s, t] = self.start.pairs()[k];
                json!({
                    "name": self.start.name(k),
                    "source": point_json(&s),
                    "target": point_json(&t),
                })
            })
            .collect();
        let plane = |p: &Option<MirrorPlane>| {
            p.as_ref()
                .map(|p| json!({ "normal": p.normal, "offset": p.offset }))
        };
        json!({
            "source": name(&self.refs.source_ref),
            "target": name(&self.refs.target_ref),
            "output": name(&self.save.path),
            "pose": self.pose.as_ref().map(|(p, _)| name(p)),
            "pairs": pairs,
            "mirror_planes": [plane(&self.planes[0]), plane(&self.planes[1])],
            "max_markers": MAX_MARKERS,
            "guide": self.guide.as_ref().map(Guide::describe),
        })
    }

    /// The page's markers, checked against the files' meshes.
    fn markers(&self, body: &[u8]) -> Result<Markers> {
        let page: PageMarkers =
            serde_json::from_slice(body).context("the request is not a list of marker pairs")?;
        if page.pairs.len() > MAX_MARKERS {
            bail!(
                "{} marker pairs: at most {MAX_MARKERS} are taken",
                page.pairs.len()
            );
        }
        let mut pairs = Vec::with_capacity(page.pairs.len());
        let mut names = Vec::with_capacity(page.pairs.len());
        for (k, p) in page.pairs.into_iter().enumerate() {
            let side = |q: PagePoint, which: &str| -> Result<SurfacePoint> {
                match (q.vertex, q.triangle, q.barycentric) {
                    (Some(v), None, None) => Ok(SurfacePoint::Vertex(v)),
                    (None, Some(triangle), Some(barycentric)) => Ok(SurfacePoint::Triangle {
                        triangle,
                        barycentric,
                    }),
                    _ => bail!(
                        "pair {}: its {which} point is neither a vertex nor a triangle with barycentric coordinates",
                        k + 1
                    ),
                }
            };
            pairs.push([side(p.source, "source")?, side(p.target, "target")?]);
            names.push(p.name.filter(|n| !n.trim().is_empty()));
        }
        let mut seen = std::collections::HashMap::new();
        for (k, name) in names.iter().enumerate() {
            if let Some(name) = name {
                if let Some(first) = seen.insert(name.clone(), k) {
                    bail!(
                        "pairs {} and {} are both named {name:?}: names must differ",
                        first + 1,
                        k + 1
                    );
                }
            }
        }
        let markers = Markers::on_surfaces(pairs).with_names(names);
        markers.validate(self.source.file_mesh(), self.target.file_mesh())?;
        Ok(markers)
    }

    /// The correspondence of `markers`: the fit report, the deformed source
    /// and the target's distances on the files' vertices and, with a pose,
    /// that pose transferred. Binary: the JSON report's length (u32, little
    /// endian), the report, padding to 4 bytes, then f32 arrays: the
    /// deformed source's positions, the distance at each target vertex (the
    /// largest of its triangles'), the transferred pose's positions (when
    /// the report says `pose`).
    fn fit(&self, markers: &Markers) -> Result<Response> {
        let _one = match self.fitting.try_lock() {
            Ok(one) => one,
            Err(std::sync::TryLockError::Poisoned(e)) => e.into_inner(),
            Err(std::sync::TryLockError::WouldBlock) => {
                bail!("another fit is running (from another page): try again when it is done")
            }
        };
        let begin = Instant::now();
        let mut warnings = Vec::new();
        let (result, marker_report, fit) = self.correspond.compute_from(
            markers.clone(),
            &format!("with the page's {} markers", markers.pairs().len()),
            &self.refs,
            &self.source,
            &self.target,
            &mut warnings,
        )?;
        let seconds = begin.elapsed().as_secs_f64();
        let target_file = self.target.file_mesh();
        let deformed = self
            .source
            .file
            .seams
            .unweld(result.deformed_source.positions());
        let mut distance = vec![0.0f64; target_file.num_vertices()];
        for (tri, &d) in target_file.triangles().iter().zip(&result.fit.distances) {
            for &v in tri {
                distance[v as usize] = distance[v as usize].max(d);
            }
        }
        let pose = match (&self.guide, &self.pose) {
            (Some(guide), _) => guide
                .preview(markers, target_file)
                .context("the preview of the expressions")?,
            (None, Some((path, pose))) => {
                let transfer = Transfer::new(
                    &self.source.mesh,
                    &self.target.mesh,
                    &result.correspondence,
                    &TransferOptions::default(),
                )
                .with_context(|| format!("transferring the pose `{}`", path.display()))?;
                let out = transfer.apply(pose)?;
                Some(self.target.file.seams.unweld(&out))
            }
            (None, None) => None,
        };
        // The page's pairs nearest each poor region, found by their target
        // points (welding keeps every position).
        let target_points: Vec<[f64; 3]> = markers
            .pairs()
            .iter()
            .map(|p| p[1].position(target_file))
            .collect();
        let welded = markers.welded(&self.source.file.seams, &self.target.file.seams);
        let regions: Vec<Vec<usize>> = fit
            .poor_regions
            .iter()
            .map(|r| {
                r.nearest_markers
                    .iter()
                    .filter_map(|m| {
                        let at = welded.pairs().get(m.marker)?[1].position(&self.target.mesh);
                        target_points.iter().position(|p| *p == at)
                    })
                    .collect()
            })
            .collect();
        let report = json!({
            "seconds": seconds,
            "fit": fit,
            "markers": marker_report,
            "warnings": warnings,
            "nearest_pairs": regions,
            "matched_pairs": result.correspondence.pairs().len(),
            "pose": pose.is_some(),
        });
        let text = report.to_string().into_bytes();
        let mut body =
            Vec::with_capacity(text.len() + 4 * (3 * deformed.len() + distance.len()) + 8);
        body.extend_from_slice(&(text.len() as u32).to_le_bytes());
        body.extend_from_slice(&text);
        while body.len() % 4 != 0 {
            body.push(b' ');
        }
        let f32s = |body: &mut Vec<u8>, values: &mut dyn Iterator<Item = f64>| {
            for x in values {
                body.extend_from_slice(&(x as f32).to_le_bytes());
            }
        };
        f32s(&mut body, &mut deformed.iter().flatten().copied());
        f32s(&mut body, &mut distance.iter().copied());
        if let Some(pose) = &pose {
            f32s(&mut body, &mut pose.iter().flatten().copied());
        }
        Ok(Response::ok("application/octet-stream", body))
    }

    /// Each pair mirrored across the meshes' planes and put back on the
    /// surfaces (the nearest point of each).
    fn mirror(&self, markers: &Markers) -> Result<Response> {
        let (Some(sp), Some(tp)) = (&self.planes[0], &self.planes[1]) else {
            bail!(
                "a pair can be mirrored only when both meshes have a mirror plane, and {} has none",
                if self.planes[0].is_none() {
                    "the source"
                } else {
                    "the target"
                }
            );
        };
        let (source, target) = (self.source.file_mesh(), self.target.file_mesh());
        let reflect = |p: [f64; 3], plane: &MirrorPlane| {
            let d =
                2.0 * (plane.normal.iter().zip(&p).map(|(n, x)| n * x).sum::<f64>() - plane.offset);
            std::array::from_fn(|i| p[i] - d * plane.normal[i])
        };
        let points: Vec<[[f64; 3]; 2]> = markers
            .pairs()
            .iter()
            .map(|[s, t]| {
                [
                    reflect(s.position(source), sp),
                    reflect(t.position(target), tp),
                ]
            })
            .collect();
        let (snapped, _) = Markers::from_points(points).snap(source, target)?;
        let pairs: Vec<Value> = snapped
            .pairs()
            .iter()
            .map(|[s, t]| json!({ "source": point_json(s), "target": point_json(t) }))
            .collect();
        Ok(Response::json(&json!({ "pairs": pairs })))
    }

    /// Writes `markers` to `-o` through the output rules (never over an
    /// input, staged and moved into place). One save at a time; none once the page has said done.
    fn save(&self, markers: &Markers) -> Result<Response> {
        let ended = self.ended.lock().unwrap_or_else(|e| e.into_inner());
        if *ended {
            bail!("the session has ended (\"done\"): nothing more is saved");
        }
        let (staging, out) = self.save.prepare()?;
        match &self.guide {
            Some(guide) => {
                let text = guide.landmark_file(markers)?;
                staging.write(out, |path| {
                    Ok(meshmorph::io::write_atomic(path, |w| {
                        w.write_all(text.as_bytes())
                    })?)
                })?;
            }
            None => staging.write(out, |path| Ok(markers.save(path)?))?,
        }
        staging.commit()?;
        Ok(Response::json(&json!({
            "saved": self.save.path.display().to_string(),
            "pairs": markers.pairs().len(),
        })))
    }
}

/// A file of the page, when `path` named one: given to GET only.
pub fn serve_file(asset: Option<page::Asset>, method: &str) -> Option<Response> {
    let asset = asset?;
    Some(if method == "GET" {
        Response::ok(asset.content_type, asset.body.to_vec())
    } else {
        Response::error(405, "use GET")
    })
}

/// The answer to the page's "done": the session marked ended (a save
/// under way finishes first, its file whole at `-o`), the last answer.
pub fn end(ended: &Mutex<bool>) -> Response {
    *ended.lock().unwrap_or_else(|e| e.into_inner()) = true;
    let mut answer = Response::json(&json!({ "done": true }));
    answer.last = true;
    answer
}

fn point_json(p: &SurfacePoint) -> Value {
    match p {
        SurfacePoint::Vertex(v) => json!({ "vertex": v }),
        SurfacePoint::Triangle {
            triangle,
            barycentric,
        } => json!({ "triangle": triangle, "barycentric": barycentric }),
    }
}

/// A mesh as the page draws it: vertex and triangle counts (u32, little
/// endian), the positions (f32) and the triangles' corners (u32).
fn mesh_bytes(mesh: &meshmorph::Mesh3) -> Response {
    let mut body = Vec::with_capacity(8 + 12 * mesh.num_vertices() + 12 * mesh.num_triangles());
    body.extend_from_slice(&(mesh.num_vertices() as u32).to_le_bytes());
    body.extend_from_slice(&(mesh.num_triangles() as u32).to_le_bytes());
    for p in mesh.positions() {
        for x in p {
            body.extend_from_slice(&(*x as f32).to_le_bytes());
        }
    }
    for t in mesh.triangles() {
        for v in t {
            body.extend_from_slice(&v.to_le_bytes());
        }
    }
    Response::ok("application/octet-stream", body)
}
