//! A light BVH: next-event estimation's choice among many lights, made in proportion to an
//! estimate of each light's contribution at the shading point rather than one table for the
//! whole scene (Conty Estevez and Kulla 2018, "Importance Sampling of Many Lights with Adaptive
//! Tree Splitting"; pbrt-v4 §12.6.3, `BVHLightSampler`). Each node bounds its lights' positions,
//! the directions they emit in and their power; a sample walks down from the root, taking each
//! child with probability proportional to its importance at the point, so a light's probability
//! is the product of its ancestors' choices. The tree is built binary by pbrt-v4's split search
//! and stored 4-wide, each node's four importances computed in one pass over SIMD lanes.
//!
//! Unlike pbrt-v4, importance ignores the receiving surface's normal: the light's probability is
//! needed again where a BSDF-sampled ray hits it (for the MIS weight), and the path keeps only
//! the position of the vertex it scattered from.

use std::f32::consts::{FRAC_PI_2, PI};

use glam::{Vec3, Vec3A, Vec4};

use crate::accel::Aabb;
use crate::sampling::ONE_MINUS_EPSILON;

/// What a node knows of the lights under it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightBounds {
    /// The box that holds the lights.
    pub(crate) bounds: Aabb,
    /// Axis of the cone that holds every emitting surface's normal (any unit vector when the
    /// cone is the whole sphere).
    pub axis: Vec3,
    /// cos theta_o: the half-angle of that cone of normals.
    pub cos_normals: f32,
    /// cos theta_e: how far from its normal each surface emits (pi / 2 for a one-sided
    /// emitter: cos 0).
    pub cos_emission: f32,
    /// Emitted power (luminance), the importance's scale.
    pub power: f32,
}

impl LightBounds {
    /// A light at one point that shines every way (a point light).
    pub fn point(position: Vec3, power: f32) -> Self {
        Self {
            bounds: Aabb::from_points([position.into()]),
            axis: Vec3::Z,
            cos_normals: -1.0,
            cos_emission: 0.0,
            power,
        }
    }

    /// The bounds of two nodes: their boxes' union, a cone holding both cones, the wider
    /// emission angle and the summed power (pbrt-v4's `Union(LightBounds, LightBounds)`).
    pub fn union(&self, other: &Self) -> Self {
        if self.power <= 0.0 {
            return *other;
        }
        if other.power <= 0.0 {
            return *self;
        }
        let (axis, cos_normals) = cone_union(
            (self.axis, self.cos_normals),
            (other.axis, other.cos_normals),
        );
        Self {
            bounds: self.bounds.union(other.bounds),
            axis,
            cos_normals,
            cos_emission: self.cos_emission.min(other.cos_emission),
            power: self.power + other.power,
        }
    }

    fn centroid(&self) -> Vec3 {
        self.bounds.centroid().into()
    }

    /// The cost of a node with these bounds in the build's split search (pbrt-v4's
    /// `EvaluateCost`, Conty Estevez and Kulla's orientation-weighted SAH): power times the
    /// solid-angle measure M_Omega of the directions the node may emit in, times the box's
    /// surface area, times the box's aspect along the split axis `axis` of `extent` (favouring
    /// cuts across long boxes).
    fn cost(&self, extent: Vec3A, axis: usize) -> f32 {
        let theta_o = self.cos_normals.clamp(-1.0, 1.0).acos();
        let theta_e = self.cos_emission.clamp(-1.0, 1.0).acos();
        let theta_w = (theta_o + theta_e).min(PI);
        let sin_o = theta_o.sin();
        // The integral of cos(theta') over the directions within theta_w of the axis, theta'
        // clamped as in [`ChildBounds::importance`] (Conty Estevez and Kulla,
        // eq. 1).
        let m_omega = 2.0 * PI * (1.0 - self.cos_normals)
            + FRAC_PI_2
                * (2.0 * theta_w * sin_o - (theta_o - 2.0 * theta_w).cos() - 2.0 * theta_o * sin_o
                    + self.cos_normals);
        let aspect = extent.max_element() / extent[axis];
        self.power * m_omega * aspect * self.bounds.surface_area()
    }
}

