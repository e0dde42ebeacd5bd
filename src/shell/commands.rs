//! The .tsd vocabulary: each scene command checks its arity, converts its
//! words to numbers and calls one `scene::Builder` method. Errors use Tcl's
//! wording (`wrong # args: should be "sphere x y z radius"`). Commands whose
//! arguments are all numbers are registered as numeric commands, so long
//! generated scenes skip building values.

use std::cell::RefCell;
use std::rc::Rc;
use std::time::Instant;

use glam::{DVec3, Vec3};

use crate::image::{Encoding, Format};
use crate::interp::{Exception, Interp, Num, Value, check_args, format_double};
use crate::render;
use crate::scene::{
    Builder, Falloff, Filter, FilterKind, Integrator, Light, Material, Scene, SceneError, Tonemap,
};

use super::stats::{Picture, RenderReport, ShellState};

pub(super) fn scene_err(e: SceneError) -> Exception {
    Exception::error(e.to_string())
}

/// A numeric command's arguments, with the names its usage gives them, so
/// every conversion error names the argument:
/// `sphere: radius: expected integer but got "2.5"`.
pub(super) struct Args<'a> {
    nums: &'a [Num],
    name: &'a str,
    usage: &'a str,
}

impl Args<'_> {
    fn err(&self, i: usize, msg: impl std::fmt::Display) -> Exception {
        let arg = self.usage.split_whitespace().nth(i).map_or("?", |w| w.trim_matches('?'));
        Exception::error(format!("{}: {arg}: {msg}", self.name))
    }

    /// Argument `i` as a finite double.
    pub(super) fn f64(&self, i: usize) -> Result<f64, Exception> {
        let x = self.nums[i].to_f64();
        if !x.is_finite() {
            return Err(
                self.err(i, format!("expected a finite number but got \"{}\"", format_double(x)))
            );
        }
        if x.abs() > f32::MAX as f64 {
            return Err(self.err(i, format!("number {} is too large", format_double(x))));
        }
        Ok(x)
    }

    /// Argument `i` as a finite single.
    pub(super) fn f32(&self, i: usize) -> Result<f32, Exception> {
        Ok(self.f64(i)? as f32)
    }

    /// Arguments `i..i+3` as a position (double precision).
    pub(super) fn pos(&self, i: usize) -> Result<DVec3, Exception> {
        Ok(DVec3::new(self.f64(i)?, self.f64(i + 1)?, self.f64(i + 2)?))
    }

    /// Arguments `i..i+3` as a direction or colour.
    pub(super) fn vec3(&self, i: usize) -> Result<Vec3, Exception> {
        Ok(Vec3::new(self.f32(i)?, self.f32(i + 1)?, self.f32(i + 2)?))
    }

    /// The optional falloff coefficients at `i..i+3` of a light command
    /// given `count` numbers: all three or none (1/r²).
    pub(super) fn falloff(&self, i: usize, count: usize) -> Result<Falloff, Exception> {
        if count == i {
            return Ok(Falloff::INVERSE_SQUARE);
        }
        if count != i + 3 {
            return Err(Exception::wrong_args(&format!("{} {}", self.name, self.usage)));
        }
        Falloff::new(self.f32(i)?, self.f32(i + 1)?, self.f32(i + 2)?).map_err(scene_err)
    }

    /// Argument `i` as an integer: any number syntax with an integral
    /// value (`5`, `5.0`, `1e3`), as C `printf` and converters write them.
    pub(super) fn int(&self, i: usize) -> Result<i64, Exception> {
        match &self.nums[i] {
            Num::Int(n) => Ok(*n),
            Num::Double(d) if d.fract() == 0.0 && d.abs() < 9.0e18 => Ok(*d as i64),
            Num::Double(d) => {
                Err(self.err(i, format!("expected integer but got \"{}\"", format_double(*d))))
            }
            Num::Big(b) => Err(self.err(i, format!("integer {b} is too large"))),
        }
    }
}

pub(super) type Shared = Rc<RefCell<Builder>>;

/// The builder, to change: counted as a change (a render after it traces
/// again), of the geometry too (it builds its BVH again).
pub(super) fn edit(scene: &Shared) -> std::cell::RefMut<'_, Builder> {
    let mut b = scene.borrow_mut();
    b.generation += 1;
    b.geometry = b.generation;
    b
}

/// `edit` for a command that changes nothing a BVH is built from (the
/// eye's position is part of the tree's key instead): a render after it
/// traces again with the last render's tree.
pub(super) fn edit_view(scene: &Shared) -> std::cell::RefMut<'_, Builder> {
    let mut b = scene.borrow_mut();
    b.generation += 1;
    b
}

/// The numeric scene commands that change only the view, the lights, the
/// materials to come or the sampling (see `edit_view`). Any other command
/// counts as a change of the geometry.
const VIEW_ONLY: &[&str] = &[
    "camera_from",
    "camera_target",
    "camera_forw",
    "camera_up",
    "camera_angle",
    "camera_resolution",
    "camera_aperture",
    "camera_focus",
    "background",
    "ambient_light",
    "parallel_light",
    "point_light",
    "spot_light",
    "area_light",
    "sphere_light",
    "material",
    "trace_depth",
    "samples",
    "seed",
    "exposure",
];

