//! Eric Haines' Neutral File Format, the format of the SPD benchmark
//! scenes: `v` (from, at, up, angle, hither, resolution), `b` background,
//! `l` lights, `f` fill materials, `c` cones and cylinders, `s` spheres,
//! `p` polygons and `pp` polygonal patches with normals; `#` comments.
//! Read as a stream of words (SPD writes a cone on one line or three), each
//! item applied to the builder as it is read.
//!
//! NFF has no ambient term and its lights do not fall off: a light is a
//! point light of its colour with `Falloff::NONE`, as POV-Ray's
//! `light_source` is.

use std::io::BufRead;

use glam::{DVec3, Vec3};

use crate::scene::{Builder, Falloff, Light, Material, SceneError};

/// What a file held, by kind.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Counts {
    pub spheres: u64,
    pub cones: u64,
    pub polygons: u64,
    pub patches: u64,
    pub lights: u64,
}

/// The words of a file with their line numbers: one line at a time in a
/// buffer kept from line to line, each word a slice of it (no allocation
/// per word: lattice-s8's 218 KB read in 1.4 ms, not 3.3).
struct Words<R> {
    reader: R,
    line: usize,
    /// The current line up to its comment, and where its next word starts.
    buf: String,
    pos: usize,
}

impl<R: BufRead> Words<R> {
    /// The next word, reading lines as needed; `None` at the end.
    fn next(&mut self) -> Result<Option<&str>, String> {
        loop {
            let rest = &self.buf.as_bytes()[self.pos..];
            if let Some(start) = rest.iter().position(|c| !c.is_ascii_whitespace()) {
                let start = self.pos + start;
                let len = self.buf.as_bytes()[start..]
                    .iter()
                    .position(u8::is_ascii_whitespace)
                    .unwrap_or(self.buf.len() - start);
                self.pos = start + len;
                return Ok(Some(&self.buf[start..start + len]));
            }
            self.buf.clear();
            self.pos = 0;
            // A line is at most MAX_LINE bytes: `/dev/zero` has no end.
            let read =
                std::io::Read::take(&mut self.reader, MAX_LINE as u64 + 1).read_line(&mut self.buf);
            match read.map_err(|e| format!("line {}: {e}", self.line + 1))? {
                0 => return Ok(None),
                n if n > MAX_LINE => {
                    // Placed at this line by the caller (`FILE:LINE: ...`).
                    self.line += 1;
                    return Err(format!("line longer than {} MiB", MAX_LINE >> 20));
                }
                _ => self.line += 1,
            }
            if let Some(hash) = self.buf.find('#') {
                self.buf.truncate(hash);
            }
        }
    }

    /// How many words are left on the current line.
    fn left_on_line(&self) -> usize {
        self.buf[self.pos..].split_ascii_whitespace().count()
    }

    fn word(&mut self, what: &str) -> Result<&str, String> {
        self.next()?.ok_or_else(|| format!("the file ends where {what} should be"))
    }

    fn num(&mut self, what: &str) -> Result<f64, String> {
        let w = self.word(what)?;
        match w.parse::<f64>() {
            Ok(x) if x.is_finite() && x.abs() <= f32::MAX as f64 => Ok(x),
            _ => Err(format!("expected {what} but got \"{w}\"")),
        }
    }

    fn vec(&mut self, what: &str) -> Result<DVec3, String> {
        Ok(DVec3::new(self.num(what)?, self.num(what)?, self.num(what)?))
    }

    fn count(&mut self, what: &str) -> Result<usize, String> {
        let w = self.word(what)?;
        match w.parse::<usize>() {
            Ok(n) if (3..=1 << 20).contains(&n) => Ok(n),
            _ => Err(format!("expected {what} (3 or more) but got \"{w}\"")),
        }
    }

    /// The next word, one of `names` (returned as that name, so that the
    /// words after it can be read); `None` at the end; `bad(word)` the
    /// error for any other word.
    fn keyword(
        &mut self,
        names: &[&'static str],
        bad: impl Fn(&str) -> String,
    ) -> Result<Option<&'static str>, String> {
        let Some(w) = self.next()? else { return Ok(None) };
        names.iter().find(|&&k| k == w).map(|&k| Some(k)).ok_or_else(|| bad(w))
    }
}

/// The items of NFF, and the keywords of its view.
const ITEMS: &[&str] = &["v", "b", "l", "f", "c", "s", "p", "pp"];
const VIEW: &[&str] = &["from", "at", "up", "angle", "hither", "resolution"];

