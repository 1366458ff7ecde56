//! A bounding volume hierarchy over fixed items in space, for nearest-item
//! queries with a filter and a distance cut-off.
//!
//! Built once, top down: each node's items are split at the median of their
//! centres along the axis where the centres spread most, down to leaves of
//! at most [`LEAF_SIZE`] items (so the tree is balanced, its depth about
//! `log2(n / LEAF_SIZE)`). A query walks it depth first, nearer child first,
//! and skips every node whose box lies farther than the best item found so
//! far (at first, the cut-off): with a cut-off small next to the model, a
//! query opens a few leaves around its point. The answer is exactly the
//! accepted item nearest to the point (ties go to the lowest item index),
//! whatever order the walk takes.
//!
//! Piles of items at one place (a triangle repeated 30,000 times) would make
//! every query open them all: items with equal keys are kept once (the
//! first), and each node knows the lowest index below it, so that a node no
//! nearer than the best item so far, with no lower index, is skipped.

/// Most items in a leaf.
const LEAF_SIZE: usize = 4;

/// Deepest tree a query's stack holds (a balanced tree of `u32` items is
/// at most 33 levels deep).
const MAX_DEPTH: usize = 64;

/// An axis-aligned box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// The smallest corner.
    pub(crate) lo: [f64; 3],
    /// The largest corner.
    pub(crate) hi: [f64; 3],
}

impl Aabb {
    /// The box around `points`.
    pub fn around(points: impl IntoIterator<Item = [f64; 3]>) -> Self {
        let mut b = Self::EMPTY;
        for p in points {
            b = b.union(&Self { lo: p, hi: p });
        }
        b
    }

    /// The length of the box's diagonal (without overflow or underflow at
    /// extreme coordinates: [`crate::mesh::bounding_box_diagonal`]).
    pub(crate) fn diagonal(&self) -> f64 {
        crate::mesh::bounding_box_diagonal(&[self.lo, self.hi])
    }

    /// The box grown by `margin` on every side.
    pub(crate) fn grown(&self, margin: f64) -> Self {
        Self {
            lo: self.lo.map(|x| x - margin),
            hi: self.hi.map(|x| x + margin),
        }
    }

    /// Whether the two boxes share a point.
    pub(crate) fn meets(&self, other: &Self) -> bool {
        (0..3).all(|i| self.lo[i] <= other.hi[i] && other.lo[i] <= self.hi[i])
    }

    const EMPTY: Self = Self {
        lo: [f64::INFINITY; 3],
        hi: [f64::NEG_INFINITY; 3],
    };

    fn union(&self, other: &Self) -> Self {
        Self {
            lo: std::array::from_fn(|i| self.lo[i].min(other.lo[i])),
            hi: std::array::from_fn(|i| self.hi[i].max(other.hi[i])),
        }
    }

    /// Squared distance from `q` to the nearest point of the box (0 inside).
    #[inline]
    fn distance_2(&self, q: [f64; 3]) -> f64 {
        let mut d2 = 0.0;
        for i in 0..3 {
            let d = (self.lo[i] - q[i]).max(q[i] - self.hi[i]).max(0.0);
            d2 += d * d;
        }
        d2
    }
}

/// A node: a leaf holds items `first..first + count`; an inner node
/// (`count == 0`) has its two children at `first` and `first + 1`.
/// `lowest` is the lowest index (in the list given to [`Bvh::new`]) of the
/// items below it.
#[derive(Clone, Copy, Debug)]
struct Node {
    bounds: Aabb,
    first: u32,
    count: u32,
    lowest: u32,
}

const EMPTY_NODE: Node = Node {
    bounds: Aabb::EMPTY,
    first: 0,
    count: 0,
    lowest: u32::MAX,
};

/// Items of type `T` in a bounding volume hierarchy.
#[derive(Clone, Debug)]
pub struct Bvh<T> {
    nodes: Vec<Node>,
    /// The items, in leaf order.
    pub items: Vec<T>,
    /// The index each item had in the list given to [`Bvh::new`].
    pub index: Vec<u32>,
}

