//! Constructive solid geometry over analytic solids, by intervals: every
//! leaf's crossings along the ray's whole line, in order, toggle whether
//! the ray is inside that leaf (each leaf is closed and bounded, so it
//! starts outside); a crossing is a surface of the composite where the
//! composite's membership changes. `union` keeps every leaf's surface (as
//! POV-Ray's does, seen through glass); `merge` keeps only the outside.

use glam::Vec3;

use super::object::{Local, Located, Place};
use super::solid::Solid;
use super::{Aabb, Ray};

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
#[derive(Clone, Copy, Debug)]
pub struct Leaf {
    pub place: Place,
    pub solid: Solid,
    pub material: u32,
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

/// Parts of a leaf's surface fit in this many bits of a hit's `sub`.
const PART_BITS: u32 = 3;

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
    /// (t, leaf, part), passed to `each` until it returns true.
    fn surfaces(&self, ray: &Ray, mut each: impl FnMut(f32, u32, u32) -> bool) {
        let mut events: Vec<(f32, u32, u32)> = Vec::new();
        for (i, leaf) in self.leaves.iter().enumerate() {
            let local = leaf.place.local(ray);
            for c in leaf.solid.crossings(&local).as_slice() {
                events.push((c.t, i as u32, c.part));
            }
        }
        events.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut inside = vec![false; self.leaves.len()];
        for (t, leaf, part) in events {
            let before = eval(&self.root, &inside);
            inside[leaf as usize] = !inside[leaf as usize];
            if is_surface(&self.root, leaf, before, &inside) && each(t, leaf, part) {
                return;
            }
        }
    }

    /// The first surface in `(t_min, t_max)`: its distance and `sub`.
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<(f32, u32)> {
        let mut found = None;
        self.surfaces(ray, |t, leaf, part| {
            if t >= t_max {
                return true;
            }
            if t > t_min {
                found = Some((t, leaf << PART_BITS | part));
                return true;
            }
            false
        });
        found
    }

    /// The product of `pass(material)` over the surfaces crossed in
    /// `(t_min, t_max)`.
    pub fn transmittance(
        &self,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
        pass: &mut dyn FnMut(u32) -> Vec3,
    ) -> Vec3 {
        let mut through = Vec3::ONE;
        self.surfaces(ray, |t, leaf, _| {
            if t >= t_max {
                return true;
            }
            if t > t_min {
                through *= pass(self.leaves[leaf as usize].material);
            }
            through == Vec3::ZERO
        });
        through
    }

    /// The surface `intersect` found at `t` with `sub`.
    pub fn locate(&self, ray: &Ray, t: f32, sub: u32) -> Located {
        let (i, part) = ((sub >> PART_BITS) as usize, sub & ((1 << PART_BITS) - 1));
        let leaf = &self.leaves[i];
        let p = leaf.place.local(ray).at(t);
        let n = leaf.solid.normal(p, part);
        Located {
            local: Local::Solid { normal: if self.flipped[i] { -n } else { n } },
            material: leaf.material,
            uv: [0.0; 2],
            to_local: leaf.place.at(ray.time),
        }
    }

    /// Whether `p` (in the CSG's coordinates) is inside: the boolean
    /// formula over the leaves' own inside tests.
    pub fn contains(&self, p: Vec3, inside_leaf: impl Fn(&Solid, Vec3) -> bool) -> bool {
        let inside: Vec<bool> = self
            .leaves
            .iter()
            .map(|l| {
                let q = l.place.to_local.map_or(p, |m| m.transform_point3(p));
                inside_leaf(&l.solid, q)
            })
            .collect();
        eval(&self.root, &inside)
    }
}

/// Whether the composite (or the subtree `n`) holds a point whose leaves'
/// memberships are `inside`.
fn eval(n: &Node, inside: &[bool]) -> bool {
    match n {
        Node::Leaf(i) => inside[*i as usize],
        Node::Op(op, kids) => match op {
            Op::Union | Op::Merge => kids.iter().any(|k| eval(k, inside)),
            Op::Intersection => kids.iter().all(|k| eval(k, inside)),
            Op::Difference => {
                kids.first().is_some_and(|k| eval(k, inside))
                    && !kids[1..].iter().any(|k| eval(k, inside))
            }
        },
    }
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

/// `eval` with `leaf`'s membership as it was before it toggled.
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
            l.place.bounds(l.solid.bounds(), [0.0, 0.0])
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
