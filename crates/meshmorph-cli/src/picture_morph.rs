//! `meshmorph interpolate` on pictures: two sprites (PNG with
//! transparency) or two photos (JPEG, opaque PNG, or `--frame-only`).
//! Their outlines (or rectangles) are made into compatible meshes, the
//! meshes interpolated, and each frame drawn with both pictures carried by
//! the mesh and blended ([`meshmorph::render::PictureMorph`]).

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use anyhow::{bail, Context, Result};
use meshmorph::io::picture::{
    picture_morph_memory, read_picture, Picture, PictureFormat, PictureShape,
};
use meshmorph::render::{
    frame_times, sprite_sheet, write_apng, write_picture_gif, write_picture_png, GifOptions,
    PictureFrames, PictureMorphOptions, MAX_FRAME_SIDE, MAX_TRACE_TOLERANCE,
};
use meshmorph::StretchMode;
use rayon::prelude::*;

use crate::interpolate::Args;
use crate::outputs::Plan;
use crate::pictures::DEFAULT_SIZE;

/// Options of `interpolate` for pictures.
#[derive(Debug, Clone, clap::Args)]
pub struct PictureMorphArgs {
    /// Pictures: morph the whole rectangle (a photo), even where the
    /// picture has transparency; anchors (--anchors) then drive the inside.
    #[arg(long)]
    pub frame_only: bool,
    /// Pictures: the blend of the two pictures goes from the first to the
    /// second between these two moments of the morph (fractions from 0 to
    /// 1), instead of over the whole morph: `--dissolve 0.3,0.7`.
    #[arg(long, value_name = "START,END", value_parser = dissolve_span)]
    pub dissolve: Option<[f64; 2]>,
    /// Pictures: the frames' size, `WIDTHxHEIGHT` in pixels [default: the
    /// first picture's]; the pictures are stretched onto it.
    #[arg(long, value_name = "WxH", value_parser = frame_size)]
    pub frame_size: Option<(u32, u32)>,
    /// Pictures: how far the traced outline of a sprite may stray from
    /// where its alpha crosses one half, in pixels.
    #[arg(long, default_value_t = 0.5, value_name = "PX", value_parser = trace_tolerance)]
    pub trace_tolerance: f64,
    /// Pictures: also write the frames as one animated PNG (APNG), played
    /// at --fps over and over.
    #[arg(long, value_name = "FILE.png", value_parser = crate::pictures::png_file)]
    pub apng: Option<PathBuf>,
    /// Pictures: also write the frames as one sprite sheet (rows of
    /// frames, as square as they go), with its JSON beside it (same name,
    /// `.json`: the "hash" layout game engines' importers read).
    #[arg(long, value_name = "FILE.png", value_parser = crate::pictures::png_file)]
    pub sprite_sheet: Option<PathBuf>,
}

impl PictureMorphArgs {
    /// The flags for pictures given on the command line (the trace
    /// tolerance, which has a default, cannot be told apart).
    fn given(&self) -> Vec<&'static str> {
        [
            (self.frame_only, "--frame-only"),
            (self.dissolve.is_some(), "--dissolve"),
            (self.frame_size.is_some(), "--frame-size"),
            (self.apng.is_some(), "--apng"),
            (self.sprite_sheet.is_some(), "--sprite-sheet"),
        ]
        .into_iter()
        .filter_map(|(given, flag)| given.then_some(flag))
        .collect()
    }

    /// Refuses flags for pictures on keys that are not pictures.
    pub fn check_not_pictures(&self) -> Result<()> {
        if let Some(flag) = self.given().first() {
            bail!(
                "{flag} applies to pictures (PNG or JPEG keys); these keys are drawings or meshes, whose pictures are --png (a still) and --gif"
            );
        }
        Ok(())
    }
}

fn fraction(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(x) if (0.0..=1.0).contains(&x) => Ok(x),
        _ => Err(format!(
            "`{text}` is not a fraction of the morph from 0 to 1"
        )),
    }
}

/// `START,END`: two fractions of the morph.
fn dissolve_span(text: &str) -> Result<[f64; 2], String> {
    let (a, b) = text.split_once(',').ok_or_else(|| {
        format!("`{text}` is not START,END (two fractions from 0 to 1), such as 0.3,0.7")
    })?;
    let span = [fraction(a.trim())?, fraction(b.trim())?];
    if span[1] < span[0] {
        return Err(format!(
            "`{text}` ends before it starts: give START first (the same fraction twice cuts from one picture to the other there)"
        ));
    }
    Ok(span)
}

