//! The scene commands of surfaces: `texture`, `highlight` and `bump`,
//! state taken by the objects made after them, as `material` is.

use std::sync::Arc;

use glam::Vec3;

use crate::interp::{Exception, Interp, Value, check_args};
use crate::scene::emitters::Sky;
use crate::scene::{Bump, Displace, Highlight, Image, Mapping, Pattern, Texture};

use super::commands::{Shared, edit, finite_arg, scene_err};

/// Words `from..` as numbers, each named in errors as `cmd: what`.
fn numbers(argv: &[Value], from: usize, what: &str) -> Result<Vec<f32>, Exception> {
    argv[from..].iter().map(|v| finite_arg(v, what).map(|x| x as f32)).collect()
}

/// Words 1..4 as a radiance (`what` names it): finite, not negative.
fn radiance(argv: &[Value], what: &str) -> Result<Vec3, Exception> {
    let n = numbers(argv, 1, what)?;
    if n.iter().any(|x| *x < 0.0) {
        return Err(Exception::error(format!(
            "{what} must not be negative, got {} {} {}",
            n[0], n[1], n[2]
        )));
    }
    Ok(Vec3::new(n[0], n[1], n[2]))
}

/// `texture image FILE MAPPING ?-once?`: reads the file into the scene's
/// images and returns the texture.
fn image_texture(scene: &Shared, argv: &[Value]) -> Result<Texture, Exception> {
    let usage = "image fileName planar|cylindrical|spherical|uv ?-once?";
    check_args(argv, 4, 5, usage)?;
    let once = match argv.get(4).map(|v| v.as_str()) {
        None => false,
        Some("-once") => true,
        Some(o) => return Err(Exception::error(format!("bad option \"{o}\": must be -once"))),
    };
    let mapping = mapping(&argv[3])?;
    let (id, _) = load_image(scene, argv[2].as_str())?;
    Ok(Texture::Image { id, mapping, once })
}

/// Reads an image file into the scene's images: its number and itself.
fn load_image(scene: &Shared, path: &str) -> Result<(u32, Arc<Image>), Exception> {
    let data = super::read_scene_file(path)?;
    let (w, h, px) =
        crate::image::read_texture(&data).map_err(|e| Exception::error(format!("{path}: {e}")))?;
    if w == 0 || h == 0 {
        return Err(Exception::error(format!("{path}: an empty image")));
    }
    // The image and its mip-map (a third more).
    crate::mem::reserve_n(w as usize * h as usize, 16)?;
    let mut b = scene.borrow_mut();
    crate::mem::room(&b.images, 1)?;
    let img = Arc::new(Image::new(w, h, px));
    b.images.push(img.clone());
    Ok((b.images.len() as u32 - 1, img))
}

/// A mapping's name.
fn mapping(v: &Value) -> Result<Mapping, Exception> {
    let m = v.as_str();
    Mapping::parse(m)
        .ok_or_else(|| Exception::error(format!("bad mapping \"{m}\": must be {}", Mapping::NAMES)))
}