/// Reads NFF from `reader` into `b`; `name` names it in messages
/// (`name:LINE: ...`).
/// The longest line an NFF file may have (the SPD's are under 100 bytes).
const MAX_LINE: usize = 1 << 20;

pub fn load(b: &mut Builder, name: &str, reader: impl BufRead) -> Result<Counts, String> {
    let mut w = Words { reader, line: 0, buf: String::new(), pos: 0 };
    let mut counts = Counts::default();
    let located = |line: usize, e: String| format!("{name}:{line}: {e}");
    let scene = |e: SceneError| e.to_string();
    loop {
        let item = w.keyword(ITEMS, |other| format!("unknown NFF item \"{other}\""));
        let word = match item {
            Ok(Some(x)) => x,
            Ok(None) => break,
            Err(e) => return Err(located(w.line, e)),
        };
        let line = w.line;
        let r: Result<(), String> = (|| {
            match word {
                "v" => {
                    let (mut from, mut target, mut up) = (None, None, None);
                    let (mut angle, mut res) = (None, None);
                    for _ in 0..6 {
                        let bad = |k: &str| {
                            format!(
                                "bad view keyword \"{k}\": must be from, at, up, angle, hither or resolution"
                            )
                        };
                        let key = w.keyword(VIEW, bad)?;
                        match key.ok_or("the file ends where a view keyword should be")? {
                            "from" => from = Some(w.vec("a number")?),
                            "at" => target = Some(w.vec("a number")?),
                            "up" => up = Some(w.vec("a number")?),
                            "angle" => angle = Some(w.num("an angle")?),
                            "hither" => {
                                w.num("a distance")?;
                            }
                            "resolution" => res = Some((w.num("a width")?, w.num("a height")?)),
                            _ => unreachable!("VIEW names each"),
                        }
                    }
                    let (Some(from), Some(target), Some(up), Some(angle), Some((rw, rh))) =
                        (from, target, up, angle, res)
                    else {
                        return Err(
                            "a view needs from, at, up, angle, hither and resolution".into()
                        );
                    };
                    b.camera_from(from).map_err(scene)?;
                    b.camera_target(target).map_err(scene)?;
                    b.camera_up(up.as_vec3()).map_err(scene)?;
                    b.camera_angle(angle as f32).map_err(scene)?;
                    b.camera_resolution(rw as i64, rh as i64).map_err(scene)?;
                }
                "b" => b.set_background(w.vec("a colour")?.as_vec3()).map_err(scene)?,
                "l" => {
                    let p = w.vec("a position")?;
                    // An optional colour: three more numbers on the line.
                    let colour = if w.left_on_line() >= 3 {
                        w.vec("a colour")?.as_vec3()
                    } else {
                        Vec3::ONE
                    };
                    b.add_light(Light::point(colour, p, Falloff::NONE).map_err(scene)?)
                        .map_err(scene)?;
                    counts.lights += 1;
                }
                "f" => {
                    let c = w.vec("a colour")?.as_vec3();
                    let (kd, ks, shine) = (w.num("Kd")?, w.num("Ks")?, w.num("Shine")?);
                    let (t, ior) = (w.num("T")?, w.num("an index of refraction")?);
                    let m = Material {
                        color: c,
                        ka: 0.0,
                        kd: kd as f32,
                        ks: ks as f32,
                        ns: shine as f32,
                        t: t as f32,
                        ior: if t > 0.0 && ior == 0.0 { 1.0 } else { ior as f32 },
                        ..Material::default()
                    };
                    b.set_material(m).map_err(scene)?;
                }
                "c" => {
                    let (base, r0) = (w.vec("a position")?, w.num("a radius")?);
                    let (apex, r1) = (w.vec("a position")?, w.num("a radius")?);
                    b.cone(base, r0.abs(), apex, r1.abs(), false).map_err(scene)?;
                    counts.cones += 1;
                }
                "s" => {
                    let (c, r) = (w.vec("a position")?, w.num("a radius")?);
                    b.sphere(c, r).map_err(scene)?;
                    counts.spheres += 1;
                }
                "p" => {
                    let n = w.count("a vertex count")?;
                    let mut v = Vec::with_capacity(n.min(1024));
                    for _ in 0..n {
                        v.push(b.vertex(w.vec("a vertex")?).map_err(scene)? as i64);
                    }
                    for k in 1..n - 1 {
                        b.tri([v[0], v[k], v[k + 1]]).map_err(scene)?;
                    }
                    counts.polygons += 1;
                }
                "pp" => {
                    let n = w.count("a vertex count")?;
                    let mut v = Vec::with_capacity(n.min(1024));
                    for _ in 0..n {
                        let p = b.vertex(w.vec("a vertex")?).map_err(scene)? as i64;
                        let nn = w.vec("a normal")?.as_vec3();
                        let ni = b.normal(nn).map_err(scene)? as i64;
                        v.push((p, ni));
                    }
                    for k in 1..n - 1 {
                        b.ntri([v[0], v[k], v[k + 1]]).map_err(scene)?;
                    }
                    counts.patches += 1;
                }
                _ => unreachable!("ITEMS names each"),
            }
            Ok(())
        })();
        r.map_err(|e| located(line, e))?;
    }
    Ok(counts)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_every_item_and_counts_them() {
        let src = "b 0.1 0.2 0.3\nv\nfrom 0 -5 1\nat 0 0 0\nup 0 0 1\nangle 40\nhither 0.1\nresolution 64 48\n\
                   l 1 2 3\nl 0 0 5 0.5 0.5 0.5\n# a comment\nf 1 0 0 0.7 0.3 20 0 1\n\
                   s 0 0 0 1\nc 0 0 0 0.5 0 0 1 0.25\np 4\n-1 -1 0\n1 -1 0\n1 1 0\n-1 1 0\n\
                   pp 3\n0 0 2 0 0 1\n1 0 2 0 0 1\n0 1 2 0 0 1\n";
        let mut b = Builder::default();
        let c = load(&mut b, "t.nff", src.as_bytes()).unwrap();
        assert_eq!(c, Counts { spheres: 1, cones: 1, polygons: 1, patches: 1, lights: 2 });
        assert_eq!((b.width, b.height), (64, 48));
        // A sphere, two triangles, a patch and a cone (native, not an object).
        assert_eq!(b.prims.len(), 1 + 2 + 1 + 1);
        assert_eq!(b.objects.len(), 0);
        assert_eq!(b.lights.len(), 2);
        // NFF's lights do not fall off: the second lights a point 5 or 50
        // away alike, with its colour.
        for p in [Vec3::ZERO, Vec3::new(0.0, 0.0, -45.0)] {
            let (l, r, arriving) = b.lights[1].at(p);
            assert_eq!((l, r - (5.0 - p.z)), (Vec3::Z, 0.0));
            assert_eq!(arriving, Vec3::splat(0.5));
        }
        assert_eq!(b.lights[0].at(Vec3::ZERO).2, Vec3::ONE);
        let bad = load(&mut Builder::default(), "t.nff", "s 0 0 0 1\ns 0 0 x 1\n".as_bytes());
        assert_eq!(bad.unwrap_err(), "t.nff:2: expected a position but got \"x\"");
        let bad = load(&mut Builder::default(), "t.nff", "q 1\n".as_bytes());
        assert_eq!(bad.unwrap_err(), "t.nff:1: unknown NFF item \"q\"");
        let bad = load(&mut Builder::default(), "t.nff", "v\nfrom 0 0 5\n".as_bytes());
        assert_eq!(bad.unwrap_err(), "t.nff:1: the file ends where a view keyword should be");
    }

    #[test]
    fn words_run_across_lines_and_stop_at_comments() {
        // A cone over three lines (as SPD writes them), tabs, CRLF line
        // ends, a comment after an item, and a light whose colour is
        // absent: the next line's numbers are not its colour.
        let src = "c\t0 0 0 0.5\r\n0 0 1\r\n  0.25\r\ns 0 0 0 1 # 2 3 4\nl 1 2 3\ns 5 5 5 0.5\n";
        let mut b = Builder::default();
        let c = load(&mut b, "t.nff", src.as_bytes()).unwrap();
        assert_eq!(c, Counts { spheres: 2, cones: 1, lights: 1, ..Counts::default() });
        assert_eq!(b.lights[0].at(Vec3::ZERO).2, Vec3::ONE);
        // Numbers are whole words: "1#" starts a comment, "1x" is no number.
        let bad = load(&mut Builder::default(), "t.nff", "s 0 0 0 1x\n".as_bytes());
        assert_eq!(bad.unwrap_err(), "t.nff:1: expected a radius but got \"1x\"");
        let ok = load(&mut Builder::default(), "t.nff", "s 0 0 0 1#x\n".as_bytes());
        assert_eq!(ok.unwrap().spheres, 1);
    }
}
