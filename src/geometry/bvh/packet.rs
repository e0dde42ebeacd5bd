//! Packets of rays from one origin (a pinhole camera's rays through a
//! block of pixels) walked through the tree together: a node is tested
//! once for the whole packet, by interval arithmetic over its rays'
//! directions (`wide::Frustum`), and a leaf's box is tested for each ray
//! by the ray's own slab test (four rays a pass) before the ray's leaf
//! tests. A ray meets every leaf its own walk would (the interval test is
//! conservative to the bit), tests it with the same arithmetic and keeps
//! its hits by the same rule (`Closest`), so each ray's hit is the one
//! `intersect` finds, to the bit.

use std::cell::Cell;

use glam::Vec4;

use super::super::aabb::ROBUST;
#[cfg(target_arch = "x86_64")]
use super::Avx2;
use super::wide::{Frustum, Kernel, Slots, in_place, inv4, near_planes};
use super::{
    Aabb, Bvh, Closest, Distance, Four, Hit, Leaf, Nodes, Pre4, Ray, Slabs4, Slot, push_sorted,
};

/// The most rays in a packet: a block of 8×8 pixels.
pub const PACKET: usize = 64;
const GROUPS: usize = PACKET / 4;

/// A packet's rays: the interval of their directions, and their
/// reciprocals by axis in lanes of four (lanes past the last ray copy the
/// first ray's, and are given no segment).
pub(super) struct Rays {
    frustum: Frustum,
    inv: [[Vec4; GROUPS]; 3],
    groups: usize,
}

impl Rays {
    /// The packet of `rays`, if they can go together: 2 to `PACKET` rays
    /// with one origin, finite, whose directions have one sign per axis.
    pub(super) fn new(rays: &[Ray]) -> Option<Rays> {
        let first = rays.first()?;
        if rays.len() < 2 || rays.len() > PACKET || !first.origin.is_finite() {
            return None;
        }
        let bits = |r: &Ray| r.origin.to_array().map(f32::to_bits);
        let o = bits(first);
        // The directions by axis in lanes (lanes past the last ray copy
        // the first ray's), then their reciprocals four at a time: the
        // same bits as `inv` ray by ray (a division is a division).
        let mut lanes = [[0.0f32; PACKET]; 3];
        for (i, r) in rays.iter().enumerate() {
            if bits(r) != o || !r.dir.is_finite() {
                return None;
            }
            lanes[0][i] = r.dir.x;
            lanes[1][i] = r.dir.y;
            lanes[2][i] = r.dir.z;
        }
        let groups = rays.len().div_ceil(4);
        for (lane, d) in lanes.iter_mut().zip(first.dir.to_array()) {
            lane[rays.len()..groups * 4].fill(d);
        }
        let mut inv = [[Vec4::ZERO; GROUPS]; 3];
        let (mut lo, mut hi) = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
        let mut signs = [0u64; 3];
        for axis in 0..3 {
            let (mut l, mut h) = (Vec4::INFINITY, Vec4::NEG_INFINITY);
            for g in 0..groups {
                let v = inv4(Vec4::from_slice(&lanes[axis][4 * g..]));
                inv[axis][g] = v;
                (l, h) = (l.min(v), h.max(v));
                signs[axis] |= (v.cmplt(Vec4::ZERO).bitmask() as u64) << (4 * g);
            }
            (lo[axis], hi[axis]) = (l.min_element(), h.max_element());
        }
        // One sign per axis: every lane's as the first ray's.
        let near = near_planes([inv[0][0].x, inv[1][0].x, inv[2][0].x]);
        for (axis, &m) in signs.iter().enumerate() {
            let want = if near[axis] == 1 { u64::MAX >> (PACKET - 4 * groups) } else { 0 };
            if m != want {
                return None;
            }
        }
        let frustum = Frustum { org: first.origin.to_array(), lo, hi, near };
        Some(Rays { frustum, inv, groups })
    }

    /// The rays whose own slab test (`wide::slab4`'s arithmetic) enters
    /// box `b` within `(t_min, t_max[i])`: bit i for ray i.
    #[inline(always)]
    pub(super) fn entering(&self, b: &Aabb, t_min: f32, t_max: &[f32; PACKET]) -> u64 {
        let f = &self.frustum;
        let d = |axis: usize, side: usize| {
            let plane = if side == 0 { b.min[axis] } else { b.max[axis] };
            Vec4::splat(plane - f.org[axis])
        };
        let [nx, ny, nz] = f.near;
        let (dn, df) = ([d(0, nx), d(1, ny), d(2, nz)], [d(0, nx ^ 1), d(1, ny ^ 1), d(2, nz ^ 1)]);
        let mut mask = 0;
        for g in 0..self.groups.min(GROUPS) {
            let t = |d: &[Vec4; 3], axis: usize| d[axis] * self.inv[axis][g];
            let near = t(&dn, 0).max(t(&dn, 1)).max(t(&dn, 2).max(Vec4::splat(t_min)));
            let t_max = Vec4::from_slice(&t_max[4 * g..]);
            let far = t(&df, 0).min(t(&df, 1)).min(t(&df, 2).min(t_max)) * ROBUST;
            mask |= (near.cmple(far).bitmask() as u64) << (4 * g);
        }
        mask
    }