fn trace_tolerance(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(x) if x > 0.0 && x <= MAX_TRACE_TOLERANCE => Ok(x),
        _ => Err(format!(
            "`{text}` is not a tolerance in pixels from 0 (excluded) to {MAX_TRACE_TOLERANCE}, such as 0.5"
        )),
    }
}

fn frame_size(text: &str) -> Result<(u32, u32), String> {
    let bad = || {
        format!(
            "`{text}` is not a frame size WIDTHxHEIGHT in pixels (1 to {MAX_FRAME_SIDE}), such as 640x480"
        )
    };
    let (w, h) = text.split_once(['x', 'X']).ok_or_else(bad)?;
    let side = |s: &str| match s.trim().parse::<u32>() {
        Ok(v) if (1..=MAX_FRAME_SIDE).contains(&v) => Ok(v),
        _ => Err(bad()),
    };
    Ok((side(w)?, side(h)?))
}

/// Whether `path` is named as a picture (`.png`, `.jpg`, `.jpeg`).
pub(crate) fn is_picture(path: &Path) -> bool {
    PictureFormat::of_path(path).is_some()
}

/// Whether the keys are pictures: refuses a mix of pictures and others.
///
/// # Errors
/// Naming a picture and a key that is not one.
pub fn named_as_pictures(keys: &[PathBuf]) -> Result<bool> {
    let (pictures, others): (Vec<&PathBuf>, Vec<&PathBuf>) =
        keys.iter().partition(|k| is_picture(k));
    match (pictures.first(), others.first()) {
        (Some(p), Some(o)) => bail!(
            "`{}` is a picture but `{}` is not: a morph is of pictures only (PNG, JPEG) or of drawings and meshes only",
            p.display(),
            o.display()
        ),
        (Some(_), None) => Ok(true),
        _ => Ok(false),
    }
}

/// Bytes a pixel of the larger picture takes at the peak (see
/// [`picture_morph_memory`]), for the size refused before decoding.
const BYTES_PER_PICTURE_PIXEL: u64 = 19;

/// The source and target pictures read, each refused when it has more
/// pixels than the free memory holds for a morph (the message says how
/// much a morph takes and how much is free).
pub(crate) fn read_pictures(paths: [&Path; 2]) -> Result<[Picture; 2]> {
    let free = crate::memory::available();
    let max_pixels = free.map_or(u64::MAX, |f| f / BYTES_PER_PICTURE_PIXEL);
    let read = |k: usize| -> Result<Picture> {
        read_picture(paths[k], max_pixels).map_err(|e| {
            let mut text = e.to_string();
            if let Some(f) = free.filter(|_| text.contains("pixels a picture may have")) {
                text.push_str(&format!(
                    " (a morph takes about {BYTES_PER_PICTURE_PIXEL} bytes a pixel of its pictures, and {} is available)",
                    crate::memory::human_bytes(f)
                ));
            }
            anyhow::anyhow!("reading the {} picture {text}", ["source", "target"][k])
        })
    };
    Ok([read(0)?, read(1)?])
}