/// The bounds of a node's (up to) four children, lane by lane (a missing child's lane has no
/// power), as [`ChildBounds::importance`] reads them: each box as its bounding sphere,
/// theta_o's sine beside its cosine.
#[derive(Clone, Copy, Debug)]
struct ChildBounds {
    centre: [Vec4; 3],
    radius: Vec4,
    radius_squared: Vec4,
    axis: [Vec4; 3],
    cos_normals: Vec4,
    sin_normals: Vec4,
    cos_emission: Vec4,
    power: Vec4,
}

impl ChildBounds {
    /// Lane k from `children[k]`; a missing child has no power.
    fn new(children: [Option<&LightBounds>; 4]) -> Self {
        let lanes =
            |f: &dyn Fn(&LightBounds) -> f32| Vec4::from_array(children.map(|c| c.map_or(0.0, f)));
        let coordinate = |f: &dyn Fn(&LightBounds) -> Vec3| {
            [0, 1, 2].map(|axis| lanes(&|b: &LightBounds| f(b)[axis]))
        };
        Self {
            centre: coordinate(&|b| b.centroid()),
            radius: lanes(&|b| b.bounds.extent().length() * 0.5),
            radius_squared: lanes(&|b| b.bounds.extent().length_squared() * 0.25),
            axis: coordinate(&|b| b.axis),
            cos_normals: lanes(&|b| b.cos_normals),
            sin_normals: lanes(&|b| (1.0 - b.cos_normals * b.cos_normals).max(0.0).sqrt()),
            cos_emission: lanes(&|b| b.cos_emission),
            power: lanes(&|b| b.power),
        }
    }

    /// Each child's importance at `p`: an upper bound of the light its lights send to `p`, up
    /// to a common factor, power * cos theta' / d^2 (pbrt-v4's `LightBounds::Importance`
    /// without the receiver's cosine). d is the distance to the box's centre, clamped below at
    /// the radius of the box's bounding sphere; theta' the smallest angle any emitter in the box
    /// can make with the direction to `p`: the angle theta_w from the cone's axis to `p`, less
    /// the cone's half-angle theta_o and less theta_b, the half-angle the bounding sphere
    /// subtends from `p`, each clamped at 0. Zero when theta' exceeds the emission angle
    /// theta_e (no emitter in the box faces `p`), and where the arithmetic fails (`p` at a point
    /// light).
    #[inline]
    fn importance(&self, p: Vec3) -> Vec4 {
        let [cx, cy, cz] = self.centre;
        let (dx, dy, dz) = (
            Vec4::splat(p.x) - cx,
            Vec4::splat(p.y) - cy,
            Vec4::splat(p.z) - cz,
        );
        let distance_squared = dx * dx + dy * dy + dz * dz;
        let r2 = self.radius_squared;
        let inverse_distance = Vec4::ONE / distance_squared.sqrt();
        // Inside the bounding sphere every direction may reach p: theta_b = pi.
        let inside = distance_squared.cmple(r2);
        let sin_b = self.radius * inverse_distance;
        let sin_b = Vec4::select(inside, Vec4::ZERO, sin_b);
        let cos_b = (Vec4::ONE - sin_b * sin_b).max(Vec4::ZERO).sqrt();
        let cos_b = Vec4::select(inside, Vec4::NEG_ONE, cos_b);
        let [ax, ay, az] = self.axis;
        let cos_w = (ax * dx + ay * dy + az * dz) * inverse_distance;
        let sin_w = (Vec4::ONE - cos_w * cos_w).max(Vec4::ZERO).sqrt();
        // theta_x = max(theta_w - theta_o, 0), then theta' = max(theta_x - theta_b, 0), each
        // difference's cosine and sine from the angles' (cos(a - b) = cos a cos b + sin a sin b).
        let (cos_o, sin_o) = (self.cos_normals, self.sin_normals);
        let within_o = cos_w.cmpge(cos_o);
        let sin_x = Vec4::select(within_o, Vec4::ZERO, sin_w * cos_o - cos_w * sin_o);
        let cos_x = Vec4::select(within_o, Vec4::ONE, cos_w * cos_o + sin_w * sin_o);
        let within_b = cos_x.cmpge(cos_b);
        let cos_prime = Vec4::select(within_b, Vec4::ONE, cos_x * cos_b + sin_x * sin_b);
        // A cone of every direction (a point light, a sphere) makes theta' 0.
        let cos_prime = Vec4::select(cos_o.cmple(Vec4::NEG_ONE), Vec4::ONE, cos_prime);
        let importance = self.power * cos_prime / distance_squared.max(r2);
        // False for NaN as well.
        let counts = cos_prime.cmpgt(self.cos_emission)
            & importance.cmpgt(Vec4::ZERO)
            & importance.cmplt(Vec4::INFINITY);
        Vec4::select(counts, importance, Vec4::ZERO)
    }
}

