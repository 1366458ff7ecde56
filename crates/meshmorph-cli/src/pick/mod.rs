//! `meshmorph pick`: marker pairs picked on the two meshes in the browser,
//! with the correspondence's fit (and a transferred pose) shown on demand;
//! or, given two pictures, the anchors of their morph, with the morph
//! shown playing as they change ([`pictures`]).
//!
//! The command reads the files named on its command line once, opens a
//! door on the loopback address ([`door`]) and serves one page
//! ([`page`], three.js built in) and what the page asks for ([`session`]):
//! the meshes as binary arrays, fits, mirrored pairs, saves to `-o`. It
//! stops when the page says done, or on Ctrl-C.

mod door;
mod guide;
mod page;
mod pictures;
mod session;

use std::path::PathBuf;
use std::sync::{mpsc, Arc, Mutex};

use anyhow::{Context, Result};
use meshmorph::Markers;

use crate::output;
use crate::transfer::{CorrespondArgs, References};

/// Pick marker pairs on two meshes in the browser and save them; or, on
/// two pictures (PNG, JPEG, ...), the anchors of their morph.
///
/// Starts a server on the loopback address (127.0.0.1 and ::1 only) and
/// prints the page's address, with a random token in it that every request
/// needs. On the page: click the source, then the target, to make a pair
/// (Alt-click snaps to the nearest vertex); "fit" shows the correspondence
/// the markers make; "save" writes them to the output. On two pictures:
/// click a point on the first, then the same point on the second; the
/// morph they make plays beside them; "save" writes the anchor file
/// `interpolate --anchors` reads.
#[derive(Debug, clap::Args)]
#[command(
    mut_arg("markers", |a| a.help("Start from these markers: one file of pairs, or twice a file of points (the source's, then the target's: MeshLab's .pp, Wrap's .json, or one point a line), as `correspond` reads them")),
    mut_arg("no_markers", |a| a.hide(true)),
)]
pub struct Args {
    /// The source mesh at rest (with --template: the head).
    #[arg(value_name = "SOURCE")]
    pub source: PathBuf,
    /// The target mesh at rest (not with --template).
    #[arg(
        value_name = "TARGET",
        required_unless_present = "template",
        conflicts_with = "template"
    )]
    pub target: Option<PathBuf>,
    /// Place an expression template's landmarks on the head (SOURCE), one
    /// by one: `arkit` (the built-in template) or a rig's GLB. The page
    /// lights the next landmark on the template and names it, a click on
    /// the head places it (skip and redo allowed), and each fit shows
    /// jawOpen and eyeBlinkLeft on the head once 12 are placed; "save"
    /// writes the landmark file `meshmorph expressions --markers` reads.
    #[arg(long, value_name = "arkit|FILE.glb", conflicts_with_all = ["pose", "markers"])]
    pub template: Option<String>,
    /// Where "save" writes the markers: meshmorph's marker file, with names
    /// and surface points. Never one of the inputs.
    #[arg(short, long, value_name = "MARKERS")]
    pub output: PathBuf,
    /// With two pictures: start from these anchors (the file
    /// `interpolate --anchors` reads).
    #[arg(long, value_name = "ANCHORS", conflicts_with_all = ["template", "pose", "markers"])]
    pub anchors: Option<PathBuf>,
    /// A pose of the source, shown transferred to the target after each fit.
    #[arg(long, value_name = "POSE")]
    pub pose: Option<PathBuf>,
    /// Open the page in the default browser.
    #[arg(long)]
    pub open: bool,
    /// The port to listen on [default: a free one].
    #[arg(
        long,
        value_name = "PORT",
        default_value_t = 0,
        hide_default_value = true
    )]
    pub port: u16,
    /// Keep apart vertices that share a place (see `correspond --help`).
    #[arg(long)]
    pub no_weld: bool,
    /// How the fit computes the correspondence (as for `correspond`).
    #[command(flatten)]
    pub correspond: CorrespondArgs,
}