/// `edit` or `edit_view` (as `VIEW_ONLY` says for the command, once, when
/// it is registered).
fn editor(name: &str) -> fn(&Shared) -> std::cell::RefMut<'_, Builder> {
    if VIEW_ONLY.contains(&name) { edit_view } else { edit }
}

/// Registers a numeric scene command that changes the builder.
pub(super) fn numeric(
    interp: &mut Interp,
    scene: &Shared,
    name: &str,
    usage: &str,
    summary: &str,
    f: impl Fn(&mut Builder, &Args) -> Result<Option<Num>, Exception> + 'static,
) {
    let arity = usage.split_whitespace().count();
    let s = scene.clone();
    let (n, u) = (name.to_string(), usage.to_string());
    let change = editor(name);
    interp.register_numeric(name, arity, usage, summary, move |_, nums| {
        let mut b = change(&s);
        f(&mut b, &Args { nums, name: &n, usage: &u })
    });
}

/// A word naming one of a closed set (`names` lists them for the message).
pub(super) fn choice<T>(
    v: &Value,
    what: &str,
    parse: fn(&str) -> Option<T>,
    names: &str,
) -> Result<T, Exception> {
    parse(v.as_str())
        .ok_or_else(|| Exception::error(format!("bad {what} \"{}\": must be {names}", v.as_str())))
}

/// A word that must be a finite number (`what` names it in the message).
pub(super) fn finite_arg(v: &Value, what: &str) -> Result<f64, Exception> {
    match v.as_num().map(|n| n.to_f64()) {
        Some(x) if x.is_finite() => Ok(x),
        _ => Err(Exception::error(format!(
            "{what}: expected a finite number but got \"{}\"",
            v.as_str()
        ))),
    }
}

/// `numeric` for a command whose last `optional` numbers may be left out
/// (`usage` writes them as `?n?`): `f` sees how many were given.
pub(super) fn numeric_opt(
    interp: &mut Interp,
    scene: &Shared,
    name: &str,
    usage: &str,
    optional: usize,
    summary: &str,
    f: impl Fn(&mut Builder, &Args, usize) -> Result<(), Exception> + 'static,
) {
    let words: Vec<String> =
        usage.split_whitespace().map(|w| w.trim_matches(['?']).to_string()).collect();
    let max = words.len();
    let s = scene.clone();
    let (n, u) = (name.to_string(), usage.to_string());
    let change = editor(name);
    interp.register_host(name, usage, summary, move |_, argv| {
        check_args(argv, max + 1 - optional, max + 1, &u)?;
        let mut nums = Vec::with_capacity(argv.len() - 1);
        for (i, v) in argv[1..].iter().enumerate() {
            nums.push(v.as_num().ok_or_else(|| {
                Exception::error(format!(
                    "{n}: {}: expected number but got \"{}\"",
                    words[i],
                    v.as_str()
                ))
            })?);
        }
        let mut b = change(&s);
        f(&mut b, &Args { nums: &nums, name: &n, usage: &u }, nums.len())?;
        Ok(Value::empty())
    });
}

