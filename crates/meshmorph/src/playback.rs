//! The order in which an animation's frames are shown.

/// Frames `0, 1, ..., count - 1`, then with `boomerang` back through
/// `count - 2, ..., 1` (the ends not repeated), so that played over and
/// over the animation goes forward and back without a jump.
pub fn shown_order(count: usize, boomerang: bool) -> Vec<usize> {
    let mut order: Vec<usize> = (0..count).collect();
    if boomerang && count > 2 {
        order.extend((1..count - 1).rev());
    }
    order
}

#[cfg(test)]
mod tests {
    use super::shown_order;

    #[test]
    fn forward_then_back_without_repeating_the_ends() {
        assert_eq!(shown_order(4, true), [0, 1, 2, 3, 2, 1]);
        assert_eq!(shown_order(4, false), [0, 1, 2, 3]);
        assert_eq!(shown_order(2, true), [0, 1]);
        assert_eq!(shown_order(0, true), Vec::<usize>::new());
    }
}
