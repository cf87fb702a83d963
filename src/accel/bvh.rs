//! A four-wide bounding volume hierarchy: a parallel binned-SAH binary build, collapsed into
//! nodes of four children whose boxes one ray tests at once (SIMD lanes), and an ordered
//! stack traversal.
//!
//! The BVH knows only boxes: the build reorders the caller's [`BuildPrim`]s so that every leaf
//! is a contiguous run of them, and hands each run to a caller closure that stores the leaf's
//! primitives however it likes and returns a 31-bit payload. Traversal hands the payload of
//! each leaf the ray reaches back to a second closure that tests the primitives. Both closures
//! are generic parameters, so every caller gets its own loop with the leaf test inlined.

use std::mem::MaybeUninit;

use glam::{Vec3A, Vec4};
use rayon::prelude::*;

use super::aabb::Aabb;
use super::memory::{on_huge_pages, prefetch};
#[cfg(target_arch = "x86_64")]
use super::packet::{PACKET_SIZE, RayPacket};
#[cfg(target_arch = "x86_64")]
use super::shadow_packet::ShadowPacket;

/// Number of SAH bins per axis; Wald 2007 finds 16 to lose almost nothing against a full sweep.
const BINS: usize = 16;
/// SAH cost of a node visit relative to one leaf block test (pbrt-v4 §7.3.2 uses 1/2).
const TRAVERSAL_COST: f32 = 0.5;
/// Leaves are tested [`LEAF_BLOCK`] primitives at a time (a SIMD packet): the SAH charges a
/// leaf by its blocks, so that it prefers full ones (Embree's "block size").
pub(crate) const LEAF_BLOCK: usize = 4;
/// A node with more primitives than this is always split, so no leaf holds more.
pub(crate) const MAX_LEAF_SIZE: usize = 2 * LEAF_BLOCK;
/// Below this depth splits are chosen by the SAH; from it on by the centroid median, which
/// halves the count at every level. With fewer than 2³² primitives the binary tree is therefore
/// at most `SAH_DEPTH_LIMIT + 32 = 63` levels deep; the wide tree is no deeper, and each of
/// its levels leaves at most 3 children on the traversal stack.
const SAH_DEPTH_LIMIT: usize = 31;
const STACK_SIZE: usize = 3 * 64 + 1;
/// Subtrees with more primitives than this are built in parallel (rayon::join).
const PARALLEL_THRESHOLD: usize = 4096;
/// Nodes with more primitives than this compute their bounds and SAH bins in parallel chunks.
const PARALLEL_FOLD_THRESHOLD: usize = 1 << 16;
/// pbrt-v4's `1 + 2γ₃` (§6.8.2): widens the slab test's far distance to cover the rounding of
/// `(bound - o) * inv_dir`, so a box is never missed by a ray that grazes it.
pub(crate) const SLAB_ROBUSTNESS: f32 =
    1.0 + 2.0 * (3.0 * f32::EPSILON * 0.5) / (1.0 - 3.0 * f32::EPSILON * 0.5);
/// Cache lines per node.
const NODE_LINES: usize = std::mem::size_of::<Node>() / 64;
/// A child word with this bit set is a leaf; the other 31 bits are the caller's payload.
const LEAF: u32 = 1 << 31;

/// A primitive as the builder sees it. `group` keeps primitives of different kinds (triangles
/// and spheres, say) out of the same leaf.
#[derive(Clone, Copy, Debug)]
pub(crate) struct BuildPrim {
    pub bounds: Aabb,
    pub centroid: Vec3A,
    pub id: u32,
    pub group: u32,
}

impl BuildPrim {
    pub fn new(bounds: Aabb, id: u32, group: u32) -> BuildPrim {
        BuildPrim {
            bounds,
            centroid: bounds.centroid(),
            id,
            group,
        }
    }
}

/// Four children's boxes as structure of arrays, one SIMD lane per child: `bounds[2 axis]` holds
/// the lower bounds on `axis`, `bounds[2 axis + 1]` the upper ones. An unused lane has the empty
/// box (lower +∞, upper -∞), which no ray enters. 112 bytes, padded to two cache lines.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(64))]
struct Node {
    bounds: [Vec4; 6],
    child: [u32; 4],
}

impl Node {
    const EMPTY: Node = Node {
        bounds: [
            Vec4::INFINITY,
            Vec4::NEG_INFINITY,
            Vec4::INFINITY,
            Vec4::NEG_INFINITY,
            Vec4::INFINITY,
            Vec4::NEG_INFINITY,
        ],
        child: [0; 4],
    };

    fn set(&mut self, lane: usize, bounds: &Aabb, child: u32) {
        for axis in 0..3 {
            self.bounds[2 * axis][lane] = bounds.min[axis];
            self.bounds[2 * axis + 1][lane] = bounds.max[axis];
        }
        self.child[lane] = child;
    }

