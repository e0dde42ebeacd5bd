//! Shadow rays of neighbouring shading points toward one light, walked
//! through the tree together: the any-hit query of `transmittance` for a
//! packet of segments that end near one point.
//!
//! The segments have their own origins, so the camera packets' interval
//! test (rays from one origin, `wide::Frustum`) cannot hold them as they
//! are. But segments that converge lie in a cone from a point behind
//! where they meet: the apex is put as far behind their mean end as their
//! mean start is in front of it (`Segments::new`). Every point of a
//! segment is the apex plus t·d, with d a convex combination of the unit
//! directions to the segment's two ends and t at most the farther end's
//! distance; so the cone's interval test, over the box of those unit
//! directions (widened by `SLACK`, for the rounding of the segments' own
//! points, far below it) and distances up to the farthest end, never
//! drops a node a segment enters. Nodes are culled by that cone; a leaf's
//! box is tested for each ray by the ray's own slab test, on its own
//! origin, and its blocks by the ray's own tests: what the ray's own walk
//! does there.
//!
//! So a segment is reported blocked exactly when `transmittance` would
//! find an opaque surface on it, and clear exactly when it would find no
//! surface at all: the same leaves are met (the cone is conservative, and
//! a ray that enters a leaf's box enters its ancestors' by the same
//! rounding), by the same tests. A segment that meets a surface letting
//! light through is `Unknown`, left to `transmittance`, which multiplies
//! in what each lets through in its own order. The picture is the one
//! single rays make, to the bit, whether or not a block goes as a packet.
//! (Packets of shadow rays: Wald, Slusallek, Benthin and Wagner,
//! "Interactive rendering with coherent ray tracing", 2001; the cone test
//! is the camera packets' interval test of Wald, Boulos and Shirley, 2007,
//! from another apex.)

use glam::{Vec3, Vec4};

use super::super::aabb::ROBUST;
use super::super::blocks::{self, Block};
#[cfg(target_arch = "x86_64")]
use super::Avx2;
use super::packet::{PACKET, PacketEntry, STACK, Scratch};
use super::wide::{Frustum, Kernel, Slots, in_place, inv, near_planes};
use super::{BlockKind, Bvh, Four, Leaf, Nodes, Occluder, Pre4, Ray, ShadowHit, Slabs4, Slot};

const GROUPS: usize = PACKET / 4;

/// The cone's widening: its interval of unit directions takes in every
/// direction within this of an end's, component by component (2⁻¹⁶, some
/// 500 units in the last place, against the few ulps by which a ray's own
/// points and slab test stray from its exact segment).
const SLACK: f32 = 1.0 / 65536.0;

/// The fewest segments that go as a packet: fewer go one by one.
const FEWEST: usize = 4;

/// The fewest primitives in a tree whose shadow rays go in packets. In a
/// smaller tree a shadow ray's own walk is a few steps, its occluder hint
/// answers most blocked rays, and a packet's setup costs more than it
/// saves: measured, on one thread, the SPD tree (1,024 primitives) 23 %
/// slower in packets, 30,000 random spheres 15 % slower, the 6,320-triangle
/// teapot even, and the 69,451-triangle bunny 9 % faster.
const FEWEST_PRIMITIVES: usize = 32768;

/// What a shadow packet learned of one segment.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
pub enum Shadow {
    /// No surface crosses it.
    Clear,
    /// A surface the caller calls opaque crosses it.
    Blocked,
    /// Not learned: a surface that lets light through crosses it.
    /// `transmittance` tells.
    #[default]
    Unknown,
}

/// A packet of segments: the cone that holds them, and each ray's slab
/// constants in lanes of four (lanes past the last copy the first ray's).
pub(super) struct Segments {
    /// The cone, of unit directions, and how far along them the segments
    /// reach.
    cone: Frustum,
    reach: f32,
    org: [[Vec4; GROUPS]; 3],
    inv: [[Vec4; GROUPS]; 3],
    /// The planes every ray meets first (they share their directions'
    /// signs).
    near: [usize; 3],
    groups: usize,
}