/// The smallest cone found by pbrt-v4's `Union(DirectionCone, DirectionCone)` that holds both
/// cones (axis, cos half-angle): if one holds the other, that one; else the cone whose edges
/// touch both, its axis turned from `a`'s towards `b`'s.
fn cone_union((axis_a, cos_a): (Vec3, f32), (axis_b, cos_b): (Vec3, f32)) -> (Vec3, f32) {
    let theta_a = cos_a.clamp(-1.0, 1.0).acos();
    let theta_b = cos_b.clamp(-1.0, 1.0).acos();
    let theta_d = axis_a.angle_between(axis_b);
    if (theta_d + theta_b).min(PI) <= theta_a {
        return (axis_a, cos_a);
    }
    if (theta_d + theta_a).min(PI) <= theta_b {
        return (axis_b, cos_b);
    }
    let theta_o = (theta_a + theta_d + theta_b) / 2.0;
    let turn = axis_a.cross(axis_b);
    if theta_o >= PI || turn.length_squared() == 0.0 {
        return (axis_a, -1.0);
    }
    let rotation = glam::Quat::from_axis_angle(turn.normalize(), theta_o - theta_a);
    ((rotation * axis_a).normalize(), theta_o.cos())
}
/// A node: its children's bounds and what each is. A binary tree built by the split search is
/// stored with each node holding its children's children (4-wide, as a BVH4 collapses a
/// BVH2): half the levels, each level's importances one pass over four lanes.
#[derive(Clone, Debug)]
struct Node {
    bounds: ChildBounds,
    children: [Child; 4],
}

#[derive(Clone, Copy, Debug)]
enum Child {
    Light(u32),
    Node(u32),
    Empty,
}

/// The binary tree as the build makes it, before it is stored 4-wide.
enum Subtree {
    Light(u32, LightBounds),
    Split(Box<Subtree>, Box<Subtree>, LightBounds),
}

impl Subtree {
    fn bounds(&self) -> &LightBounds {
        match self {
            Subtree::Light(_, bounds) | Subtree::Split(_, _, bounds) => bounds,
        }
    }

    /// Its children and, for a split, their children in place of them: up to four.
    fn grandchildren(&self) -> Vec<&Subtree> {
        match self {
            Subtree::Light(..) => vec![self],
            Subtree::Split(a, b, _) => [a, b]
                .into_iter()
                .flat_map(|child| match child.as_ref() {
                    Subtree::Split(c, d, _) => vec![c.as_ref(), d.as_ref()],
                    light => vec![light],
                })
                .collect(),
        }
    }
}

/// Lights in a 4-wide tree, sampled by importance at a point.
#[derive(Clone, Debug)]
pub struct LightBvh {
    /// The root first.
    nodes: Vec<Node>,
    /// Per light (the index `new` was given it at): the root-to-leaf path, two bits per step
    /// (the child taken), and its length; `None` for a light of no power.
    trails: Vec<Option<(u128, u32)>>,
}

/// Buckets the split search sorts centroids into per axis (pbrt-v4's 12).
const BUCKETS: usize = 12;
/// Beyond this depth the build splits at the median, so no trail is longer than 64 steps.
const MEDIAN_SPLITS_FROM: u32 = 40;

