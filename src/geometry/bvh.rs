//! The bounding volume hierarchy: a binned-SAH build over every primitive
//! (triangles and spheres alike), flattened into 32-byte nodes in
//! depth-first order, traversed with an explicit stack, near child first.
//! `intersect` finds the closest hit; `transmittance` is the any-hit query
//! for shadow rays, which multiplies in what each surface lets through.

use glam::{Vec3, Vec3A, Vec4};
use rayon::prelude::*;

use super::aabb::ROBUST;
use super::shapes::RayPre;
use super::{Aabb, Hit, Ray, Shape};

const BINS: usize = 16;
const MAX_LEAF: usize = 8;
/// Cost of a traversal step relative to one primitive test.
const TRAVERSAL_COST: f32 = 1.0;

/// A flattened node: a leaf holds `count > 0` primitives from `offset`; an
/// interior node's first child follows it and its second is at `offset`.
/// The bounds sit in two SIMD lanes-of-four whose spare fourth lanes carry
/// `offset` and `count`, encoded as normal (not denormal) floats so the
/// slab test's arithmetic on those lanes stays fast.
#[derive(Clone, Copy, Debug)]
struct Node {
    lo: Vec4,
    hi: Vec4,
}

const TAG: u32 = 0x4000_0000;

impl Node {
    fn new(bounds: Aabb, offset: u32, count: u32) -> Node {
        debug_assert!(offset < 1 << 29 && count < 1 << 29);
        Node {
            lo: bounds.min.extend(f32::from_bits(TAG | offset)),
            hi: bounds.max.extend(f32::from_bits(TAG | count)),
        }
    }

    #[inline(always)]
    fn offset(&self) -> u32 {
        self.lo.w.to_bits() & !TAG
    }

    #[inline(always)]
    fn count(&self) -> u32 {
        self.hi.w.to_bits() & !TAG
    }

    fn set_offset(&mut self, offset: u32) {
        self.lo.w = f32::from_bits(TAG | offset);
    }

    fn bounds(&self) -> Aabb {
        Aabb { min: self.lo.truncate(), max: self.hi.truncate() }
    }

    /// The slab test in SIMD lanes; the entry distance when hit.
    #[inline(always)]
    fn hit(&self, origin: Vec3A, inv: Vec3A, t_min: f32, t_max: f32) -> Option<f32> {
        let t0 = (Vec3A::from_vec4(self.lo) - origin) * inv;
        let t1 = (Vec3A::from_vec4(self.hi) - origin) * inv;
        // Plain comparisons rather than f32::max/min: no NaN bookkeeping on
        // the hottest path (a NaN lane widens the interval, which is safe).
        let near = t0.min(t1).max_element();
        let far = t0.max(t1).min_element();
        let tn = if near > t_min { near } else { t_min };
        let tf = if far < t_max { far } else { t_max } * ROBUST;
        if tn <= tf { Some(tn) } else { None }
    }
}

#[derive(Clone, Copy, Debug, Default)]
pub struct BvhStats {
    pub nodes: usize,
    pub leaves: usize,
    pub depth: usize,
    pub bytes: usize,
}

pub struct Bvh {
    nodes: Vec<Node>,
    /// The primitives in leaf order.
    pub shapes: Vec<Shape>,
    depth: usize,
}

struct BuildPrim {
    bounds: Aabb,
    centroid: Vec3,
    index: u32,
}

impl Bvh {
    /// Builds over `shapes`, copying each once into leaf order.
    pub fn build(shapes: &[Shape]) -> Bvh {
        Bvh::build_from(shapes.len(), |i| shapes[i])
    }

