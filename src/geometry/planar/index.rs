//! A bounding-volume hierarchy over a profile's elements: the nearest element to a point and
//! the elements near a point in O(log n) for a profile of n elements, where a scan of every
//! element made the profile computation quadratic (30 000 points took over a minute, issue 36).
//!
//! The tree is built over runs of consecutive elements (a profile is a chain, so a run is
//! compact), halved until a leaf holds at most [`LEAF`] elements; each node keeps the box of its
//! run. Queries visit the nearer child first and skip every node whose box is farther than what
//! is already found, so they return exactly what a scan returns (ties go to the lower index, as
//! [`super::closest_on`] does).

use glam::DVec2;

use super::Element;

/// Most elements in a leaf.
const LEAF: usize = 8;

#[derive(Clone, Copy, Debug)]
struct Node {
    lo: DVec2,
    hi: DVec2,
    /// First element (leaf) or first child (inner node).
    start: usize,
    /// One past the last element, for a leaf; `usize::MAX` for an inner node (children at
    /// `start` and `start + 1`).
    end: usize,
    /// The element range under the node.
    first: usize,
    last: usize,
}

/// Distance from `p` to the box `[lo, hi]` (0 inside).
#[must_use]
pub fn box_distance(lo: DVec2, hi: DVec2, p: DVec2) -> f64 {
    let d = (lo - p).max(p - hi).max(DVec2::ZERO);
    d.length()
}

/// A hierarchy of boxes over items in a fixed order (elements of a profile, or any other
/// features with boxes).
#[derive(Clone, Debug, Default)]
pub struct BoxTree {
    nodes: Vec<Node>,
    boxes: Vec<(DVec2, DVec2)>,
}

impl BoxTree {
    /// The tree over `boxes` (`(lo, hi)` per item, in the items' order).
    #[must_use]
    pub fn new(boxes: Vec<(DVec2, DVec2)>) -> Self {
        let mut tree = Self {
            nodes: Vec::new(),
            boxes,
        };
        if !tree.boxes.is_empty() {
            tree.nodes.push(Node {
                lo: DVec2::ZERO,
                hi: DVec2::ZERO,
                start: 0,
                end: 0,
                first: 0,
                last: tree.boxes.len(),
            });
            tree.build(0, 0, tree.boxes.len());
        }
        tree
    }

    fn build(&mut self, at: usize, first: usize, last: usize) {
        let mut lo = DVec2::splat(f64::INFINITY);
        let mut hi = DVec2::splat(f64::NEG_INFINITY);
        for (a, b) in self.boxes.get(first..last).unwrap_or(&[]) {
            lo = lo.min(*a);
            hi = hi.max(*b);
        }
        if last - first <= LEAF {
            if let Some(n) = self.nodes.get_mut(at) {
                *n = Node {
                    lo,
                    hi,
                    start: first,
                    end: last,
                    first,
                    last,
                };
            }
            return;
        }
        let child = self.nodes.len();
        let mid = first + (last - first) / 2;
        let blank = Node {
            lo: DVec2::ZERO,
            hi: DVec2::ZERO,
            start: 0,
            end: 0,
            first: 0,
            last: 0,
        };
        self.nodes.push(blank);
        self.nodes.push(blank);
        if let Some(n) = self.nodes.get_mut(at) {
            *n = Node {
                lo,
                hi,
                start: child,
                end: usize::MAX,
                first,
                last,
            };
        }
        self.build(child, first, mid);
        self.build(child + 1, mid, last);
    }

    /// The box of item `i`.
    #[must_use]
    pub fn item_box(&self, i: usize) -> Option<(DVec2, DVec2)> {
        self.boxes.get(i).copied()
    }

    /// Visit the items in every node that `keep(lo, hi, first, last)` keeps (a node's box and
    /// the range of items under it), calling `visit(i)` for each item of a kept leaf; `visit`
    /// returns false to stop. The test is asked again after every item, so it may tighten.
    pub fn search(
        &self,
        keep: &mut dyn FnMut(DVec2, DVec2, usize, usize) -> bool,
        visit: &mut dyn FnMut(usize) -> bool,
    ) {
        if self.nodes.is_empty() {
            return;
        }
        let mut stack = vec![0usize];
        while let Some(at) = stack.pop() {
            let Some(n) = self.nodes.get(at).copied() else {
                continue;
            };
            if !keep(n.lo, n.hi, n.first, n.last) {
                continue;
            }
            if n.end == usize::MAX {
                stack.push(n.start + 1);
                stack.push(n.start);
            } else {
                for i in n.start..n.end {
                    let Some(&(lo, hi)) = self.boxes.get(i) else {
                        continue;
                    };
                    if keep(lo, hi, i, i + 1) && !visit(i) {
                        return;
                    }
                }
            }
        }
    }
}

