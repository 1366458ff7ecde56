use meshmorph::io::gltf::base64::*;

#[test]
fn every_length_round_trips() {
    let bytes: Vec<u8> = (0..=255u8).collect();
    for n in 0..40 {
        let text = encode(&bytes[..n]);
        assert_eq!(text.len() % 4, 0);
        assert_eq!(decode(&text).unwrap(), &bytes[..n]);
    }
    assert_eq!(encode(b"glTF"), "Z2xURg==");
    assert!(decode("Z2x*").is_none());
}
