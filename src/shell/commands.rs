//! The .tsd vocabulary: each scene command checks its arity, converts its
//! words to numbers and calls one `scene::Builder` method. Errors use Tcl's
//! wording (`wrong # args: should be "vertex x y z"`).

use std::cell::RefCell;
use std::rc::Rc;

use glam::Vec3;

use crate::interp::{Exception, Interp, Num, Value, check_args, format_double};
use crate::scene::{Builder, SceneError};

fn scene_err(e: SceneError) -> Exception {
    Exception::error(e.to_string())
}

fn finite(n: Num) -> Result<f32, Exception> {
    let x = n.to_f64();
    if !x.is_finite() {
        return Err(Exception::error(format!(
            "expected a finite number but got \"{}\"",
            format_double(x)
        )));
    }
    Ok(x as f32)
}

fn vec3(a: &[Num]) -> Result<Vec3, Exception> {
    Ok(Vec3::new(finite(a[0])?, finite(a[1])?, finite(a[2])?))
}

fn index(n: Num) -> Result<i64, Exception> {
    match n {
        Num::Int(i) => Ok(i),
        Num::Double(d) => {
            Err(Exception::error(format!("expected integer but got \"{}\"", format_double(d))))
        }
    }
}

/// Registers the scene commands, sharing one builder.
pub fn register(interp: &mut Interp, scene: Rc<RefCell<Builder>>) {
    let s = scene.clone();
    interp.register_numeric(
        "vertex",
        3,
        "x y z",
        "add a vertex; returns its index",
        move |_, a| {
            let i = s.borrow_mut().vertex(vec3(a)?).map_err(scene_err)?;
            Ok(Some(Num::Int(i as i64)))
        },
    );
    let s = scene.clone();
    interp.register_numeric(
        "normal",
        3,
        "x y z",
        "add a normal; returns its index",
        move |_, a| {
            let i = s.borrow_mut().normal(vec3(a)?).map_err(scene_err)?;
            Ok(Some(Num::Int(i as i64)))
        },
    );
    let s = scene.clone();
    interp.register_numeric(
        "tri",
        3,
        "v1 v2 v3",
        "add a flat triangle (vertex indices, counter-clockwise)",
        move |_, a| {
            let v = [index(a[0])?, index(a[1])?, index(a[2])?];
            s.borrow_mut().tri(v).map_err(scene_err)?;
            Ok(None)
        },
    );
    let s = scene.clone();
    interp.register_numeric(
        "ntri",
        6,
        "v1 n1 v2 n2 v3 n3",
        "add a smooth triangle (vertex and normal indices)",
        move |_, a| {
            let mut vn = [(0, 0); 3];
            for (k, slot) in vn.iter_mut().enumerate() {
                *slot = (index(a[2 * k])?, index(a[2 * k + 1])?);
            }
            s.borrow_mut().ntri(vn).map_err(scene_err)?;
            Ok(None)
        },
    );
    let s = scene;
    interp.register_host(
        "clear_scene",
        "",
        "reset the scene to its initial state",
        move |_, argv| {
            check_args(argv, 1, 1, "")?;
            s.borrow_mut().clear();
            Ok(Value::empty())
        },
    );
}
