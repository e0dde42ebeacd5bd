//! The nodes the renderer walks, and their slab tests: 4-wide nodes
//! (glam's four lanes: SSE, NEON, or scalar code elsewhere) and, where the
//! CPU has AVX2, 8-wide nodes tested in one 256-bit pass. The width is
//! chosen when a tree is built (`Width::detect`); both kinds of node give
//! a child the same box and the same entry test to the bit, so which one a
//! tree uses changes its speed, never what a ray hits.
//!
//! The 8-wide test goes through `pulp`'s safe wrappers of the AVX
//! intrinsics, inside a function compiled for AVX2 (`Avx2::run`), so the
//! crate keeps `unsafe_code = "forbid"`. The same token tests a leaf's two
//! blocks of triangles or spheres in one 256-bit pass (`Avx2::triangles2`,
//! `Avx2::spheres2`), each lane the four-lane test's arithmetic.

use glam::Vec4;

use super::super::Aabb;
use super::super::Ray;
use super::super::aabb::ROBUST;
use super::Prefetch;
use super::packet::{PACKET, Rays};
use super::shadow::Segments;

/// What the tree builder needs of a node: `N` child slots, each a box and
/// a child reference (`count` 0: an interior node at `child`; otherwise a
/// leaf's first block and its block counts).
pub(super) trait Slots: Copy {
    const N: usize;
    /// No children: every slot holds an inverted box (lo +inf, hi -inf),
    /// entered at +inf and left at -inf on every axis, whatever the ray.
    const EMPTY: Self;
    fn set(&mut self, i: usize, bounds: Aabb, child: u32, count: u32);
    fn child(&self, i: usize) -> (u32, u32);
    fn lo(&self, axis: usize, i: usize) -> f32;
    fn hi(&self, axis: usize, i: usize) -> f32;

    /// Slot `i`'s box (inverted when the slot is empty).
    fn bounds(&self, i: usize) -> Aabb {
        let b = |f: fn(&Self, usize, usize) -> f32| {
            glam::Vec3A::new(f(self, 0, i), f(self, 1, i), f(self, 2, i))
        };
        Aabb { min: b(Self::lo), max: b(Self::hi) }
    }
}

/// A walk's ray constants (`Kernel::slabs`, `Kernel::frustum`), kept in
/// their own place in memory for the whole walk, at their type's
/// alignment (32 bytes for the 256-bit ones), and read from there after
/// each leaf. Held in registers instead, they are saved around every
/// call of the leaf test (which may use every vector register) in stack
/// slots that LLVM aligns to 16 bytes only, without realigning the
/// frame: where the callers' frames leave the stack at 16 modulo 32,
/// every 256-bit save and reload straddles a 32-byte boundary, and half
/// of them a cache line. The tree-s8 render, one thread, spent 40 % of
/// its shadow walks at that one stall: 93 -> 75 ms; balls-s3 163 ->
/// 152 ms (README, "The walks' ray constants in place"). The reference
/// goes through `black_box` so the compiler keeps the value where it is
/// (the frame is realigned for it) and does not copy it into registers
/// and spill slots.
#[inline(always)]
pub(super) fn in_place<T>(constants: &T) -> &T {
    std::hint::black_box(constants)
}