/// `meshmorph interpolate` on two pictures.
pub fn run(args: &Args) -> Result<()> {
    let start = Instant::now();
    let p = &args.picture;
    let keys = &args.keys;
    if keys.len() != 2 {
        bail!(
            "{} pictures given: a picture morph is between two pictures (give two, or run one morph for each pair)",
            keys.len()
        );
    }
    for (given, flag) in [
        (args.frames.svg, "--svg"),
        (args.frames.pictures.png.is_some(), "--png"),
        (args.drawing.animated_svg.is_some(), "--animated-svg"),
        (args.drawing.lottie.is_some(), "--lottie"),
        (args.drawing.meshes.is_some(), "--meshes"),
        (args.format.is_some(), "--format"),
        (args.frames.times.is_some(), "--t"),
        (args.frames.gltf.gltf.is_some(), "--gltf"),
    ] {
        if given {
            bail!("{flag} does not apply to pictures: their frames are pictures (PNG), with --gif, --apng and --sprite-sheet");
        }
    }
    let draw = &args.frames.pictures.draw;
    for (given, flag) in [
        (draw.size != DEFAULT_SIZE, "--size"),
        (draw.gif_width.is_some(), "--gif-width"),
        (draw.gif_height.is_some(), "--gif-height"),
    ] {
        if given {
            bail!("{flag} does not apply to pictures: their frames, GIF and APNG are the first picture's size, or --frame-size WIDTHxHEIGHT");
        }
    }
    let count = args.frames.frames;
    let mut plan = Plan::new();
    plan.input(&keys[0], "source picture");
    plan.input(&keys[1], "target picture");
    if let Some(a) = &args.drawing.anchors {
        plan.input(a, "anchor file");
    }
    let frame_outputs = plan.frames(&args.output, count, "png");
    let gif = args
        .frames
        .pictures
        .gif
        .as_deref()
        .map(|g| plan.file(g, "animation"));
    let apng = p.apng.as_deref().map(|g| plan.file(g, "animated PNG"));
    let sheet_json = p.sprite_sheet.as_ref().map(|s| s.with_extension("json"));
    let sheet = p
        .sprite_sheet
        .as_deref()
        .map(|s| plan.file(s, "sprite sheet"));
    let sheet_json_out = sheet_json
        .as_deref()
        .map(|s| plan.file(s, "sprite sheet's JSON"));
    let staging = plan.prepare()?;

    let [a, b] = read_pictures([&keys[0], &keys[1]])?;
    let read_seconds = start.elapsed().as_secs_f64();
    let (width, height) = p.frame_size.unwrap_or((a.width, a.height));
    let held =
        2 * rayon::current_num_threads() as u64 + if sheet.is_some() { count as u64 } else { 0 };
    let pixels = u64::from(a.width) * u64::from(a.height);
    let pixels = pixels.max(u64::from(b.width) * u64::from(b.height));
    crate::memory::check(
        picture_morph_memory(pixels, u64::from(width) * u64::from(height), held),
        &format!(
            "morphing {} × {} and {} × {} pictures into {count} frames of {width} × {height}",
            a.width, a.height, b.width, b.height
        ),
    )?;
    let names: Vec<String> = keys.iter().map(|k| format!("`{}`", k.display())).collect();
    let rows = match &args.drawing.anchors {
        Some(path) => meshmorph::io::read_anchor_file(path, 2)?,
        None => Vec::new(),
    };
    let anchors: Vec<Vec<[f64; 2]>> = rows.iter().map(|r| r.points.clone()).collect();
    let begin = Instant::now();
    let options = PictureMorphOptions::default()
        .with_frame_only(p.frame_only)
        .with_trace_tolerance(p.trace_tolerance)
        .with_frame_size(Some((width, height)))
        .with_dissolve(p.dissolve)
        .with_interpolation(
            args.frames
                .options_or(StretchMode::AreaBlend)
                .with_untie_outlines(true)
                .with_mend_folds(true),
        );
    let morph = PictureFrames::new(
        [&a, &b],
        &anchors,
        &options,
        &[names[0].clone(), names[1].clone()],
    )
    .map_err(|e| anyhow::anyhow!(crate::drawings::name_anchors(&e.to_string(), &rows)))
    .with_context(|| format!("morphing {}", names.join(" into ")))?;
    let [da, db] = &morph.drawings;
    for (d, name) in [(da, &names[0]), (db, &names[1])] {
        if d.faint_left_out > 0 {
            tell!(
                "warning: {name} has {} pixels less than half opaque beyond its edges (a glow or a soft shadow?): the sprite is traced where alpha crosses one half, and they are left out of every frame; morph the whole picture with --frame-only to keep them",
                d.faint_left_out
            );
        }
        if !d.left_out.is_empty() {
            let list: Vec<String> = d
                .left_out
                .iter()
                .map(|r| {
                    format!(
                        "{:.0} px² at x {:.0}..{:.0}, y {:.0}..{:.0}",
                        r.area, r.bounds[0][0], r.bounds[1][0], r.bounds[0][1], r.bounds[1][1]
                    )
                })
                .collect();
            tell!(
                "warning: {name} has {} separate regions: the largest is morphed, these are left out: {}",
                d.left_out.len() + 1,
                list.join("; ")
            );
        }
    }
    if da.shape == PictureShape::Photo && anchors.is_empty() {
        tell!(
            "warning: photos morph as whole rectangles, and without anchors nothing inside them is matched (a stretch and a blend): match eyes to eyes, corners to corners with --anchors FILE, whose points `meshmorph pick {} {} -o anchors.txt` places",
            keys[0].display(),
            keys[1].display()
        );
    }
    if p.frame_size.is_none() && (a.width, a.height) != (b.width, b.height) {
        tell!(
            "note: {} ({} × {}) is stretched onto the frames' size, {}'s {} × {} (--frame-size sets another)",
            names[1],
            b.width,
            b.height,
            names[0],
            a.width,
            a.height
        );
    }
    let set = &morph.meshes.set;
    let setup_seconds = begin.elapsed().as_secs_f64();
    let times = frame_times(count);
    let frame = |k: usize| -> Picture { morph.draw(times[k]) };
    let draw_begin = Instant::now();
    frame_outputs
        .par_iter()
        .enumerate()
        .try_for_each(|(k, out)| {
            let picture = frame(k);
            staging.write_to(*out, |_, w| Ok(write_picture_png(w, &picture)?))
        })?;
    let frames_seconds = draw_begin.elapsed().as_secs_f64();
    // Shown as the drawings' and meshes' GIFs are: each frame for one frame
    // time, the first and the last longer.
    let schedule = GifOptions {
        fps: args.frames.pictures.draw.fps,
        boomerang: !args.frames.pictures.draw.no_boomerang,
        ..GifOptions::default()
    }
    .schedule(count);
    let mut written: Vec<PathBuf> = Vec::new();
    if let Some(out) = gif {
        staging.write_to(out, |_, w| {
            Ok(write_picture_gif(
                w,
                (width, height),
                &schedule,
                &mut |k| frame(k),
            )?)
        })?;
        written.extend(args.frames.pictures.gif.clone());
    }
    if let Some(out) = apng {
        staging.write_to(out, |_, w| {
            Ok(write_apng(w, (width, height), &schedule, &mut |k| {
                frame(k)
            })?)
        })?;
        written.extend(p.apng.clone());
    }
    if let (Some(out), Some(json_out), Some(path)) = (sheet, sheet_json_out, &p.sprite_sheet) {
        let frames: Vec<Picture> = (0..count).into_par_iter().map(frame).collect();
        let columns = (count as f64).sqrt().ceil() as usize;
        let image = path
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        // A sheet's frames each last one frame time: the game engine plays them.
        let delay = Duration::from_secs_f64(1.0 / args.frames.pictures.draw.fps);
        let (picture, json) = sprite_sheet(&frames, columns, delay, &image, &|k| {
            format!("frame_{k:04}.png")
        });
        staging.write_to(out, |_, w| Ok(write_picture_png(w, &picture)?))?;
        staging.write_to(json_out, |_, w| Ok(w.write_all(json.as_bytes())?))?;
        written.push(path.clone());
        written.extend(sheet_json.clone());
    }
    let removed = staging.commit()?;
    if args.json {
        let mut files: Vec<PathBuf> = (0..count)
            .map(|k| crate::outputs::frame_path(&args.output, k, count, "png"))
            .collect();
        files.extend(written.iter().cloned());
        crate::output::print_json(&serde_json::json!({
            "pictures": keys.iter().map(|k| k.display().to_string()).collect::<Vec<_>>(),
            "sizes": [[a.width, a.height], [b.width, b.height]],
            "shape": match da.shape {
                PictureShape::Sprite => "sprite",
                PictureShape::Photo => "photo",
            },
            "outline_points": [da.drawing.num_points(), db.drawing.num_points()],
            "triangles": set.report.triangles,
            "min_angle_degrees": set.report.min_angle_degrees,
            "anchors": anchors.len(),
            "frames_written": count,
            "frame_size": [width, height],
            "output": args.output.display().to_string(),
            "setup_seconds": setup_seconds,
            "read_seconds": read_seconds,
            "seconds_per_frame": frames_seconds / count as f64,
            "files_written": files.iter().map(|f| f.display().to_string()).collect::<Vec<_>>(),
            "surplus_frames_removed": removed,
            "total_seconds": start.elapsed().as_secs_f64(),
        }));
        return Ok(());
    }
    say!(
        "pictures:       {} ({} × {}) and {} ({} × {}), {}",
        names[0],
        a.width,
        a.height,
        names[1],
        b.width,
        b.height,
        match da.shape {
            PictureShape::Sprite => format!(
                "sprites traced at alpha ½ within {} px ({} + {} outline points)",
                da.tolerance.max(db.tolerance),
                da.drawing.num_points(),
                db.drawing.num_points()
            ),
            PictureShape::Photo => "photos (whole rectangles)".to_string(),
        }
    );
    say!("compatible:     {}", set.report);
    if !anchors.is_empty() {
        say!("anchors:        {} kept matched", anchors.len());
    }
    say!(
        "frames:         {count} of {width} × {height} in {} (setup {:.2} s, read {:.2} s, drawing and writing {:.1} ms a frame)",
        args.output.display(),
        setup_seconds,
        read_seconds,
        1e3 * frames_seconds / count as f64
    );
    for w in &written {
        say!("written:        {}", w.display());
    }
    if removed > 0 {
        say!("removed:        {removed} frames of an earlier run");
    }
    say!("total:          {:.2} s", start.elapsed().as_secs_f64());
    Ok(())
}
