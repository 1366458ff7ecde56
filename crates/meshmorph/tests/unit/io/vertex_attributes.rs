use meshmorph::io::vertex_attributes::*;

#[test]
fn values_agree_per_vertex_or_not_at_all() {
    let vertex_of = [0, 1, 2, 2, 1, 3];
    let same = per_vertex(5, &vertex_of, |c| vertex_of[c] * 10, 99).unwrap();
    assert_eq!(same, [0, 10, 20, 30, 99]);
    let values = [0, 1, 2, 2, 7, 3];
    assert_eq!(per_vertex(4, &vertex_of, |c| values[c], 0), None);
    assert_eq!(channel_byte(1.0), 255);
    assert_eq!(channel_byte(0.5), 128);
}