/// A slab test over one kind of node: `hit` gives a bit mask of the
/// children the segment `(t_min, t_max)` enters, and their entry distances.
pub(super) trait Kernel: Copy {
    type Node: Slots;
    /// The per-ray constants, splatted across the lanes.
    type Slabs;
    type Near: std::ops::Index<usize, Output = f32> + Copy;
    /// A packet's constants (see `Frustum`), splatted across the lanes.
    type Frustum;
    fn slabs(self, ray: &Ray) -> Self::Slabs;
    fn hit(self, node: &Self::Node, r: &Self::Slabs, t_min: f32, t_max: f32) -> (u32, Self::Near);
    fn frustum(self, f: &Frustum) -> Self::Frustum;
    /// The packet test: the children that any ray of the packet may enter
    /// within `(t_min, t_max)` (`t_max`: the packet's farthest), and the
    /// nearest any ray may enter each at.
    fn hit_frustum(
        self,
        node: &Self::Node,
        f: &Self::Frustum,
        t_min: f32,
        t_max: f32,
    ) -> (u32, Self::Near);
    /// `Rays::entering`: the rays of `p` that enter box `b`.
    #[inline(always)]
    fn entering(self, p: &Rays, b: &Aabb, t_min: f32, t_max: &[f32; PACKET]) -> u64 {
        p.entering(b, t_min, t_max)
    }
    /// `Segments::entering`: the live shadow rays of `p` that enter `b`.
    #[inline(always)]
    fn segments_entering(self, p: &Segments, b: &Aabb, t_max: &[f32; PACKET], live: u64) -> u64 {
        p.entering(b, t_max, live)
    }
    /// How a walk asks for a node or leaf it has put on its stack ahead of
    /// its test: not at all where the kernel has no token for it.
    #[inline(always)]
    fn prefetch(self) -> Prefetch {
        Prefetch::NONE
    }
}

/// A packet of rays from one origin whose directions' components have
/// one sign per axis, for the interval test of Wald, Boulos and Shirley
/// ("Ray tracing deformable scenes using dynamic bounding volume
/// hierarchies", 2007): the lowest and highest reciprocal per axis. A
/// ray's distance to a plane is `(plane - origin) * inv`, monotonic in
/// `inv` with rounding included, so the interval's entry is never later
/// and its exit never earlier than any of its rays' own (the same
/// operations on the same operands): the test never drops a child a ray
/// of the packet would enter.
pub(super) struct Frustum {
    pub org: [f32; 3],
    pub lo: [f32; 3],
    pub hi: [f32; 3],
    /// Per axis, the plane the rays meet first (as `near_planes`).
    pub near: [usize; 3],
}

/// The reciprocal of a direction component, with a huge finite value
/// instead of infinity for zero, so `0 * inv` never makes a NaN at a
/// slab's plane.
pub(super) fn inv(d: f32) -> f32 {
    if d.abs() < 1e-30 { 1e30f32.copysign(d) } else { d.recip() }
}

/// `inv` of four directions' coordinates at once, lane for lane the same
/// bits (a division is correctly rounded either way).
#[inline(always)]
pub(super) fn inv4(d: Vec4) -> Vec4 {
    Vec4::select(d.abs().cmplt(Vec4::splat(1e-30)), Vec4::splat(1e30).copysign(d), d.recip())
}

/// For each axis, which of the two planes (0: lo, 1: hi) the ray meets
/// first, so the test needs no per-lane min/max.
pub(super) fn near_planes(i: [f32; 3]) -> [usize; 3] {
    i.map(|i| (i < 0.0) as usize)
}

/// A node of up to `N` children, their bounds in lanes by axis: 128 bytes
/// (two cache lines) for four, 256 for eight.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(64))]
pub(super) struct Wide<const N: usize> {
    /// The children's bounds by axis: [lo, hi] for x, y and z.
    b: [[[f32; N]; 2]; 3],
    /// Child i: an interior node's index, or a leaf's first block.
    child: [u32; N],
    /// Leaf child i's block counts (see `SHIFT` in the tree); 0 for an
    /// interior node.
    count: [u32; N],
}

/// The 4-wide node; `Wide8` is the 8-wide one.
pub(super) type Wide4 = Wide<4>;

impl<const N: usize> Slots for Wide<N> {
    const N: usize = N;
    const EMPTY: Wide<N> =
        Wide { b: [[[f32::INFINITY; N], [f32::NEG_INFINITY; N]]; 3], child: [0; N], count: [0; N] };