impl Segments {
    /// The packet of `rays` over `(0, t_max[i])`, if they can go together:
    /// finite segments whose directions share their signs, in a cone
    /// whose directions do too.
    pub(super) fn new(rays: &[Ray], t_max: &[f32]) -> Option<Segments> {
        let first = rays.first()?;
        let n = rays.len() as f32;
        let ends = |i: usize| (rays[i].origin, rays[i].at(t_max[i]));
        let (mut a, mut b) = (Vec3::ZERO, Vec3::ZERO);
        for i in 0..rays.len() {
            let (s, e) = ends(i);
            (a, b) = (a + s, b + e);
        }
        let apex = b / n + (b / n - a / n);
        if !apex.is_finite() {
            return None;
        }
        let of = |d: Vec3| [inv(d.x), inv(d.y), inv(d.z)];
        let near = near_planes(of(first.dir));
        let (mut lo, mut hi) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
        let mut reach = 0.0f32;
        let mut org = first.origin.to_array().map(|x| [Vec4::splat(x); GROUPS]);
        let mut inverse = of(first.dir).map(|x| [Vec4::splat(x); GROUPS]);
        for (i, r) in rays.iter().enumerate() {
            let v = of(r.dir);
            if !r.origin.is_finite() || !r.dir.is_finite() || near_planes(v) != near {
                return None;
            }
            let (s, e) = ends(i);
            for d in [s - apex, e - apex] {
                // Unit directions: the interval holds angles, not lengths.
                let len = d.length();
                let u = d / len;
                (lo, hi) = (lo.min(u - SLACK), hi.max(u + SLACK));
                reach = reach.max(len);
            }
            for axis in 0..3 {
                org[axis][i / 4][i % 4] = r.origin[axis];
                inverse[axis][i / 4][i % 4] = v[axis];
            }
        }
        // One sign per axis over the whole interval, so its reciprocals'
        // interval is that of its ends.
        let signs = lo.cmpgt(Vec3::ZERO) | hi.cmplt(Vec3::ZERO);
        if !(signs.all() && lo.is_finite() && hi.is_finite()) {
            return None;
        }
        let (a, b) = (lo.recip(), hi.recip());
        let cone = Frustum {
            org: apex.to_array(),
            lo: a.min(b).to_array(),
            hi: a.max(b).to_array(),
            near: near_planes(a.to_array()),
        };
        let groups = rays.len().div_ceil(4);
        let reach = reach * (1.0 + SLACK);
        Some(Segments { cone, reach, org, inv: inverse, near, groups })
    }

    /// The rays whose own slab test (`wide::slab4`'s arithmetic, lane for
    /// lane) enters box `b` within `(0, t_max[i])`, among `live`.
    #[inline(always)]
    pub(super) fn entering(&self, b: &super::Aabb, t_max: &[f32; PACKET], live: u64) -> u64 {
        let [nx, ny, nz] = self.near;
        let plane = |axis: usize, side: usize| {
            Vec4::splat(if side == 0 { b.min[axis] } else { b.max[axis] })
        };
        let (pn, pf) = (
            [plane(0, nx), plane(1, ny), plane(2, nz)],
            [plane(0, nx ^ 1), plane(1, ny ^ 1), plane(2, nz ^ 1)],
        );
        let mut mask = 0;
        for g in 0..self.groups.min(GROUPS) {
            if live >> (4 * g) & 0xf == 0 {
                continue;
            }
            let t = |p: &[Vec4; 3], axis: usize| (p[axis] - self.org[axis][g]) * self.inv[axis][g];
            let near = t(&pn, 0).max(t(&pn, 1)).max(t(&pn, 2).max(Vec4::ZERO));
            let t_max = Vec4::from_slice(&t_max[4 * g..]);
            let far = t(&pf, 0).min(t(&pf, 1)).min(t(&pf, 2).min(t_max)) * ROBUST;
            mask |= (near.cmple(far).bitmask() as u64) << (4 * g);
        }
        mask & live
    }