/// Registers the scene commands, sharing one builder and the shell state.
pub fn register(interp: &mut Interp, scene: Shared, state: Rc<RefCell<ShellState>>) {
    super::structure::register(interp, &scene);
    super::surface::register(interp, &scene);
    let e = scene_err;
    numeric(interp, &scene, "camera_from", "x y z", "where the camera is", move |b, a| {
        b.camera_from(a.pos(0)?).map_err(e)?;
        Ok(None)
    });
    numeric(
        interp,
        &scene,
        "camera_target",
        "x y z",
        "the point the camera looks at",
        move |b, a| {
            b.camera_target(a.pos(0)?).map_err(e)?;
            Ok(None)
        },
    );
    numeric(
        interp,
        &scene,
        "camera_forw",
        "x y z",
        "the direction the camera looks along",
        move |b, a| {
            b.camera_forward(a.pos(0)?).map_err(e)?;
            Ok(None)
        },
    );
    numeric(interp, &scene, "camera_up", "x y z", "the camera's up direction", move |b, a| {
        b.camera_up(a.vec3(0)?).map_err(e)?;
        Ok(None)
    });
    numeric(
        interp,
        &scene,
        "camera_angle",
        "theta",
        "field of view in degrees, left edge to right edge",
        move |b, a| {
            b.camera_angle(a.f32(0)?).map_err(e)?;
            Ok(None)
        },
    );
    numeric(
        interp,
        &scene,
        "camera_resolution",
        "width height",
        "image size in pixels",
        move |b, a| {
            b.camera_resolution(a.int(0)?, a.int(1)?).map_err(e)?;
            Ok(None)
        },
    );
    numeric(
        interp,
        &scene,
        "max_vertices",
        "n",
        "capacity hint for the vertex pool",
        move |b, a| {
            b.reserve_vertices(a.int(0)?);
            Ok(None)
        },
    );
    numeric(
        interp,
        &scene,
        "max_normals",
        "n",
        "capacity hint for the normal pool",
        move |b, a| {
            b.reserve_normals(a.int(0)?);
            Ok(None)
        },
    );
    numeric(interp, &scene, "vertex", "x y z", "add a vertex; returns its index", move |b, a| {
        Ok(Some(Num::Int(b.vertex(a.pos(0)?).map_err(e)? as i64)))
    });
    numeric(interp, &scene, "normal", "x y z", "add a normal; returns its index", move |b, a| {
        Ok(Some(Num::Int(b.normal(a.vec3(0)?).map_err(e)? as i64)))
    });
    numeric(
        interp,
        &scene,
        "tri",
        "v1 v2 v3",
        "add a flat triangle (vertex indices, counter-clockwise)",
        move |b, a| {
            b.tri([a.int(0)?, a.int(1)?, a.int(2)?]).map_err(e)?;
            Ok(None)
        },
    );
    numeric(
        interp,
        &scene,
        "ntri",
        "v1 n1 v2 n2 v3 n3",
        "add a smooth triangle (vertex and normal indices)",
        move |b, a| {
            let mut vn = [(0, 0); 3];
            for (k, slot) in vn.iter_mut().enumerate() {
                *slot = (a.int(2 * k)?, a.int(2 * k + 1)?);
            }
            b.ntri(vn).map_err(e)?;
            Ok(None)
        },
    );
    numeric(interp, &scene, "sphere", "x y z radius", "add a sphere", move |b, a| {
        b.sphere(a.pos(0)?, a.f64(3)?).map_err(e)?;
        Ok(None)
    });
    numeric(
        interp,
        &scene,
        "background",
        "r g b",
        "the colour of rays that hit nothing",
        move |b, a| {
            b.set_background(a.vec3(0)?).map_err(e)?;
            Ok(None)
        },
    );
    numeric(
        interp,
        &scene,
        "ambient_light",
        "r g b",
        "the ambient light (a later call replaces it)",
        move |b, a| {
            b.set_ambient(a.vec3(0)?).map_err(e)?;
            Ok(None)
        },
    );
    numeric(
        interp,
        &scene,
        "parallel_light",
        "r g b x y z",
        "a light infinitely far away, travelling along (x, y, z)",
        move |b, a| {
            b.add_light(Light::parallel(a.vec3(0)?, a.vec3(3)?).map_err(e)?).map_err(e)?;
            Ok(None)
        },
    );
    numeric_opt(
        interp,
        &scene,
        "point_light",
        "r g b x y z ?constant linear quadratic?",
        3,
        "a light at (x, y, z), falling off as 1/r^2 (or 1/(constant + linear r + quadratic r^2))",
        move |b, a, count| {
            let falloff = a.falloff(6, count)?;
            b.add_light(Light::point(a.vec3(0)?, a.pos(3)?, falloff).map_err(e)?).map_err(e)
        },
    );
    numeric_opt(
        interp,
        &scene,
        "spot_light",
        "r g b px py pz nx ny nz angle1 angle2 ?constant linear quadratic?",
        3,
        "a spot light at p shining along n: full within angle1, fading to nothing at angle2 (degrees)",
        move |b, a, count| {
            let falloff = a.falloff(11, count)?;
            let l = Light::spot(a.vec3(0)?, a.pos(3)?, a.vec3(6)?, a.f32(9)?, a.f32(10)?, falloff)
                .map_err(e)?;
            b.add_light(l).map_err(e)
        },
    );
    numeric_opt(
        interp,
        &scene,
        "area_light",
        "r g b x y z ux uy uz vx vy vz ?n?",
        1,
        "a parallelogram light of radiance (r, g, b), corner (x, y, z), edges u and v, lit side u × v; n × n samples",
        move |b, a, count| {
            let n = if count > 12 { a.int(12)? } else { 4 };
            let l = Light::area(a.vec3(0)?, a.pos(3)?, a.vec3(6)?, a.vec3(9)?, n).map_err(e)?;
            b.add_light(l).map_err(e)
        },
    );
    numeric_opt(
        interp,
        &scene,
        "sphere_light",
        "r g b x y z radius ?n?",
        1,
        "a spherical light of radiance (r, g, b); n × n samples by solid angle",
        move |b, a, count| {
            let n = if count > 7 { a.int(7)? } else { 4 };
            let l = Light::sphere(a.vec3(0)?, a.pos(3)?, a.f32(6)?, n).map_err(e)?;
            b.add_light(l).map_err(e)
        },
    );
    numeric(
        interp,
        &scene,
        "material",
        "r g b Ka Kd Ks n_s T index_of_refraction",
        "the material of the objects that follow",
        move |b, a| {
            let m = Material {
                color: a.vec3(0)?,
                ka: a.f32(3)?,
                kd: a.f32(4)?,
                ks: a.f32(5)?,
                ns: a.f32(6)?,
                t: a.f32(7)?,
                ior: a.f32(8)?,
                ..Material::default()
            };
            b.set_material(m).map_err(e)?;
            Ok(None)
        },
    );
    numeric(interp, &scene, "trace_depth", "n", "the most bounces a ray makes", move |b, a| {
        b.set_trace_depth(a.int(0)?).map_err(e)?;
        Ok(None)
    });
    numeric(interp, &scene, "camera_aperture", "r", "the thin lens's radius", move |b, a| {
        b.set_aperture(a.f64(0)?).map_err(e)?;
        Ok(None)
    });
    numeric(interp, &scene, "camera_focus", "d", "the distance in focus", move |b, a| {
        b.set_focus(a.f64(0)?).map_err(e)?;
        Ok(None)
    });
    numeric(
        interp,
        &scene,
        "shutter",
        "t0 t1",
        "the shutter interval camera rays sample",
        move |b, a| {
            b.sampling.set_shutter(a.f64(0)?, a.f64(1)?).map_err(e)?;
            Ok(None)
        },
    );
    numeric(
        interp,
        &scene,
        "motion",
        "dx dy dz",
        "the velocity of the objects that follow, per unit of time",
        move |b, a| {
            b.set_motion(a.pos(0)?).map_err(e)?;
            Ok(None)
        },
    );
    numeric(interp, &scene, "samples", "n", "camera rays per pixel, stratified", move |b, a| {
        b.sampling.set_samples(a.int(0)?).map_err(e)?;
        Ok(None)
    });
    numeric(interp, &scene, "seed", "n", "the noise pattern", move |b, a| {
        b.sampling.seed = a.int(0)? as u64;
        Ok(None)
    });
    numeric(interp, &scene, "exposure", "ev", "multiply by 2^ev before output", move |b, a| {
        b.sampling.set_exposure(a.f64(0)?).map_err(e)?;
        Ok(None)
    });
    let s = scene.clone();
    interp.register_host(
        "filter",
        "box|tent|gaussian|mitchell ?radius?",
        "the pixel reconstruction filter (radius in pixels)",
        move |_, argv| {
            check_args(argv, 2, 3, "box|tent|gaussian|mitchell ?radius?")?;
            let kind = choice(&argv[1], "filter", FilterKind::parse, FilterKind::NAMES)?;
            let radius = match argv.get(2) {
                Some(v) => Some(finite_arg(v, "filter: radius")? as f32),
                None => None,
            };
            let mut b = edit_view(&s);
            b.sampling.filter = Filter::new(kind, radius).map_err(e)?;
            Ok(Value::empty())
        },
    );
    let s = scene.clone();
    interp.register_host(
        "adaptive",
        "threshold ?max?",
        "add samples where the pixel is still uncertain",
        move |_, argv| {
            check_args(argv, 2, 3, "threshold ?max?")?;
            let threshold = finite_arg(&argv[1], "adaptive: threshold")?;
            let max = match argv.get(2) {
                Some(v) => Some(v.as_int()?),
                None => None,
            };
            let mut b = edit_view(&s);
            b.sampling.set_adaptive(threshold, max).map_err(e)?;
            Ok(Value::empty())
        },
    );
    let s = scene.clone();
    interp.register_host(
        "tonemap",
        "clamp|reinhard|aces",
        "how values above 1 reach the file",
        move |_, argv| {
            check_args(argv, 2, 2, "clamp|reinhard|aces")?;
            let t = choice(&argv[1], "tone map", Tonemap::parse, Tonemap::NAMES)?;
            let mut b = edit_view(&s);
            b.sampling.tonemap = t;
            Ok(Value::empty())
        },
    );
    let s = scene.clone();
    interp.register_host(
        "integrator",
        "whitted|path",
        "the light transport of the next renders",
        move |_, argv| {
            check_args(argv, 2, 2, "whitted|path")?;
            let i = choice(&argv[1], "integrator", Integrator::parse, Integrator::NAMES)?;
            edit_view(&s).sampling.integrator = i;
            Ok(Value::empty())
        },
    );
    let s = scene.clone();
    interp.register_host(
        "clear_scene",
        "",
        "reset the scene (camera, geometry, lights, materials) to the defaults",
        move |_, argv| {
            check_args(argv, 1, 1, "")?;
            s.borrow_mut().clear();
            Ok(Value::empty())
        },
    );
    let s = scene.clone();
    interp.register_host(
        "scene_bounds",
        "",
        "the bounding box of all geometry: xmin ymin zmin xmax ymax zmax",
        move |_, argv| {
            check_args(argv, 1, 1, "")?;
            let Some((lo, hi)) = s.borrow().bounds() else {
                return Ok(Value::empty());
            };
            let v = [lo.x, lo.y, lo.z, hi.x, hi.y, hi.z];
            Ok(Value::from_list(v.iter().map(|&x| Value::from_f64(x)).collect()))
        },
    );
    let s = scene.clone();
    interp.register_host(
        "mesh",
        "fileName ?-scale s? ?-translate x y z? ?-subdivide n? ?-flat?",
        "add an OBJ mesh with the current material; returns its triangle count",
        move |_, argv| {
            let mut b = edit(&s);
            mesh_command(&mut b, argv)
        },
    );
    let s = scene.clone();
    let st = state.clone();
    interp.register_host(
        "render",
        "?-srgb? ?-heatmap? ?-progressive? fileName",
        "trace the scene and write it (.ppm or .png); -heatmap colours pixels by BVH traversal steps, -progressive traces coarse-to-fine",
        move |interp, argv| render_command(interp, &s.borrow(), &st, argv),
    );
    let s = scene.clone();
    let st = state.clone();
    interp.register_host(
        "raybench",
        "?-shadow? ?-brute? ?-threads count?",
        "trace the primary rays (and shadow rays to the first light) without shading; returns timings (-brute adds the brute-force baseline; -threads runs on a pool of that many threads)",
        move |_, argv| raybench_command(&s.borrow(), &st, argv),
    );
    let st = state.clone();
    interp.register_host(
        "preview",
        "?on|term|off?",
        "show renders in a window as they are traced (on: needs the preview feature and a display), or in the terminal when each finishes (term)",
        move |_, argv| {
            check_args(argv, 1, 2, "?on|term|off?")?;
            let fb = &mut st.borrow_mut().feedback;
            match argv.get(1).map(|v| v.as_str()) {
                None => {}
                Some("on") if fb.preview.is_none() => {
                    fb.preview = Some(super::preview::Preview::open().map_err(Exception::error)?);
                }
                Some("on") => {}
                Some("term") => fb.show_in_terminal = true,
                Some("off") => {
                    fb.preview = None;
                    fb.show_in_terminal = false;
                }
                Some(o) => {
                    return Err(Exception::error(format!(
                        "bad option \"{o}\": must be on, term or off"
                    )));
                }
            }
            Ok(Value::from(match (fb.preview.is_some(), fb.show_in_terminal) {
                (true, true) => "on term",
                (true, false) => "on",
                (false, true) => "term",
                (false, false) => "off",
            }))
        },
    );
    let s = scene.clone();
    let st = state.clone();
    interp.register_host(
        "show",
        "?-blocks? ?-width cells? ?fileName?",
        "draw the last render (or an image file, or a quick preview of the scene) in the terminal: kitty, iTerm2 or sixel graphics where the terminal has them, else colour half-blocks",
        move |interp, argv| show_command(interp, &s.borrow(), &st, argv),
    );
    interp.register_host("stats", "", "statistics of the last render", move |_, argv| {
        check_args(argv, 1, 1, "")?;
        Ok(Value::from_string(
            state
                .borrow()
                .last
                .as_ref()
                .map(|r| r.to_string())
                .unwrap_or_else(|| "no render yet".into()),
        ))
    });
}