    fn set(&mut self, i: usize, bounds: Aabb, child: u32, count: u32) {
        for axis in 0..3 {
            self.b[axis][0][i] = bounds.min[axis];
            self.b[axis][1][i] = bounds.max[axis];
        }
        self.child[i] = child;
        self.count[i] = count;
    }

    #[inline(always)]
    fn child(&self, i: usize) -> (u32, u32) {
        // N is a power of two: provably in bounds, so no checks.
        let i = i & (N - 1);
        (self.child[i], self.count[i])
    }

    fn lo(&self, axis: usize, i: usize) -> f32 {
        self.b[axis][0][i]
    }

    fn hi(&self, axis: usize, i: usize) -> f32 {
        self.b[axis][1][i]
    }
}

/// The 4-wide test, on glam's lanes.
#[derive(Clone, Copy)]
pub(super) struct Four;

pub(super) struct Slabs4 {
    org: [Vec4; 3],
    inv: [Vec4; 3],
    near: [usize; 3],
}

pub(super) struct Frustum4 {
    org: [Vec4; 3],
    lo: [Vec4; 3],
    hi: [Vec4; 3],
    near: [usize; 3],
}

impl Kernel for Four {
    type Node = Wide4;
    type Slabs = Slabs4;
    type Near = [f32; 4];
    type Frustum = Frustum4;

    fn slabs(self, ray: &Ray) -> Slabs4 {
        let i = [inv(ray.dir.x), inv(ray.dir.y), inv(ray.dir.z)];
        Slabs4 {
            org: [ray.origin.x, ray.origin.y, ray.origin.z].map(Vec4::splat),
            inv: i.map(Vec4::splat),
            near: near_planes(i),
        }
    }

    #[inline(always)]
    fn hit(self, n: &Wide4, r: &Slabs4, t_min: f32, t_max: f32) -> (u32, [f32; 4]) {
        // `& 1`: provably in bounds, so no checks.
        slab4(|axis, side| Vec4::from_array(n.b[axis][side & 1]), r, t_min, t_max)
    }

    fn frustum(self, f: &Frustum) -> Frustum4 {
        Frustum4 {
            org: f.org.map(Vec4::splat),
            lo: f.lo.map(Vec4::splat),
            hi: f.hi.map(Vec4::splat),
            near: f.near,
        }
    }

    #[inline(always)]
    fn hit_frustum(self, n: &Wide4, f: &Frustum4, t_min: f32, t_max: f32) -> (u32, [f32; 4]) {
        let [nx, ny, nz] = f.near;
        let d = |axis: usize, side: usize| Vec4::from_array(n.b[axis][side & 1]) - f.org[axis];
        let enter = |axis: usize, side: usize| {
            let d = d(axis, side);
            (d * f.lo[axis]).min(d * f.hi[axis])
        };
        let exit = |axis: usize, side: usize| {
            let d = d(axis, side);
            (d * f.lo[axis]).max(d * f.hi[axis])
        };
        let near = enter(0, nx).max(enter(1, ny)).max(enter(2, nz).max(Vec4::splat(t_min)));
        let far = exit(0, nx ^ 1).min(exit(1, ny ^ 1)).min(exit(2, nz ^ 1).min(Vec4::splat(t_max)))
            * ROBUST;
        (near.cmple(far).bitmask(), near.to_array())
    }
}

impl Four {
    /// The same test on four boxes held as lanes: `[lo, hi]`, each by axis.
    #[inline(always)]
    pub fn hit_boxes(self, b: &[[Vec4; 3]; 2], r: &Slabs4, t_min: f32, t_max: f32) -> u32 {
        slab4(|axis, side| b[side & 1][axis], r, t_min, t_max).0
    }
}