    /// `entering` eight rays a pass (AVX2), each lane doing the four-lane
    /// test's arithmetic operand for operand: the same mask, to the bit.
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    pub(super) fn entering8(
        &self,
        v3: pulp::x86::V3,
        b: &super::Aabb,
        t_max: &[f32; PACKET],
        live: u64,
    ) -> u64 {
        use std::arch::x86_64::{__m256, _CMP_LE_OS};
        let avx = v3.avx;
        let [nx, ny, nz] = self.near;
        let plane = |axis: usize, side: usize| {
            avx._mm256_set1_ps(if side == 0 { b.min[axis] } else { b.max[axis] })
        };
        let (pn, pf) = (
            [plane(0, nx), plane(1, ny), plane(2, nz)],
            [plane(0, nx ^ 1), plane(1, ny ^ 1), plane(2, nz ^ 1)],
        );
        let (zero, robust) = (avx._mm256_set1_ps(0.0), avx._mm256_set1_ps(ROBUST));
        let (min, max) = (|a, b| avx._mm256_min_ps(a, b), |a, b| avx._mm256_max_ps(a, b));
        let mut mask = 0;
        for g in 0..self.groups.div_ceil(2).min(GROUPS / 2) {
            if live >> (8 * g) & 0xff == 0 {
                continue;
            }
            let pair = |v: &[[Vec4; GROUPS]; 3], axis: usize| -> __m256 {
                pulp::cast([v[axis][2 * g], v[axis][2 * g + 1]])
            };
            let (org, inv) =
                ([0, 1, 2].map(|a| pair(&self.org, a)), [0, 1, 2].map(|a| pair(&self.inv, a)));
            let t = |p: &[__m256; 3], axis: usize| {
                avx._mm256_mul_ps(avx._mm256_sub_ps(p[axis], org[axis]), inv[axis])
            };
            let near = max(max(t(&pn, 0), t(&pn, 1)), max(t(&pn, 2), zero));
            let far8: [f32; 8] =
                t_max[8 * g..8 * g + 8].try_into().unwrap_or([f32::NEG_INFINITY; 8]);
            let far = min(min(t(&pf, 0), t(&pf, 1)), min(t(&pf, 2), pulp::cast(far8)));
            let far = avx._mm256_mul_ps(far, robust);
            let m = avx._mm256_movemask_ps(avx._mm256_cmp_ps::<_CMP_LE_OS>(near, far));
            mask |= (m as u32 as u64) << (8 * g);
        }
        mask & live
    }
}

impl Bvh {
    /// Whether shadow rays go in packets in this tree (`FEWEST_PRIMITIVES`;
    /// the answers are the same either way).
    pub fn packs_shadows(&self) -> bool {
        self.len() >= FEWEST_PRIMITIVES
    }

    /// What each ray of `rays` (at most `PACKET`) meets on its segment
    /// `(0, t_max[i])`, into `out`: `Blocked` where `transmittance` would
    /// find a surface `opaque(material)` calls opaque (and give zero),
    /// `Clear` where it would find no surface (and give one), `Unknown`
    /// where a surface that lets light through comes first. Shadow rays
    /// toward one light from neighbouring points go together (see the
    /// module's notes); others, and a few, go one by one. `last`: the
    /// occluder hint of `transmittance_hinted`, tested first by each ray
    /// and left on the block that blocked the last ray blocked.
    pub fn shadow_packet(
        &self,
        rays: &[Ray],
        t_max: &[f32],
        last: &mut Occluder,
        opaque: impl Fn(u32) -> bool,
        out: &mut [Shadow],
    ) {
        self.shadows(rays, t_max, last, &opaque, out, self.packs_shadows());
    }

