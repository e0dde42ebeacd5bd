//! Reading Wavefront OBJ meshes (with tobj; gzip-compressed with flate2)
//! into `scene::MeshData`. Polygons
//! are triangulated; `vn` normals and `vt` texture coordinates are kept
//! (each only when every face has them); materials and groups are ignored. Each line is checked on its way to tobj, so a bad one is named
//! by its line number.

use std::io::{BufRead, Read};

use glam::Vec3;

use crate::scene::MeshData;

/// Reads an OBJ file; a name ending in `.gz` is gzip-compressed OBJ.
pub fn load(path: &str) -> Result<MeshData, String> {
    let file = std::fs::File::open(path)
        .map_err(|e| format!("couldn't read \"{path}\": {}", super::io_reason(&e)))?;
    // Streamed: a large file is never held in memory whole.
    if path.ends_with(".gz") {
        let gz = flate2::read::GzDecoder::new(std::io::BufReader::new(file));
        return from_reader(path, std::io::BufReader::new(gz));
    }
    from_reader(path, std::io::BufReader::new(file))
}

/// Parses OBJ text held in memory; `path` names it in messages.
pub fn parse(path: &str, bytes: &[u8]) -> Result<MeshData, String> {
    from_reader(path, bytes)
}

fn from_reader(path: &str, reader: impl BufRead) -> Result<MeshData, String> {
    let opts = tobj::LoadOptions {
        triangulate: true,
        single_index: false,
        ignore_points: true,
        ignore_lines: true,
    };
    let mut checked = Checked::new(reader);
    let loaded = tobj::load_obj_buf(&mut checked, &opts, |_| Err(tobj::LoadError::OpenFileFailed));
    if let Some((line, why)) = checked.stop {
        return Err(format!("{path}:{line}: {why}"));
    }
    if let Some((line, text)) = checked.bad {
        return Err(format!("{path}:{line}: bad OBJ line \"{}\"", text.trim()));
    }
    let models = match loaded {
        Ok((models, _materials)) => models,
        Err(e) => return Err(format!("{path}: bad OBJ file: {e}")),
    };
    let mut mesh = MeshData::default();
    let mut normal_tris = Vec::new();
    let mut uv_tris = Vec::new();
    let (mut all_have_normals, mut all_have_uvs) = (true, true);
    for m in &models {
        let msh = &m.mesh;
        let vbase = mesh.positions.len() as u32;
        let nbase = mesh.normals.len() as u32;
        let tbase = mesh.uvs.len() as u32;
        mesh.positions.extend(msh.positions.chunks_exact(3).map(|c| Vec3::new(c[0], c[1], c[2])));
        mesh.normals.extend(msh.normals.chunks_exact(3).map(|c| Vec3::new(c[0], c[1], c[2])));
        mesh.uvs.extend(msh.texcoords.chunks_exact(2).map(|c| [c[0], c[1]]));
        let n_v = msh.positions.len() / 3;
        for t in msh.indices.chunks_exact(3) {
            if t.iter().any(|&i| i as usize >= n_v) {
                return Err(format!("{path}: a face refers to a vertex that does not exist"));
            }
            mesh.tris.push([vbase + t[0], vbase + t[1], vbase + t[2]]);
        }
        if msh.normal_indices.len() == msh.indices.len() && !msh.normals.is_empty() {
            normal_tris.extend(
                msh.normal_indices
                    .chunks_exact(3)
                    .map(|t| [nbase + t[0], nbase + t[1], nbase + t[2]]),
            );
        } else {
            all_have_normals = false;
        }
        if msh.texcoord_indices.len() == msh.indices.len() && !msh.texcoords.is_empty() {
            uv_tris.extend(
                msh.texcoord_indices
                    .chunks_exact(3)
                    .map(|t| [tbase + t[0], tbase + t[1], tbase + t[2]]),
            );
        } else {
            all_have_uvs = false;
        }
    }
    if all_have_normals && !mesh.tris.is_empty() {
        mesh.normal_tris = Some(normal_tris);
    }
    if all_have_uvs && !mesh.tris.is_empty() {
        mesh.uv_tris = Some(uv_tris);
    }
    if mesh.tris.is_empty() {
        return Err(format!("{path}: the file has no faces"));
    }
    Ok(mesh)
}

