use std::path::{Path, PathBuf};

use meshmorph::io::mtl::*;

#[test]
fn names_every_texture_map() {
    let text = "newmtl a\nmap_Kd -s 1 1 1 skin albedo.png\nmap_Bump -bm 0.5 n.png\nbump n.png\n\
                disp /abs/d.png\nrefl -type sphere r.png\nKd 1 1 1\n# map_Ks c.png\n";
    let files = named_files(text, Path::new("/assets/head.mtl"));
    let expect = [
        "/assets/skin albedo.png",
        "/assets/n.png",
        "/abs/d.png",
        "/assets/r.png",
    ];
    assert_eq!(files, expect.map(PathBuf::from));
}

#[test]
fn reads_colours_opacity_and_textures() {
    let text = "# Blender MTL File\nnewmtl Skin\nNs 250.000000\nKa 1 1 1\nKd 0.8 0.5 0.4\nd 0.5\n\
                map_Kd -bm 1.0 -s 1 1 1 textures/skin albedo.png\n\nnewmtl Eye\nKd 0.1\nPr 0.2\nPm 1\nTr 0.25\n";
    let m = parse_mtl(text, Path::new("/assets/head.mtl")).unwrap();
    assert_eq!(m.len(), 2);
    assert_eq!(m[0].name, "Skin");
    assert_eq!(m[0].diffuse, [0.8, 0.5, 0.4]);
    assert_eq!(m[0].opacity, 0.5);
    assert!((m[0].roughness.unwrap() - 0.5).abs() < 1e-6);
    assert_eq!(
        m[0].diffuse_map.as_deref(),
        Some(Path::new("/assets/textures/skin albedo.png"))
    );
    assert_eq!(m[1].diffuse, [0.1; 3]);
    assert_eq!(m[1].roughness, Some(0.2));
    assert_eq!(m[1].metallic, Some(1.0));
    assert_eq!(m[1].opacity, 0.75);
    assert_eq!(m[1].diffuse_map, None);
}

#[test]
fn a_bad_number_names_its_line() {
    let e = parse_mtl("newmtl a\nKd 1 x 1\n", Path::new("m.mtl")).unwrap_err();
    let message = e.to_string();
    assert!(
        message.contains("m.mtl") && message.contains('2'),
        "{message}"
    );
}

#[test]
fn texture_options_are_skipped() {
    assert_eq!(texture_file("a.png"), "a.png");
    assert_eq!(texture_file("-clamp on a b.png"), "a b.png");
    assert_eq!(texture_file("-o 0.5 b.png"), "b.png");
    assert_eq!(texture_file("-mm 0 1 c.jpg"), "c.jpg");
}