    /// `shadow_packet`, in packets where `packets` says they may go.
    pub(super) fn shadows(
        &self,
        rays: &[Ray],
        t_max: &[f32],
        last: &mut Occluder,
        opaque: &impl Fn(u32) -> bool,
        out: &mut [Shadow],
        packets: bool,
    ) {
        let n = rays.len().min(PACKET);
        let found =
            |h: ShadowHit| if opaque(h.material) { Shadow::Blocked } else { Shadow::Unknown };
        let mut scratch = Scratch::take();
        let Scratch { pre, slabs } = &mut *scratch;
        // The rays that made constants (put back to `None` at the end).
        let mut used = 0u64;
        // The hint first; the rays it does not block go on.
        let mut live = 0u64;
        for i in 0..n {
            out[i] = Shadow::Clear;
            if let Some((kind, b)) = last.block(self) {
                used |= 1 << i;
                let mut s = Shadow::Clear;
                let mut each = |h| {
                    s = found(h);
                    s == Shadow::Blocked
                };
                if self.block_hits(b, kind, &rays[i], (0.0, t_max[i]), &mut pre[i], &mut each) {
                    out[i] = Shadow::Blocked;
                    continue;
                }
            }
            live |= 1 << i;
        }
        // Objects without bounds, ray by ray.
        let mut far = [f32::NEG_INFINITY; PACKET];
        if !self.unbounded.is_empty() {
            for i in 0..n {
                let mut s = Shadow::Clear;
                let mut pass = |h| {
                    s = found(h);
                    Vec3::ZERO
                };
                let seg = (0.0, t_max[i]);
                if live & 1 << i != 0
                    && self.objects_through(&self.unbounded, &rays[i], seg, &mut pass) == Vec3::ZERO
                {
                    (out[i], live) = (s, live & !(1 << i));
                }
            }
        }
        let packet = if packets && live.count_ones() as usize >= FEWEST && self.nodes.len() > 0 {
            Segments::new(&rays[..n], &t_max[..n])
        } else {
            None
        };
        match packet {
            None => {
                used |= live;
                while live != 0 {
                    let i = live.trailing_zeros() as usize & (PACKET - 1);
                    live &= live - 1;
                    out[i] = self.shadow_one(&rays[i], t_max[i], &mut pre[i], last, &found);
                }
            }
            Some(p) => {
                for i in 0..n {
                    if live & 1 << i != 0 {
                        far[i] = t_max[i];
                    }
                }
                self.shadow_walk(rays, &p, &mut far, (pre, slabs), &mut used, last, &found, out);
            }
        }
        scratch.put(used);
    }

    /// The packet walk of `shadow_packet`: the rays whose `t_max` is not
    /// minus infinity, through the nodes cone `p` enters.
    #[allow(clippy::too_many_arguments)]
    fn shadow_walk(
        &self,
        rays: &[Ray],
        p: &Segments,
        far: &mut [f32; PACKET],
        (pres, slabs): (&mut [Option<Pre4>; PACKET], &mut [Option<Slabs4>; PACKET]),
        used: &mut u64,
        last: &mut Occluder,
        found: &impl Fn(ShadowHit) -> Shadow,
        out: &mut [Shadow],
    ) {
        let leaf = |i: usize, leaf: &Leaf, t_max: &mut f32| {
            let i = i & (PACKET - 1);
            *used |= 1 << i;
            let mut s = Shadow::Clear;
            let mut each = |h| {
                s = found(h);
                true
            };
            let ray = &rays[i];
            if let Some(b) =
                self.leaf_any(ray, *leaf, *t_max, (&mut pres[i], &mut slabs[i]), &mut each)
            {
                out[i] = s;
                if let Some((b, kind)) = b.filter(|_| s == Shadow::Blocked) {
                    *last = Occluder::of(self, b, kind);
                }
                *t_max = f32::NEG_INFINITY;
            }
        };
        let mut stack = STACK.take();
        stack.clear();
        match &self.nodes {
            Nodes::Four(nodes) => self.walk_segments(Four, nodes, &mut stack, p, far, leaf),
            #[cfg(target_arch = "x86_64")]
            Nodes::Eight(nodes, avx) => {
                // One reference into the AVX2 function, as in `traverse`.
                let mut args = (self, nodes, &mut stack, p, far, leaf);
                let args = &mut args;
                avx.run(move || {
                    let (me, nodes, stack, p, far, leaf) = args;
                    me.walk_segments::<Avx2>(*avx, nodes, stack, p, far, leaf)
                })
            }
        }
        STACK.set(stack);
    }

    /// `shadow_packet` for one ray, by its own walk.
    fn shadow_one(
        &self,
        ray: &Ray,
        t_max: f32,
        pre: &mut Option<Pre4>,
        last: &mut Occluder,
        found: &impl Fn(ShadowHit) -> Shadow,
    ) -> Shadow {
        let (mut out, mut slabs) = (Shadow::Clear, None);
        let mut t_end = t_max;
        self.traverse::<false>(ray, 0.0, &mut t_end, |slot, t_max| {
            let mut each = |h| {
                out = found(h);
                true
            };
            let leaf = self.leaf_blocks(slot);
            let Some(b) = self.leaf_any(ray, leaf, *t_max, (pre, &mut slabs), &mut each) else {
                return false;
            };
            if let Some((b, kind)) = b.filter(|_| out == Shadow::Blocked) {
                *last = Occluder::of(self, b, kind);
            }
            true
        });
        out
    }