/// The nearest accepted item: its index in the list given to [`Bvh::new`],
/// the item, and its squared distance.
pub(crate) type Nearest<'a, T> = (u32, &'a T, f64);

impl<T> Bvh<T> {
    /// The hierarchy over `items`, each within the box `bounds(item)`.
    /// Items with the same `key` must be alike for every query (the same
    /// box, accepted or not together, at the same distance): of those, only
    /// the first is kept, the only one a query could answer.
    ///
    /// # Performance
    /// `O(n log n)`; keys are compared only among items whose boxes have
    /// the same centre.
    ///
    /// # Panics
    /// If there are `u32::MAX` items or more.
    pub fn new<K: Ord>(items: Vec<T>, bounds: impl Fn(&T) -> Aabb, key: impl Fn(&T) -> K) -> Self {
        assert!(items.len() < u32::MAX as usize, "too many items");
        let boxes: Vec<Aabb> = items.iter().map(&bounds).collect();
        let centres: Vec<[f64; 3]> = boxes
            .iter()
            .map(|b| std::array::from_fn(|i| 0.5 * (b.lo[i] + b.hi[i])))
            .collect();
        let mut order: Vec<u32> = (0..items.len() as u32).collect();
        let mut nodes = vec![EMPTY_NODE];
        let mut kept = Vec::with_capacity(items.len());
        if !items.is_empty() {
            let tree = Tree {
                boxes: &boxes,
                centres: &centres,
                key: |k: u32| key(&items[k as usize]),
            };
            tree.build(&mut nodes, 0, &mut order, &mut kept, false);
        }
        drop(order);
        let mut slots: Vec<Option<T>> = items.into_iter().map(Some).collect();
        let items = kept
            .iter()
            .map(|&k| slots[k as usize].take().expect("each item once"))
            .collect();
        Self {
            nodes,
            items,
            index: kept,
        }
    }

    /// The item nearest to `q` among those `accept` takes, with
    /// `distance_2(item)` its squared distance from `q`, if one lies within
    /// `max_distance_2`; of equally near ones, the one given first to
    /// [`Bvh::new`]. `distance_2` must be at least the squared distance from
    /// `q` to the item's box.
    pub fn nearest(
        &self,
        q: [f64; 3],
        max_distance_2: f64,
        accept: impl Fn(&T) -> bool,
        distance_2: impl Fn(&T) -> f64,
    ) -> Option<Nearest<'_, T>> {
        let mut best: Option<(usize, f64)> = None;
        let mut bound = max_distance_2;
        let mut stack = [(0u32, 0.0f64); MAX_DEPTH];
        let root = self.nodes[0].bounds.distance_2(q);
        if self.items.is_empty() || root > bound {
            return None;
        }
        stack[0] = (0, root);
        let mut depth = 1;
        while depth > 0 {
            depth -= 1;
            let (n, d2) = stack[depth];
            if d2 > bound {
                continue;
            }
            let node = self.nodes[n as usize];
            if d2 == bound && best.is_some_and(|(b, _)| node.lowest > self.index[b]) {
                // Nothing below is nearer, nor as near with a lower index.
                continue;
            }
            if node.count > 0 {
                let start = node.first as usize;
                for k in start..start + node.count as usize {
                    let item = &self.items[k];
                    if !accept(item) {
                        continue;
                    }
                    let d2 = distance_2(item);
                    let better = match best {
                        None => d2 <= bound,
                        Some((b, _)) => {
                            d2 < bound || (d2 == bound && self.index[k] < self.index[b])
                        }
                    };
                    if better {
                        best = Some((k, d2));
                        bound = d2;
                    }
                }
                continue;
            }
            let (a, b) = (node.first, node.first + 1);
            let (da, db) = (
                self.nodes[a as usize].bounds.distance_2(q),
                self.nodes[b as usize].bounds.distance_2(q),
            );
            // The nearer child is taken first: pushed last.
            let (near, far) = if db < da {
                ((b, db), (a, da))
            } else {
                ((a, da), (b, db))
            };
            for (c, d) in [far, near] {
                if d <= bound {
                    stack[depth] = (c, d);
                    depth += 1;
                }
            }
        }
        best.map(|(k, d2)| (self.index[k], &self.items[k], d2))
    }
}

