//! The bounding volume hierarchy: a binned-SAH build over every primitive
//! (triangles and spheres alike), flattened into 32-byte nodes in
//! depth-first order, traversed with an explicit stack, near child first.
//! `intersect` finds the closest hit; `transmittance` is the any-hit query
//! for shadow rays, which multiplies in what each surface lets through.

use glam::Vec3;

use super::shapes::RayPre;
use super::{Aabb, Hit, Ray, Shape};

const BINS: usize = 16;
const MAX_LEAF: usize = 8;
/// Cost of a traversal step relative to one primitive test.
const TRAVERSAL_COST: f32 = 1.0;

/// A flattened node: a leaf holds `count > 0` primitives from `offset`; an
/// interior node's first child follows it and its second is at `offset`.
#[derive(Clone, Copy, Debug)]
struct Node {
    min: [f32; 3],
    offset: u32,
    max: [f32; 3],
    count: u16,
    axis: u16,
}

impl Node {
    fn bounds(&self) -> Aabb {
        Aabb { min: Vec3::from(self.min), max: Vec3::from(self.max) }
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
    pub fn build(shapes: Vec<Shape>) -> Bvh {
        let mut prims: Vec<BuildPrim> = shapes
            .iter()
            .enumerate()
            .map(|(i, s)| {
                let b = s.bounds();
                BuildPrim { bounds: b, centroid: b.centroid(), index: i as u32 }
            })
            .collect();
        let mut nodes = Vec::with_capacity(2 * shapes.len().div_ceil(2).max(1));
        let mut depth = 0;
        if !prims.is_empty() {
            build_rec(&mut prims, 0, &mut nodes, 1, &mut depth);
        }
        let ordered = prims.iter().map(|p| shapes[p.index as usize]).collect();
        Bvh { nodes, shapes: ordered, depth }
    }

    pub fn stats(&self) -> BvhStats {
        BvhStats {
            nodes: self.nodes.len(),
            leaves: self.nodes.iter().filter(|n| n.count > 0).count(),
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
        if self.nodes.is_empty() {
            return (None, 0);
        }
        let inv = ray.dir.recip();
        let neg = [inv.x < 0.0, inv.y < 0.0, inv.z < 0.0];
        let pre = RayPre::new(ray.dir);
        let mut best: Option<Hit> = None;
        let mut t_max = t_max;
        let mut stack = [0u32; 64];
        let mut sp = 0;
        let mut node = 0usize;
        let mut visited = 0;
        loop {
            let n = &self.nodes[node];
            visited += 1;
            if n.bounds().hit(ray.origin, inv, t_min, t_max).is_some() {
                if n.count > 0 {
                    let first = n.offset as usize;
                    for (k, s) in self.shapes[first..first + n.count as usize].iter().enumerate() {
                        if let Some((t, uv)) = s.intersect(ray, &pre, t_min, t_max) {
                            t_max = t;
                            best = Some(Hit { t, prim: (first + k) as u32, uv });
                        }
                    }
                } else {
                    // Visit the near child first; remember the far one.
                    let (near, far) = if neg[n.axis as usize] {
                        (n.offset as usize, node + 1)
                    } else {
                        (node + 1, n.offset as usize)
                    };
                    if sp < stack.len() {
                        stack[sp] = far as u32;
                        sp += 1;
                    }
                    node = near;
                    continue;
                }
            }
            if sp == 0 {
                break;
            }
            sp -= 1;
            node = stack[sp] as usize;
        }
        (best, visited)
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
        if self.nodes.is_empty() {
            return through;
        }
        let inv = ray.dir.recip();
        let pre = RayPre::new(ray.dir);
        let mut stack = [0u32; 64];
        let mut sp = 0;
        let mut node = 0usize;
        loop {
            let n = &self.nodes[node];
            if n.bounds().hit(ray.origin, inv, t_min, t_max).is_some() {
                if n.count > 0 {
                    let first = n.offset as usize;
                    for (k, s) in self.shapes[first..first + n.count as usize].iter().enumerate() {
                        let mut from = t_min;
                        while let Some((t, _)) = s.intersect(ray, &pre, from, t_max) {
                            through *= pass((first + k) as u32);
                            if through == Vec3::ZERO {
                                return through;
                            }
                            from = t;
                        }
                    }
                } else {
                    if sp < stack.len() {
                        stack[sp] = n.offset;
                        sp += 1;
                    }
                    node += 1;
                    continue;
                }
            }
            if sp == 0 {
                break;
            }
            sp -= 1;
            node = stack[sp] as usize;
        }
        through
    }
}

fn make_leaf(prims: &[BuildPrim], first: usize, bounds: Aabb) -> Node {
    Node {
        min: bounds.min.into(),
        max: bounds.max.into(),
        offset: first as u32,
        count: prims.len() as u16,
        axis: 0,
    }
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
    let bounds = prims.iter().fold(Aabb::EMPTY, |b, p| b.union(p.bounds));
    let me = nodes.len();
    if prims.len() <= 2 || level >= 60 {
        nodes.push(make_leaf(prims, first, bounds));
        return me;
    }
    let cbounds = prims.iter().fold(Aabb::EMPTY, |b, p| b.grow(p.centroid));
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
    let mid;
    if span <= 0.0 || !span.is_finite() {
        // All centroids coincide: split in the middle of the list.
        if prims.len() <= MAX_LEAF {
            nodes.push(make_leaf(prims, first, bounds));
            return me;
        }
        mid = prims.len() / 2;
    } else {
        // Partition with the surface area heuristic over BINS buckets.
        let bin_of = |c: Vec3| (((c[axis] - lo) / span * BINS as f32) as usize).min(BINS - 1);
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
            let cost =
                acc.surface_area() * n as f32 + right_area[i + 1] * right_count[i + 1] as f32;
            if cost < best.0 {
                best = (cost, i);
            }
        }
        let area = bounds.surface_area().max(f32::MIN_POSITIVE);
        let split_cost = TRAVERSAL_COST + best.0 / area;
        if best.0.is_infinite() || (split_cost >= prims.len() as f32 && prims.len() <= MAX_LEAF) {
            nodes.push(make_leaf(prims, first, bounds));
            return me;
        }
        let split = best.1;
        let mut i = 0;
        for j in 0..prims.len() {
            if bin_of(prims[j].centroid) <= split {
                prims.swap(i, j);
                i += 1;
            }
        }
        mid = if i == 0 || i == prims.len() { prims.len() / 2 } else { i };
    }
    nodes.push(Node {
        min: bounds.min.into(),
        max: bounds.max.into(),
        offset: 0,
        count: 0,
        axis: axis as u16,
    });
    let (left, right) = prims.split_at_mut(mid);
    build_rec(left, first, nodes, level + 1, depth);
    let second = build_rec(right, first + mid, nodes, level + 1, depth);
    nodes[me].offset = second as u32;
    me
}

#[cfg(test)]
mod tests;