fn mesh_command(b: &mut Builder, argv: &[Value]) -> Result<Value, Exception> {
    let usage = "mesh fileName ?-scale s? ?-translate x y z? ?-subdivide n? ?-flat?";
    if argv.len() < 2 {
        return Err(Exception::wrong_args(usage));
    }
    let (mut scale, mut translate, mut flat) = (1.0f64, DVec3::ZERO, false);
    let mut subdivide = 0u32;
    let num = |v: &Value, what: &str| -> Result<f64, Exception> {
        let bad = |msg: String| Exception::error(format!("mesh: {what}: {msg}"));
        let x = v
            .as_num()
            .ok_or_else(|| bad(format!("expected number but got \"{}\"", v.as_str())))?
            .to_f64();
        if !x.is_finite() || x.abs() > f32::MAX as f64 {
            return Err(bad(format!("expected a finite number but got \"{}\"", v.as_str())));
        }
        Ok(x)
    };
    let mut i = 2;
    while i < argv.len() {
        match argv[i].as_str() {
            "-scale" if i + 1 < argv.len() => {
                scale = num(&argv[i + 1], "-scale")?;
                if scale == 0.0 {
                    return Err(Exception::error("mesh -scale must not be zero"));
                }
                i += 2;
            }
            "-translate" if i + 3 < argv.len() => {
                translate = DVec3::new(
                    num(&argv[i + 1], "-translate x")?,
                    num(&argv[i + 2], "-translate y")?,
                    num(&argv[i + 3], "-translate z")?,
                );
                i += 4;
            }
            "-flat" => {
                flat = true;
                i += 1;
            }
            "-subdivide" if i + 1 < argv.len() => {
                let n = num(&argv[i + 1], "-subdivide")?;
                let max = crate::scene::MAX_SUBDIVIDE;
                if !(n >= 0.0 && n <= max as f64 && n.fract() == 0.0) {
                    return Err(Exception::error(format!(
                        "mesh -subdivide must be a whole number from 0 to {max}, got {}",
                        argv[i + 1].as_str()
                    )));
                }
                subdivide = n as u32;
                i += 2;
            }
            "-scale" | "-translate" | "-subdivide" => return Err(Exception::wrong_args(usage)),
            o => {
                return Err(Exception::error(format!(
                    "bad option \"{o}\": must be -flat, -scale, -subdivide, or -translate"
                )));
            }
        }
    }
    let path = argv[1].as_str().to_string();
    super::safe::check_read(&path)?;
    let p = path.clone();
    let data = super::feedback::blocking(&path, move || super::obj::load(&p))
        .map_err(|_| super::interrupted())?
        .map_err(|e| {
            if super::feedback::INTERRUPTED.load(std::sync::atomic::Ordering::Relaxed) {
                super::interrupted()
            } else {
                Exception::error(e)
            }
        })?;
    // Subdivided and displaced in the mesh's own coordinates.
    let data = if subdivide > 0 || b.displace.is_some() {
        let grown = data.tris.len().saturating_mul(1 << (2 * subdivide));
        crate::mem::reserve_n(grown, 3 * 4 + 2 * 12)?;
        crate::scene::subdivide(&data, subdivide, b.displace.as_ref())
    } else {
        data
    };
    let n = b.add_mesh(&data, scale, translate, flat).map_err(scene_err)?;
    Ok(Value::from_int(n as i64))
}