    /// `entering` eight rays a pass (AVX2): each lane does the four-lane
    /// test's arithmetic, operand for operand, so the mask is the same
    /// to the bit (lanes past the packet's rays have no segment).
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    pub(super) fn entering8(
        &self,
        v3: pulp::x86::V3,
        b: &Aabb,
        t_min: f32,
        t_max: &[f32; PACKET],
    ) -> u64 {
        use std::arch::x86_64::{__m256, _CMP_LE_OS};
        let (avx, f) = (v3.avx, &self.frustum);
        let d = |axis: usize, side: usize| {
            let plane = if side == 0 { b.min[axis] } else { b.max[axis] };
            avx._mm256_set1_ps(plane - f.org[axis])
        };
        let [nx, ny, nz] = f.near;
        let (dn, df) = ([d(0, nx), d(1, ny), d(2, nz)], [d(0, nx ^ 1), d(1, ny ^ 1), d(2, nz ^ 1)]);
        let (lo, hi) = (avx._mm256_set1_ps(t_min), avx._mm256_set1_ps(ROBUST));
        let (min, max) = (|a, b| avx._mm256_min_ps(a, b), |a, b| avx._mm256_max_ps(a, b));
        let mut mask = 0;
        for g in 0..self.groups.div_ceil(2).min(GROUPS / 2) {
            let inv = |axis: usize| -> __m256 {
                pulp::cast([self.inv[axis][2 * g], self.inv[axis][2 * g + 1]])
            };
            let inv = [inv(0), inv(1), inv(2)];
            let t = |d: &[__m256; 3], axis: usize| avx._mm256_mul_ps(d[axis], inv[axis]);
            let near = max(max(t(&dn, 0), t(&dn, 1)), max(t(&dn, 2), lo));
            let far8: [f32; 8] =
                t_max[8 * g..8 * g + 8].try_into().unwrap_or([f32::NEG_INFINITY; 8]);
            let far = min(min(t(&df, 0), t(&df, 1)), min(t(&df, 2), pulp::cast(far8)));
            let far = avx._mm256_mul_ps(far, hi);
            let m = avx._mm256_movemask_ps(avx._mm256_cmp_ps::<_CMP_LE_OS>(near, far));
            mask |= (m as u32 as u64) << (8 * g);
        }
        // (The last group's upper lanes hold no rays: no segment.)
        mask & (u64::MAX >> (PACKET - (4 * self.groups).min(PACKET)))
    }
}

/// A packet walk's stack entry: a child, where the packet may enter it,
/// and the node and slot it hangs from (where a leaf's box is).
#[derive(Clone, Copy)]
pub(super) struct PacketEntry {
    pub(super) child: u32,
    pub(super) count: u32,
    pub(super) t: f32,
    pub(super) node: u32,
    pub(super) slot: u32,
}

impl Distance for PacketEntry {
    #[inline(always)]
    fn t(&self) -> f32 {
        self.t
    }
}

/// Each ray's leaf-test constants (the triangle test's and the slab
/// test's), made at the first leaf it reaches. Kept by each thread from
/// packet to packet, every entry `None` in between (a packet puts back
/// those its rays made), so a packet does not clear 18 KiB that most of
/// its rays never touch: camera rays mostly miss a framed model. Shadow
/// packets (`shadow`) use it too.
pub(super) struct Scratch {
    pub(super) pre: [Option<Pre4>; PACKET],
    pub(super) slabs: [Option<Slabs4>; PACKET],
}

impl Scratch {
    /// The thread's scratch, every entry `None` (a new one inside a walk
    /// that holds it already).
    pub(super) fn take() -> Box<Scratch> {
        SCRATCH.take().unwrap_or_else(|| {
            Box::new(Scratch { pre: [const { None }; PACKET], slabs: [const { None }; PACKET] })
        })
    }

    /// Gives the scratch back to the thread, putting back to `None` the
    /// entries of the rays in `used` (bit i: ray i).
    pub(super) fn put(mut self: Box<Scratch>, mut used: u64) {
        while used != 0 {
            let i = used.trailing_zeros() as usize & (PACKET - 1);
            used &= used - 1;
            (self.pre[i], self.slabs[i]) = (None, None);
        }
        SCRATCH.set(Some(self));
    }
}

thread_local! {
    /// The packet walks' stack, as `traverse`'s (camera and shadow
    /// packets alike).
    pub(super) static STACK: Cell<Vec<PacketEntry>> = const { Cell::new(Vec::new()) };
    static SCRATCH: Cell<Option<Box<Scratch>>> = const { Cell::new(None) };
}

