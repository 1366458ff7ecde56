//! `meshmorph interpolate` on pictures: two sprites made in code, two
//! photos with anchors, every output asked for, and the refusals.

use std::fs;
use std::path::Path;

use meshmorph::io::picture::{read_picture, Picture};

use super::drawings::{fails, mentions, run, succeeds};

/// A disc of radius `r` at `c`, anti-aliased, textured.
fn disc(size: u32, c: [f64; 2], r: f64) -> Picture {
    Picture::from_fn(size, size, |x, y| {
        let (px, py) = (f64::from(x) + 0.5, f64::from(y) + 0.5);
        let d = r - (px - c[0]).hypot(py - c[1]);
        let a = ((d + 0.5).clamp(0.0, 1.0) * 255.0).round() as u8;
        [(x * 7 % 256) as u8, (y * 5 % 256) as u8, 128, a]
    })
}

fn save(dir: &Path, name: &str, p: &Picture) {
    let mut f = fs::File::create(dir.join(name)).unwrap();
    meshmorph::render::write_picture_png(&mut f, p).unwrap();
}

/// The frame count an animated PNG declares (its `acTL` chunk).
fn apng_frames(path: &std::path::Path) -> u32 {
    let bytes = fs::read(path).unwrap();
    let at = bytes.windows(4).position(|w| w == b"acTL").unwrap();
    u32::from_be_bytes(bytes[at + 4..at + 8].try_into().unwrap())
}

#[test]
fn sprites_morph_into_pngs_gif_apng_and_a_sprite_sheet() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let a = disc(48, [20.0, 24.0], 14.0);
    save(d, "a.png", &a);
    save(d, "b.png", &disc(64, [40.0, 30.0], 18.0));
    let out = run(
        &[
            "interpolate",
            "a.png",
            "b.png",
            "-o",
            "frames",
            "--frames",
            "5",
            "--gif",
            "m.gif",
            "--apng",
            "m.apng.png",
            "--sprite-sheet",
            "sheet.png",
        ],
        d,
    );
    let text = succeeds(&out);
    mentions(&text, &["sprites traced", "frames:"]);
    let quiet = String::from_utf8_lossy(&out.stderr);
    assert!(!quiet.contains("less than half opaque"), "{quiet}");
    for k in 0..5 {
        let f = read_picture(&d.join(format!("frames/frame_{k:04}.png")), u64::MAX).unwrap();
        assert_eq!((f.width, f.height), (48, 48));
    }
    let first = read_picture(&d.join("frames/frame_0000.png"), u64::MAX).unwrap();
    let visible = |p: &Picture| -> Vec<u8> {
        p.rgba
            .chunks_exact(4)
            .flat_map(|q| {
                if q[3] == 0 {
                    [0; 4]
                } else {
                    [q[0], q[1], q[2], q[3]]
                }
            })
            .collect()
    };
    assert_eq!(visible(&first), visible(&a));
    assert!(fs::read(d.join("m.gif")).unwrap().starts_with(b"GIF89a"));
    // Forward and back, as drawings' and meshes' animations play: 5 + 3.
    assert_eq!(apng_frames(&d.join("m.apng.png")), 8);
    let sheet = read_picture(&d.join("sheet.png"), u64::MAX).unwrap();
    assert_eq!((sheet.width, sheet.height), (3 * 48, 2 * 48));
    let json: serde_json::Value =
        serde_json::from_slice(&fs::read(d.join("sheet.json")).unwrap()).unwrap();
    assert_eq!(json["frames"]["frame_0004.png"]["frame"]["x"], 48);
    assert_eq!(json["meta"]["image"], "sheet.png");
    // Again into the same folder with fewer frames: the earlier run's
    // surplus frames go, so the folder holds one animation.
    let out = run(
        &[
            "interpolate",
            "a.png",
            "b.png",
            "-o",
            "frames",
            "--frames",
            "3",
        ],
        d,
    );
    mentions(
        &succeeds(&out),
        &["removed:        2 frames of an earlier run"],
    );
    // A soft shadow under half opaque around b: named as left out.
    let mut glow = disc(64, [40.0, 30.0], 18.0);
    for p in glow.rgba.chunks_exact_mut(4) {
        if p[3] == 0 {
            p[3] = 50;
        }
    }
    save(d, "glow.png", &glow);
    let out = run(&["interpolate", "a.png", "glow.png", "-o", "soft"], d);
    succeeds(&out);
    mentions(
        &String::from_utf8_lossy(&out.stderr),
        &[
            "`glow.png` has",
            "pixels less than half opaque",
            "--frame-only",
        ],
    );
    let once = [
        "interpolate",
        "a.png",
        "b.png",
        "--frames",
        "5",
        "-o",
        "once",
        "--apng",
        "once.png",
        "--no-boomerang",
    ];
    succeeds(&run(&once, d));
    assert_eq!(apng_frames(&d.join("once.png")), 5);
    let mut left: Vec<String> = fs::read_dir(d.join("frames"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    left.sort();
    assert_eq!(left, ["frame_0000.png", "frame_0001.png", "frame_0002.png"]);
}

#[test]
fn photos_with_anchors_and_the_refusals() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let photo = |shift: u32| {
        Picture::from_fn(40, 30, move |x, y| {
            [((x + shift) * 6 % 256) as u8, (y * 8) as u8, 90, 255]
        })
    };
    save(d, "p.png", &photo(0));
    save(d, "q.png", &photo(5));
    fs::write(d.join("faces.txt"), "eye 10 10 14 12\nmouth 20 20 22 19\n").unwrap();
    let text = succeeds(&run(
        &[
            "interpolate",
            "p.png",
            "q.png",
            "--anchors",
            "faces.txt",
            "-o",
            "f",
            "--frames",
            "3",
        ],
        d,
    ));
    mentions(&text, &["photos", "2 kept matched"]);
    // Without anchors the morph runs, and says what anchors would do;
    // pictures of different sizes say which is stretched onto which.
    save(
        d,
        "r.png",
        &Picture::from_fn(50, 30, |x, y| [x as u8, y as u8, 9, 255]),
    );
    let out = run(
        &[
            "interpolate",
            "p.png",
            "r.png",
            "-o",
            "plain",
            "--frames",
            "3",
        ],
        d,
    );
    succeeds(&out);
    mentions(
        &String::from_utf8_lossy(&out.stderr),
        &[
            "without anchors nothing inside them is matched",
            "meshmorph pick p.png r.png -o anchors.txt",
            "`r.png` (50 × 30) is stretched onto the frames' size, `p.png`'s 40 × 30",
        ],
    );
    // Anchors outside a picture.
    fs::write(
        d.join("bad.txt"),
        "# name, then x y on each\neye 10 10 44 12\n",
    )
    .unwrap();
    let err = fails(&run(
        &[
            "interpolate",
            "p.png",
            "q.png",
            "--anchors",
            "bad.txt",
            "-o",
            "g",
        ],
        d,
    ));
    mentions(
        &err,
        &[
            "anchor 1 (`eye`, `bad.txt`, line 2)",
            "outside the picture",
            "`q.png`",
        ],
    );
    assert!(!d.join("g").exists());
    // Fully transparent.
    save(d, "clear.png", &Picture::from_fn(8, 8, |_, _| [0, 0, 0, 0]));
    save(d, "s.png", &disc(8, [4.0, 4.0], 3.0));
    let err = fails(&run(&["interpolate", "clear.png", "s.png", "-o", "h"], d));
    mentions(&err, &["`clear.png` is fully transparent"]);
    // A sprite with a photo, pictures with drawings.
    let err = fails(&run(&["interpolate", "s.png", "p.png", "-o", "h"], d));
    mentions(&err, &["has transparency", "--frame-only"]);
    fs::write(d.join("a.svg"), "<svg/>").unwrap();
    let err = fails(&run(&["interpolate", "s.png", "a.svg", "-o", "h"], d));
    mentions(&err, &["is a picture but", "`a.svg`"]);
    // Not a picture inside.
    fs::write(d.join("fake.png"), "hello").unwrap();
    let err = fails(&run(&["interpolate", "fake.png", "p.png", "-o", "h"], d));
    mentions(&err, &["neither a PNG nor a JPEG"]);
    assert!(!d.join("h").exists());
}

