//! A bounding volume hierarchy: binned-SAH build, depth-first flattening, stack-based traversal.
//!
//! The BVH knows only boxes and primitive ids: it reorders the ids so that every leaf holds a
//! contiguous range of "slots", and traversal hands each leaf's slot range to a caller-supplied
//! closure that tests the primitives. The closure is a generic parameter, so every caller gets its
//! own monomorphised traversal loop with the leaf test inlined.

use std::ops::Range;

use glam::{Vec3, Vec3A};

use super::aabb::Aabb;

/// Number of SAH bins per axis; Wald 2007 finds 16 to lose almost nothing against a full sweep.
const BINS: usize = 16;
/// SAH costs relative to one primitive intersection (pbrt-v4 §7.3.2 uses 1/2 per node visit).
const TRAVERSAL_COST: f32 = 0.5;
/// A node with more primitives than this is always split, so no leaf holds more.
pub(crate) const MAX_LEAF_SIZE: usize = 8;
/// Below this depth splits are chosen by the SAH; from it on by the centroid median, which
/// halves the count at every level. With fewer than 2³² primitives the tree is therefore at
/// most `SAH_DEPTH_LIMIT + 32 = 63` levels deep, which bounds the traversal stack.
const SAH_DEPTH_LIMIT: usize = 31;
const STACK_SIZE: usize = 64;
const _: () = assert!(SAH_DEPTH_LIMIT + 32 < STACK_SIZE);
/// Subtrees with more primitives than this are built in parallel (rayon::join).
const PARALLEL_THRESHOLD: usize = 4096;
/// pbrt-v4's `1 + 2γ₃` (§6.8.2): widens the slab test's far distance to cover the rounding of
/// `(bound - o) * inv_dir`, so a box is never missed by a ray that grazes it.
const SLAB_ROBUSTNESS: f32 =
    1.0 + 2.0 * (3.0 * f32::EPSILON * 0.5) / (1.0 - 3.0 * f32::EPSILON * 0.5);

/// A primitive as the builder sees it.
#[derive(Clone, Copy, Debug)]
pub(crate) struct BuildPrim {
    pub bounds: Aabb,
    pub centroid: Vec3A,
    pub id: u32,
}

impl BuildPrim {
    pub fn new(bounds: Aabb, id: u32) -> BuildPrim {
        BuildPrim {
            bounds,
            centroid: bounds.centroid(),
            id,
        }
    }
}

/// A flattened node, 32 bytes so that two share a cache line. Children are laid out depth-first:
/// an interior node's first child follows it, `offset` is the index of its second child and
/// `axis` its split axis. A leaf (`count > 0`) holds the slots `offset..offset + count`.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(32))]
struct Node {
    min: Vec3,
    offset: u32,
    max: Vec3,
    count: u16,
    axis: u8,
}

const _: () = assert!(std::mem::size_of::<Node>() == 32);

impl Node {
    /// The slab test (Kay & Kajiya 1986): the ray is inside the box where it is inside all three
    /// slabs, i.e. for `t` between the largest entry and the smallest exit distance.
    #[inline(always)]
    fn hit(&self, ray: &Ray, t_min: f32, t_max: f32) -> bool {
        let t0 = (Vec3A::from(self.min) - ray.origin) * ray.inv_dir;
        let t1 = (Vec3A::from(self.max) - ray.origin) * ray.inv_dir;
        let near = t0.min(t1).max_element();
        let far = t0.max(t1).min_element() * SLAB_ROBUSTNESS;
        // `max(near, t_min) <= min(far, t_max)` as plain comparisons: no NaN can occur (see
        // `Ray::new`), and `t_min < t_max` holds already.
        (near <= far) & (near <= t_max) & (far >= t_min)
    }
}

/// A ray prepared for traversal: the reciprocal direction and its signs, computed once.
pub(crate) struct Ray {
    pub origin: Vec3A,
    pub dir: Vec3A,
    inv_dir: Vec3A,
    dir_is_neg: [bool; 3],
}

