//! The scene commands of shapes and structure: analytic shapes, the
//! transform stack, CSG, groups and instances. Like the rest of the
//! vocabulary, each converts words and calls one `scene::Builder` method;
//! the ones that take a script run it between a begin and an end.

use glam::DVec3;

use crate::geometry::CsgOp;
use crate::interp::{Exception, Interp, Value, check_args};
use crate::scene::Builder;

use super::commands::{Shared, choice, edit, finite_arg, numeric, numeric_opt, scene_err};

/// `n` numbers, then optionally the flag `flag`: the numbers and whether
/// the flag was given.
fn numbers_and_flag(
    argv: &[Value],
    names: &[&str],
    flag: &str,
    usage: &str,
) -> Result<(Vec<f64>, bool), Exception> {
    let n = names.len();
    check_args(argv, n + 1, n + 2, usage)?;
    let given = argv.len() == n + 2;
    if given && argv[n + 1].as_str() != flag {
        return Err(Exception::error(format!(
            "bad option \"{}\": must be {flag}",
            argv[n + 1].as_str()
        )));
    }
    let cmd = argv[0].as_str();
    let nums = names
        .iter()
        .enumerate()
        .map(|(i, name)| {
            let x = finite_arg(&argv[i + 1], &format!("{cmd}: {name}"))?;
            if x.abs() > f32::MAX as f64 {
                return Err(Exception::error(format!(
                    "{cmd}: {name}: number {} is too large",
                    argv[i + 1].as_str()
                )));
            }
            Ok(x)
        })
        .collect::<Result<Vec<f64>, Exception>>()?;
    Ok((nums, given))
}

/// Runs `script` between `begin` and `end(ok)` on the builder (not
/// borrowed while the script runs, which makes scene commands of its own).
fn around(
    interp: &mut Interp,
    scene: &Shared,
    script: &Value,
    begin: impl FnOnce(&mut Builder) -> Result<(), crate::scene::SceneError>,
    end: impl FnOnce(&mut Builder, bool) -> Result<(), crate::scene::SceneError>,
) -> Result<Value, Exception> {
    {
        let mut b = edit(scene);
        begin(&mut b).map_err(scene_err)?;
    }
    let r = interp.eval(script);
    let mut b = edit(scene);
    let ended = end(&mut b, r.is_ok());
    r?;
    ended.map_err(scene_err)?;
    Ok(Value::empty())
}