    /// The slab test (Kay & Kajiya 1986) on all four boxes at once: a ray is inside a box for
    /// `t` between the largest entry and the smallest exit distance over the three slabs. By
    /// the direction's sign the entry plane of each slab is known in advance (Williams et al.
    /// 2005), so entry and exit are one subtraction and one product each, with no min/max.
    /// Returns each box's entry distance and the mask of boxes entered in `(t_min, t_max)`.
    #[inline(always)]
    fn hit(&self, ray: &Ray, slabs: &Slabs, t_min: Vec4, t_max: f32) -> (Vec4, u32) {
        let slab = |axis: usize, offset: usize| {
            // SAFETY: `offset` is one of `Slabs::new`'s byte offsets of a `bounds` entry,
            // `16 (2 axis + side)` with `side` 0 or 1: in bounds and 16-byte aligned.
            let bound = unsafe { *self.bounds.as_ptr().byte_add(offset) };
            (bound - ray.origin4[axis]) * slabs.inv_dir4[axis]
        };
        let near = (slab(0, slabs.near[0]).max(slab(1, slabs.near[1]))).max(slab(2, slabs.near[2]));
        let far = (slab(0, slabs.far[0]).min(slab(1, slabs.far[1]))).min(slab(2, slabs.far[2]))
            * SLAB_ROBUSTNESS;
        // `max(near, t_min) <= min(far, t_max)`: a box is entered in the range when its slab
        // interval and `(t_min, t_max)` overlap. One comparison where three did it (`near <=
        // far`, `near <= t_max`, `far >= t_min`, equivalent as `t_min < t_max`); `near` itself
        // stays unclamped, so the children are ordered as before. No NaN occurs: origins and
        // bounds are finite or the empty box's ±∞, and `Slabs::new` keeps `inv_dir` finite and
        // nonzero.
        let mask = near.max(t_min).cmple(far.min(Vec4::splat(t_max)));
        (near, mask.bitmask())
    }
}

/// A ray prepared for the leaf tests: its origin and direction, and each of their coordinates
/// splatted over four lanes.
pub(crate) struct Ray {
    pub origin: Vec3A,
    pub dir: Vec3A,
    pub origin4: [Vec4; 3],
    pub dir4: [Vec4; 3],
}

impl Ray {
    /// `None` for a ray that cannot hit anything: a non-finite origin or direction, or a zero
    /// direction.
    #[inline(always)]
    pub fn new(origin: Vec3A, dir: Vec3A) -> Option<Ray> {
        // `x · 0` is 0 for a finite `x` and NaN for ±∞ or NaN, and NaN equals nothing: one
        // comparison checks all six coordinates.
        let finite = (origin * Vec3A::ZERO + dir * Vec3A::ZERO).cmpeq(Vec3A::ZERO);
        if !(finite.all() && dir.cmpne(Vec3A::ZERO).any()) {
            return None;
        }
        Some(Ray {
            origin,
            dir,
            origin4: [0, 1, 2].map(|axis| Vec4::splat(origin[axis])),
            dir4: [0, 1, 2].map(|axis| Vec4::splat(dir[axis])),
        })
    }
}

/// What the box tests need of a ray besides its origin: the reciprocal direction splatted over
/// four lanes and which side of each slab it enters first. Prepared by the traversal only when
/// the tree has a node to test: a tree that is one leaf (a scene of a few primitives) goes
/// straight to its primitives.
struct Slabs {
    inv_dir4: [Vec4; 3],
    /// Per axis, the byte offset in a node's `bounds` of the plane the ray enters the slab
    /// through (the lower bound where the direction is positive, the upper where negative),
    /// and of the one it leaves through. Offsets, not indices, so that the node loop adds
    /// them to the node's address as they are (an index would be scaled by 16 at every node:
    /// x86's addressing scales by at most 8).
    near: [usize; 3],
    far: [usize; 3],
}

impl Slabs {
    const UNUSED: Slabs = Slabs {
        inv_dir4: [Vec4::ZERO; 3],
        near: [0; 3],
        far: [0; 3],
    };

    /// A direction component below the smallest normal float (zero, say) is replaced by that
    /// float with the same sign, so the reciprocal stays finite (at most ~8.5e37) and nonzero,
    /// and the slab test's `(bound - o) · inv_dir` is never `0 · ∞ = NaN`. The slab of such an
    /// axis then spans `t` in `±δ · 8.5e37` for an origin `δ` inside it: unbounded for any
    /// practical purpose.
    #[inline(always)]
    fn new(dir: Vec3A) -> Slabs {
        let inv_dir = finite_reciprocal(dir);
        let (near, far) = slab_planes(inv_dir.is_negative_bitmask());
        Slabs {
            inv_dir4: [0, 1, 2].map(|axis| Vec4::splat(inv_dir[axis])),
            near,
            far,
        }
    }
}

/// `1 / dir` with each component's magnitude first raised to the smallest normal float, the
/// sign kept ([`Slabs::new`] says why), all three at once (no branch per axis): -0 becomes
/// -MIN_POSITIVE, and its slab is entered from the upper bound.
#[inline(always)]
pub(super) fn finite_reciprocal(dir: Vec3A) -> Vec3A {
    let tiny = Vec3A::splat(f32::MIN_POSITIVE);
    dir.abs().max(tiny).copysign(dir).recip()
}

