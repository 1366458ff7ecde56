//! Frame file names, and the removal of frames an earlier run left behind.

use std::path::{Path, PathBuf};

/// Extensions of the frame files meshmorph writes (meshes, drawings and
/// pictures).
const FRAME_EXTENSIONS: [&str; 7] = ["obj", "off", "ply", "stl", "svg", "txt", "png"];

/// `dir/frame_0007.ext`, with enough digits for `count` frames (at least 4).
pub fn frame_path(dir: &Path, index: usize, count: usize, ext: &str) -> PathBuf {
    let digits = (count.max(2) - 1).to_string().len().max(4);
    dir.join(format!("frame_{index:0digits$}.{ext}"))
}

/// Whether `name` is exactly a frame name meshmorph writes: `frame_`, four
/// or more ASCII digits, a dot and one of the frame extensions.
pub fn is_frame_name(name: &str) -> bool {
    let Some(rest) = name.strip_prefix("frame_") else {
        return false;
    };
    let Some((digits, ext)) = rest.split_once('.') else {
        return false;
    };
    digits.len() >= 4
        && digits.bytes().all(|b| b.is_ascii_digit())
        && FRAME_EXTENSIONS.contains(&ext)
}

/// The regular files in `dir` with frame names for which `keep` is false.
pub fn surplus_frames(dir: &Path, mut keep: impl FnMut(&Path) -> bool) -> Vec<PathBuf> {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Vec::new();
    };
    let mut found: Vec<PathBuf> = entries
        .filter_map(Result::ok)
        .filter(|e| e.file_type().is_ok_and(|t| t.is_file()))
        .filter(|e| e.file_name().to_str().is_some_and(is_frame_name))
        .map(|e| e.path())
        .filter(|p| !keep(p))
        .collect();
    found.sort();
    found
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_exact_frame_names() {
        for good in [
            "frame_0000.obj",
            "frame_12345.svg",
            "frame_0031.ply",
            "frame_0002.png",
        ] {
            assert!(is_frame_name(good), "{good}");
        }
        for bad in [
            "frame_001.obj",
            "frame_0001.obj.bak",
            "frame_0001.OBJ",
            "frame_00a1.obj",
            "frame_0001.gif",
            "myframe_0001.obj",
            "frame_0001",
            "frame_.obj",
        ] {
            assert!(!is_frame_name(bad), "{bad}");
        }
        assert_eq!(
            frame_path(Path::new("d"), 7, 30, "obj"),
            Path::new("d/frame_0007.obj")
        );
        assert_eq!(
            frame_path(Path::new("d"), 7, 100_001, "svg"),
            Path::new("d/frame_000007.svg")
        );
    }
}