/// Registers the commands.
pub fn register(interp: &mut Interp, scene: &Shared) {
    let e = scene_err;
    numeric(interp, scene, "plane", "nx ny nz d", "the infinite plane n̂·p = d", move |b, a| {
        b.plane(a.pos(0)?, a.f64(3)?).map_err(e)?;
        Ok(None)
    });
    numeric(
        interp,
        scene,
        "box",
        "x0 y0 z0 x1 y1 z1",
        "the box between two corners",
        move |b, a| {
            b.add_box(a.pos(0)?, a.pos(3)?).map_err(e)?;
            Ok(None)
        },
    );
    let s = scene.clone();
    interp.register_host(
        "cylinder",
        "x0 y0 z0 x1 y1 z1 r ?-open?",
        "a cylinder from one end's centre to the other's, capped unless -open",
        move |_, argv| {
            let usage = "x0 y0 z0 x1 y1 z1 r ?-open?";
            let names = ["x0", "y0", "z0", "x1", "y1", "z1", "r"];
            let (n, open) = numbers_and_flag(argv, &names, "-open", usage)?;
            let mut b = edit(&s);
            let (a, c) = (DVec3::new(n[0], n[1], n[2]), DVec3::new(n[3], n[4], n[5]));
            b.cone(a, n[6], c, n[6], !open).map_err(e)?;
            Ok(Value::empty())
        },
    );
    let s = scene.clone();
    interp.register_host(
        "cone",
        "x0 y0 z0 r0 x1 y1 z1 r1 ?-open?",
        "a truncated cone from (x0, y0, z0), radius r0, to (x1, y1, z1), radius r1; capped unless -open",
        move |_, argv| {
            let usage = "x0 y0 z0 r0 x1 y1 z1 r1 ?-open?";
            let names = ["x0", "y0", "z0", "r0", "x1", "y1", "z1", "r1"];
            let (n, open) = numbers_and_flag(argv, &names, "-open", usage)?;
            let mut b = edit(&s);
            let (a, c) = (DVec3::new(n[0], n[1], n[2]), DVec3::new(n[4], n[5], n[6]));
            b.cone(a, n[3], c, n[7], !open).map_err(e)?;
            Ok(Value::empty())
        },
    );
    numeric_opt(
        interp,
        scene,
        "disk",
        "x y z nx ny nz r ?inner?",
        1,
        "a flat disk (an annulus with an inner radius)",
        move |b, a, count| {
            let inner = if count > 7 { a.f64(7)? } else { 0.0 };
            b.disk(a.pos(0)?, a.pos(3)?, a.f64(6)?, inner).map_err(e)
        },
    );
    numeric(interp, scene, "torus", "R r", "a torus around the y axis", move |b, a| {
        b.torus(a.f64(0)?, a.f64(1)?).map_err(e)?;
        Ok(None)
    });

    // -- Transforms -------------------------------------------------------
    numeric(interp, scene, "translate", "x y z", "move what follows", move |b, a| {
        b.translate(a.pos(0)?).map_err(e)?;
        Ok(None)
    });
    numeric(
        interp,
        scene,
        "rotate",
        "x y z",
        "rotate what follows: degrees about x, then y, then z",
        move |b, a| {
            b.rotate(a.pos(0)?).map_err(e)?;
            Ok(None)
        },
    );
    numeric(
        interp,
        scene,
        "rotate_axis",
        "angle ax ay az",
        "rotate what follows by degrees about an axis",
        move |b, a| {
            b.rotate_axis(a.f64(0)?, a.pos(1)?).map_err(e)?;
            Ok(None)
        },
    );
    numeric_opt(
        interp,
        scene,
        "scale",
        "sx ?sy? ?sz?",
        2,
        "scale what follows (one factor, or one per axis)",
        move |b, a, count| {
            let s = match count {
                1 => DVec3::splat(a.f64(0)?),
                3 => a.pos(0)?,
                _ => return Err(Exception::wrong_args("scale s | scale sx sy sz")),
            };
            b.scale(s).map_err(e)
        },
    );
    numeric(interp, scene, "push", "", "save the current transform", move |b, _| {
        b.push().map_err(e)?;
        Ok(None)
    });
    numeric(interp, scene, "pop", "", "restore the last saved transform", move |b, _| {
        b.pop().map_err(e)?;
        Ok(None)
    });
    let s = scene.clone();
    interp.register_host(
        "transform",
        "script",
        "run the script between push and pop",
        move |interp, argv| {
            check_args(argv, 2, 2, "script")?;
            around(interp, &s, &argv[1], |b| b.push(), |b, _| b.pop())
        },
    );

    // -- Files --------------------------------------------------------------
    let s = scene.clone();
    interp.register_host(
        "nff",
        "fileName",
        "read an NFF scene (Eric Haines' SPD format); returns what it held, by kind",
        move |_, argv| {
            check_args(argv, 2, 2, "fileName")?;
            let path = argv[1].as_str().to_string();
            let p = path.clone();
            let f = super::feedback::blocking(&path, move || super::safe::open_read(&p))
                .map_err(|_| super::interrupted())?
                .map_err(|e| e.into_exception(&path))?;
            let mut b = edit(&s);
            let c = super::nff::load(&mut b, &path, std::io::BufReader::new(f))
                .map_err(Exception::error)?;
            let n = |x: u64| Value::from_int(x as i64);
            Ok(Value::from_list(vec![
                Value::from("spheres"),
                n(c.spheres),
                Value::from("cones"),
                n(c.cones),
                Value::from("polygons"),
                n(c.polygons),
                Value::from("patches"),
                n(c.patches),
                Value::from("lights"),
                n(c.lights),
            ]))
        },
    );

    // -- Fractals ---------------------------------------------------------
    numeric(
        interp,
        scene,
        "sphereflake",
        "x y z r depth",
        "Haines' sphereflake, generated as rays reach it",
        move |b, a| {
            b.sphereflake(a.pos(0)?, a.f64(3)?, a.int(4)?).map_err(e)?;
            Ok(None)
        },
    );
    numeric(
        interp,
        scene,
        "menger",
        "x y z size depth",
        "a Menger sponge, generated as rays reach it",
        move |b, a| {
            b.menger(a.pos(0)?, a.f64(3)?, a.int(4)?).map_err(e)?;
            Ok(None)
        },
    );

    // -- Blobs ------------------------------------------------------------
    let s = scene.clone();
    interp.register_host(
        "blob",
        "threshold script",
        "metaballs: the surface where the blob_spheres' field equals the threshold",
        move |interp, argv| {
            check_args(argv, 3, 3, "threshold script")?;
            let threshold = finite_arg(&argv[1], "blob: threshold")?;
            around(interp, &s, &argv[2], |b| b.begin_blob(threshold), |b, ok| b.end_blob(ok))
        },
    );
    numeric(
        interp,
        scene,
        "blob_sphere",
        "x y z radius strength",
        "a component of the blob being made",
        move |b, a| {
            b.blob_sphere(a.pos(0)?, a.f64(3)?, a.f64(4)?).map_err(e)?;
            Ok(None)
        },
    );

    // -- CSG, groups and instances ----------------------------------------
    let s = scene.clone();
    interp.register_host(
        "csg",
        "union|intersection|difference|merge script",
        "constructive solid geometry of the solids the script makes",
        move |interp, argv| {
            check_args(argv, 3, 3, "union|intersection|difference|merge script")?;
            let op = choice(&argv[1], "csg operation", CsgOp::parse, CsgOp::NAMES)?;
            around(interp, &s, &argv[2], |b| b.begin_csg(op), |b, ok| b.end_csg(ok))
        },
    );
    let s = scene.clone();
    interp.register_host(
        "group",
        "name script",
        "make a named group (drawn only by instance) from the script",
        move |interp, argv| {
            check_args(argv, 3, 3, "name script")?;
            let name = argv[1].as_str().to_string();
            around(interp, &s, &argv[2], |b| b.begin_group(&name), |b, ok| b.end_group(ok))
        },
    );
    let s = scene.clone();
    interp.register_host(
        "instance",
        "name",
        "place a group under the current transform",
        move |_, argv| {
            check_args(argv, 2, 2, "name")?;
            let mut b = edit(&s);
            b.instance(argv[1].as_str()).map_err(scene_err)?;
            Ok(Value::empty())
        },
    );
}