pub fn run(args: &Args) -> Result<()> {
    let on_pictures = args.template.is_none()
        && crate::picture_morph::is_picture(&args.source)
        && args
            .target
            .as_deref()
            .is_some_and(crate::picture_morph::is_picture);
    if on_pictures {
        return run_on_pictures(args);
    }
    if let Some(anchors) = &args.anchors {
        anyhow::bail!(
            "--anchors {} is for two pictures (PNG, JPEG, ...): on meshes give --markers",
            anchors.display()
        );
    }
    let marker_files = if args.correspond.markers.is_empty() {
        &[][..]
    } else {
        args.correspond.marker_files()?
    };
    // With --template, the template's head is the source and the one mesh
    // given, the head, the target.
    let (source_path, target_path) = match (&args.template, &args.target) {
        (Some(template), _) => (PathBuf::from(template), args.source.clone()),
        (None, Some(target)) => (args.source.clone(), target.clone()),
        (None, None) => {
            anyhow::bail!("give the source and the target meshes (or --template and a head)")
        }
    };
    let mut inputs: Vec<(PathBuf, &'static str)> = match &args.template {
        Some(t) if t == "arkit" => vec![(target_path.clone(), "head")],
        Some(_) => vec![
            (source_path.clone(), "template"),
            (target_path.clone(), "head"),
        ],
        None => vec![
            (source_path.clone(), "source reference"),
            (target_path.clone(), "target reference"),
        ],
    };
    inputs.extend(marker_files.iter().map(|p| (p.clone(), "marker file")));
    inputs.extend(args.pose.iter().map(|p| (p.clone(), "source pose")));
    // The output is checked before anything is read, as every save checks
    // it again: never an input.
    let save = session::SaveTarget {
        path: args.output.clone(),
        inputs,
    };
    drop(save.prepare()?);
    let refs = References {
        source_ref: source_path,
        target_ref: target_path,
        no_weld: args.no_weld,
        source_mesh: None,
        target_mesh: None,
    };
    let guide = args
        .template
        .as_deref()
        .map(guide::Guide::read)
        .transpose()?;
    let (source, target) = match &guide {
        Some(guide) => (
            guide.source()?,
            crate::transfer::Reference::read(&refs.target_ref, "head", None, !args.no_weld)?,
        ),
        None => refs.read()?,
    };
    let start = if marker_files.is_empty() {
        Markers::new(Vec::new())
    } else {
        let read = args.correspond.read_markers(&source, &target)?;
        let (snapped, _) = read
            .snap(source.file_mesh(), target.file_mesh())
            .context("snapping the marker points to the surfaces")?;
        snapped.check_ranges(source.file_mesh(), target.file_mesh())?;
        snapped
    };
    let pose = match &args.pose {
        Some(path) => {
            let (pose, _) = output::read_pose(&source.file.file, "source reference", path, "pose")?;
            let welded = source
                .mesh
                .with_positions(source.file.seams.weld_positions(pose.positions()))?;
            Some((path.clone(), welded))
        }
        None => None,
    };
    let planes = rayon::join(
        || source.file_mesh().mirror_plane(),
        || target.file_mesh().mirror_plane(),
    );
    let door = door::Door::open(args.port)?;
    let (done, finished) = mpsc::channel();
    let session = session::Session {
        refs,
        correspond: args.correspond.clone(),
        source,
        target,
        pose,
        save,
        start,
        planes: [planes.0, planes.1],
        fitting: Mutex::new(()),
        done: Mutex::new(done),
        ended: Mutex::new(false),
        guide,
    };
    serve_until_done(door, Arc::new(session), &finished, args.open);
    Ok(())
}

