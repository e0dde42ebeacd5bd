//! rayshell: a ray tracer driven by a Tcl-style scene language.
//!
//! A scene file is a Tcl script. The `shell` runs it in the `interp`reter,
//! whose scene commands change a `scene::Builder`; `render` freezes the
//! builder into a `scene::Scene` (building its BVH) and the `render` module
//! traces it into an `image::Image`.
//!
//! # Codemap (in reading order)
//!
//! - `interp`: a Tcl 8.6-compatible interpreter: `parser` (Script, Command,
//!   Word), `value` (Value), `eval` (Interp), `compile` (proc bodies as
//!   trees with locals in slots), `stream` (whole files, the scanner
//!   thread), `expr`, `builtins`. It knows nothing about graphics.
//! - `geometry`: rays (with a time), boxes, spheres, watertight triangles,
//!   cones and cylinders,
//!   the BVH (a binned SAH binary tree collapsed by the least-area plan,
//!   `bvh::Plan`, into 8-wide nodes where the CPU has AVX2, else 4-wide:
//!   `bvh::wide`) whose leaves hold blocks of four primitives tested in
//!   SIMD lanes (`blocks`: coordinates only; a record per lane; a leaf's
//!   two blocks of triangles or spheres in one AVX2 pass), walked
//!   by single rays, by packets of camera rays (`bvh::packet`) or of
//!   shadow rays toward one light (`bvh::shadow`), and
//!   objects, leaves of their own kind (`object`): placed
//!   analytic solids (`solid`, with `poly`'s root finder for the torus),
//!   CSG by intervals (`csg`), blobs (`blob`), lazily generated fractals
//!   (`fractal`), and trees of their own (instances, moving primitives).
//! - `scene`: `Builder` (mutable, checked, double precision; its transform
//!   stack, CSG, blobs and groups in `objects`), textures and our Perlin
//!   noise (`texture`), displacement (`displace`), what the path tracer
//!   samples light from (`emitters`: lights, emitting surfaces, the sky
//!   map, chosen by power), `Scene`
//!   (frozen, single precision relative to the eye: one BVH over the still
//!   primitives and one per velocity of moving ones, walked by rays moved
//!   back to time 0), camera, lights, materials, sampling settings.
//! - `render`: the Whitted tracer (`tracer`: samples per pixel, shading,
//!   lights with a size, the media a ray is in, ray offsets) and the path
//!   tracer (`path`: next-event estimation with MIS, Russian roulette),
//!   parallel over tiles; `sample`: hashed random numbers, stratified points (CMJ) and
//!   filter importance sampling; `job` says which pixels (crops), in what
//!   order (progressive passes), and carries progress and cancellation;
//!   a picture for a file gets its look and its bytes band by band as it
//!   is traced (`render_finished`).
//! - `image`: the linear f32 image, PPM and PNG writers and readers (with a
//!   crop's placement).
//! - `mem`: the memory budget: a counting allocator, `reserve` before big
//!   growth, `grew_past` after each command. A leaf every layer may use.
//! - `shell`: the glue and the only module that touches files, the terminal,
//!   signals, the environment and exit codes: arguments, the REPL (with
//!   completion), the scene commands (`commands`, `structure` for shapes,
//!   transforms, CSG and groups, `surface` for textures, highlights, bumps
//!   and displacement) and their documentation
//!   (`docs`, also the README's table), OBJ loading (`obj`: plain or gzip,
//!   in one pass of our own, tobj the reference it falls back to), NFF
//!   scenes (`nff`), atomic
//!   files, statistics and the last picture (`stats`), progress bars, ETA
//!   and Ctrl-C (`feedback`), the preview window (`preview`), pictures in
//!   the terminal (`term`), animation batches, merges and movies (`frames`),
//!   and the `--safe` fence (`safe`: every path a scene names is resolved
//!   by the kernel beneath an allowed directory, `docs/safe.md`).
//!
//! # Invariants
//!
//! - `interp` imports nothing else from this crate but `mem`; `geometry`, `scene`,
//!   `render` and `image` never see interpreter values (`tests/it/tidy.rs`
//!   checks the layering).
//! - Only `shell` does I/O; `image` writes to `impl Write`.
//! - Rendering reads a frozen `Scene`; every random number is a hash of
//!   (seed, frame, pixel, sample, dimension), and each pixel depends on its
//!   own samples only: the picture is the same for any thread count, tile
//!   order, pass order, crop or shard.
//! - The BVH's four-lane triangle test does the scalar watertight test's
//!   arithmetic lane for lane: the same hits, to the bit.
//! - A packet of rays finds each ray's hit as the ray alone does, to the
//!   bit: its node test is conservative to the bit, its leaf tests are the
//!   single ray's. A shadow packet's answer (blocked, clear) is the ray's
//!   own walk's, so whether a block goes as a packet changes no pixel.
//! - The builder keeps positions in double precision; a frozen `Scene` is
//!   single precision with the eye at the origin, and no tolerance in the
//!   renderer is absolute: the picture does not depend on where the scene
//!   sits or on its scale.
//! - Of hits within `bvh::TIE` of each other, the primitive added to the
//!   scene first wins: coplanar surfaces resolve the same way for any tree
//!   (still or moving), walk order, lane or thread count (a tree numbers
//!   up to 2^29 primitives; past that they share a number, and their ties
//!   follow the walk, still the same for any thread count).
//! - A compiled proc body (`interp/compile.rs`) is an optimisation, never
//!   a second semantics: each compiled command keeps its parsed source and
//!   runs it the ordinary way whenever a builtin it inlines was redefined
//!   (`inline_epoch`) or a trace is set; a variable is found by name from
//!   anywhere, slots included (`Frame::get`).
//! - A Tcl coroutine runs on its own native stack and the `Interp` moves by
//!   value between it and its resumer (`interp/builtins/coro.rs`): nothing
//!   keeps a reference into the `Interp` across a `yield`, and a variable
//!   trace or a coroutine never needs `unsafe`.
//! - A BVH depends only on the builder's geometry and its eye: every scene
//!   command bumps `Builder::geometry` but those the shell lists as
//!   changing the view alone (`shell/commands.rs`, `VIEW_ONLY`), and the
//!   shell reuses the last render's tree only for the same geometry and eye
//!   (bit for bit), so a reused tree is the tree a fresh run builds.
//! - A ray carries its time; every ray spawned from it keeps it.
//! - An object is entered by its inverse transform with the direction left
//!   unnormalized, so a hit's `t` is the same in every coordinate system;
//!   normals leave by the inverse transpose.
//! - Nothing recurses without a bound at render time: instances nest at
//!   most 32 deep, fractals 10, CSG and `push` 1,000.
//! - An image reaches its final name only whole (`shell::AtomicFile`).
//! - Under `--safe`, no path a scene names reaches a file or directory that
//!   is not beneath an allowed directory as the kernel resolves it
//!   (`openat2` with `RESOLVE_BENEATH`): every command that takes a path
//!   asks `shell::safe` (`tests/it/safe.rs` walks the command table), and
//!   a picture is never written through a link.
//! - No input makes the program abort or run the machine out of memory:
//!   growth that could pass the budget (`mem`) is refused as an error, and
//!   nothing recurses natively without a bound (nested lists are printed
//!   and freed with explicit stacks; evaluation depth is capped).
//! - No input makes the program panic: bad scripts are `Exception`s with a
//!   file and line; a panic that slips through still exits 70, never 101.

pub mod geometry;
pub mod image;
pub mod interp;
pub mod mem;
pub mod render;
pub mod scene;
pub mod shell;