/// The 4-wide slab test on the boxes whose planes `plane(axis, side)`
/// gives (side 0: lo, 1: hi).
#[inline(always)]
fn slab4(
    plane: impl Fn(usize, usize) -> Vec4,
    r: &Slabs4,
    t_min: f32,
    t_max: f32,
) -> (u32, [f32; 4]) {
    let [nx, ny, nz] = r.near;
    let t = |axis: usize, side: usize| (plane(axis, side) - r.org[axis]) * r.inv[axis];
    let (tnx, tfx) = (t(0, nx), t(0, nx ^ 1));
    let (tny, tfy) = (t(1, ny), t(1, ny ^ 1));
    let (tnz, tfz) = (t(2, nz), t(2, nz ^ 1));
    let near = tnx.max(tny).max(tnz.max(Vec4::splat(t_min)));
    // Robust traversal (Ize 2013): the exit widened by 2 ulps of error.
    let far = tfx.min(tfy).min(tfz.min(Vec4::splat(t_max))) * ROBUST;
    (near.cmple(far).bitmask(), near.to_array())
}

/// The width of the nodes a tree is built with.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Width {
    #[default]
    Four,
    /// Only on x86-64 CPUs with AVX2 (and the rest of x86-64-v3).
    Eight,
}

impl Width {
    /// The children a node holds.
    pub fn lanes(self) -> u32 {
        match self {
            Width::Four => 4,
            Width::Eight => 8,
        }
    }

    /// The widest this CPU tests in one pass; `RAYSHELL_BVH=4` asks for
    /// 4-wide nodes anyway (to compare the two).
    pub fn detect() -> Width {
        static WIDTH: std::sync::OnceLock<Width> = std::sync::OnceLock::new();
        *WIDTH.get_or_init(|| {
            let asked_four = std::env::var("RAYSHELL_BVH").is_ok_and(|v| v.trim() == "4");
            #[cfg(target_arch = "x86_64")]
            if !asked_four && Avx2::new().is_some() {
                return Width::Eight;
            }
            let _ = asked_four;
            Width::Four
        })
    }
}

#[cfg(target_arch = "x86_64")]
pub(super) use avx::{Avx2, Wide8};

#[cfg(target_arch = "x86_64")]
mod avx {
    use glam::Vec4;
    use pulp::x86::V3;
    use std::arch::x86_64::{
        __m128, __m256, _CMP_EQ_OQ, _CMP_LE_OQ, _CMP_LE_OS, _CMP_LT_OQ, _CMP_NEQ_UQ,
    };

    use super::super::super::blocks::{Block, Pre4};

    use super::{
        Aabb, Frustum, Kernel, PACKET, Prefetch, ROBUST, Ray, Rays, Segments, inv, near_planes,
    };

    /// The 8-wide node.
    pub(in super::super) type Wide8 = super::Wide<8>;

    /// The 8-wide test: the proof (a `V3` token) that this CPU has AVX2.
    #[derive(Clone, Copy)]
    pub(in super::super) struct Avx2(V3);

    pub(in super::super) struct Slabs8 {
        org: [__m256; 3],
        inv: [__m256; 3],
        near: [usize; 3],
    }

    pub(in super::super) struct Frustum8 {
        org: [__m256; 3],
        lo: [__m256; 3],
        hi: [__m256; 3],
        near: [usize; 3],
    }

    impl Avx2 {
        pub fn new() -> Option<Avx2> {
            V3::try_new().map(Avx2)
        }

        /// Runs `f` compiled for AVX2: what it inlines (the walk, and the
        /// slab tests in it) uses the 256-bit instructions.
        #[inline(always)]
        pub fn run<R>(self, f: impl FnOnce() -> R) -> R {
            self.0.vectorize(f)
        }
    }

    /// What `Avx2::triangles2` finds: the lanes hit (block 0's in bits
    /// 0-3, block 1's in 4-7), and per lane hit its t and the weights of
    /// vertices 1 and 2 (`each_triangle_hit`'s).
    pub(in super::super) struct Hits8 {
        pub mask: u32,
        pub t: [f32; 8],
        pub u: [f32; 8],
        pub v: [f32; 8],
    }