/// [`finite_reciprocal`] of eight lanes (one axis of a packet's rays): the same operations lane
/// by lane (the magnitude raised to the smallest normal float, the sign copied back, one IEEE
/// division), so the same bits. Only for functions compiled for AVX2 (the packets'), into
/// which it is inlined.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
pub(super) fn finite_reciprocals(dir: std::arch::x86_64::__m256) -> std::arch::x86_64::__m256 {
    use std::arch::x86_64::*;
    // SAFETY: called only where AVX is enabled (see above).
    unsafe {
        let sign = _mm256_set1_ps(-0.0);
        let tiny = _mm256_set1_ps(f32::MIN_POSITIVE);
        let magnitude = _mm256_max_ps(_mm256_andnot_ps(sign, dir), tiny);
        let signed = _mm256_or_ps(_mm256_and_ps(dir, sign), _mm256_andnot_ps(sign, magnitude));
        _mm256_div_ps(_mm256_set1_ps(1.0), signed)
    }
}

/// For directions with the sign bits `negative` (bit `axis` set for a negative component),
/// per axis the byte offset in a node's `bounds` of the plane a ray enters the slab through,
/// and of the one it leaves through: the upper bound first where the component is negative.
#[inline(always)]
pub(super) fn slab_planes(negative: u32) -> ([usize; 3], [usize; 3]) {
    let offset = |axis: usize, side: u32| (2 * axis + side as usize) * size_of::<Vec4>();
    (
        [0, 1, 2].map(|axis| offset(axis, negative >> axis & 1)),
        [0, 1, 2].map(|axis| offset(axis, 1 - (negative >> axis & 1))),
    )
}

/// What the build reports about the tree's shape.
#[derive(Default)]
pub(crate) struct Shape {
    pub leaves: usize,
    pub max_depth: usize,
    pub max_leaf_size: usize,
}

pub(crate) struct Bvh {
    nodes: Vec<Node>,
    /// The root's child word and box; `None` for an empty tree.
    root: Option<(u32, Aabb)>,
}

impl Bvh {
    /// Builds the tree over `prims`, reordering them, and calls `leaf(first, run)` on each
    /// leaf's run of primitives (all of one group, at most [`MAX_LEAF_SIZE`], from
    /// `prims[first]` on) in depth-first order; `leaf` returns the payload traversal hands
    /// back, below 2³¹.
    pub fn build(
        prims: &mut [BuildPrim],
        mut leaf: impl FnMut(usize, &[BuildPrim]) -> u32,
    ) -> (Bvh, Shape) {
        let mut shape = Shape::default();
        let mut nodes = Vec::new();
        let root = (!prims.is_empty()).then(|| {
            let root = build_recursive(prims, 0, 0);
            nodes.reserve(prims.len() / 4);
            let word = collapse(&root, 0, prims, &mut nodes, &mut shape, &mut leaf);
            (word, *root.bounds())
        });
        let nodes = on_huge_pages(nodes);
        (Bvh { nodes, root }, shape)
    }

    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// The box around everything in the tree; `None` for an empty tree.
    pub fn bounds(&self) -> Option<Aabb> {
        self.root.map(|(_, bounds)| bounds)
    }

    pub fn bytes(&self) -> usize {
        self.nodes.len() * std::mem::size_of::<Node>()
    }