/// Registers the commands.
pub fn register(interp: &mut Interp, scene: &Shared) {
    let s = scene.clone();
    interp.register_host(
        "displace",
        "none | noise amount ?size? | image fileName amount",
        "move the vertices of the meshes that follow along their normals by a noise's height",
        move |_, argv| {
            check_args(argv, 2, 4, "none | noise amount ?size? | image fileName amount")?;
            if argv[1].as_str() == "image" {
                check_args(argv, 4, 4, "image fileName amount")?;
                let amount = finite_arg(&argv[3], "displace image: amount")? as f32;
                let (_, img) = load_image(&s, argv[2].as_str())?;
                let mut b = edit(&s);
                b.displace = Some(Displace { amount, size: 1.0, image: Some(img) });
                return Ok(Value::empty());
            }
            let n = numbers(argv, 2, "displace noise")?;
            let d = match (argv[1].as_str(), n.len()) {
                ("none", 0) => None,
                ("noise", 1 | 2) => {
                    let size = n.get(1).copied().unwrap_or(1.0);
                    if size.is_nan() || size <= 0.0 {
                        return Err(Exception::error(format!(
                            "displace needs a size above 0, got {size}"
                        )));
                    }
                    Some(Displace { amount: n[0], size, image: None })
                }
                ("none" | "noise", _) => {
                    return Err(Exception::wrong_args("none | noise amount ?size?"));
                }
                (k, _) => {
                    return Err(Exception::error(format!(
                        "bad displace \"{k}\": must be noise or none"
                    )));
                }
            };
            let mut b = edit(&s);
            b.displace = d;
            Ok(Value::empty())
        },
    );
    let s = scene.clone();
    let usage = "none | checker r1 g1 b1 r2 g2 b2 ?size? | noise|marble|wood|granite ?r1 g1 b1 r2 g2 b2? ?scale? | image fileName planar|cylindrical|spherical|uv ?-once?";
    interp.register_host(
        "texture",
        usage,
        "the colour pattern of the objects that follow, in the coordinates they are written in",
        move |_, argv| {
            check_args(argv, 2, 9, usage)?;
            let kind = argv[1].as_str();
            if kind == "image" {
                let t = image_texture(&s, argv)?;
                let mut b = edit(&s);
                b.set_texture(Some(t)).map_err(scene_err)?;
                return Ok(Value::empty());
            }
            let n = numbers(argv, 2, &format!("texture {kind}"))?;
            let colours = |n: &[f32]| (Vec3::new(n[0], n[1], n[2]), Vec3::new(n[3], n[4], n[5]));
            let t = match kind {
                "none" if n.is_empty() => None,
                "checker" if n.len() == 6 || n.len() == 7 => {
                    let (a, b) = colours(&n);
                    Some(Texture::Checker { a, b, size: n.get(6).copied().unwrap_or(1.0) })
                }
                "none" | "checker" => return Err(Exception::wrong_args(usage)),
                k => {
                    let Some(p) = Pattern::parse(k) else {
                        return Err(Exception::error(format!(
                            "bad texture \"{k}\": must be {}",
                            Pattern::NAMES
                        )));
                    };
                    if !matches!(n.len(), 0 | 1 | 6 | 7) {
                        return Err(Exception::wrong_args(usage));
                    }
                    let (a, b) = if n.len() >= 6 { colours(&n) } else { p.colours() };
                    let scale = if n.len() % 2 == 1 { n[n.len() - 1] } else { 1.0 };
                    Some(Texture::Pattern { kind: p, a, b, scale })
                }
            };
            let mut b = edit(&s);
            b.set_texture(t).map_err(scene_err)?;
            Ok(Value::empty())
        },
    );
    let s = scene.clone();
    interp.register_host(
        "emission",
        "r g b",
        "the radiance the objects that follow emit (from their front side)",
        move |_, argv| {
            check_args(argv, 4, 4, "r g b")?;
            edit(&s).look.emission = radiance(argv, "emission")?;
            Ok(Value::empty())
        },
    );
    let s = scene.clone();
    let usage = "r g b | fileName ?scale? | none";
    interp.register_host(
        "environment",
        usage,
        "the light from every direction nothing blocks: a constant radiance or an equirectangular image",
        move |_, argv| {
            check_args(argv, 2, 4, usage)?;
            let sky = match argv.len() {
                4 => Some(Sky::constant(radiance(argv, "environment radiance")?)),
                _ if argv[1].as_str() == "none" && argv.len() == 2 => None,
                _ => {
                    let scale = match argv.get(2) {
                        Some(v) => finite_arg(v, "environment: scale")? as f32,
                        None => 1.0,
                    };
                    if scale < 0.0 {
                        return Err(Exception::error(format!(
                            "environment scale must not be negative, got {scale}"
                        )));
                    }
                    let path = argv[1].as_str();
                    let data = super::read_scene_file(path)?;
                    let (w, h, px) = crate::image::read_texture(&data)
                        .map_err(|e| Exception::error(format!("{path}: {e}")))?;
                    if w == 0 || h == 0 {
                        return Err(Exception::error(format!("{path}: an empty image")));
                    }
                    // The map and its sampling tables.
                    crate::mem::reserve_n(w as usize * h as usize, 24)?;
                    Some(Sky::map(w, h, px.into_iter().map(|c| c * scale).collect()))
                }
            };
            edit(&s).environment = sky.map(Arc::new);
            Ok(Value::empty())
        },
    );
    let s = scene.clone();
    interp.register_host(
        "highlight",
        "phong|blinn|ward ?ax ay?",
        "the specular model of the objects that follow",
        move |_, argv| {
            check_args(argv, 2, 4, "phong|blinn|ward ?ax ay?")?;
            let n = numbers(argv, 2, "highlight ward")?;
            let h = match (argv[1].as_str(), n.len()) {
                ("phong", 0) => Highlight::Phong,
                ("blinn", 0) => Highlight::Blinn,
                ("ward", 2) => Highlight::Ward { ax: n[0], ay: n[1] },
                ("phong" | "blinn" | "ward", _) => {
                    return Err(Exception::wrong_args("phong|blinn|ward ?ax ay?"));
                }
                (k, _) => {
                    return Err(Exception::error(format!(
                        "bad highlight \"{k}\": must be phong, blinn or ward"
                    )));
                }
            };
            let mut b = edit(&s);
            b.set_highlight(h).map_err(scene_err)?;
            Ok(Value::empty())
        },
    );
    let s = scene.clone();
    interp.register_host(
        "bump",
        "none | noise amount ?size? | image fileName amount mapping",
        "tilt the shading normals of the objects that follow by a noise's gradient",
        move |_, argv| {
            check_args(argv, 2, 5, "none | noise amount ?size? | image fileName amount mapping")?;
            if argv[1].as_str() == "image" {
                check_args(argv, 5, 5, "image fileName amount mapping")?;
                let amount = finite_arg(&argv[3], "bump image: amount")? as f32;
                let m = mapping(&argv[4])?;
                let (id, _) = load_image(&s, argv[2].as_str())?;
                let mut b = edit(&s);
                b.set_bump(Some(Bump { amount, size: 1.0, image: Some((id, m)) }))
                    .map_err(scene_err)?;
                return Ok(Value::empty());
            }
            let n = numbers(argv, 2, "bump noise")?;
            let bump = match (argv[1].as_str(), n.len()) {
                ("none", 0) => None,
                ("noise", 1 | 2) => {
                    Some(Bump { amount: n[0], size: n.get(1).copied().unwrap_or(1.0), image: None })
                }
                ("none" | "noise", _) => {
                    return Err(Exception::wrong_args("none | noise amount ?size?"));
                }
                (k, _) => {
                    return Err(Exception::error(format!(
                        "bad bump \"{k}\": must be noise or none"
                    )));
                }
            };
            let mut b = edit(&s);
            b.set_bump(bump).map_err(scene_err)?;
            Ok(Value::empty())
        },
    );
}