    /// The 256-bit operations of the two-block tests, as methods (written
    /// as closures they were not inlined into the AVX2 function: each
    /// operation a call, and renders twice as slow).
    #[derive(Clone, Copy)]
    struct Ops(V3);

    impl Ops {
        #[inline(always)]
        fn sub(self, a: __m256, b: __m256) -> __m256 {
            self.0.avx._mm256_sub_ps(a, b)
        }
        #[inline(always)]
        fn mul(self, a: __m256, b: __m256) -> __m256 {
            self.0.avx._mm256_mul_ps(a, b)
        }
        #[inline(always)]
        fn add(self, a: __m256, b: __m256) -> __m256 {
            self.0.avx._mm256_add_ps(a, b)
        }
        #[inline(always)]
        fn or(self, a: __m256, b: __m256) -> __m256 {
            self.0.avx._mm256_or_ps(a, b)
        }
        #[inline(always)]
        fn and(self, a: __m256, b: __m256) -> __m256 {
            self.0.avx._mm256_and_ps(a, b)
        }
        /// `a & !b`.
        #[inline(always)]
        fn and_not(self, a: __m256, b: __m256) -> __m256 {
            self.0.avx._mm256_andnot_ps(b, a)
        }
        #[inline(always)]
        fn eq(self, a: __m256, b: __m256) -> __m256 {
            self.0.avx._mm256_cmp_ps::<_CMP_EQ_OQ>(a, b)
        }
        #[inline(always)]
        fn lt(self, a: __m256, b: __m256) -> __m256 {
            self.0.avx._mm256_cmp_ps::<_CMP_LT_OQ>(a, b)
        }
        #[inline(always)]
        fn le(self, a: __m256, b: __m256) -> __m256 {
            self.0.avx._mm256_cmp_ps::<_CMP_LE_OQ>(a, b)
        }
        #[inline(always)]
        fn ne(self, a: __m256, b: __m256) -> __m256 {
            self.0.avx._mm256_cmp_ps::<_CMP_NEQ_UQ>(a, b)
        }
        #[inline(always)]
        fn bits(self, a: __m256) -> u32 {
            self.0.avx._mm256_movemask_ps(a) as u32
        }
        #[inline(always)]
        fn div(self, a: __m256, b: __m256) -> __m256 {
            self.0.avx._mm256_div_ps(a, b)
        }
        #[inline(always)]
        fn splat(self, a: f32) -> __m256 {
            self.0.avx._mm256_set1_ps(a)
        }
        /// Where `m`, `a`; elsewhere `b` (`Vec4::select`'s bits).
        #[inline(always)]
        fn select(self, m: __m256, a: __m256, b: __m256) -> __m256 {
            self.or(self.and_not(b, m), self.and(a, m))
        }
        /// Lanes 0-3 from `lo`, 4-7 from `hi`.
        #[inline(always)]
        fn join(self, lo: Vec4, hi: Vec4) -> __m256 {
            let (lo, hi): (__m128, __m128) = (pulp::cast(lo), pulp::cast(hi));
            self.0.avx._mm256_set_m128(hi, lo)
        }
    }