    /// Visits every leaf whose box the ray enters with `t` in `(t_min, t_max)` and calls
    /// `leaf(payload, &mut t_max)` on it: nearest box first when `nearest_first` (a closest
    /// hit then shrinks `t_max` early), else in the node's lane order, which spares sorting the
    /// entered children (an any-hit query, which stops at the first hit, gains nothing from
    /// the order on average). The closure may shrink `t_max`
    /// (closest hit): subtrees entered beyond it are then skipped. It returns `true` to stop
    /// (any hit), and so does `traverse`. `prefetch_leaf(payload)` is called as soon as a
    /// leaf's box is entered, before the leaf is visited (if it is), to start loading its
    /// primitives.
    #[inline(always)]
    pub fn traverse<F, P>(
        &self,
        ray: &Ray,
        t_min: f32,
        t_max: &mut f32,
        nearest_first: bool,
        mut leaf: F,
        prefetch_leaf: P,
    ) -> bool
    where
        F: FnMut(u32, &mut f32) -> bool,
        P: Fn(u32),
    {
        let Some((mut current, _)) = self.root else {
            return false;
        };
        // A tree that is one leaf (a scene of a few primitives) has no box to test: its rays
        // skip the slab preparation (and the leaf test stays inlined once, in the loop).
        let slabs = if current & LEAF == 0 {
            Slabs::new(ray.dir)
        } else {
            Slabs::UNUSED
        };
        let t_min4 = Vec4::splat(t_min);
        // Children still to visit, with the distance at which the ray enters them. Left
        // uninitialised: zeroing 1.5 KiB per ray costs as much as a small scene's traversal.
        let mut stack = [const { MaybeUninit::<(u32, f32)>::uninit() }; STACK_SIZE];
        let mut depth = 0;
        loop {
            if current & LEAF == 0 {
                // SAFETY: every interior child word was written by `collapse` as the index of
                // a node it had pushed.
                let node = unsafe { self.nodes.get_unchecked(current as usize) };
                let (near, mask) = node.hit(ray, &slabs, t_min4, *t_max);
                if mask != 0 {
                    // The entered children by count, as Embree's traversal does: one is
                    // visited at once; of two the nearer is visited and the other pushed; of
                    // three or four, all but the nearest are pushed farthest first. Without
                    // `nearest_first` the lane order stands in for the distance order.
                    let near = near.to_array();
                    let entry = |mask: u32| {
                        let lane = mask.trailing_zeros() as usize;
                        (node.child[lane], near[lane])
                    };
                    let first = entry(mask);
                    let mut rest = mask & (mask - 1);
                    if rest == 0 {
                        current = first.0;
                        continue;
                    }
                    let second = entry(rest);
                    rest &= rest - 1;
                    if rest == 0 {
                        let (visit, later) = if nearest_first && second.1 < first.1 {
                            (second, first)
                        } else {
                            (first, second)
                        };
                        self.push_child(&mut stack, &mut depth, later.0, later, &prefetch_leaf);
                        current = visit.0;
                        continue;
                    }
                    let mut entered = [first, second, entry(rest), (0, 0.0)];
                    rest &= rest - 1;
                    let count = if rest == 0 {
                        3
                    } else {
                        entered[3] = entry(rest);
                        4
                    };
                    if nearest_first {
                        sort_farthest_first(&mut entered[..count], |item| item.1);
                    }
                    for &item in &entered[..count - 1] {
                        self.push_child(&mut stack, &mut depth, item.0, item, &prefetch_leaf);
                    }
                    current = entered[count - 1].0;
                    continue;
                }
            } else if leaf(current & !LEAF, t_max) {
                return true;
            }
            // Pop the next child the ray enters before the closest hit so far.
            loop {
                if depth == 0 {
                    return false;
                }
                depth -= 1;
                // SAFETY: entries below `depth < STACK_SIZE` were all written by the pushes
                // above.
                let (child, near) = unsafe { stack.get_unchecked(depth).assume_init() };
                if near <= *t_max {
                    current = child;
                    break;
                }
            }
        }
    }
}

/// A stack entry of [`Bvh::traverse_packet`]: a child word, the rays of the packet that
/// entered it and their entry distances.
#[cfg(target_arch = "x86_64")]
type PacketEntry = (u32, u32, std::arch::x86_64::__m256);

impl Bvh {
    /// Pushes `item`, the traversal's record of child word `child`, on a traversal stack to
    /// visit later. Nearly every node of a large tree misses the caches: its loading (or the
    /// leaf's, through `prefetch_leaf`) starts now, to overlap the work on the children
    /// visited before it.
    #[inline(always)]
    fn push_child<T>(
        &self,
        stack: &mut [MaybeUninit<T>],
        depth: &mut usize,
        child: u32,
        item: T,
        prefetch_leaf: &impl Fn(u32),
    ) {
        if child & LEAF == 0 {
            prefetch(self.nodes.as_ptr().wrapping_add(child as usize), NODE_LINES);
        } else {
            prefetch_leaf(child & !LEAF);
        }
        // SAFETY: at most 3 entries wait per level of a tree at most 63 levels deep (see
        // `SAH_DEPTH_LIMIT`), so `*depth < STACK_SIZE`.
        debug_assert!(*depth < STACK_SIZE);
        unsafe { stack.get_unchecked_mut(*depth).write(item) };
        *depth += 1;
    }
}