fn render_command(
    interp: &mut Interp,
    b: &Builder,
    state: &RefCell<ShellState>,
    argv: &[Value],
) -> Result<Value, Exception> {
    let usage = "render ?-srgb? ?-heatmap? ?-progressive? fileName";
    if argv.len() < 2 {
        return Err(Exception::wrong_args(usage));
    }
    let (mut enc, mut heatmap, mut progressive) = (Encoding::Linear, false, false);
    for o in &argv[1..argv.len() - 1] {
        match o.as_str() {
            "-srgb" => enc = Encoding::Srgb,
            "-heatmap" => heatmap = true,
            "-progressive" => progressive = true,
            o => {
                return Err(Exception::error(format!(
                    "bad option \"{o}\": must be -heatmap, -progressive, or -srgb"
                )));
            }
        }
    }
    let path = argv[argv.len() - 1].as_str();
    super::safe::check(path, crate::interp::Access::Image)
        .map_err(|m| Exception::error(m).with_error_code("TCL SAFE ACCESS"))?;
    let format = Format::from_path(path).ok_or_else(|| {
        Exception::error(format!(
            "unknown image format for \"{path}\": the name must end in .ppm, .png or .pfm"
        ))
    })?;
    let write_err = |err: std::io::Error| {
        let e = Exception::error(format!("couldn't write \"{path}\": {}", super::io_reason(&err)));
        // A missing directory or a forbidden one is the script's mistake
        // (exit 1: the same again fails the same way); a full disk or a
        // failing device may pass on a retry (exit 74).
        match err.kind() {
            std::io::ErrorKind::NotFound
            | std::io::ErrorKind::PermissionDenied
            | std::io::ErrorKind::IsADirectory
            | std::io::ErrorKind::InvalidFilename => e,
            _ => e.with_error_code(super::IO_ERROR_CODE),
        }
    };
    let parse_seconds = state.borrow().since_last.elapsed().as_secs_f64();
    let (width, height) = (b.width, b.height);
    let crop = state.borrow().feedback.crop;
    let placement = match crop {
        Some(r) if r.x1 > width || r.y1 > height => {
            return Err(Exception::error(format!(
                "crop region {} {} {} {} is outside the {width}x{height} picture",
                r.x0, r.y0, r.x1, r.y1
            )));
        }
        Some(r) => Some(crate::image::Placement {
            x0: r.x0,
            y0: r.y0,
            full_width: width,
            full_height: height,
        }),
        None => None,
    };
    // Nothing changed since the last picture was traced: write that one.
    let unchanged = state
        .borrow()
        .last_picture
        .as_ref()
        .is_some_and(|p| p.generation == b.generation && p.heatmap == heatmap);
    if unchanged {
        let mut out = super::AtomicFile::create(path).map_err(write_err)?;
        let mut st = state.borrow_mut();
        let st = &mut *st;
        let img = &st.last_picture.as_ref().expect("checked above").image;
        img.write_placed(out.writer(), format, enc, placement, &interrupted, &mut st.bytes)
            .map_err(write_err)?;
        out.commit().map_err(write_err)?;
        let (w, h) = (img.width, img.height);
        st.feedback.finished(&super::feedback::Finished {
            file: path,
            width: w,
            height: h,
            seconds: 0.0,
            rays: 0,
            traced: false,
        });
        st.renders += 1;
        st.since_last = Instant::now();
        return Ok(Value::empty());
    }
    // The frozen shapes and the BVH (an upper bound per primitive).
    crate::mem::reserve_n(b.prims.len(), BVH_BYTES_PER_PRIM)?;
    let scene = freeze(b, state)?;
    // Open the output before the work, so a bad path fails at once.
    let mut out = super::AtomicFile::create(path).map_err(write_err)?;
    for w in scene.warnings() {
        interp.write_stderr(&format!("warning: {w}\n"))?;
    }
    let start = Instant::now();
    let mut st = state.borrow_mut();
    // The old picture goes before the new one is traced (peak memory);
    // its pixels are the new one's buffer when the sizes agree (every
    // pixel is written again: no clearing, no fresh pages).
    let old = st.last_picture.take().map(|p| p.image.pixels).unwrap_or_default();
    // The picture in floats, then in bytes for the file.
    let pixels = crop.map_or(width as usize * height as usize, |r| {
        (r.x1 - r.x0) as usize * (r.y1 - r.y0) as usize
    });
    crate::mem::reserve_n(pixels, 12 + 3)?;
    // The bytes for the file are made as the picture is traced, band by
    // band (`render_finished`), in the buffer kept from the last render.
    let mut bytes = std::mem::take(&mut st.bytes);
    let done = st.feedback.watch(path, (width, height), progressive, |job| {
        if heatmap {
            render::render_heatmap(&scene, job).map(|(img, rays)| (img, rays, false))
        } else if format == Format::Pfm {
            render::render_into(&scene, job, old).map(|(img, rays)| (img, rays, false))
        } else {
            render::render_finished(&scene, job, old, &mut bytes, enc)
        }
    });
    // Cancelled (Ctrl-C): the temporary file goes with `out`, and the time
    // it traced is not the next render's parse time (`stats`).
    let Some((mut img, rays, finished)) = done else {
        st.since_last = Instant::now();
        return Err(super::interrupted());
    };
    if !heatmap && !finished {
        render::apply_look(&scene.sampling, &mut img);
    }
    let render_seconds = start.elapsed().as_secs_f64();
    if finished {
        img.write_bytes_placed(out.writer(), format, enc, placement, &interrupted, &bytes)
    } else {
        img.write_placed(out.writer(), format, enc, placement, &interrupted, &mut bytes)
    }
    .map_err(write_err)?;
    st.bytes = bytes;
    out.commit().map_err(write_err)?;
    st.feedback.show_final(&img.pixels, img.width, img.height);
    st.feedback.finished(&super::feedback::Finished {
        file: path,
        width: img.width,
        height: img.height,
        seconds: render_seconds,
        rays: rays.total(),
        traced: true,
    });
    let report = RenderReport::new(&scene, parse_seconds, render_seconds, rays);
    if st.print_stats {
        interp.write_stderr(&format!("{report}\n"))?;
    }
    st.renders += 1;
    if st.feedback.show_in_terminal {
        interp.flush();
        super::term::show(&img.to_rgb8(Encoding::Srgb), img.width, img.height, Default::default())
            .map_err(Exception::error)?;
    }
    st.last_picture = Some(Picture { generation: b.generation, heatmap, image: img });
    st.last = Some(report);
    st.since_last = Instant::now();
    Ok(Value::empty())
}