    /// Whether a surface of `leaf` crosses the segment `(0, t_max)` of
    /// `ray`, by `transmittance`'s tests: calls `each` on the crossings
    /// until it returns true, and then returns the block (with its kind)
    /// the crossing is on, `None` within it for an object's.
    #[inline(always)]
    fn leaf_any<'a>(
        &self,
        ray: &Ray,
        leaf: Leaf<'a>,
        t_max: f32,
        (pre, slabs): (&mut Option<Pre4>, &mut Option<Slabs4>),
        each: &mut impl FnMut(ShadowHit) -> bool,
    ) -> Option<Option<(&'a Block, BlockKind)>> {
        let seg = (0.0, t_max);
        let kinds = [(BlockKind::Triangles, leaf.tris), (BlockKind::Spheres, leaf.spheres)];
        for (kind, blocks) in kinds {
            if let Some(b) = self.first_blocking((kind, blocks), ray, seg, pre, each) {
                return Some(Some((b, kind)));
            }
        }
        if leaf.cones != 0
            && let Some(b) = self.cones_blocking(leaf.cones(), ray, seg, each)
        {
            return Some(Some((b, BlockKind::Cones)));
        }
        for b in leaf.objects() {
            let prims = self.entered(b, ray, slabs, 0.0, t_max);
            if prims.iter().all(|&p| p == blocks::NONE) {
                continue;
            }
            let mut stop = false;
            let mut pass = |h| {
                stop = each(h);
                if stop { Vec3::ZERO } else { Vec3::ONE }
            };
            self.objects_through(&prims, ray, seg, &mut pass);
            if stop {
                return Some(None);
            }
        }
        None
    }

    /// Walks the nodes the packet's cone enters (in slot order: an any-hit
    /// walk), and calls `leaf(i, blocks, t_max[i])` for each ray `i` still
    /// unblocked that enters a leaf's box; `leaf` makes `t_max[i]` minus
    /// infinity when the ray is blocked. Stops when every ray is.
    #[inline(always)]
    fn walk_segments<K: Kernel>(
        &self,
        kernel: K,
        nodes: &[K::Node],
        stack: &mut Vec<PacketEntry>,
        p: &Segments,
        t_max: &mut [f32; PACKET],
        mut leaf: impl FnMut(usize, &Leaf, &mut f32),
    ) {
        let (cone, reach) = (kernel.frustum(&p.cone), p.reach);
        let cone = in_place(&cone);
        let limit = (K::Node::N - 1) * self.depth + 4;
        let mut live = t_max
            .iter()
            .enumerate()
            .fold(0u64, |m, (i, &t)| m | ((t != f32::NEG_INFINITY) as u64) << i);
        // (Entries' `t` unused: no order among children.)
        stack.push(PacketEntry { child: 0, count: 0, t: 0.0, node: 0, slot: 0 });
        while let Some(PacketEntry { child, count, node, slot, .. }) = stack.pop() {
            if count == 0 {
                let n = &nodes[child as usize];
                let (mut mask, _) = kernel.hit_frustum(n, cone, 0.0, reach);
                if stack.len() > limit {
                    break;
                }
                while mask != 0 {
                    let s = mask.trailing_zeros() as usize & (K::Node::N - 1);
                    mask &= mask - 1;
                    let (c, k) = n.child(s);
                    self.prefetch(kernel, nodes, (c, k));
                    stack.push(PacketEntry {
                        child: c,
                        count: k,
                        t: 0.0,
                        node: child,
                        slot: s as u32,
                    });
                }
                continue;
            }
            let b = nodes[node as usize].bounds(slot as usize);
            let mut rays = kernel.segments_entering(p, &b, t_max, live);
            if rays == 0 {
                continue;
            }
            let blocks = self.leaf_blocks(Slot { first: child, count });
            while rays != 0 {
                let i = rays.trailing_zeros() as usize & (PACKET - 1);
                rays &= rays - 1;
                leaf(i, &blocks, &mut t_max[i]);
                if t_max[i] == f32::NEG_INFINITY {
                    live &= !(1 << i);
                }
            }
            if live == 0 {
                break;
            }
        }
    }
}
