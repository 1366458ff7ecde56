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