impl LightBvh {
    /// The tree over `lights` (bounds per light; lights of no power are left out). `None` if
    /// none has power.
    pub fn new(lights: &[LightBounds]) -> Option<Self> {
        let mut items: Vec<(u32, LightBounds)> = (0..lights.len() as u32)
            .zip(lights.iter().copied())
            .filter(|(_, b)| b.power > 0.0 && b.power.is_finite())
            .collect();
        if items.is_empty() {
            return None;
        }
        let root = build(&mut items, 0);
        let mut bvh = Self {
            nodes: Vec::with_capacity(items.len()),
            trails: vec![None; lights.len()],
        };
        bvh.store(&root, 0, 0);
        Some(bvh)
    }

    /// Stores `subtree` as a node whose path from the root is `trail` (`depth` steps);
    /// returns its index.
    fn store(&mut self, subtree: &Subtree, trail: u128, depth: u32) -> u32 {
        let index = self.nodes.len();
        let children = subtree.grandchildren();
        let mut bounds = [None; 4];
        for (lane, child) in children.iter().enumerate() {
            bounds[lane] = Some(child.bounds());
        }
        self.nodes.push(Node {
            bounds: ChildBounds::new(bounds),
            children: [Child::Empty; 4],
        });
        for (lane, child) in children.into_iter().enumerate() {
            let child_trail = trail | (lane as u128) << (2 * depth);
            self.nodes[index].children[lane] = match child {
                Subtree::Light(light, _) => {
                    self.trails[*light as usize] = Some((child_trail, depth + 1));
                    Child::Light(*light)
                }
                split => Child::Node(self.store(split, child_trail, depth + 1)),
            };
        }
        index as u32
    }

    /// Chooses a light for `p` with the uniform number `u`: (light, probability), or `None`
    /// where no light in the tree can reach `p`.
    pub fn sample(&self, p: Vec3, mut u: f32) -> Option<(u32, f32)> {
        let (mut node, mut probability) = (&self.nodes[0], 1.0);
        loop {
            let shares = child_probabilities(node, p)?.to_array();
            // The child whose share of [0, 1) holds u (the last one with a share, should
            // rounding leave u past them all), and u rescaled to [0, 1) within that share.
            let (mut chosen, mut last, mut below) = (None, (0, 0.0), 0.0);
            for (k, &share) in shares.iter().enumerate() {
                if share > 0.0 {
                    if u < below + share {
                        chosen = Some((k, below));
                        break;
                    }
                    last = (k, below);
                    below += share;
                }
            }
            let (lane, below) = chosen.unwrap_or(last);
            let share = shares[lane];
            probability *= share;
            match node.children[lane] {
                Child::Light(light) => return Some((light, probability)),
                Child::Node(index) => node = &self.nodes[index as usize],
                Child::Empty => return None,
            }
            u = ((u - below) / share).clamp(0.0, ONE_MINUS_EPSILON);
        }
    }

    /// The probability that `sample` at `p` chooses `light`: the same products along its trail,
    /// in the same order, so the same bits as `sample` gives.
    pub fn probability(&self, light: usize, p: Vec3) -> f32 {
        let Some(Some((trail, depth))) = self.trails.get(light) else {
            return 0.0;
        };
        let (mut node, mut probability) = (&self.nodes[0], 1.0);
        for step in 0..*depth {
            let Some(shares) = child_probabilities(node, p) else {
                return 0.0;
            };
            let lane = (trail >> (2 * step) & 3) as usize;
            probability *= shares[lane];
            if let Child::Node(index) = node.children[lane] {
                node = &self.nodes[index as usize];
            }
        }
        probability
    }
}

/// Builds the binary tree over `items` (at least one) at `depth`.
fn build(items: &mut [(u32, LightBounds)], depth: u32) -> Subtree {
    if let [(light, bounds)] = items {
        return Subtree::Light(*light, *bounds);
    }
    let mid = if depth < MEDIAN_SPLITS_FROM {
        split_by_cost(items)
    } else {
        None
    }
    .unwrap_or_else(|| split_at_median(items));
    let (first, second) = items.split_at_mut(mid);
    let (a, b) = (build(first, depth + 1), build(second, depth + 1));
    let bounds = a.bounds().union(b.bounds());
    Subtree::Split(Box::new(a), Box::new(b), bounds)
}