impl Ray {
    /// `None` for a ray that cannot hit anything: a non-finite origin or direction, or a zero
    /// direction. A direction component below the smallest normal float (zero, say) is replaced
    /// by that float with the same sign, so the reciprocal stays finite (at most ~8.5e37) and
    /// nonzero, and the slab test's `(bound - o) · inv_dir` is never `0 · ∞ = NaN`. The slab of
    /// such an axis then spans `t` in `±δ · 8.5e37` for an origin `δ` inside it: unbounded for
    /// any practical purpose.
    pub fn new(origin: Vec3, dir: Vec3) -> Option<Ray> {
        if !(origin.is_finite() && dir.is_finite()) || dir == Vec3::ZERO {
            return None;
        }
        const TINY: f32 = f32::MIN_POSITIVE;
        let safe = |x: f32| if x.abs() < TINY { TINY.copysign(x) } else { x };
        let inv_dir = Vec3A::new(safe(dir.x), safe(dir.y), safe(dir.z)).recip();
        Some(Ray {
            origin: origin.into(),
            dir: dir.into(),
            inv_dir,
            dir_is_neg: inv_dir.cmplt(Vec3A::ZERO).into(),
        })
    }
}

/// What the build reports about the tree's shape.
pub(crate) struct Shape {
    pub leaves: usize,
    pub max_depth: usize,
    pub max_leaf_size: usize,
}

pub(crate) struct Bvh {
    nodes: Vec<Node>,
}

impl Bvh {
    /// Builds the tree over `prims`, reordering them: afterwards leaf slots index `prims`.
    pub fn build(prims: &mut [BuildPrim]) -> (Bvh, Shape) {
        let mut shape = Shape {
            leaves: 0,
            max_depth: 0,
            max_leaf_size: 0,
        };
        let mut nodes = Vec::new();
        if !prims.is_empty() {
            let root = build_recursive(prims, 0, 0);
            nodes.reserve(2 * prims.len());
            flatten(&root, 0, &mut nodes, &mut shape);
        }
        (Bvh { nodes }, shape)
    }

    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// Visits, front to back by the direction's sign on each split axis, every leaf whose box
    /// the ray enters with `t` in `(t_min, t_max)`, and calls `leaf(slots, &mut t_max)` on it.
    /// The closure may shrink `t_max` (closest hit) and returns `true` to stop (any hit).
    #[inline(always)]
    pub fn traverse<F>(&self, ray: &Ray, t_min: f32, mut t_max: f32, mut leaf: F)
    where
        F: FnMut(Range<usize>, &mut f32) -> bool,
    {
        if self.nodes.is_empty() {
            return;
        }
        let mut stack = [0u32; STACK_SIZE];
        let mut depth = 0;
        let mut index = 0;
        loop {
            let node = &self.nodes[index];
            if node.hit(ray, t_min, t_max) {
                let start = node.offset as usize;
                if node.count > 0 {
                    if leaf(start..start + node.count as usize, &mut t_max) {
                        return;
                    }
                } else {
                    // Visit the child on the near side of the split plane first: the first child
                    // holds the smaller coordinates, so it is near unless the ray goes negative.
                    let (near, far) = if ray.dir_is_neg[node.axis as usize] {
                        (start, index + 1)
                    } else {
                        (index + 1, start)
                    };
                    stack[depth] = far as u32;
                    depth += 1;
                    index = near;
                    continue;
                }
            }
            if depth == 0 {
                return;
            }
            depth -= 1;
            index = stack[depth] as usize;
        }
    }
}

/// The unflattened tree, as the recursive build produces it.
enum BuildNode {
    Leaf {
        bounds: Aabb,
        start: usize,
        count: usize,
    },
    Interior {
        bounds: Aabb,
        axis: usize,
        children: Box<[BuildNode; 2]>,
    },
}

/// Builds the subtree over `prims`, which are slots `start..start + prims.len()`.
fn build_recursive(prims: &mut [BuildPrim], start: usize, depth: usize) -> BuildNode {
    let (bounds, centroids) = prims.iter().fold((Aabb::EMPTY, Aabb::EMPTY), |(b, c), p| {
        (b.union(p.bounds), c.grow(p.centroid))
    });
    let n = prims.len();
    let leaf = BuildNode::Leaf {
        bounds,
        start,
        count: n,
    };
    if n == 1 {
        return leaf;
    }
    let (axis, mid) = if depth >= SAH_DEPTH_LIMIT {
        median_split(prims, &centroids)
    } else {
        match sah_split(prims, &bounds, &centroids) {
            // SAH says a leaf is cheaper, and the leaf is small enough.
            None if n <= MAX_LEAF_SIZE => return leaf,
            // All centroids coincide and there are too many for a leaf: split arbitrarily.
            None => median_split(prims, &centroids),
            Some(split) => split,
        }
    };
    let (left, right) = prims.split_at_mut(mid);
    let (left, right) = if n > PARALLEL_THRESHOLD {
        rayon::join(
            || build_recursive(left, start, depth + 1),
            || build_recursive(right, start + mid, depth + 1),
        )
    } else {
        (
            build_recursive(left, start, depth + 1),
            build_recursive(right, start + mid, depth + 1),
        )
    };
    BuildNode::Interior {
        bounds,
        axis,
        children: Box::new([left, right]),
    }
}

