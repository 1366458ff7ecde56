//! The real 2D meshes of ../shared/data (elephant, man, bar): no triangle
//! flips on the way, and the target is reached.

use std::path::PathBuf;

use meshmorph::{Interpolator, InterpolatorOptions, Mesh2};

use crate::common::{max_distance, max_flipped};

fn read2(path: &std::path::Path) -> Mesh2 {
    meshmorph::io::read_mesh(path).unwrap().to_2d().unwrap()
}

pub fn real_2d_meshes_interpolate_without_flips(dir: PathBuf) {
    let pairs = [
        ("elephant/elephant_s.obj", "elephant/elephant_t.obj"),
        ("man/man.obj", "man/man0.obj"),
        ("man/man.obj", "man/man1.obj"),
        ("man/man.obj", "man/man2.obj"),
        ("man/man.obj", "man/man3.obj"),
        ("man/man-bend-a.obj", "man/man-bend-b.obj"),
        ("bar/ref.obj", "bar/twist1.obj"),
        ("bar/ref.obj", "bar/twist2.obj"),
    ];
    for (s, t) in pairs {
        let (source, target) = (read2(&dir.join(s)), read2(&dir.join(t)));
        let m = Interpolator::new(&source, &target, &InterpolatorOptions::default())
            .unwrap_or_else(|e| panic!("{s} -> {t}: {e}"));
        assert_eq!(max_flipped(&m, 101), 0, "{s} -> {t}");
        let tol = 1e-9 * source.bounding_box_diagonal();
        assert!(
            max_distance(&m.at(1.0), target.positions()) < tol,
            "{s} -> {t}"
        );
    }
}