/// What the build reads: the items' boxes, their centres and their keys.
struct Tree<'a, F> {
    boxes: &'a [Aabb],
    centres: &'a [[f64; 3]],
    key: F,
}

impl<F: Fn(u32) -> K, K: Ord> Tree<'_, F> {
    /// Makes `nodes[at]` the node of the items `order[..]`, and its
    /// subtree, appending the items it keeps to `kept` in leaf order.
    /// `distinct`: the keys of `order` are known to differ.
    fn build(
        &self,
        nodes: &mut Vec<Node>,
        at: usize,
        order: &mut [u32],
        kept: &mut Vec<u32>,
        distinct: bool,
    ) {
        let bounds = order
            .iter()
            .fold(Aabb::EMPTY, |b, &k| b.union(&self.boxes[k as usize]));
        if order.len() <= LEAF_SIZE {
            self.leaf(nodes, at, bounds, order, kept);
            return;
        }
        let spread = order.iter().fold(Aabb::EMPTY, |b, &k| {
            let c = self.centres[k as usize];
            b.union(&Aabb { lo: c, hi: c })
        });
        let (order, distinct) = if !distinct && spread.lo == spread.hi {
            // All at one place: keep the first of each key.
            let n = self.first_of_each_key(order);
            (&mut order[..n], true)
        } else {
            (order, distinct)
        };
        if order.len() <= LEAF_SIZE {
            self.leaf(nodes, at, bounds, order, kept);
            return;
        }
        let axis = (0..3)
            .max_by(|&i, &j| {
                (spread.hi[i] - spread.lo[i]).total_cmp(&(spread.hi[j] - spread.lo[j]))
            })
            .unwrap_or(0);
        let mid = order.len() / 2;
        order.select_nth_unstable_by(mid, |&i, &j| {
            self.centres[i as usize][axis]
                .total_cmp(&self.centres[j as usize][axis])
                .then(i.cmp(&j))
        });
        let children = nodes.len();
        nodes.extend([EMPTY_NODE, EMPTY_NODE]);
        let (left, right) = order.split_at_mut(mid);
        self.build(nodes, children, left, kept, distinct);
        self.build(nodes, children + 1, right, kept, distinct);
        nodes[at] = Node {
            bounds,
            first: children as u32,
            count: 0,
            lowest: nodes[children].lowest.min(nodes[children + 1].lowest),
        };
    }

    /// Moves the first item (lowest index) of each key in `order` to its
    /// front; returns how many there are.
    fn first_of_each_key(&self, order: &mut [u32]) -> usize {
        order.sort_unstable_by(|&i, &j| (self.key)(i).cmp(&(self.key)(j)).then(i.cmp(&j)));
        let mut n = 0;
        for k in 0..order.len() {
            if n == 0 || (self.key)(order[n - 1]) != (self.key)(order[k]) {
                order[n] = order[k];
                n += 1;
            }
        }
        n
    }

    /// Makes `nodes[at]` the leaf of the items `order`.
    fn leaf(
        &self,
        nodes: &mut [Node],
        at: usize,
        bounds: Aabb,
        order: &[u32],
        kept: &mut Vec<u32>,
    ) {
        nodes[at] = Node {
            bounds,
            first: kept.len() as u32,
            count: order.len() as u32,
            lowest: order.iter().copied().min().unwrap_or(u32::MAX),
        };
        kept.extend_from_slice(order);
    }
}