/// The probabilities of a node's children at `p`, in proportion to their importance; `None`
/// if none can reach `p`.
#[inline]
fn child_probabilities(node: &Node, p: Vec3) -> Option<Vec4> {
    let importance = node.bounds.importance(p);
    let total = importance.element_sum();
    (total > 0.0).then(|| importance / total)
}

/// Reorders `items` for the cheapest split by [`LightBounds::cost`] among the bucket
/// boundaries along each axis of the centroids' box; returns where the second part starts, or
/// `None` when no split has a finite positive cost (centroids that coincide, or boxes and
/// cones of no measure).
fn split_by_cost(items: &mut [(u32, LightBounds)]) -> Option<usize> {
    let extent = (items.iter())
        .fold(Aabb::EMPTY, |bounds, (_, b)| bounds.union(b.bounds))
        .extent();
    let Aabb {
        min: low,
        max: high,
    } = centroid_bounds(items);
    let bucket_of = |b: &LightBounds, axis: usize| {
        let t = (b.centroid()[axis] - low[axis]) / (high[axis] - low[axis]);
        ((t * BUCKETS as f32) as usize).min(BUCKETS - 1)
    };
    let mut best: Option<(f32, usize, usize)> = None;
    for axis in 0..3 {
        if high[axis] <= low[axis] || extent[axis] <= 0.0 {
            continue;
        }
        let mut buckets: [Option<LightBounds>; BUCKETS] = [None; BUCKETS];
        for (_, b) in items.iter() {
            let bucket = &mut buckets[bucket_of(b, axis)];
            *bucket = Some(bucket.map_or(*b, |u| u.union(b)));
        }
        let merge = |range: &[Option<LightBounds>]| {
            range
                .iter()
                .flatten()
                .fold(None, |acc: Option<LightBounds>, b| {
                    Some(acc.map_or(*b, |a| a.union(b)))
                })
        };
        for split in 1..BUCKETS {
            let (Some(a), Some(b)) = (merge(&buckets[..split]), merge(&buckets[split..])) else {
                continue;
            };
            let cost = a.cost(extent, axis) + b.cost(extent, axis);
            if cost.is_finite() && cost > 0.0 && best.is_none_or(|(c, ..)| cost < c) {
                best = Some((cost, axis, split));
            }
        }
    }
    let (_, axis, split) = best?;
    items.sort_by_key(|(_, b)| bucket_of(b, axis) >= split);
    let mid = items.partition_point(|(_, b)| bucket_of(b, axis) < split);
    (0 < mid && mid < items.len()).then_some(mid)
}

/// The box of the lights' centroids.
fn centroid_bounds(items: &[(u32, LightBounds)]) -> Aabb {
    Aabb::from_points(items.iter().map(|(_, b)| b.bounds.centroid()))
}

