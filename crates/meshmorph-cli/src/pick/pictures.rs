//! `meshmorph pick A.png B.png`: anchors for a picture morph, clicked on
//! both pictures in the browser, with the morph shown playing as they
//! change.
//!
//! The same door as the meshes' page ([`super::door`]: loopback, the
//! token, Host and Origin checked, bounded requests); the page may ask
//! for its own files, the two pictures (as PNG), the session (names,
//! sizes, the starting anchors), a preview of the morph the anchors make
//! (its frames side by side in one PNG), a save of the anchors to `-o`
//! (the file `interpolate --anchors` reads) and the end of the session.
//! Nothing else is read or written: the pictures are those named on the
//! command line, read once at the start.

use std::path::{Path, PathBuf};
use std::sync::mpsc::Sender;
use std::sync::Mutex;
use std::time::{Duration, Instant};

use anyhow::{bail, Result};
use meshmorph::io::picture::Picture;
use meshmorph::render::{
    frame_times, sprite_sheet, write_picture_png, PictureFrames, PictureMorphOptions,
};
use rayon::prelude::*;
use serde::Deserialize;
use serde_json::{json, Value};

use super::door::{Handler, Request, Response};
use super::page;
use super::session::{end, serve_file, SaveTarget};

/// The most anchors a request may hold.
pub const MAX_ANCHORS: usize = 1_000;

/// The frames of a preview, from the first picture to the second.
pub const PREVIEW_FRAMES: usize = 12;

/// The longer side of a preview's frames, in pixels.
pub const PREVIEW_SIDE: u32 = 256;

/// One run of `pick` on two pictures.
pub struct PictureSession {
    /// The two pictures' paths as given (for the page and the messages).
    pub paths: [PathBuf; 2],
    pub pictures: [Picture; 2],
    /// Where "save" writes.
    pub save: SaveTarget,
    /// The anchors the page starts from (`--anchors`).
    pub start: Vec<PageAnchor>,
    /// One preview at a time (each takes the machine's cores).
    pub previewing: Mutex<()>,
    /// Told when the page's "done" has been answered.
    pub done: Mutex<Sender<()>>,
    /// Held by a save for its whole length, and by "done" (which sets it).
    pub ended: Mutex<bool>,
}

/// An anchor as the page sends it: a name, and its point on each picture
/// (pixels, x right and y down from the top-left corner).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PageAnchor {
    #[serde(default)]
    pub name: String,
    pub a: [f64; 2],
    pub b: [f64; 2],
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct PageAnchors {
    anchors: Vec<PageAnchor>,
}