/// The binned SAH split of Wald 2007 ("On fast construction of SAH-based bounding volume
/// hierarchies"), tried on all three axes: primitives are binned by centroid into `BINS` equal
/// slabs of the centroid bounds, and the `BINS - 1` planes between bins are scored by
///
///   cost = C_trav + (N_left · A_left + N_right · A_right) / A_node,
///
/// against the cost `N` of a leaf (intersection cost 1). Returns `(axis, mid)` after
/// partitioning `prims` so that `..mid` goes left, or `None` when no split beats a leaf (or no
/// axis has centroid extent).
fn sah_split(prims: &mut [BuildPrim], bounds: &Aabb, centroids: &Aabb) -> Option<(usize, usize)> {
    let extent = centroids.extent();
    // Wald's k1 = BINS (1 - ε) / extent keeps the largest centroid in the last bin.
    let scale = Vec3A::splat(BINS as f32 * (1.0 - 1e-5)) / extent;
    let bin_of = |p: &BuildPrim, axis: usize| -> usize {
        let k = ((p.centroid[axis] - centroids.min[axis]) * scale[axis]) as usize;
        k.min(BINS - 1)
    };

    let mut counts = [[0usize; BINS]; 3];
    let mut boxes = [[Aabb::EMPTY; BINS]; 3];
    for p in prims.iter() {
        for axis in 0..3 {
            if extent[axis] > 0.0 {
                let k = bin_of(p, axis);
                counts[axis][k] += 1;
                boxes[axis][k] = boxes[axis][k].union(p.bounds);
            }
        }
    }

    let mut best: Option<(f32, usize, usize)> = None;
    for axis in (0..3).filter(|&axis| extent[axis] > 0.0) {
        // Sweep right to left for the areas and counts to the right of each plane, then left to
        // right scoring plane k (between bins k and k + 1).
        let mut right_cost = [0.0f32; BINS];
        let (mut b, mut c) = (Aabb::EMPTY, 0);
        for k in (1..BINS).rev() {
            b = b.union(boxes[axis][k]);
            c += counts[axis][k];
            right_cost[k - 1] = c as f32 * b.surface_area();
        }
        let (mut b, mut c) = (Aabb::EMPTY, 0);
        for k in 0..BINS - 1 {
            b = b.union(boxes[axis][k]);
            c += counts[axis][k];
            let cost = c as f32 * b.surface_area() + right_cost[k];
            if best.is_none_or(|(best_cost, ..)| cost < best_cost) {
                best = Some((cost, axis, k));
            }
        }
    }

    let (cost, axis, k) = best?;
    let area = bounds.surface_area();
    let split_cost = TRAVERSAL_COST + if area > 0.0 { cost / area } else { 0.0 };
    if prims.len() <= MAX_LEAF_SIZE && prims.len() as f32 <= split_cost {
        return None;
    }
    let mid = partition(prims, |p| bin_of(p, axis) <= k);
    // The first bin and the last are both occupied, so neither side is empty.
    (mid > 0 && mid < prims.len()).then_some((axis, mid))
}

/// Splits at the median centroid on the axis of largest centroid extent: `(axis, mid)`.
fn median_split(prims: &mut [BuildPrim], centroids: &Aabb) -> (usize, usize) {
    let axis = centroids.extent().max_position();
    let mid = prims.len() / 2;
    prims.select_nth_unstable_by(mid, |a, b| a.centroid[axis].total_cmp(&b.centroid[axis]));
    (axis, mid)
}