/// A line-by-line filter in front of tobj: it checks each line as it
/// passes (numbers parse, face indices exist, counting `v`/`vt`/`vn` so far)
/// and ends the input at the first bad one, remembering it for a `file:line`
/// message. tobj itself trusts face indices (an out-of-range one overflows
/// its arithmetic), so nothing unchecked reaches it.
struct Checked<R> {
    inner: R,
    buf: Vec<u8>,
    pos: usize,
    line: usize,
    counts: [i64; 3],
    bad: Option<(usize, String)>,
    /// Why reading stopped early: a line too long, the memory budget, Ctrl-C.
    stop: Option<(usize, String)>,
}

/// The longest OBJ line read (a face of a million corners fits).
const MAX_LINE: u64 = 16 << 20;

impl<R: BufRead> Checked<R> {
    fn new(inner: R) -> Checked<R> {
        Checked { inner, buf: Vec::new(), pos: 0, line: 0, counts: [0; 3], bad: None, stop: None }
    }

    /// Why the next line should not be read, if it should not.
    fn stop_reason(&self) -> Option<String> {
        if self.buf.len() as u64 >= MAX_LINE && !self.buf.ends_with(b"\n") {
            return Some(format!("line longer than {}", crate::mem::human(MAX_LINE as usize)));
        }
        if self.line.is_multiple_of(4096) {
            if let Err(e) = crate::mem::check() {
                return Some(e.to_string());
            }
            if super::feedback::INTERRUPTED.load(std::sync::atomic::Ordering::Relaxed) {
                return Some("interrupted".into());
            }
        }
        None
    }
}

/// Whether `line` is one tobj can take safely; `counts` holds the `v`, `vt`
/// and `vn` lines seen so far.
fn line_ok(line: &str, counts: &mut [i64; 3]) -> bool {
    let mut words = line.split_whitespace();
    // Finite numbers only: a NaN or infinite coordinate is named by its line.
    let floats = |w: std::str::SplitWhitespace, n: usize| {
        w.take(n).filter(|x| x.parse::<f32>().is_ok_and(f32::is_finite)).count() == n
    };
    let index_ok = |p: &str, n: i64| {
        p.is_empty()
            || p.parse::<i64>().is_ok_and(|i| (1..=n).contains(&i) || (-n..=-1).contains(&i))
    };
    match words.next() {
        Some("v") => {
            counts[0] += 1;
            floats(words, 3)
        }
        // u and v (a third, w, is ignored).
        Some("vt") => {
            counts[1] += 1;
            floats(words, 2)
        }
        Some("vn") => {
            counts[2] += 1;
            floats(words, 3)
        }
        // tobj reads `l` (polyline) corners like a face's, then drops them.
        Some(kind @ ("f" | "l")) => {
            let mut corners = 0;
            let all = words.all(|c| {
                corners += 1;
                let mut parts = c.split('/');
                let v = parts.next().unwrap_or("");
                !v.is_empty()
                    && index_ok(v, counts[0])
                    && index_ok(parts.next().unwrap_or(""), counts[1])
                    && index_ok(parts.next().unwrap_or(""), counts[2])
                    && parts.next().is_none()
            });
            all && corners >= if kind == "f" { 3 } else { 2 }
        }
        _ => true,
    }
}

impl<R: BufRead> std::io::Read for Checked<R> {
    fn read(&mut self, out: &mut [u8]) -> std::io::Result<usize> {
        let avail = self.fill_buf()?;
        let n = avail.len().min(out.len());
        out[..n].copy_from_slice(&avail[..n]);
        self.consume(n);
        Ok(n)
    }
}

impl<R: BufRead> BufRead for Checked<R> {
    fn fill_buf(&mut self) -> std::io::Result<&[u8]> {
        if self.pos == self.buf.len() && self.bad.is_none() && self.stop.is_none() {
            self.buf.clear();
            self.pos = 0;
            (&mut self.inner).take(MAX_LINE).read_until(b'\n', &mut self.buf)?;
            if let Some(why) = self.stop_reason() {
                self.stop = Some((self.line + 1, why));
                self.buf.clear();
                return Ok(&[]);
            }
            // A UTF-8 byte order mark opening the file is not OBJ text.
            if self.line == 0 && self.buf.starts_with(b"\xef\xbb\xbf") {
                self.buf.drain(..3);
            }
            if !self.buf.is_empty() {
                self.line += 1;
                let ok = std::str::from_utf8(&self.buf)
                    .is_ok_and(|text| line_ok(text, &mut self.counts));
                if !ok {
                    self.bad = Some((self.line, String::from_utf8_lossy(&self.buf).into_owned()));
                    self.buf.clear();
                }
            }
        }
        Ok(&self.buf[self.pos..])
    }

    fn consume(&mut self, n: usize) {
        self.pos = (self.pos + n).min(self.buf.len());
    }
}