impl Bvh {
    /// [`Bvh::traverse`] (nearest first) for the rays of `packet` set in `active`, together:
    /// each node is fetched once and its boxes tested against all of them
    /// ([`RayPacket::hit_boxes`]); a child is visited with the rays that entered it, nearest
    /// first by the entry distance of the first of those rays, and skipped when popped once
    /// none of them enters it before its `t_max`. `leaf(payload, rays, t_max)` is called on
    /// each leaf with the mask of rays that reach it; it may shrink their `t_max`. Every ray
    /// reaches every leaf it would reach alone with the final `t_max`, so the closest hit is
    /// the same (but for ties between leaves at the same `t`, found in another order).
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    pub fn traverse_packet<F, P>(
        &self,
        packet: &RayPacket,
        active: u32,
        t_min: f32,
        t_max: &mut [f32; PACKET_SIZE],
        mut leaf: F,
        prefetch_leaf: P,
    ) where
        F: FnMut(u32, u32, &mut [f32; PACKET_SIZE]),
        P: Fn(u32),
    {
        use std::arch::x86_64::*;
        let Some((mut current, _)) = self.root else {
            return;
        };
        let mut rays = active;
        // SAFETY (every intrinsic below): `RayPacket`'s module documentation.
        let t_min8 = unsafe { _mm256_set1_ps(t_min) };
        let mut stack = [const { MaybeUninit::<PacketEntry>::uninit() }; STACK_SIZE];
        let mut depth = 0;
        loop {
            if current & LEAF == 0 {
                // SAFETY: as in `traverse`.
                let node = unsafe { self.nodes.get_unchecked(current as usize) };
                let t_max8 = unsafe { _mm256_loadu_ps(t_max.as_ptr()) };
                let boxes = packet.hit_boxes(&node.bounds, t_min8, t_max8);
                let first = rays.trailing_zeros() as usize;
                // (child word, rays, their entry distances, the first active ray's)
                let mut entered = [(0, 0, t_min8, 0.0); 4];
                let mut count = 0;
                for (lane, &(near, mask)) in boxes.iter().enumerate() {
                    let mask = mask & rays;
                    if mask != 0 {
                        let mut nears = [0.0f32; PACKET_SIZE];
                        unsafe { _mm256_storeu_ps(nears.as_mut_ptr(), near) };
                        entered[count] = (node.child[lane], mask, near, nears[first]);
                        count += 1;
                    }
                }
                if count > 0 {
                    // All but the nearest wait on the stack.
                    sort_farthest_first(&mut entered[..count], |item| item.3);
                    for &(child, mask, near, _) in &entered[..count - 1] {
                        let item = (child, mask, near);
                        self.push_child(&mut stack, &mut depth, child, item, &prefetch_leaf);
                    }
                    (current, rays) = (entered[count - 1].0, entered[count - 1].1);
                    continue;
                }
            } else {
                leaf(current & !LEAF, rays, t_max);
            }
            // Pop the next child that some of its rays enter before their closest hit so far.
            loop {
                if depth == 0 {
                    return;
                }
                depth -= 1;
                // SAFETY: as in `traverse`.
                let (child, mask, near) = unsafe { stack.get_unchecked(depth).assume_init() };
                let t_max8 = unsafe { _mm256_loadu_ps(t_max.as_ptr()) };
                let before = unsafe { _mm256_cmp_ps::<_CMP_LE_OQ>(near, t_max8) };
                let mask = mask & unsafe { _mm256_movemask_ps(before) } as u32;
                if mask != 0 {
                    (current, rays) = (child, mask);
                    break;
                }
            }
        }
    }
}

impl Bvh {
    /// [`Bvh::traverse`] as an any-hit query for the rays of `packet` set in `active`,
    /// together: each node is fetched once and its boxes tested against all of them
    /// ([`ShadowPacket::hit_boxes`]); children are visited in the node's lane order, each
    /// with the rays that entered it and have not yet hit anything. `leaf(payload, rays)` is
    /// called on each leaf with the mask of rays that reach it and returns the mask of those
    /// that hit something there; they retire. Returns the mask of rays that hit, as soon as
    /// all have. A ray's range never shrinks, so it reaches every leaf it would reach alone
    /// until its first hit.
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    pub fn traverse_shadow_packet<F, P>(
        &self,
        packet: &ShadowPacket,
        active: u32,
        t_min: f32,
        t_max: &[f32; PACKET_SIZE],
        mut leaf: F,
        prefetch_leaf: P,
    ) -> u32
    where
        F: FnMut(u32, u32) -> u32,
        P: Fn(u32),
    {
        use std::arch::x86_64::*;
        let Some((mut current, _)) = self.root else {
            return 0;
        };
        // The rays still looking for a hit, and those that reach the current child.
        let (mut live, mut rays) = (active, active);
        // SAFETY (every intrinsic below): `ShadowPacket`'s module documentation.
        let t_min8 = unsafe { _mm256_set1_ps(t_min) };
        let t_max8 = unsafe { _mm256_loadu_ps(t_max.as_ptr()) };
        let mut stack = [const { MaybeUninit::<(u32, u32)>::uninit() }; STACK_SIZE];
        let mut depth = 0;
        loop {
            if current & LEAF == 0 {
                // SAFETY: as in `traverse`.
                let node = unsafe { self.nodes.get_unchecked(current as usize) };
                let boxes = packet.hit_boxes(&node.bounds, t_min8, t_max8);
                let mut entered = [(0, 0); 4];
                let mut count = 0;
                for (lane, &mask) in boxes.iter().enumerate() {
                    let mask = mask & rays;
                    if mask != 0 {
                        entered[count] = (node.child[lane], mask);
                        count += 1;
                    }
                }
                if count > 0 {
                    // The first entered is visited now, the others wait, the second on top.
                    for &(child, mask) in entered[1..count].iter().rev() {
                        let item = (child, mask);
                        self.push_child(&mut stack, &mut depth, child, item, &prefetch_leaf);
                    }
                    (current, rays) = entered[0];
                    continue;
                }
            } else {
                live &= !leaf(current & !LEAF, rays);
                if live == 0 {
                    return active;
                }
            }
            // Pop the next child that some of its rays still looking for a hit enter.
            loop {
                if depth == 0 {
                    return active & !live;
                }
                depth -= 1;
                // SAFETY: as in `traverse`.
                let (child, mask) = unsafe { stack.get_unchecked(depth).assume_init() };
                if mask & live != 0 {
                    (current, rays) = (child, mask & live);
                    break;
                }
            }
        }
    }
}

/// The binary tree, as the recursive build produces it.
enum BuildNode {
    Leaf {
        bounds: Aabb,
        start: usize,
        count: usize,
    },
    Interior {
        bounds: Aabb,
        children: Box<[BuildNode; 2]>,
    },
}