impl Bvh {
    /// `intersect` for each ray of `rays` (at most `PACKET`), into `out`:
    /// the same hits, found together when the rays share an origin and
    /// their directions' signs, else one by one. A ray's steps are its own
    /// leaves and blocks plus its share of the packet's nodes.
    pub fn intersect_packet(
        &self,
        rays: &[Ray],
        t_min: f32,
        t_max: f32,
        out: &mut [(Option<Hit>, u32)],
    ) {
        debug_assert_eq!(rays.len(), out.len());
        let packet = if self.nodes.len() == 0 { None } else { Rays::new(rays) };
        let Some(p) = packet else {
            for (o, r) in out.iter_mut().zip(rays) {
                *o = self.intersect(r, t_min, t_max);
            }
            return;
        };
        let n = rays.len();
        let mut c = [Closest::default(); PACKET];
        // Lanes with no ray have no segment.
        let mut far = [f32::NEG_INFINITY; PACKET];
        far[..n].fill(t_max);
        if !self.unbounded.is_empty() {
            for (i, r) in rays.iter().enumerate() {
                let mut consider = |hit, t: &mut f32| c[i].consider(&self.recs, hit, t);
                self.objects_hit(&self.unbounded, r, t_min, &mut far[i], &mut consider);
            }
        }
        let mut scratch = Scratch::take();
        let Scratch { pre, slabs } = &mut *scratch;
        // The rays that reached a leaf (and may have made constants).
        let mut used = 0u64;
        let mut steps = [0u32; PACKET];
        let leaf = |i: usize, leaf: &Leaf, t_max: &mut f32| {
            let leaf = *leaf;
            let i = i & (PACKET - 1);
            used |= 1 << i;
            steps[i] += 1 + leaf.len() as u32;
            self.leaf_closest(
                &rays[i],
                (&mut pre[i], &mut slabs[i]),
                leaf,
                t_min,
                t_max,
                &mut c[i],
            );
        };
        let mut stack = STACK.take();
        stack.clear();
        let nodes = match &self.nodes {
            Nodes::Four(nodes) => {
                self.walk_packet(Four, nodes, &mut stack, &p, t_min, &mut far, leaf)
            }
            #[cfg(target_arch = "x86_64")]
            Nodes::Eight(nodes, avx) => {
                // One reference into the AVX2 function, as in `traverse`.
                let mut args = (self, nodes, &mut stack, &p, t_min, &mut far, leaf);
                let args = &mut args;
                avx.run(move || {
                    let (me, nodes, stack, p, t_min, far, leaf) = args;
                    me.walk_packet::<Avx2>(*avx, nodes, stack, p, *t_min, far, leaf)
                })
            }
        };
        STACK.set(stack);
        scratch.put(used);
        let share = nodes / n as u32;
        for (i, o) in out.iter_mut().enumerate() {
            *o = (c[i].best, steps[i] + share);
        }
    }

    /// Walks the nodes any ray of the packet may enter, nearest first, and
    /// calls `leaf(i, blocks, t_max[i])` for each ray `i` that enters a
    /// leaf's box; returns the nodes visited.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    fn walk_packet<K: Kernel>(
        &self,
        kernel: K,
        nodes: &[K::Node],
        stack: &mut Vec<PacketEntry>,
        p: &Rays,
        t_min: f32,
        t_max: &mut [f32; PACKET],
        mut leaf: impl FnMut(usize, &Leaf, &mut f32),
    ) -> u32 {
        let frustum = kernel.frustum(&p.frustum);
        let frustum = in_place(&frustum);
        // As in `walk`: more entries would mean a broken tree.
        let limit = (K::Node::N - 1) * self.depth + 4;
        // Four lanes at a time (no segment end is NaN).
        let farthest = |t_max: &[f32; PACKET]| {
            let lanes = t_max.chunks_exact(4).map(Vec4::from_slice);
            lanes.fold(Vec4::NEG_INFINITY, Vec4::max).max_element()
        };
        let mut far = farthest(t_max);
        let mut steps = 0;
        stack.push(PacketEntry { child: 0, count: 0, t: t_min, node: 0, slot: 0 });
        while let Some(e) = stack.pop() {
            if e.t > far {
                continue;
            }
            steps += 1;
            if e.count == 0 {
                let n = &nodes[e.child as usize];
                let (mut mask, near) = kernel.hit_frustum(n, frustum, t_min, far);
                let base = stack.len();
                if base > limit {
                    break;
                }
                while mask != 0 {
                    let slot = mask.trailing_zeros() as usize & (K::Node::N - 1);
                    mask &= mask - 1;
                    let (child, count) = n.child(slot);
                    self.prefetch(kernel, nodes, (child, count));
                    let e = PacketEntry {
                        child,
                        count,
                        t: near[slot],
                        node: e.child,
                        slot: slot as u32,
                    };
                    push_sorted(stack, base, e);
                }
                continue;
            }
            let b = nodes[e.node as usize].bounds(e.slot as usize);
            let mut rays = kernel.entering(p, &b, t_min, t_max);
            if rays == 0 {
                continue;
            }
            let blocks = self.leaf_blocks(Slot { first: e.child, count: e.count });
            let mut shortened = false;
            while rays != 0 {
                let i = rays.trailing_zeros() as usize & (PACKET - 1);
                rays &= rays - 1;
                let before = t_max[i];
                leaf(i, &blocks, &mut t_max[i]);
                shortened |= t_max[i] != before;
            }
            if shortened {
                far = farthest(t_max);
            }
        }
        steps
    }
}