    impl Avx2 {
        /// `Block::triangles::<EARLY>` on two blocks at once, 256 bits
        /// wide: each lane the 4-wide test's arithmetic, to the bit (no
        /// fused multiply-adds; the edge functions that come out zero
        /// decided again in double precision, lane by lane).
        #[inline(never)]
        pub fn triangles2<const EARLY: bool>(
            self,
            b: [&Block; 2],
            r: &Pre4,
            t_min: f32,
            t_max: f32,
        ) -> Hits8 {
            let x = Ops(self.0);
            self.0.vectorize(
                #[inline(always)]
                move || {
                    let [kx, ky, kz] = r.k;
                    let o = r.o.map(|v| x.join(v, v));
                    let s = r.s.map(|v| x.join(v, v));
                    let v = |k: usize| x.join(b[0].v[k], b[1].v[k]);
                    let (a0, a1, a2) = (x.sub(v(kx), o[0]), x.sub(v(ky), o[1]), x.sub(v(kz), o[2]));
                    let (b0, b1, b2) =
                        (x.sub(v(3 + kx), o[0]), x.sub(v(3 + ky), o[1]), x.sub(v(3 + kz), o[2]));
                    let (c0, c1, c2) =
                        (x.sub(v(6 + kx), o[0]), x.sub(v(6 + ky), o[1]), x.sub(v(6 + kz), o[2]));
                    let (ax, ay) = (x.sub(a0, x.mul(s[0], a2)), x.sub(a1, x.mul(s[1], a2)));
                    let (bx, by) = (x.sub(b0, x.mul(s[0], b2)), x.sub(b1, x.mul(s[1], b2)));
                    let (cx, cy) = (x.sub(c0, x.mul(s[0], c2)), x.sub(c1, x.mul(s[1], c2)));
                    let mut u = x.sub(x.mul(cx, by), x.mul(cy, bx));
                    let mut vv = x.sub(x.mul(ax, cy), x.mul(ay, cx));
                    let mut w = x.sub(x.mul(bx, ay), x.mul(by, ax));
                    let zero = self.0.avx._mm256_setzero_ps();
                    let edge = x.bits(x.or(x.or(x.eq(u, zero), x.eq(vv, zero)), x.eq(w, zero)));
                    if edge != 0 {
                        let f = |x: __m256| -> [f32; 8] { pulp::cast(x) };
                        let (cx, cy, bx, by, ax, ay) = (f(cx), f(cy), f(bx), f(by), f(ax), f(ay));
                        let (mut ua, mut va, mut wa) = (f(u), f(vv), f(w));
                        let d = |x1: f32, y1: f32, x2: f32, y2: f32| {
                            (x1 as f64 * y2 as f64 - y1 as f64 * x2 as f64) as f32
                        };
                        for l in (0..8).filter(|&l| edge & (1 << l) != 0) {
                            ua[l] = d(cx[l], cy[l], bx[l], by[l]);
                            va[l] = d(ax[l], ay[l], cx[l], cy[l]);
                            wa[l] = d(bx[l], by[l], ax[l], ay[l]);
                        }
                        (u, vv, w) = (pulp::cast(ua), pulp::cast(va), pulp::cast(wa));
                    }
                    let neg = x.or(x.or(x.lt(u, zero), x.lt(vv, zero)), x.lt(w, zero));
                    let pos = x.or(x.or(x.lt(zero, u), x.lt(zero, vv)), x.lt(zero, w));
                    let det = x.add(x.add(u, vv), w);
                    let inside = x.and_not(x.ne(det, zero), x.and(neg, pos));
                    let none = Hits8 { mask: 0, t: [0.0; 8], u: [0.0; 8], v: [0.0; 8] };
                    if EARLY && x.bits(inside) == 0 {
                        return none;
                    }
                    let (az, bz, cz) = (x.mul(s[2], a2), x.mul(s[2], b2), x.mul(s[2], c2));
                    let t = x.add(x.add(x.mul(u, az), x.mul(vv, bz)), x.mul(w, cz));
                    let t = x.div(t, det);
                    let (lo, hi) = (x.splat(t_min), x.splat(t_max));
                    let mask = x.bits(x.and(x.and(inside, x.lt(lo, t)), x.lt(t, hi)));
                    if mask == 0 {
                        return none;
                    }
                    let (u, v) = (x.div(vv, det), x.div(w, det));
                    Hits8 { mask, t: pulp::cast(t), u: pulp::cast(u), v: pulp::cast(v) }
                },
            )
        }