/// The nearest-element and near-elements queries over one list of elements.
#[derive(Clone, Debug)]
pub struct ElementIndex<'a> {
    elements: &'a [Element],
    tree: BoxTree,
}

impl<'a> ElementIndex<'a> {
    /// The index over `elements` (kept by reference; their order is the tie-break).
    #[must_use]
    pub fn new(elements: &'a [Element]) -> Self {
        let tree = BoxTree::new(elements.iter().map(Element::bounds).collect());
        Self { elements, tree }
    }

    /// The elements.
    #[must_use]
    pub fn elements(&self) -> &'a [Element] {
        self.elements
    }

    /// Distance from `p` to the nearest element, its index and the closest point (the lowest
    /// index among equals): what `closest_on` returns.
    #[must_use]
    pub fn closest(&self, p: DVec2) -> Option<(f64, usize, DVec2)> {
        let mut best: Option<(f64, usize, DVec2)> = None;
        let mut stack = vec![0usize];
        while let Some(at) = stack.pop() {
            let Some(n) = self.tree.nodes.get(at).copied() else {
                continue;
            };
            let d = box_distance(n.lo, n.hi, p);
            if best.is_some_and(|b| d > b.0) {
                continue;
            }
            if n.end == usize::MAX {
                let (a, b) = (n.start, n.start + 1);
                let da = self
                    .tree
                    .nodes
                    .get(a)
                    .map_or(f64::INFINITY, |c| box_distance(c.lo, c.hi, p));
                let db = self
                    .tree
                    .nodes
                    .get(b)
                    .map_or(f64::INFINITY, |c| box_distance(c.lo, c.hi, p));
                // The nearer child is popped first.
                if da <= db {
                    stack.push(b);
                    stack.push(a);
                } else {
                    stack.push(a);
                    stack.push(b);
                }
            } else {
                for i in n.start..n.end {
                    let Some(e) = self.elements.get(i) else {
                        continue;
                    };
                    let (q, _) = e.closest(p);
                    let d = (q - p).length();
                    let better = match best {
                        None => true,
                        Some(b) => d < b.0 || (d == b.0 && i < b.1),
                    };
                    if better {
                        best = Some((d, i, q));
                    }
                }
            }
        }
        best
    }

    /// Calls `f(i)` for every element whose box comes within `r` of `p` (a superset of the
    /// elements within `r`), in no particular order.
    pub fn for_each_near(&self, p: DVec2, r: f64, f: &mut dyn FnMut(usize)) {
        self.tree
            .search(&mut |lo, hi, _, _| box_distance(lo, hi, p) <= r, &mut |i| {
                f(i);
                true
            });
    }

    /// The indices of the elements within `r` of `p` (by their exact distance), ascending.
    #[must_use]
    pub fn within(&self, p: DVec2, r: f64) -> Vec<usize> {
        let mut out = Vec::new();
        self.for_each_near(p, r, &mut |i| {
            if self.elements.get(i).is_some_and(|e| e.distance(p) <= r) {
                out.push(i);
            }
        });
        out.sort_unstable();
        out
    }
}

#[cfg(test)]
mod tests {
    use super::super::closest_on;
    use super::*;

    /// The index answers exactly what the scan answers, on a dense wavy chain with arcs, at
    /// points on, near and far from it.
    #[test]
    fn nearest_and_near_agree_with_the_scan() {
        let mut elements = Vec::new();
        let mut prev = DVec2::ZERO;
        for k in 1..2000 {
            let x = f64::from(k) * 0.05;
            let p = DVec2::new(x, (x * 0.7).sin() * 3.0 + (x * 5.1).cos() * 0.2);
            let bulge = if k % 7 == 0 { 0.3 } else { 0.0 };
            elements.push(Element::from_bulge(prev, p, bulge));
            prev = p;
        }
        let index = ElementIndex::new(&elements);
        let mut seed = 12345u64;
        let mut rnd = || {
            seed = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        for _ in 0..500 {
            let p = DVec2::new(rnd() * 140.0 - 20.0, rnd() * 30.0 - 15.0);
            let scan = closest_on(&elements, p).expect("some");
            let fast = index.closest(p).expect("some");
            assert_eq!(scan.1, fast.1, "at {p}");
            assert_eq!(scan.0, fast.0);
            let r = rnd() * 4.0;
            let want: Vec<usize> = (0..elements.len())
                .filter(|&i| elements[i].distance(p) <= r)
                .collect();
            assert_eq!(index.within(p, r), want, "at {p} within {r}");
        }
    }
}