/// Moves the elements satisfying `left` to the front; returns how many there are.
fn partition(prims: &mut [BuildPrim], left: impl Fn(&BuildPrim) -> bool) -> usize {
    let mut mid = 0;
    for i in 0..prims.len() {
        if left(&prims[i]) {
            prims.swap(i, mid);
            mid += 1;
        }
    }
    mid
}

/// Appends `node`'s subtree depth-first, returning its index.
fn flatten(node: &BuildNode, depth: usize, nodes: &mut Vec<Node>, shape: &mut Shape) -> usize {
    let index = nodes.len();
    let flat = |bounds: &Aabb, offset: usize, count: usize, axis: usize| Node {
        min: bounds.min.into(),
        offset: offset as u32,
        max: bounds.max.into(),
        count: count as u16,
        axis: axis as u8,
    };
    match node {
        BuildNode::Leaf {
            bounds,
            start,
            count,
        } => {
            shape.leaves += 1;
            shape.max_depth = shape.max_depth.max(depth);
            shape.max_leaf_size = shape.max_leaf_size.max(*count);
            nodes.push(flat(bounds, *start, *count, 0));
        }
        BuildNode::Interior {
            bounds,
            axis,
            children,
        } => {
            // The first child goes right after this node; the second child's index is known
            // only once the first subtree is laid out.
            nodes.push(flat(bounds, 0, 0, *axis));
            flatten(&children[0], depth + 1, nodes, shape);
            let second = flatten(&children[1], depth + 1, nodes, shape);
            nodes[index].offset = second as u32;
        }
    }
    index
}

#[cfg(test)]
mod tests {
    use super::*;

    fn prims(n: usize) -> Vec<BuildPrim> {
        // A deterministic scatter of small boxes with clustered, repeated and spread centroids.
        (0..n)
            .map(|i| {
                let c = Vec3A::new(
                    (i % 7) as f32,
                    (i * i % 13) as f32,
                    1.1f32.powi((i % 50) as i32),
                );
                BuildPrim::new(Aabb::from_points([c, c + Vec3A::splat(0.5)]), i as u32)
            })
            .collect()
    }

    fn contains(outer: &Node, inner: &Aabb) -> bool {
        Vec3::from(inner.min).cmpge(outer.min).all() && Vec3::from(inner.max).cmple(outer.max).all()
    }

    /// Every node bounds its subtree, leaves partition the slots, and the ids are a permutation.
    #[test]
    fn flattened_tree_is_consistent() {
        let mut p = prims(5000);
        let (bvh, shape) = Bvh::build(&mut p);
        let mut ids: Vec<u32> = p.iter().map(|p| p.id).collect();
        ids.sort_unstable();
        assert!(ids.iter().enumerate().all(|(i, &id)| id == i as u32));

        let mut covered = vec![0u32; p.len()];
        let mut stack = vec![0usize];
        while let Some(i) = stack.pop() {
            let node = &bvh.nodes[i];
            let start = node.offset as usize;
            if node.count > 0 {
                for slot in start..start + node.count as usize {
                    assert!(contains(node, &p[slot].bounds));
                    covered[slot] += 1;
                }
            } else {
                for child in [i + 1, start] {
                    let c = &bvh.nodes[child];
                    assert!(contains(
                        node,
                        &Aabb {
                            min: c.min.into(),
                            max: c.max.into()
                        }
                    ));
                    stack.push(child);
                }
            }
        }
        assert!(covered.iter().all(|&c| c == 1));
        assert_eq!(bvh.node_count(), 2 * shape.leaves - 1);
        assert!(shape.max_leaf_size <= MAX_LEAF_SIZE);
    }

    /// Past the SAH depth limit every split halves the count, so a subtree over `n` primitives
    /// adds at most `ceil(log2 n)` levels: the bound the traversal stack relies on.
    #[test]
    fn median_splits_past_the_depth_limit_halve() {
        let mut p = prims(1000);
        let root = build_recursive(&mut p, 0, SAH_DEPTH_LIMIT);
        let mut shape = Shape {
            leaves: 0,
            max_depth: 0,
            max_leaf_size: 0,
        };
        flatten(&root, SAH_DEPTH_LIMIT, &mut Vec::new(), &mut shape);
        assert!(
            shape.max_depth <= SAH_DEPTH_LIMIT + 10,
            "depth {}",
            shape.max_depth
        );
    }
}