/// The last picture traced, in bytes, and its size.
fn last_rgb8(state: &RefCell<ShellState>) -> Option<(Vec<u8>, u32, u32)> {
    let st = state.borrow();
    let p = st.last_picture.as_ref()?;
    Some((p.image.to_rgb8(Encoding::Srgb), p.image.width, p.image.height))
}

/// Whether Ctrl-C has come (a long PNG encode asks).
fn interrupted() -> bool {
    super::feedback::INTERRUPTED.load(std::sync::atomic::Ordering::Relaxed)
}

/// Freezes the scene for a render, with the last render's BVH when the
/// geometry and the eye are the same (its bytes: the same tree); keeps the
/// tree for the next. A tree that cannot be reused is let go before the
/// new one is built.
fn freeze(b: &Builder, state: &RefCell<ShellState>) -> Result<Scene, Exception> {
    let from = b.from.to_array().map(f64::to_bits);
    let tree = state.borrow_mut().tree.take();
    let tree = tree.filter(|t| t.geometry == b.geometry && t.from == from).map(|t| t.bvh);
    let scene = Scene::freeze_reusing(b, tree).map_err(scene_err)?;
    let bvh = scene.bvh.clone();
    state.borrow_mut().tree = Some(super::stats::Tree { geometry: b.geometry, from, bvh });
    Ok(scene)
}