    /// Builds over the `n` shapes that `shape(i)` makes (called from many
    /// threads, twice per shape), so no unordered copy of them is kept.
    pub fn build_from(n: usize, shape: impl Fn(usize) -> Shape + Sync) -> Bvh {
        let mut prims: Vec<BuildPrim> = (0..n)
            .into_par_iter()
            .map(|i| {
                let b = shape(i).bounds();
                BuildPrim { bounds: b, centroid: b.centroid(), index: i as u32 }
            })
            .collect();
        let (nodes, depth) =
            if prims.is_empty() { (Vec::new(), 0) } else { build_par(&mut prims, 0, 1) };
        let ordered = prims.par_iter().map(|p| shape(p.index as usize)).collect();
        Bvh { nodes, shapes: ordered, depth }
    }

    pub fn stats(&self) -> BvhStats {
        BvhStats {
            nodes: self.nodes.len(),
            leaves: self.nodes.iter().filter(|n| n.count() > 0).count(),
            depth: self.depth,
            bytes: self.nodes.len() * std::mem::size_of::<Node>()
                + self.shapes.len() * std::mem::size_of::<Shape>(),
        }
    }

    pub fn bounds(&self) -> Aabb {
        self.nodes.first().map(|n| n.bounds()).unwrap_or(Aabb::EMPTY)
    }

    /// The closest hit in `(t_min, t_max)`, and the number of nodes visited.
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> (Option<Hit>, u32) {
        let mut best: Option<Hit> = None;
        let mut t_max = t_max;
        let visited = self.traverse(ray, t_min, &mut t_max, |s, k, pre, t_min, t_max| {
            if let Some((t, uv)) = s.intersect(ray, pre, t_min, *t_max) {
                *t_max = t;
                best = Some(Hit { t, prim: k, uv });
            }
            false
        });
        (best, visited)
    }

