//! Constructive solid geometry over closed solids (analytic ones, blobs
//! and closed meshes), by intervals: every
//! leaf's crossings along the ray's whole line, in order, toggle whether
//! the ray is inside that leaf (each leaf is closed and bounded, so it
//! starts outside); a crossing is a surface of the composite where the
//! composite's membership changes. `union` keeps every leaf's surface (as
//! POV-Ray's does, seen through glass); `merge` keeps only the outside.

use std::sync::Arc;

use glam::Vec3;

use super::blob::Blob;
use super::object::{Local, Located, Place, ShadowHit};
use super::solid::Solid;
use super::{Aabb, Bvh, Ray, Shape};

/// The CSG operations.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Op {
    Union,
    Intersection,
    /// The first child less the others.
    Difference,
    /// A union without its inner surfaces.
    Merge,
}

impl Op {
    pub const NAMES: &'static str = "union, intersection, difference or merge";

    pub fn parse(s: &str) -> Option<Op> {
        Some(match s {
            "union" => Op::Union,
            "intersection" => Op::Intersection,
            "difference" => Op::Difference,
            "merge" => Op::Merge,
            _ => return None,
        })
    }
}

/// A solid of the CSG, placed in the CSG's coordinates.
#[derive(Clone, Debug)]
pub struct Leaf {
    pub place: Place,
    pub shape: LeafShape,
    pub material: u32,
}

/// What a leaf is: each closed, so a line starts and ends outside it.
#[derive(Clone, Debug)]
pub enum LeafShape {
    Solid(Solid),
    Blob(Arc<Blob>),
    /// A closed mesh (its triangles wound counter-clockwise seen from
    /// outside, as `mesh` reads them).
    Mesh(Arc<Bvh>),
}

impl LeafShape {
    fn bounds(&self) -> Aabb {
        match self {
            LeafShape::Solid(s) => s.bounds(),
            LeafShape::Blob(b) => b.bounds(),
            LeafShape::Mesh(m) => m.bounds(),
        }
    }

    /// Every crossing of the ray's line, as (t, part), into `out`.
    fn crossings(&self, ray: &Ray, out: &mut Vec<(f32, u32)>) {
        match self {
            LeafShape::Solid(s) => {
                out.extend(s.crossings(ray).as_slice().iter().map(|c| (c.t, c.part)))
            }
            LeafShape::Blob(b) => b.crossings(ray, |t| {
                out.push((t, 0));
                false
            }),
            LeafShape::Mesh(m) => {
                let from = out.len();
                m.crossings(ray, &mut |t, prim| out.push((t, prim)));
                out[from..].sort_by(|a, b| a.0.total_cmp(&b.0));
                // Along a line through a closed mesh, crossings alternate:
                // in (against the outward normals), out, in... A line
                // through an edge or a vertex meets two triangles or more
                // there facing the same way: keep one of each run.
                let entering = |prim: u32| match m.shape(prim) {
                    Shape::Triangle(t) => t.cross().dot(ray.dir) < 0.0,
                    _ => true,
                };
                let mut k = from;
                for i in from..out.len() {
                    let want_entering = (k - from).is_multiple_of(2);
                    if entering(out[i].1) == want_entering {
                        out[k] = out[i];
                        k += 1;
                    }
                }
                out.truncate(k);
            }
        }
    }

    /// The outward normal at `p` on `part`.
    fn normal(&self, p: Vec3, part: u32) -> Vec3 {
        match self {
            LeafShape::Solid(s) => s.normal(p, part),
            LeafShape::Blob(b) => b.normal(p),
            LeafShape::Mesh(m) => match m.shape(part) {
                Shape::Triangle(t) => t.cross(),
                _ => Vec3::Z,
            },
        }
    }
}

/// The tree of operations over the leaves.
#[derive(Clone, Debug)]
pub enum Node {
    Leaf(u32),
    Op(Op, Vec<Node>),
}

/// The most leaves one CSG may have.
pub const MAX_LEAVES: usize = 1 << 16;

#[derive(Debug)]
pub struct Csg {
    leaves: Vec<Leaf>,
    root: Node,
    /// Whether each leaf's surface faces the other way in the composite
    /// (it is subtracted an odd number of times).
    flipped: Vec<bool>,
    bounds: Aabb,
}

impl Csg {
    /// `leaves` must be closed solids, each named once by `root`.
    pub fn new(leaves: Vec<Leaf>, root: Node) -> Csg {
        let mut flipped = vec![false; leaves.len()];
        mark_flipped(&root, false, &mut flipped);
        let bounds = node_bounds(&root, &leaves);
        Csg { leaves, root, flipped, bounds }
    }

    pub fn bounds(&self) -> Aabb {
        self.bounds
    }

    /// Every surface of the composite along the ray's line, in order, as
    /// (t, leaf), passed to `each` until it returns true.
    fn surfaces(&self, ray: &Ray, mut each: impl FnMut(f32, u32) -> bool) {
        let mut events: Vec<(f32, u32)> = Vec::new();
        let mut one = Vec::new();
        for (i, leaf) in self.leaves.iter().enumerate() {
            one.clear();
            leaf.shape.crossings(&leaf.place.local(ray), &mut one);
            events.extend(one.iter().map(|&(t, _)| (t, i as u32)));
        }
        events.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut inside = vec![false; self.leaves.len()];
        for (t, leaf) in events {
            let before = eval(&self.root, &inside);
            inside[leaf as usize] = !inside[leaf as usize];
            if is_surface(&self.root, leaf, before, &inside) && each(t, leaf) {
                return;
            }
        }
    }