        /// `Block::spheres` on two blocks at once, 256 bits wide, each
        /// lane its arithmetic to the bit: the lanes hit (block 0's in bits
        /// 0-3, block 1's in 4-7) and per lane the nearest root within
        /// the segment.
        #[inline(never)]
        pub fn spheres2(
            self,
            b: [&Block; 2],
            ray: &Ray,
            t_min: f32,
            t_max: f32,
        ) -> (u32, [f32; 8]) {
            let x = Ops(self.0);
            self.0.vectorize(
                #[inline(always)]
                move || {
                    let v = |k: usize| x.join(b[0].v[k], b[1].v[k]);
                    let (d, o) = (ray.dir, ray.origin);
                    let (dx, dy, dz) = (x.splat(d.x), x.splat(d.y), x.splat(d.z));
                    let (fx, fy, fz) = (
                        x.sub(x.splat(o.x), v(0)),
                        x.sub(x.splat(o.y), v(1)),
                        x.sub(x.splat(o.z), v(2)),
                    );
                    let r = v(3);
                    let r2 = x.mul(r, r);
                    let a = x.splat(d.length_squared());
                    let dot = |px, py, pz, qx, qy, qz| {
                        x.add(x.add(x.mul(px, qx), x.mul(py, qy)), x.mul(pz, qz))
                    };
                    let minus = x.splat(-0.0);
                    let bb = self.0.avx._mm256_xor_ps(minus, dot(fx, fy, fz, dx, dy, dz));
                    let ba = x.div(bb, a);
                    let (lx, ly, lz) = (
                        x.add(fx, x.mul(dx, ba)),
                        x.add(fy, x.mul(dy, ba)),
                        x.add(fz, x.mul(dz, ba)),
                    );
                    let disc = x.mul(a, x.sub(r2, dot(lx, ly, lz, lx, ly, lz)));
                    let zero = self.0.avx._mm256_setzero_ps();
                    if x.bits(x.le(zero, disc)) == 0 {
                        return (0, [0.0; 8]);
                    }
                    let c = x.sub(dot(fx, fy, fz, fx, fy, fz), r2);
                    // `Vec4::signum`: ±1 by the sign bit, NaN kept.
                    let one = x.or(x.and(bb, minus), x.splat(1.0));
                    let sign = x.select(x.ne(bb, bb), bb, one);
                    let q = x.add(bb, x.mul(sign, self.0.avx._mm256_sqrt_ps(disc)));
                    let (t0, t1) = (x.div(c, q), x.div(q, a));
                    let order = x.lt(t0, t1);
                    let (lo, hi) = (x.select(order, t0, t1), x.select(order, t1, t0));
                    let (min, max) = (x.splat(t_min), x.splat(t_max));
                    let in_lo = x.and(x.lt(min, lo), x.lt(lo, max));
                    let in_hi = x.and(x.lt(min, hi), x.lt(hi, max));
                    let ok = x.and(x.and_not(x.ne(q, zero), x.lt(disc, zero)), x.or(in_lo, in_hi));
                    (x.bits(ok), pulp::cast(x.select(in_lo, lo, hi)))
                },
            )
        }
    }

    impl Kernel for Avx2 {
        type Node = Wide8;
        type Slabs = Slabs8;
        type Near = [f32; 8];
        type Frustum = Frustum8;

        #[inline(always)]
        fn slabs(self, ray: &Ray) -> Slabs8 {
            let avx = self.0.avx;
            let i = [inv(ray.dir.x), inv(ray.dir.y), inv(ray.dir.z)];
            Slabs8 {
                org: [ray.origin.x, ray.origin.y, ray.origin.z].map(|o| avx._mm256_set1_ps(o)),
                inv: i.map(|i| avx._mm256_set1_ps(i)),
                near: near_planes(i),
            }
        }

