use meshmorph::playback::shown_order;

#[test]
fn forward_then_back_without_repeating_the_ends() {
    assert_eq!(shown_order(4, true), [0, 1, 2, 3, 2, 1]);
    assert_eq!(shown_order(4, false), [0, 1, 2, 3]);
    assert_eq!(shown_order(2, true), [0, 1]);
    assert_eq!(shown_order(0, true), Vec::<usize>::new());
}