impl Handler for PictureSession {
    fn handle(&self, request: Request) -> Response {
        let Request { method, path, body } = request;
        if let Some(answer) = serve_file(page::picture_asset(&path), &method) {
            return answer;
        }
        let answer = match (method.as_str(), path.as_str()) {
            ("GET", "/api/session") => Ok(Response::json(&self.describe())),
            ("GET", "/api/picture/a") => picture_png(&self.pictures[0]),
            ("GET", "/api/picture/b") => picture_png(&self.pictures[1]),
            ("POST", "/api/preview") => self.anchors(&body).and_then(|a| self.preview(&a)),
            ("POST", "/api/save") => self.anchors(&body).and_then(|a| self.save_anchors(&a)),
            ("POST", "/api/done") => Ok(end(&self.ended)),
            (_, "/api/session" | "/api/picture/a" | "/api/picture/b") => {
                return Response::error(405, "use GET")
            }
            (_, "/api/preview" | "/api/save" | "/api/done") => {
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

impl PictureSession {
    fn describe(&self) -> Value {
        let name = |p: &Path| p.display().to_string();
        let pictures: Vec<Value> = (0..2)
            .map(|k| {
                json!({
                    "name": name(&self.paths[k]),
                    "width": self.pictures[k].width,
                    "height": self.pictures[k].height,
                })
            })
            .collect();
        json!({
            "pictures": pictures,
            "output": name(&self.save.path),
            "anchors": self.start.iter().map(|a| json!({ "name": a.name, "a": a.a, "b": a.b })).collect::<Vec<_>>(),
            "preview": { "frames": PREVIEW_FRAMES, "side": PREVIEW_SIDE },
        })
    }

    /// The anchors of a request, checked: at most [`MAX_ANCHORS`], each
    /// point finite and on its picture, each name one word that is not a
    /// number (as the anchor file reads it), no name twice. Errors name the
    /// anchor.
    fn anchors(&self, body: &[u8]) -> Result<Vec<PageAnchor>> {
        let given: PageAnchors = serde_json::from_slice(body)
            .map_err(|e| anyhow::anyhow!("the anchors sent are not understood: {e}"))?;
        check_anchors(&given.anchors, [&self.pictures[0], &self.pictures[1]])?;
        Ok(given.anchors)
    }

    /// The morph the anchors make, as `interpolate` makes it, drawn small:
    /// [`PREVIEW_FRAMES`] frames of at most [`PREVIEW_SIDE`] pixels side by
    /// side in one PNG.
    fn preview(&self, anchors: &[PageAnchor]) -> Result<Response> {
        let _one = match self.previewing.try_lock() {
            Ok(one) => one,
            Err(std::sync::TryLockError::Poisoned(e)) => e.into_inner(),
            Err(std::sync::TryLockError::WouldBlock) => {
                bail!("a preview is being made: send the next when it is answered")
            }
        };
        let begin = Instant::now();
        let [a, b] = &self.pictures;
        let scale = f64::from(PREVIEW_SIDE) / f64::from(a.width.max(a.height));
        let scale = scale.min(1.0);
        let size = (
            ((f64::from(a.width) * scale).round() as u32).max(1),
            ((f64::from(a.height) * scale).round() as u32).max(1),
        );
        let points: Vec<Vec<[f64; 2]>> = anchors.iter().map(|x| vec![x.a, x.b]).collect();
        let names = self.paths.clone().map(|p| format!("`{}`", p.display()));
        let options = PictureMorphOptions::default().with_frame_size(Some(size));
        let morph = PictureFrames::new([a, b], &points, &options, &names)?;
        let frames: Vec<Picture> = frame_times(PREVIEW_FRAMES)
            .par_iter()
            .map(|&t| morph.draw(t))
            .collect();
        let (sheet, _) = sprite_sheet(
            &frames,
            PREVIEW_FRAMES,
            Duration::from_millis(80),
            "preview.png",
            &|k| k.to_string(),
        );
        let mut png = Vec::new();
        write_picture_png(&mut png, &sheet)?;
        say!(
            "pick: preview with {} anchor{}: {} triangles, {:.2} s",
            anchors.len(),
            if anchors.len() == 1 { "" } else { "s" },
            morph.meshes.set.report.triangles,
            begin.elapsed().as_secs_f64()
        );
        Ok(Response::ok("image/png", png))
    }

    /// Writes the anchors to `-o` through the output rules (never over an
    /// input, staged and moved into place), as `interpolate --anchors`
    /// reads them. None once the page has said done.
    fn save_anchors(&self, anchors: &[PageAnchor]) -> Result<Response> {
        let ended = self.ended.lock().unwrap_or_else(|e| e.into_inner());
        if *ended {
            bail!("the session has ended (\"done\"): nothing more is saved");
        }
        let (staging, out) = self.save.prepare()?;
        let text = anchor_file(anchors, &self.paths);
        staging.write(out, |path| {
            Ok(meshmorph::io::write_atomic(path, |w| {
                w.write_all(text.as_bytes())
            })?)
        })?;
        staging.commit()?;
        Ok(Response::json(&json!({
            "saved": self.save.path.display().to_string(),
            "anchors": anchors.len(),
        })))
    }
}

/// Refuses more than [`MAX_ANCHORS`] anchors, a point that is not finite
/// or lies outside its picture, and a name the anchor file cannot hold
/// (more than one word, a number, a `#`) or given twice.
pub fn check_anchors(anchors: &[PageAnchor], pictures: [&Picture; 2]) -> Result<()> {
    if anchors.len() > MAX_ANCHORS {
        bail!(
            "{} anchors sent: at most {MAX_ANCHORS} are taken",
            anchors.len()
        );
    }
    let mut seen = std::collections::HashSet::new();
    for (k, anchor) in anchors.iter().enumerate() {
        let what = if anchor.name.is_empty() {
            format!("anchor {}", k + 1)
        } else {
            format!("anchor {} ({:?})", k + 1, anchor.name)
        };
        let name = &anchor.name;
        if name
            .chars()
            .any(|c| c.is_whitespace() || c == ',' || c == '#')
            || name.parse::<f64>().is_ok()
            || name.len() > 200
        {
            bail!("{what}: a name is one word of at most 200 bytes, not a number, without a comma or '#'");
        }
        if !name.is_empty() && !seen.insert(name.as_str()) {
            bail!("{what}: the name is given twice");
        }
        for (point, (picture, which)) in [anchor.a, anchor.b]
            .iter()
            .zip([(pictures[0], "first"), (pictures[1], "second")])
        {
            let (w, h) = (f64::from(picture.width), f64::from(picture.height));
            if !point.iter().all(|x| x.is_finite()) {
                bail!("{what}: its point on the {which} picture is not a finite number");
            }
            if point[0] < 0.0 || point[1] < 0.0 || point[0] > w || point[1] > h {
                bail!(
                    "{what}: ({}, {}) is outside the {which} picture ({} × {} pixels)",
                    point[0],
                    point[1],
                    picture.width,
                    picture.height
                );
            }
        }
    }
    Ok(())
}

/// The anchor file `interpolate --anchors` reads: one anchor a line, its
/// name (when it has one), then x y on each picture.
pub fn anchor_file(anchors: &[PageAnchor], paths: &[PathBuf; 2]) -> String {
    let mut text = format!(
        "# anchors: name, then x y (pixels, y down) on {} and on {}\n",
        paths[0].display(),
        paths[1].display()
    );
    for anchor in anchors {
        let name = if anchor.name.is_empty() {
            String::new()
        } else {
            format!("{} ", anchor.name)
        };
        text.push_str(&format!(
            "{name}{} {} {} {}\n",
            anchor.a[0], anchor.a[1], anchor.b[0], anchor.b[1]
        ));
    }
    text
}

/// A picture as the page shows it: PNG.
fn picture_png(picture: &Picture) -> Result<Response> {
    let mut png = Vec::new();
    write_picture_png(&mut png, picture)?;
    Ok(Response::ok("image/png", png))
}

/// Reads the starting anchors (`--anchors`), checked as the page's are.
pub fn read_start(path: &Path, pictures: [&Picture; 2]) -> Result<Vec<PageAnchor>> {
    let read = meshmorph::io::read_anchor_file(path, 2)?;
    let anchors: Vec<PageAnchor> = read
        .into_iter()
        .map(|r| PageAnchor {
            name: r.name,
            a: r.points[0],
            b: r.points[1],
        })
        .collect();
    check_anchors(&anchors, pictures)
        .map_err(|e| anyhow::anyhow!("the anchor file {}: {e:#}", path.display()))?;
    Ok(anchors)
}