#[test]
fn dissolve_takes_two_fractions_and_refuses_others() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    save(d, "a.png", &disc(48, [20.0, 24.0], 14.0));
    save(d, "b.png", &disc(48, [28.0, 24.0], 16.0));
    let morph = |span: &str| {
        run(
            &[
                "interpolate",
                "a.png",
                "b.png",
                "-o",
                "frames",
                "--frames",
                "3",
                "--dissolve",
                span,
            ],
            d,
        )
    };
    succeeds(&morph("0.3,0.7"));
    // Refused as the arguments are read (a usage error, status 2).
    succeeds(&morph("0.5,0.5"));
    for bad in ["0.3", "0.2,1.5", "a,b", "0.7,0.3"] {
        let out = morph(bad);
        assert_eq!(out.status.code(), Some(2));
        mentions(&String::from_utf8_lossy(&out.stderr), &["--dissolve", bad]);
    }
    assert!(!d.join("frames").join("frame_0003.png").exists());
}

/// The flags of meshes' and drawings' outputs that pictures do not take
/// are refused, naming the flag, and nothing is written.
#[test]
fn flags_pictures_do_not_take_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    save(d, "a.png", &disc(32, [14.0, 16.0], 10.0));
    save(d, "b.png", &disc(32, [18.0, 16.0], 11.0));
    for (flag, value) in [
        ("--gltf", "x.glb"),
        ("--size", "300"),
        ("--gif-width", "200"),
        ("--gif-height", "200"),
    ] {
        let err = fails(&run(
            &[
                "interpolate",
                "a.png",
                "b.png",
                "-o",
                "frames",
                "--gif",
                "m.gif",
                flag,
                value,
            ],
            d,
        ));
        mentions(&err, &[flag, "does not apply to pictures"]);
        assert!(
            !d.join("frames").exists() && !d.join("m.gif").exists() && !d.join("x.glb").exists()
        );
    }
}