/// Serves `session` behind `door` until the page says done (`finished`
/// is told), opening the page in the browser when asked.
fn serve_until_done(
    door: door::Door,
    session: Arc<dyn door::Handler>,
    finished: &mpsc::Receiver<()>,
    open: bool,
) {
    let url = door.url();
    let served = door.serve(session);
    say!("pick: open {url} in a browser (Ctrl-C or \"done\" on the page stops)");
    // Kept until the session ends: the browser may read it late.
    let _opened = open.then(|| open_browser(&url)).flatten();
    // Until the page says done; Ctrl-C ends the process from its handler.
    let _ = finished.recv();
    // Requests that showed the token before "done" are answered (a save
    // among them is refused: the session has ended) before the process ends.
    served.settle();
    say!("pick: done");
}

/// `pick` on two pictures: the anchors of their morph.
fn run_on_pictures(args: &Args) -> Result<()> {
    let Some(target) = &args.target else {
        anyhow::bail!("give two pictures");
    };
    if args.pose.is_some() {
        anyhow::bail!("--pose is for meshes: on two pictures the page shows their morph");
    }
    if !args.correspond.markers.is_empty() {
        anyhow::bail!("--markers is for meshes: on two pictures give --anchors");
    }
    let paths = [args.source.clone(), target.clone()];
    let mut inputs: Vec<(PathBuf, &'static str)> = vec![
        (paths[0].clone(), "source picture"),
        (paths[1].clone(), "target picture"),
    ];
    inputs.extend(args.anchors.iter().map(|p| (p.clone(), "anchor file")));
    let save = session::SaveTarget {
        path: args.output.clone(),
        inputs,
    };
    drop(save.prepare()?);
    let pictures = crate::picture_morph::read_pictures([&paths[0], &paths[1]])?;
    let start = match &args.anchors {
        Some(path) => pictures::read_start(path, [&pictures[0], &pictures[1]])?,
        None => Vec::new(),
    };
    let door = door::Door::open(args.port)?;
    let (done, finished) = mpsc::channel();
    let session = pictures::PictureSession {
        paths,
        pictures,
        save,
        start,
        previewing: Mutex::new(()),
        done: Mutex::new(done),
        ended: Mutex::new(false),
    };
    serve_until_done(door, Arc::new(session), &finished, args.open);
    Ok(())
}

/// Opens `url` in the default browser, or says how to. The browser is
/// given a file that only this user can read (in a new private folder,
/// returned so that it stays until the session ends) which sends it on to
/// `url`: the token never appears on a command line, which every user of
/// the machine can read (`/proc/PID/cmdline`).
fn open_browser(url: &str) -> Option<tempfile::TempDir> {
    let page = || -> std::io::Result<(tempfile::TempDir, PathBuf)> {
        let dir = tempfile::Builder::new()
            .prefix("meshmorph-pick-")
            .tempdir()?;
        let path = dir.path().join("open.html");
        let mut options = std::fs::OpenOptions::new();
        options.write(true).create_new(true);
        #[cfg(unix)]
        std::os::unix::fs::OpenOptionsExt::mode(&mut options, 0o600);
        std::io::Write::write_all(
            &mut options.open(&path)?,
            format!(
                "<!doctype html><meta charset=\"utf-8\"><meta http-equiv=\"refresh\" content=\"0;url={url}\"><title>meshmorph pick</title><a href=\"{url}\">meshmorph pick</a>\n"
            )
            .as_bytes(),
        )?;
        Ok((dir, path))
    };
    let (dir, path) = match page() {
        Ok(made) => made,
        Err(e) => {
            tell!("warning: cannot open a browser ({e}): open the address above by hand");
            return None;
        }
    };
    let opener = if cfg!(target_os = "macos") {
        std::process::Command::new("open").arg(&path).spawn()
    } else if cfg!(windows) {
        std::process::Command::new("cmd")
            .args(["/C", "start", ""])
            .arg(&path)
            .spawn()
    } else {
        std::process::Command::new("xdg-open").arg(&path).spawn()
    };
    if let Err(e) = opener {
        tell!("warning: cannot open a browser ({e}): open the address above by hand");
    }
    Some(dir)
}