impl BuildNode {
    fn bounds(&self) -> &Aabb {
        match self {
            BuildNode::Leaf { bounds, .. } | BuildNode::Interior { bounds, .. } => bounds,
        }
    }
}

/// Builds the subtree over `prims`, which are slots `start..start + prims.len()`.
fn build_recursive(prims: &mut [BuildPrim], start: usize, depth: usize) -> BuildNode {
    let (bounds, centroids) = over_chunks(
        prims,
        || (Aabb::EMPTY, Aabb::EMPTY),
        |(b, c): &mut (Aabb, Aabb), p| (*b, *c) = (b.union(p.bounds), c.grow(p.centroid)),
        |(b0, c0), (b1, c1)| (b0.union(b1), c0.union(c1)),
    );
    let n = prims.len();
    let leaf = BuildNode::Leaf {
        bounds,
        start,
        count: n,
    };
    if n == 1 {
        return leaf;
    }
    let mid = if depth >= SAH_DEPTH_LIMIT {
        median_split(prims, &centroids)
    } else {
        match sah_split(prims, &bounds, &centroids) {
            // SAH says a leaf is cheaper, the leaf is small enough and holds one group only;
            // with several groups, split them apart.
            None if n <= MAX_LEAF_SIZE => {
                let group = prims[0].group;
                if prims.iter().all(|p| p.group == group) {
                    return leaf;
                }
                partition(prims, |p| p.group == group)
            }
            // All centroids coincide and there are too many for a leaf: split arbitrarily.
            None => median_split(prims, &centroids),
            Some(mid) => mid,
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
        children: Box::new([left, right]),
    }
}

/// Accumulates `prims` with `add` into `empty()`: in parallel chunks whose results `merge` combines
/// when there are many of them (the top levels of the tree, where the recursion has not yet
/// spread over the threads). `merge` must be associative (unions and sums are), so the result
/// does not depend on how the chunks fall.
fn over_chunks<T: Send>(
    prims: &[BuildPrim],
    empty: impl Fn() -> T + Sync + Send,
    add: impl Fn(&mut T, &BuildPrim) + Sync + Send,
    merge: impl Fn(T, T) -> T + Sync + Send,
) -> T {
    let accumulate = |chunk: &[BuildPrim]| {
        let mut acc = empty();
        for p in chunk {
            add(&mut acc, p);
        }
        acc
    };
    if prims.len() <= PARALLEL_FOLD_THRESHOLD {
        return accumulate(prims);
    }
    (prims.par_chunks(PARALLEL_FOLD_THRESHOLD / 4))
        .map(accumulate)
        .reduce(&empty, &merge)
}

/// The SAH cost weight of `n` primitives in a leaf: the number of blocks that test them.
fn blocks(n: usize) -> f32 {
    n.div_ceil(LEAF_BLOCK) as f32
}

/// The binned SAH split of Wald 2007 ("On fast construction of SAH-based bounding volume
/// hierarchies"), tried on all three axes: primitives are binned by centroid into `BINS` equal
/// slabs of the centroid bounds, and the `BINS - 1` planes between bins are scored by
///
///   cost = C_trav + (B(N_left) · A_left + B(N_right) · A_right) / A_node,
///
/// against the cost `B(N)` of a leaf, where `B(n)` counts the leaf blocks of `n` primitives
/// (one block test costs 1). Returns `mid` after partitioning `prims` so that `..mid` goes
/// left, or `None` when no split beats a leaf (or no axis has centroid extent).
fn sah_split(prims: &mut [BuildPrim], bounds: &Aabb, centroids: &Aabb) -> Option<usize> {
    let extent = centroids.extent();
    // Wald's k1 = BINS (1 - ε) / extent keeps the largest centroid in the last bin.
    let scale = Vec3A::splat(BINS as f32 * (1.0 - 1e-5)) / extent;
    let bin_of = |p: &BuildPrim, axis: usize| -> usize {
        let k = ((p.centroid[axis] - centroids.min[axis]) * scale[axis]) as usize;
        k.min(BINS - 1)
    };

    // Per axis and bin: how many centroids fall in it, and the box around their primitives.
    type Bins = ([[usize; BINS]; 3], [[Aabb; BINS]; 3]);
    let empty_bins = || -> Bins { ([[0; BINS]; 3], [[Aabb::EMPTY; BINS]; 3]) };
    let (counts, boxes) = over_chunks(
        prims,
        empty_bins,
        |(counts, boxes): &mut Bins, p| {
            for axis in 0..3 {
                if extent[axis] > 0.0 {
                    let k = bin_of(p, axis);
                    counts[axis][k] += 1;
                    boxes[axis][k] = boxes[axis][k].union(p.bounds);
                }
            }
        },
        |(mut counts, mut boxes), (more_counts, more_boxes)| {
            for axis in 0..3 {
                for k in 0..BINS {
                    counts[axis][k] += more_counts[axis][k];
                    boxes[axis][k] = boxes[axis][k].union(more_boxes[axis][k]);
                }
            }
            (counts, boxes)
        },
    );

    let mut best: Option<(f32, usize, usize)> = None;
    for axis in (0..3).filter(|&axis| extent[axis] > 0.0) {
        // Sweep right to left for the areas and counts to the right of each plane, then left to
        // right scoring plane k (between bins k and k + 1).
        let mut right_cost = [0.0f32; BINS];
        let (mut b, mut c) = (Aabb::EMPTY, 0);
        for k in (1..BINS).rev() {
            b = b.union(boxes[axis][k]);
            c += counts[axis][k];
            right_cost[k - 1] = blocks(c) * b.surface_area();
        }
        let (mut b, mut c) = (Aabb::EMPTY, 0);
        for k in 0..BINS - 1 {
            b = b.union(boxes[axis][k]);
            c += counts[axis][k];
            let cost = blocks(c) * b.surface_area() + right_cost[k];
            if best.is_none_or(|(best_cost, ..)| cost < best_cost) {
                best = Some((cost, axis, k));
            }
        }
    }

    let (cost, axis, k) = best?;
    let area = bounds.surface_area();
    let split_cost = TRAVERSAL_COST + if area > 0.0 { cost / area } else { 0.0 };
    if prims.len() <= MAX_LEAF_SIZE && blocks(prims.len()) <= split_cost {
        return None;
    }
    let mid = partition(prims, |p| bin_of(p, axis) <= k);
    // The first bin and the last are both occupied, so neither side is empty.
    (mid > 0 && mid < prims.len()).then_some(mid)
}

/// Splits at the median centroid on the axis of largest centroid extent.
fn median_split(prims: &mut [BuildPrim], centroids: &Aabb) -> usize {
    let axis = centroids.extent().max_position();
    let mid = prims.len() / 2;
    prims.select_nth_unstable_by(mid, |a, b| a.centroid[axis].total_cmp(&b.centroid[axis]));
    mid
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

/// Appends `node`'s subtree as four-wide nodes, depth-first, and returns its child word.
///
/// A binary node becomes one wide node whose children are found by opening, up to four, the
/// interior child of largest surface area (the one a random ray most likely enters): the
/// collapse of Wald et al. 2008, "Getting rid of packets".
fn collapse(
    node: &BuildNode,
    depth: usize,
    prims: &[BuildPrim],
    nodes: &mut Vec<Node>,
    shape: &mut Shape,
    leaf: &mut impl FnMut(usize, &[BuildPrim]) -> u32,
) -> u32 {
    match node {
        BuildNode::Leaf { start, count, .. } => {
            shape.leaves += 1;
            shape.max_depth = shape.max_depth.max(depth);
            shape.max_leaf_size = shape.max_leaf_size.max(*count);
            let payload = leaf(*start, &prims[*start..start + count]);
            debug_assert!(payload < LEAF);
            LEAF | payload
        }
        BuildNode::Interior { children, .. } => {
            let mut kids: Vec<&BuildNode> = children.iter().collect();
            while kids.len() < 4 {
                let largest = (kids.iter().enumerate())
                    .filter(|(_, kid)| matches!(kid, BuildNode::Interior { .. }))
                    .max_by(|a, b| {
                        let area = |kid: &BuildNode| kid.bounds().surface_area();
                        area(a.1).total_cmp(&area(b.1))
                    })
                    .map(|(i, _)| i);
                let Some(i) = largest else { break };
                let BuildNode::Interior { children, .. } = kids.swap_remove(i) else {
                    unreachable!("filtered to interior nodes")
                };
                kids.extend(children.iter());
            }
            let index = nodes.len();
            nodes.push(Node::EMPTY);
            for (lane, kid) in kids.into_iter().enumerate() {
                let child = collapse(kid, depth + 1, prims, nodes, shape, leaf);
                nodes[index].set(lane, kid.bounds(), child);
            }
            index as u32
        }
    }
}

/// Insertion sort by `key`, largest first: a node's entered children (at most four), so that
/// the nearest is taken now and the others are pushed farthest first.
#[inline(always)]
fn sort_farthest_first<T: Copy>(items: &mut [T], key: impl Fn(&T) -> f32) {
    for k in 1..items.len() {
        let item = items[k];
        let mut i = k;
        while i > 0 && key(&items[i - 1]) < key(&item) {
            items[i] = items[i - 1];
            i -= 1;
        }
        items[i] = item;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn prims(n: usize) -> Vec<BuildPrim> {
        // A deterministic scatter of small boxes with clustered, repeated and spread centroids,
        // in two groups.
        (0..n)
            .map(|i| {
                let c = Vec3A::new(
                    (i % 7) as f32,
                    (i * i % 13) as f32,
                    1.1f32.powi((i % 50) as i32),
                );
                let bounds = Aabb::from_points([c, c + Vec3A::splat(0.5)]);
                BuildPrim::new(bounds, i as u32, (i % 3 == 0) as u32)
            })
            .collect()
    }

    fn lane_box(node: &Node, lane: usize) -> Aabb {
        let corner = |side: usize| {
            Vec3A::new(
                node.bounds[side][lane],
                node.bounds[2 + side][lane],
                node.bounds[4 + side][lane],
            )
        };
        Aabb {
            min: corner(0),
            max: corner(1),
        }
    }

    fn contains(outer: &Aabb, inner: &Aabb) -> bool {
        inner.min.cmpge(outer.min).all() && inner.max.cmple(outer.max).all()
    }

    /// Every lane's box bounds its subtree, every leaf holds one group, the leaves partition
    /// the primitives and hand back their payloads, and nodes are mostly full.
    #[test]
    fn wide_tree_is_consistent() {
        let mut p = prims(5000);
        let mut leaves = Vec::new();
        let (bvh, shape) = Bvh::build(&mut p, |_, run| {
            leaves.push(run.to_vec());
            (leaves.len() - 1) as u32
        });
        let mut covered = vec![0u32; p.len()];
        // (child word, the box its parent's lane gives it)
        let mut stack = vec![(bvh.root.unwrap().0, bvh.bounds().unwrap())];
        let mut used_lanes = 0;
        while let Some((child, bounds)) = stack.pop() {
            if child & LEAF != 0 {
                let run = &leaves[(child & !LEAF) as usize];
                assert!(run.len() <= MAX_LEAF_SIZE);
                assert!(run.iter().all(|q| q.group == run[0].group));
                for q in run {
                    assert!(contains(&bounds, &q.bounds));
                    covered[q.id as usize] += 1;
                }
            } else {
                let node = &bvh.nodes[child as usize];
                for lane in 0..4 {
                    let b = lane_box(node, lane);
                    if b.min.x <= b.max.x {
                        assert!(contains(&bounds, &b));
                        used_lanes += 1;
                        stack.push((node.child[lane], b));
                    }
                }
            }
        }
        assert!(covered.iter().all(|&c| c == 1));
        assert_eq!(shape.leaves, leaves.len());
        // n nodes hold n - 1 nodes and all leaves; a binary tree would use 2 of 4 lanes.
        assert_eq!(used_lanes, bvh.node_count() - 1 + shape.leaves);
        assert!(
            used_lanes * 10 >= bvh.node_count() * 4 * 6,
            "lanes {used_lanes}"
        );
    }

    /// A ray reaches exactly the leaves whose box its range `(t_min, t_max)` overlaps: none
    /// wholly before `t_min` or after `t_max` (they cost work and can hold no hit in range),
    /// and every one that overlaps it (else hits would be lost). Boxes along a line, every
    /// fourth one off it, and ranges starting and ending inside boxes and in the gaps (one wholly in a gap).
    #[test]
    fn rays_reach_the_leaves_their_range_overlaps() {
        let mut p: Vec<BuildPrim> = (0..200)
            .map(|i| {
                let x = i as f32;
                let y = if i % 4 == 3 { 5.0 } else { 0.0 };
                let b =
                    Aabb::from_points([Vec3A::new(x, y, 0.0), Vec3A::new(x + 0.5, y + 1.0, 1.0)]);
                BuildPrim::new(b, i, 0)
            })
            .collect();
        let mut leaves = Vec::new();
        let (bvh, _) = Bvh::build(&mut p, |_, run| {
            leaves.push(run.iter().fold(Aabb::EMPTY, |b, q| b.union(q.bounds)));
            (leaves.len() - 1) as u32
        });
        // Along +x through the boxes on the line, from x = -1: `t` is x + 1.
        let ray = Ray::new(Vec3A::new(-1.0, 0.5, 0.5), Vec3A::X).unwrap();
        let mut checked = 0;
        let ranges = [
            (0.0, 300.0),
            (10.2, 20.7),
            (30.0, 31.0),
            (50.75, 90.25),
            (40.6, 40.9),
        ];
        for (t_min, t_max) in ranges {
            let mut reached = vec![false; leaves.len()];
            let mut t = t_max;
            bvh.traverse(
                &ray,
                t_min,
                &mut t,
                true,
                |payload, _| {
                    reached[payload as usize] = true;
                    false
                },
                |_| {},
            );
            for (leaf, bounds) in leaves.iter().enumerate() {
                let on_line = bounds.min.y <= 0.5 && bounds.max.y >= 0.5;
                let (enter, exit) = (bounds.min.x + 1.0, bounds.max.x + 1.0);
                let overlaps = on_line && enter <= t_max && exit >= t_min;
                assert_eq!(
                    reached[leaf], overlaps,
                    "leaf {leaf} for ({t_min}, {t_max})"
                );
                checked += overlaps as usize;
            }
        }
        assert!(checked > 20, "{checked}");
    }

    /// Past the SAH depth limit every split halves the count, so a subtree over `n` primitives
    /// adds at most `ceil(log2 n)` levels: the bound the traversal stack relies on.
    #[test]
    fn median_splits_past_the_depth_limit_halve() {
        let mut p = prims(1000);
        let root = build_recursive(&mut p, 0, SAH_DEPTH_LIMIT);
        let mut shape = Shape::default();
        collapse(
            &root,
            SAH_DEPTH_LIMIT,
            &p,
            &mut Vec::new(),
            &mut shape,
            &mut |_, _| 0,
        );
        assert!(
            shape.max_depth <= SAH_DEPTH_LIMIT + 10,
            "depth {}",
            shape.max_depth
        );
    }
}