    /// The first surface in `(t_min, t_max)`: its distance and `sub`.
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<(f32, u32)> {
        let mut found = None;
        self.surfaces(ray, |t, leaf| {
            if t >= t_max {
                return true;
            }
            if t > t_min {
                found = Some((t, leaf));
                return true;
            }
            false
        });
        found
    }

    /// The product of `pass` over the surfaces crossed in `(t_min, t_max)`.
    pub fn transmittance(
        &self,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
        pass: &mut dyn FnMut(ShadowHit) -> Vec3,
    ) -> Vec3 {
        let mut through = Vec3::ONE;
        self.surfaces(ray, |t, leaf| {
            if t >= t_max {
                return true;
            }
            if t > t_min {
                through *= pass(ShadowHit::new(self.leaves[leaf as usize].material, t));
            }
            through == Vec3::ZERO
        });
        through
    }

    /// The surface `intersect` found at `t` on leaf `sub`: the leaf's
    /// crossing there, asked again.
    pub fn locate(&self, ray: &Ray, t: f32, sub: u32) -> Located {
        let i = sub as usize;
        let leaf = &self.leaves[i];
        let local = leaf.place.local(ray);
        let mut all = Vec::new();
        leaf.shape.crossings(&local, &mut all);
        let part = all
            .iter()
            .min_by(|a, b| (a.0 - t).abs().total_cmp(&(b.0 - t).abs()))
            .map_or(0, |c| c.1);
        let n = leaf.shape.normal(local.at(t), part);
        Located {
            local: Local::Solid { normal: if self.flipped[i] { -n } else { n } },
            material: leaf.material,
            uv: [0.0; 2],
            to_local: leaf.place.at(ray.time),
            level: None,
            moved: Vec3::ZERO,
        }
    }
}

/// Whether the composite (or the subtree `n`) holds a point whose leaves'
/// memberships are `inside`.
fn eval(n: &Node, inside: &[bool]) -> bool {
    eval_before(n, inside, u32::MAX)
}

/// Whether toggling `leaf` (membership `before` of `n`, leaves now
/// `after`) crossed a surface of `n`: any surface of a union's child is
/// one of the union's; otherwise the membership must change.
fn is_surface(n: &Node, leaf: u32, before: bool, after: &[bool]) -> bool {
    match n {
        Node::Leaf(i) => *i == leaf,
        Node::Op(Op::Union, kids) => kids.iter().any(|k| {
            contains_leaf(k, leaf) && is_surface(k, leaf, eval_before(k, after, leaf), after)
        }),
        Node::Op(..) => before != eval(n, after),
    }
}

/// `eval` with `leaf`'s membership as it was before it toggled (none
/// for `u32::MAX`).
fn eval_before(n: &Node, after: &[bool], leaf: u32) -> bool {
    match n {
        Node::Leaf(i) => after[*i as usize] ^ (*i == leaf),
        Node::Op(op, kids) => match op {
            Op::Union | Op::Merge => kids.iter().any(|k| eval_before(k, after, leaf)),
            Op::Intersection => kids.iter().all(|k| eval_before(k, after, leaf)),
            Op::Difference => {
                kids.first().is_some_and(|k| eval_before(k, after, leaf))
                    && !kids[1..].iter().any(|k| eval_before(k, after, leaf))
            }
        },
    }
}

fn contains_leaf(n: &Node, leaf: u32) -> bool {
    match n {
        Node::Leaf(i) => *i == leaf,
        Node::Op(_, kids) => kids.iter().any(|k| contains_leaf(k, leaf)),
    }
}

fn mark_flipped(n: &Node, flip: bool, out: &mut [bool]) {
    match n {
        Node::Leaf(i) => out[*i as usize] = flip,
        Node::Op(op, kids) => {
            for (k, kid) in kids.iter().enumerate() {
                mark_flipped(kid, flip ^ (*op == Op::Difference && k > 0), out);
            }
        }
    }
}

fn node_bounds(n: &Node, leaves: &[Leaf]) -> Aabb {
    match n {
        Node::Leaf(i) => {
            let l = &leaves[*i as usize];
            l.place.bounds(l.shape.bounds(), [0.0, 0.0])
        }
        Node::Op(op, kids) => {
            let mut b = kids.iter().map(|k| node_bounds(k, leaves));
            match op {
                Op::Union | Op::Merge => b.fold(Aabb::EMPTY, Aabb::union),
                Op::Intersection => {
                    let both = b
                        .reduce(|a, c| Aabb { min: a.min.max(c.min), max: a.max.min(c.max) })
                        .unwrap_or(Aabb::EMPTY);
                    if both.min.cmpgt(both.max).any() { Aabb::EMPTY } else { both }
                }
                Op::Difference => b.next().unwrap_or(Aabb::EMPTY),
            }
        }
    }
}