/// What freezing a scene takes per primitive, at most: its shape, its leaf
/// record, its share of the nodes and of the build's scratch.
const BVH_BYTES_PER_PRIM: usize = 160;

/// The session's pool of `n` threads, made on first use.
fn pool(
    state: &RefCell<ShellState>,
    n: usize,
) -> Result<std::sync::Arc<rayon::ThreadPool>, Exception> {
    let mut st = state.borrow_mut();
    if let Some((_, p)) = st.pools.iter().find(|(k, _)| *k == n) {
        return Ok(p.clone());
    }
    let p = rayon::ThreadPoolBuilder::new()
        .num_threads(n)
        .build()
        .map_err(|e| Exception::error(format!("cannot start {n} threads: {e}")))?;
    let p = std::sync::Arc::new(p);
    st.pools.push((n, p.clone()));
    Ok(p)
}

fn raybench_command(
    b: &Builder,
    state: &RefCell<ShellState>,
    argv: &[Value],
) -> Result<Value, Exception> {
    check_args(argv, 1, 5, "?-shadow? ?-brute? ?-threads count?")?;
    let (mut shadow, mut brute, mut threads) = (false, false, None);
    let mut args = argv[1..].iter();
    while let Some(o) = args.next() {
        match o.as_str() {
            "-shadow" => shadow = true,
            "-brute" => brute = true,
            "-threads" => {
                let n = args.next().map(|v| v.as_str()).unwrap_or("");
                match n.parse::<usize>() {
                    Ok(n @ 1..=256) => threads = Some(n),
                    _ => {
                        return Err(Exception::error(format!(
                            "expected a thread count from 1 to 256 but got \"{n}\""
                        )));
                    }
                }
            }
            o => {
                return Err(Exception::error(format!(
                    "bad option \"{o}\": must be -shadow, -brute or -threads"
                )));
            }
        }
    }
    let parse_seconds = state.borrow().since_last.elapsed().as_secs_f64();
    let scene = Scene::freeze(b).map_err(scene_err)?;
    // With -threads, on a pool of its own: a script can time one and two
    // threads in turn, in one process, so both see the same machine.
    let (primary_s, shadow_s, rays) = match threads {
        None => render::raybench(&scene, shadow),
        Some(n) => pool(state, n)?.install(|| render::raybench(&scene, shadow)),
    };
    let report = RenderReport::new(&scene, parse_seconds, primary_s + shadow_s, rays);
    let n = rays.primary as f64;
    let mut out = vec![
        Value::from("primary_mrays_per_s"),
        Value::from_f64(n / primary_s.max(1e-9) / 1e6),
        Value::from("shadow_mrays_per_s"),
        Value::from_f64(if shadow { rays.shadow as f64 / shadow_s.max(1e-9) / 1e6 } else { 0.0 }),
        Value::from("build_ms"),
        Value::from_f64(report.build_seconds * 1e3),
        Value::from("primitives"),
        Value::from_int(report.primitives as i64),
        Value::from("bvh_nodes"),
        Value::from_int(report.nodes as i64),
        Value::from("bytes_per_triangle"),
        Value::from_f64(report.bytes_per_triangle()),
        Value::from("bvh_steps_per_ray"),
        Value::from_f64(rays.bvh_steps as f64 / n.max(1.0)),
    ];
    if brute {
        // About 2e8 ray-primitive tests: a second or two.
        let (rays, seconds) = render::raybench_brute(&scene, 200_000_000);
        out.push(Value::from("brute_mrays_per_s"));
        out.push(Value::from_f64(rays as f64 / seconds.max(1e-9) / 1e6));
    }
    let mut st = state.borrow_mut();
    st.renders += 1;
    st.last = Some(report);
    st.since_last = Instant::now();
    Ok(Value::from_list(out))
}

