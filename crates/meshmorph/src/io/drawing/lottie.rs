//! A morph as Lottie JSON (Bodymovin, version 5): one shape layer whose
//! paths have a keyframe a frame, for After Effects and the web and mobile
//! players.

use std::io::Write;

use serde_json::{json, Value};

use super::Animation;
use crate::playback::shown_order;

fn still(k: Value) -> Value {
    json!({"a": 0, "k": k})
}

/// A value rounded to 1/1000 of a pixel: what a player shows, in a third of
/// the text of a full number.
fn round(x: f64) -> f64 {
    (x * 1000.0).round() / 1000.0
}

/// Writes every frame of `animation.frames` as a Lottie animation at `fps` (frames
/// shown forward, then back with `boomerang`): a composition of
/// `canvas.size` pixels holding one shape layer, a group of one closed
/// path (`sh`) per loop, each with a linear keyframe a frame (straight
/// edges: in- and out-tangents zero), an even-odd fill (`fl`, rule 2) and
/// the stroke of `style`. Points are in pixels of the canvas: the drawing's
/// units less the viewBox's corner, times the canvas's scale.
///
/// # Errors
/// The writer's.
pub fn write_lottie(w: &mut dyn Write, animation: &Animation<'_>) -> std::io::Result<()> {
    let a = animation;
    let order = shown_order(a.frames.num_frames(), a.boomerang);
    let v = a.canvas.view_box;
    let scale = [a.canvas.size[0] / v[2], a.canvas.size[1] / v[3]];
    let px = |p: [f64; 2]| {
        let q = a.canvas.map(p);
        [
            round((q[0] - v[0]) * scale[0]),
            round((q[1] - v[1]) * scale[1]),
        ]
    };
    // shapes[k][l]: loop l of frame k.
    let mut shapes: Vec<Vec<Value>> = Vec::with_capacity(a.frames.num_frames());
    for k in 0..a.frames.num_frames() {
        a.frames.with_frame(k, &mut |positions| {
            shapes.push(
                a.loops
                    .iter()
                    .map(|l| {
                        let vs: Vec<[f64; 2]> =
                            l.iter().map(|&i| px(positions[i as usize])).collect();
                        let zeros = vec![[0.0, 0.0]; vs.len()];
                        json!({"c": true, "v": vs, "i": zeros, "o": zeros})
                    })
                    .collect(),
            )
        });
    }
    let last = order.len().saturating_sub(1);
    let mut items: Vec<Value> = (0..a.loops.len())
        .map(|l| {
            let ks = if order.len() == 1 {
                still(shapes[0][l].clone())
            } else {
                let keys: Vec<Value> = order
                    .iter()
                    .enumerate()
                    .map(|(t, &k)| {
                        let mut key = json!({"t": t, "s": [shapes[k][l].clone()]});
                        if t < last {
                            key["i"] = json!({"x": 1, "y": 1});
                            key["o"] = json!({"x": 0, "y": 0});
                        }
                        key
                    })
                    .collect();
                json!({"a": 1, "k": keys})
            };
            json!({"ty": "sh", "nm": if l == 0 { "outline".to_string() } else { format!("hole {l}") }, "ks": ks})
        })
        .collect();
    let rgb = |c: [u8; 3]| c.map(|x| round(f64::from(x) / 255.0));
    let fill = rgb(a.style.fill.unwrap_or([0, 0, 0]));
    items.push(json!({
        "ty": "fl", "nm": "fill",
        "c": still(json!([fill[0], fill[1], fill[2], 1])),
        "o": still(json!(round(a.style.fill_opacity * 100.0))),
        "r": 2
    }));
    if let Some(s) = a.style.stroke.filter(|_| a.style.stroke_width > 0.0) {
        let c = rgb(s);
        items.push(json!({
            "ty": "st", "nm": "stroke",
            "c": still(json!([c[0], c[1], c[2], 1])),
            "o": still(json!(round(a.style.stroke_opacity * 100.0))),
            "w": still(json!(round(a.style.stroke_width * scale[0]))),
            "lc": 2, "lj": 2
        }));
    }
    items.push(json!({
        "ty": "tr",
        "p": still(json!([0, 0])), "a": still(json!([0, 0])),
        "s": still(json!([100, 100])), "r": still(json!(0)), "o": still(json!(100))
    }));
    let end = order.len().max(1);
    let size = [
        a.canvas.size[0].round().max(1.0),
        a.canvas.size[1].round().max(1.0),
    ];
    let doc = json!({
        "v": "5.7.4",
        "nm": "meshmorph",
        "fr": a.fps,
        "ip": 0,
        "op": end,
        "w": size[0] as u64,
        "h": size[1] as u64,
        "ddd": 0,
        "assets": [],
        "layers": [{
            "ddd": 0, "ind": 1, "ty": 4, "nm": "drawing", "sr": 1,
            "ks": {
                "o": still(json!(100)), "r": still(json!(0)),
                "p": still(json!([0, 0, 0])), "a": still(json!([0, 0, 0])),
                "s": still(json!([100, 100, 100]))
            },
            "ao": 0, "ip": 0, "op": end, "st": 0, "bm": 0,
            "shapes": [{"ty": "gr", "nm": "drawing", "it": items}]
        }]
    });
    serde_json::to_writer(&mut *w, &doc).map_err(std::io::Error::other)?;
    w.write_all(b"\n")
}
