//! Meshes of ../shared/data read with their vertex and triangle counts.

use std::path::PathBuf;

use meshmorph::io::read_mesh;

pub fn shared_data_meshes(root: PathBuf) {
    for (file, nv, nt) in [
        ("2d/elephant/elephant_s.obj", 1105, 1796),
        ("2d/man/man.obj", 214, 332),
        (
            "dt/horse-camel/camel-poses/camel-reference.obj",
            21887,
            43814,
        ),
    ] {
        let path = root.join(file);
        let start = std::time::Instant::now();
        let m = read_mesh(&path).unwrap_or_else(|e| panic!("{e}"));
        println!(
            "{file}: {} V, {} T in {:?}",
            m.num_vertices(),
            m.num_triangles(),
            start.elapsed()
        );
        assert_eq!((m.num_vertices(), m.num_triangles()), (nv, nt), "{file}");
    }
    let m = read_mesh(&root.join("2d/man/man.obj")).unwrap();
    assert!(m.to_2d().is_ok());
}