        /// The same arithmetic as the 4-wide test, lane for lane (no fused
        /// multiply-adds; `min`/`max`/`<=` as SSE's), so a child's entry
        /// and exit are the same to the bit in either kind of node.
        #[inline(always)]
        fn hit(self, n: &Wide8, r: &Slabs8, t_min: f32, t_max: f32) -> (u32, [f32; 8]) {
            let avx = self.0.avx;
            let [nx, ny, nz] = r.near;
            let t = |axis: usize, side: usize| {
                let b: __m256 = pulp::cast(n.b[axis][side & 1]);
                avx._mm256_mul_ps(avx._mm256_sub_ps(b, r.org[axis]), r.inv[axis])
            };
            let (tnx, tfx) = (t(0, nx), t(0, nx ^ 1));
            let (tny, tfy) = (t(1, ny), t(1, ny ^ 1));
            let (tnz, tfz) = (t(2, nz), t(2, nz ^ 1));
            let (min, max) = (|a, b| avx._mm256_min_ps(a, b), |a, b| avx._mm256_max_ps(a, b));
            let near = max(max(tnx, tny), max(tnz, avx._mm256_set1_ps(t_min)));
            let far = avx._mm256_mul_ps(
                min(min(tfx, tfy), min(tfz, avx._mm256_set1_ps(t_max))),
                avx._mm256_set1_ps(ROBUST),
            );
            let mask = avx._mm256_movemask_ps(avx._mm256_cmp_ps::<_CMP_LE_OS>(near, far));
            (mask as u32, pulp::cast(near))
        }

        #[inline(always)]
        fn entering(self, p: &Rays, b: &Aabb, t_min: f32, t_max: &[f32; PACKET]) -> u64 {
            p.entering8(self.0, b, t_min, t_max)
        }

        #[inline(always)]
        fn segments_entering(
            self,
            p: &Segments,
            b: &Aabb,
            t_max: &[f32; PACKET],
            live: u64,
        ) -> u64 {
            p.entering8(self.0, b, t_max, live)
        }

        #[inline(always)]
        fn prefetch(self) -> Prefetch {
            Prefetch::of(self.0)
        }

        #[inline(always)]
        fn frustum(self, f: &Frustum) -> Frustum8 {
            let avx = self.0.avx;
            let splat = |v: [f32; 3]| v.map(|x| avx._mm256_set1_ps(x));
            Frustum8 { org: splat(f.org), lo: splat(f.lo), hi: splat(f.hi), near: f.near }
        }

        /// The 4-wide interval test's arithmetic, lane for lane.
        #[inline(always)]
        fn hit_frustum(self, n: &Wide8, f: &Frustum8, t_min: f32, t_max: f32) -> (u32, [f32; 8]) {
            let avx = self.0.avx;
            let [nx, ny, nz] = f.near;
            let (min, max) = (|a, b| avx._mm256_min_ps(a, b), |a, b| avx._mm256_max_ps(a, b));
            let mul = |a, b| avx._mm256_mul_ps(a, b);
            let d = |axis: usize, side: usize| {
                let b: __m256 = pulp::cast(n.b[axis][side & 1]);
                avx._mm256_sub_ps(b, f.org[axis])
            };
            let enter = |axis: usize, side: usize| {
                let d = d(axis, side);
                min(mul(d, f.lo[axis]), mul(d, f.hi[axis]))
            };
            let exit = |axis: usize, side: usize| {
                let d = d(axis, side);
                max(mul(d, f.lo[axis]), mul(d, f.hi[axis]))
            };
            let near =
                max(max(enter(0, nx), enter(1, ny)), max(enter(2, nz), avx._mm256_set1_ps(t_min)));
            let far = mul(
                min(
                    min(exit(0, nx ^ 1), exit(1, ny ^ 1)),
                    min(exit(2, nz ^ 1), avx._mm256_set1_ps(t_max)),
                ),
                avx._mm256_set1_ps(ROBUST),
            );
            let mask = avx._mm256_movemask_ps(avx._mm256_cmp_ps::<_CMP_LE_OS>(near, far));
            (mask as u32, pulp::cast(near))
        }
    }
}
