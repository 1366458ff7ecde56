use meshmorph::interpolate::attached::*;

#[test]
fn a_part_centred_on_its_anchors_follows_them() {
    // A ball centred in a pipe of size 4 that turns: its offsets from
    // the pipe's vertices around it are rounding, 2e-12 in the world
    // and a hair more in the anchors' frame (as read from files of 12
    // digits). That is a tie, and the ball goes with the pipe.
    let anchors = PartAnchors {
        count: 2,
        parts: vec![(1, vec![0, 1, 2])],
    };
    let key = |world: [f64; 3], local: [f64; 3]| {
        vec![KeyOffset {
            world,
            local,
            size: 4.0,
        }]
    };
    let keys = [
        key([0.0, 6.9e-18, -1.4e-17], [0.0, 6.9e-18, -1.4e-17]),
        key(
            [2.0827783941967937e-12, 6.25e-14, -1.4e-17],
            [2.0827818646478e-12, 6.25e-14, -1.4e-17],
        ),
    ];
    assert!(anchors.attached(&keys).holds(1));
    // Offsets that differ in the anchors' frame beyond rounding do not.
    let keys = [
        key([0.5, 0.0, 0.0], [0.5, 0.0, 0.0]),
        key([0.5, 0.0, 0.0], [0.0, 0.5, 0.0]),
    ];
    assert!(!anchors.attached(&keys).holds(1));
}