    /// The closest hit found by testing every primitive in turn: the
    /// baseline the hierarchy is measured against (and checked against).
    pub fn intersect_brute(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<Hit> {
        let pre = RayPre::new(ray.dir);
        let mut best: Option<Hit> = None;
        let mut t_max = t_max;
        for (k, s) in self.shapes.iter().enumerate() {
            if let Some((t, uv)) = s.intersect(ray, &pre, t_min, t_max) {
                t_max = t;
                best = Some(Hit { t, prim: k as u32, uv });
            }
        }
        best
    }

    /// What reaches the end of a shadow segment: the product of `pass(prim)`
    /// over every surface crossed in `(t_min, t_max)` (zero for an opaque
    /// one, which ends the search at once).
    pub fn transmittance(
        &self,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
        mut pass: impl FnMut(u32) -> Vec3,
    ) -> Vec3 {
        let mut through = Vec3::ONE;
        let mut t_end = t_max;
        self.traverse(ray, t_min, &mut t_end, |s, k, pre, t_min, t_max| {
            let mut from = t_min;
            while let Some((t, _)) = s.intersect(ray, pre, from, *t_max) {
                through *= pass(k);
                if through == Vec3::ZERO {
                    return true;
                }
                if !matches!(s, Shape::Sphere { .. }) {
                    break;
                }
                from = t;
            }
            false
        });
        through
    }

    /// Walks the nodes the ray's segment overlaps, nearer child first, and
    /// calls `leaf` on each primitive there (with the current `t_max`, which
    /// it may shorten); `leaf` returning true stops the walk. Returns the
    /// number of nodes visited.
    #[inline]
    fn traverse(
        &self,
        ray: &Ray,
        t_min: f32,
        t_max: &mut f32,
        mut leaf: impl FnMut(&Shape, u32, &RayPre, f32, &mut f32) -> bool,
    ) -> u32 {
        if self.nodes.is_empty() {
            return 0;
        }
        let inv = Vec3A::from(ray.dir.recip());
        let origin = Vec3A::from(ray.origin);
        let pre = RayPre::new(ray.dir);
        let mut stack = [(0u32, 0f32); 64];
        let mut sp = 0;
        let mut visited = 1;
        let Some(t_root) = self.nodes[0].hit(origin, inv, t_min, *t_max) else { return visited };
        let mut current = Some((0usize, t_root));
        // Take the next node: the nearer child, else pop one, skipping nodes
        // that start beyond the closest hit so far.
        while let Some((node, t_enter)) = current.take().or_else(|| {
            while sp > 0 {
                sp -= 1;
                let (n, t) = stack[sp];
                if t <= *t_max {
                    return Some((n as usize, t));
                }
            }
            None
        }) {
            if t_enter > *t_max {
                continue;
            }
            let n = &self.nodes[node];
            let count = n.count();
            if count > 0 {
                let first = n.offset() as usize;
                for (k, s) in self.shapes[first..first + count as usize].iter().enumerate() {
                    if leaf(s, (first + k) as u32, &pre, t_min, t_max) {
                        return visited;
                    }
                }
                continue;
            }
            // Test both children here; go to the nearer, keep the farther.
            let (a, b) = (node + 1, n.offset() as usize);
            visited += 2;
            let ta = self.nodes[a].hit(origin, inv, t_min, *t_max);
            let tb = self.nodes[b].hit(origin, inv, t_min, *t_max);
            current = match (ta, tb) {
                (Some(ta), Some(tb)) => {
                    let (near, far) =
                        if ta <= tb { ((a, ta), (b, tb)) } else { ((b, tb), (a, ta)) };
                    if sp < stack.len() {
                        stack[sp] = (far.0 as u32, far.1);
                        sp += 1;
                    }
                    Some(near)
                }
                (Some(ta), None) => Some((a, ta)),
                (None, Some(tb)) => Some((b, tb)),
                (None, None) => None,
            };
        }
        visited
    }
}

fn make_leaf(prims: &[BuildPrim], first: usize, bounds: Aabb) -> Node {
    Node::new(bounds, first as u32, prims.len() as u32)
}

/// Subtrees larger than this are built on two threads at once.
const PARALLEL_BUILD: usize = 8 * 1024;

enum Split {
    Leaf,
    /// Partitioned: the left child holds `prims[..mid]`.
    Inner(usize),
}

/// Decides how to split `prims` (reordering them) with the surface area
/// heuristic over `BINS` buckets along the widest centroid axis.
fn split(prims: &mut [BuildPrim], (bounds, cbounds): (Aabb, Aabb), level: usize) -> Split {
    if prims.len() <= 2 || level >= 60 {
        return Split::Leaf;
    }
    let ext = cbounds.extent();
    let axis = if ext.x >= ext.y && ext.x >= ext.z {
        0
    } else if ext.y >= ext.z {
        1
    } else {
        2
    };
    let lo = cbounds.min[axis];
    let span = ext[axis];
    if span <= 0.0 || !span.is_finite() {
        // All centroids coincide: split in the middle of the list.
        return if prims.len() <= MAX_LEAF { Split::Leaf } else { Split::Inner(prims.len() / 2) };
    }
    let scale = BINS as f32 / span;
    let bin_of = |c: Vec3| (((c[axis] - lo) * scale) as usize).min(BINS - 1);
    let mut counts = [0usize; BINS];
    let mut boxes = [Aabb::EMPTY; BINS];
    for p in prims.iter() {
        let b = bin_of(p.centroid);
        counts[b] += 1;
        boxes[b] = boxes[b].union(p.bounds);
    }
    let mut right_area = [0.0f32; BINS];
    let mut right_count = [0usize; BINS];
    let (mut acc, mut n) = (Aabb::EMPTY, 0);
    for i in (1..BINS).rev() {
        acc = acc.union(boxes[i]);
        n += counts[i];
        right_area[i] = acc.surface_area();
        right_count[i] = n;
    }
    let (mut acc, mut n) = (Aabb::EMPTY, 0);
    let mut best = (f32::INFINITY, 0);
    for i in 0..BINS - 1 {
        acc = acc.union(boxes[i]);
        n += counts[i];
        if n == 0 || right_count[i + 1] == 0 {
            continue;
        }
        let cost = acc.surface_area() * n as f32 + right_area[i + 1] * right_count[i + 1] as f32;
        if cost < best.0 {
            best = (cost, i);
        }
    }
    let area = bounds.surface_area().max(f32::MIN_POSITIVE);
    let split_cost = TRAVERSAL_COST + best.0 / area;
    if best.0.is_infinite() || (split_cost >= prims.len() as f32 && prims.len() <= MAX_LEAF) {
        return Split::Leaf;
    }
    let mut i = 0;
    for j in 0..prims.len() {
        if bin_of(prims[j].centroid) <= best.1 {
            prims.swap(i, j);
            i += 1;
        }
    }
    Split::Inner(if i == 0 || i == prims.len() { prims.len() / 2 } else { i })
}

/// The bounds of the primitives and of their centroids, in one pass.
fn bounds_of(prims: &[BuildPrim]) -> (Aabb, Aabb) {
    prims
        .iter()
        .fold((Aabb::EMPTY, Aabb::EMPTY), |(b, c), p| (b.union(p.bounds), c.grow(p.centroid)))
}

fn inner(bounds: Aabb) -> Node {
    Node::new(bounds, 0, 0)
}

/// Builds the subtree over `prims` (which start at `first` in the final
/// order) and appends its nodes depth-first; returns the node index.
fn build_rec(
    prims: &mut [BuildPrim],
    first: usize,
    nodes: &mut Vec<Node>,
    level: usize,
    depth: &mut usize,
) -> usize {
    *depth = (*depth).max(level);
    let both = bounds_of(prims);
    let bounds = both.0;
    let me = nodes.len();
    match split(prims, both, level) {
        Split::Leaf => nodes.push(make_leaf(prims, first, bounds)),
        Split::Inner(mid) => {
            nodes.push(inner(bounds));
            let (left, right) = prims.split_at_mut(mid);
            build_rec(left, first, nodes, level + 1, depth);
            let second = build_rec(right, first + mid, nodes, level + 1, depth);
            nodes[me].set_offset(second as u32);
        }
    }
    me
}

/// The same tree as `build_rec`, building large subtrees on two threads;
/// returns the subtree's nodes (interior offsets relative to its root).
fn build_par(prims: &mut [BuildPrim], first: usize, level: usize) -> (Vec<Node>, usize) {
    if prims.len() < PARALLEL_BUILD {
        let (mut nodes, mut depth) = (Vec::with_capacity(prims.len()), 0);
        build_rec(prims, first, &mut nodes, level, &mut depth);
        return (nodes, depth);
    }
    let both = prims
        .par_chunks(4096)
        .map(bounds_of)
        .reduce(|| (Aabb::EMPTY, Aabb::EMPTY), |a, b| (a.0.union(b.0), a.1.union(b.1)));
    let bounds = both.0;
    match split(prims, both, level) {
        Split::Leaf => (vec![make_leaf(prims, first, bounds)], level),
        Split::Inner(mid) => {
            let (left, right) = prims.split_at_mut(mid);
            let ((ln, ld), (rn, rd)) = rayon::join(
                || build_par(left, first, level + 1),
                || build_par(right, first + mid, level + 1),
            );
            let mut nodes = Vec::with_capacity(1 + ln.len() + rn.len());
            let mut root = inner(bounds);
            root.set_offset((1 + ln.len()) as u32);
            nodes.push(root);
            let shift = |n: &Node, by: usize| {
                let mut n = *n;
                if n.count() == 0 {
                    n.set_offset(n.offset() + by as u32);
                }
                n
            };
            nodes.extend(ln.iter().map(|n| shift(n, 1)));
            nodes.extend(rn.iter().map(|n| shift(n, 1 + ln.len())));
            (nodes, ld.max(rd))
        }
    }
}

#[cfg(test)]
mod tests;