fn show_command(
    interp: &mut Interp,
    b: &Builder,
    state: &RefCell<ShellState>,
    argv: &[Value],
) -> Result<Value, Exception> {
    let usage = "show ?-blocks? ?-width cells? ?fileName?";
    let mut previewed = false;
    let mut opts = super::term::ShowOptions::default();
    let mut file = None;
    let mut args = argv[1..].iter();
    while let Some(a) = args.next() {
        match a.as_str() {
            "-blocks" => opts.blocks = true,
            "-width" => {
                let n = args.next().ok_or_else(|| Exception::wrong_args(usage))?;
                match n.as_str().parse::<u32>() {
                    Ok(w @ 1..=1000) => opts.width = Some(w),
                    _ => {
                        return Err(Exception::error(format!(
                            "show: -width: expected a width from 1 to 1000 cells but got \"{}\"",
                            n.as_str()
                        )));
                    }
                }
            }
            o if o.starts_with('-') => {
                return Err(Exception::error(format!(
                    "bad option \"{o}\": must be -blocks or -width"
                )));
            }
            f if file.is_none() => file = Some(f.to_string()),
            _ => return Err(Exception::wrong_args(usage)),
        }
    }
    let (rgb, w, h) = match file {
        Some(path) => {
            let bytes = super::read_scene_file(&path)?;
            let img = crate::image::read_rgb8(&bytes)
                .map_err(|e| Exception::error(format!("\"{path}\": {e}")))?;
            // A PNG that says its values are linear is shown as sRGB.
            let rgb = match img.encoding {
                Some(Encoding::Linear) => crate::image::linear_bytes_to_srgb(&img.rgb),
                _ => img.rgb,
            };
            (rgb, img.width, img.height)
        }
        None => match last_rgb8(state) {
            Some(shown) => shown,
            None => {
                // Nothing rendered yet: a quick preview, sized to the
                // terminal (and never past the picture size limit), which
                // Ctrl-C stops like any render.
                let (mut pw, mut ph) = super::term::preview_size(b.width as f64 / b.height as f64);
                while pw as u64 * ph as u64 > b.max_pixels && (pw > 1 || ph > 1) {
                    (pw, ph) = ((pw / 2).max(1), (ph / 2).max(1));
                }
                let mut scene = freeze(b, state)?;
                scene.camera = b.camera_at(pw, ph).map_err(scene_err)?;
                let job = render::Job {
                    cancel: Some(&super::feedback::INTERRUPTED),
                    ..render::Job::default()
                };
                let (img, _) = render::render(&scene, &job).ok_or_else(super::interrupted)?;
                previewed = true;
                (img.to_rgb8(Encoding::Srgb), pw, ph)
            }
        },
    };
    if previewed {
        // Looking at the scene: no "rendered nothing" hint.
        state.borrow_mut().renders += 1;
    }
    interp.flush();
    super::term::show(&rgb, w, h, opts).map_err(Exception::error)?;
    Ok(Value::empty())
}