/// Sorts `items` by centroid along the axis of their centroids' widest spread and returns the
/// middle.
fn split_at_median(items: &mut [(u32, LightBounds)]) -> usize {
    let axis = centroid_bounds(items).extent().max_position();
    items.sort_by(|(_, a), (_, b)| a.centroid()[axis].total_cmp(&b.centroid()[axis]));
    items.len() / 2
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A one-sided square lamp of side `size` at `centre`, facing `normal`.
    fn lamp(centre: Vec3, normal: Vec3, size: f32, power: f32) -> LightBounds {
        let half = Vec3::splat(size / 2.0) * (Vec3::ONE - normal.abs());
        LightBounds {
            bounds: Aabb::from_points([(centre - half).into(), (centre + half).into()]),
            axis: normal,
            cos_normals: 1.0,
            cos_emission: 0.0,
            power,
        }
    }

    /// A grid of lamps facing down over the plane z = 0, of differing power.
    fn ceiling() -> Vec<LightBounds> {
        (0..64)
            .map(|i| {
                let (x, y) = ((i % 8) as f32, (i / 8) as f32);
                lamp(
                    Vec3::new(x, y, 2.0 + 0.1 * (i % 3) as f32),
                    Vec3::NEG_Z,
                    0.2,
                    1.0 + (i % 5) as f32,
                )
            })
            .collect()
    }

    /// The choice's probabilities sum to one over the lights at points where some light
    /// reaches, `probability` gives `sample`'s probability to the bit, and each light is chosen
    /// as often as its probability says (4,096 stratified draws: a light's count is within 5
    /// standard deviations of binomial noise, plus one for the stratification).
    #[test]
    fn sampling_matches_its_probabilities() {
        let lights = ceiling();
        let bvh = LightBvh::new(&lights).unwrap();
        for p in [
            Vec3::new(3.3, 4.1, 0.0),
            Vec3::new(-2.0, 9.0, 1.0),
            Vec3::new(0.0, 0.0, 1.99),
        ] {
            let total: f32 = (0..lights.len()).map(|i| bvh.probability(i, p)).sum();
            assert!((total - 1.0).abs() < 1e-4, "{p}: {total}");
            let draws = 4096;
            let mut counts = vec![0u32; lights.len()];
            for k in 0..draws {
                let u = (k as f32 + 0.5) / draws as f32;
                let (light, probability) = bvh.sample(p, u).unwrap();
                assert_eq!(
                    probability.to_bits(),
                    bvh.probability(light as usize, p).to_bits()
                );
                counts[light as usize] += 1;
            }
            for (light, &count) in counts.iter().enumerate() {
                let expected = bvh.probability(light, p) as f64 * draws as f64;
                let sigma = (expected * (1.0 - expected / draws as f64)).sqrt();
                assert!(
                    (count as f64 - expected).abs() <= 5.0 * sigma + 1.0,
                    "{p} light {light}: {count} of {draws}, expected {expected:.1}"
                );
            }
        }
    }

    /// A point above the lamps, which face down, gets no light from any: no choice, and
    /// probability 0 for each.
    #[test]
    fn lamps_facing_away_are_never_chosen() {
        let lights = ceiling();
        let bvh = LightBvh::new(&lights).unwrap();
        let above = Vec3::new(3.5, 3.5, 5.0);
        assert_eq!(bvh.sample(above, 0.3), None);
        assert!((0..lights.len()).all(|i| bvh.probability(i, above) == 0.0));
    }

    /// Near one lamp the choice favours it over the far ones: under lamp 27, whose importance
    /// power / d^2 is 3 / 4 (its neighbours' 0.4 to 1), its probability is at least twice the
    /// uniform 1 / 64, and lamp 63 in the far corner (5 / 36.5 = 0.137 of importance) gets less
    /// than a third of it. The tree's nodes bound their lights' importance loosely, so their
    /// choice is no exact match of the importances: these are margins, not ratios.
    #[test]
    fn a_near_lamp_is_chosen_over_far_ones() {
        let lights = ceiling();
        let bvh = LightBvh::new(&lights).unwrap();
        let under = lights[27].centroid() * Vec3::new(1.0, 1.0, 0.0);
        let near = bvh.probability(27, under);
        assert!(near > 2.0 / 64.0, "{near}");
        let far = bvh.probability(63, under);
        assert!(far < near / 3.0, "{far} vs {near}");
    }

    /// The union of two cones holds both: each input cone's edge lies within it.
    #[test]
    fn cone_union_holds_both() {
        let cones = [
            (Vec3::Z, 0.9f32),
            (Vec3::X, 1.0),
            (Vec3::new(0.0, 0.6, -0.8), 0.5),
            (Vec3::NEG_Z, 1.0),
        ];
        for a in cones {
            for b in cones {
                let (axis, cos) = cone_union(a, b);
                for (w, c) in [a, b] {
                    // The cone (w, c) lies within (axis, cos) if angle(axis, w) + acos(c)
                    // <= acos(cos).
                    let spread = axis.angle_between(w) + c.clamp(-1.0, 1.0).acos();
                    assert!(
                        cos <= -1.0 + 1e-6 || spread <= cos.clamp(-1.0, 1.0).acos() + 1e-4,
                        "{a:?} {b:?} -> {axis} {cos}"
                    );
                }
            }
        }
    }
}
