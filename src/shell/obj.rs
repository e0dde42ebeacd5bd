//! Reading Wavefront OBJ meshes into `scene::MeshData` (gzip-compressed
//! with flate2). Polygons are triangulated; `vn` normals and `vt` texture
//! coordinates are kept (each only when every face has them); materials
//! and groups are ignored.
//!
//! Two readers, one result. tobj is the reference: each line is checked on
//! its way to it, so a bad one is named by its line number. Most files
//! (one object, faces of one form, plain `v`/`vn`/`vt` lines) are read by
//! `Fast`, a single pass over the bytes that makes what tobj makes, down
//! to the order of the vertices; it hands anything else (an error, a
//! second object, a `w` coordinate, a vertex colour, a line tobj reads
//! with a quirk) back to tobj, which reads the file again from the start.
//! tobj took 36-90 ms for the 69k-triangle bunny, most of it checking
//! each line and then parsing it again, hashing each corner and growing
//! its vectors; `Fast` takes a few.

use std::io::{BufRead, Read};

use glam::Vec3;

use crate::scene::MeshData;

/// Reads an OBJ file; a name ending in `.gz` is gzip-compressed OBJ.
pub fn load(path: &str) -> Result<MeshData, String> {
    if let Some(mesh) = Fast::read(open(path)?) {
        return Ok(mesh);
    }
    load_with_tobj(path)
}

/// `load` by tobj alone (the reference `Fast` is checked against).
pub fn load_with_tobj(path: &str) -> Result<MeshData, String> {
    from_reader(path, open(path)?)
}

/// The file at `path`, buffered, decompressed when its name ends in `.gz`.
/// Streamed: a large file is never held in memory whole.
fn open(path: &str) -> Result<Box<dyn BufRead>, String> {
    let file = super::safe::open_read(path).map_err(|e| e.message(path))?;
    if path.ends_with(".gz") {
        let gz = flate2::read::GzDecoder::new(std::io::BufReader::new(file));
        return Ok(Box::new(std::io::BufReader::with_capacity(CHUNK, gz)));
    }
    Ok(Box::new(std::io::BufReader::with_capacity(CHUNK, file)))
}

/// Parses OBJ text held in memory; `path` names it in messages.
pub fn parse(path: &str, bytes: &[u8]) -> Result<MeshData, String> {
    if let Some(mesh) = Fast::read(bytes) {
        return Ok(mesh);
    }
    parse_with_tobj(path, bytes)
}

/// `parse` by tobj alone.
pub fn parse_with_tobj(path: &str, bytes: &[u8]) -> Result<MeshData, String> {
    from_reader(path, bytes)
}

/// `Fast` alone: the mesh, or `None` where it leaves the file to tobj.
pub fn parse_fast(bytes: &[u8]) -> Option<MeshData> {
    Fast::read(bytes)
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

/// The bytes `Fast` reads at a time.
const CHUNK: usize = 1 << 20;

/// The single-pass reader of the common OBJ file (see the module's notes).
/// It makes tobj's mesh of one object: each pool (positions, normals,
/// texture coordinates) holds the entries the faces use, in the order
/// their corners first use them, and polygons become fans, (a, b, c),
/// (a, c, d), and so on.
#[derive(Default)]
struct Fast {
    /// Every `v`, `vn` and `vt` line's values so far, in the file's order.
    v: Vec<Vec3>,
    vn: Vec<Vec3>,
    vt: Vec<[f32; 2]>,
    /// Each pool entry's number in the mesh, once a corner has used it
    /// (`u32::MAX` before).
    v_at: Vec<u32>,
    vn_at: Vec<u32>,
    vt_at: Vec<u32>,
    /// Whether the faces' corners give texture coordinates and normals
    /// (one form for all of them; set by the first face).
    form: Option<(bool, bool)>,
    mesh: MeshData,
    normal_tris: Vec<[u32; 3]>,
    uv_tris: Vec<[u32; 3]>,
    lines: usize,
}

impl Fast {
    /// The mesh of the OBJ text `reader` gives, or `None` where the file
    /// is one for tobj (and a read error: tobj reads it again and says).
    fn read(mut reader: impl BufRead) -> Option<MeshData> {
        let mut fast = Fast::default();
        let mut carry: Vec<u8> = Vec::new();
        loop {
            let chunk = reader.fill_buf().ok()?;
            if chunk.is_empty() {
                break;
            }
            let n = chunk.len();
            // Whole lines from the chunk; a line cut at its end waits in
            // `carry` for the rest.
            let lines = match chunk.iter().rposition(|&b| b == b'\n') {
                Some(end) if carry.is_empty() => {
                    fast.lines_of(&chunk[..=end])?;
                    &chunk[end + 1..]
                }
                Some(end) => {
                    carry.extend_from_slice(&chunk[..=end]);
                    fast.lines_of(&carry)?;
                    carry.clear();
                    &chunk[end + 1..]
                }
                None => chunk,
            };
            carry.extend_from_slice(lines);
            if carry.len() as u64 > MAX_LINE {
                return None;
            }
            reader.consume(n);
        }
        fast.lines_of(&carry)?;
        fast.finish()
    }

    /// Reads the lines of `text` (whole lines).
    fn lines_of(&mut self, text: &[u8]) -> Option<()> {
        for line in text.split(|&b| b == b'\n') {
            // A UTF-8 byte order mark opening the file is not OBJ text.
            let line = match self.lines {
                0 => line.strip_prefix(b"\xef\xbb\xbf").unwrap_or(line),
                _ => line,
            };
            self.lines += 1;
            if self.lines.is_multiple_of(4096)
                && (crate::mem::check().is_err()
                    || super::feedback::INTERRUPTED.load(std::sync::atomic::Ordering::Relaxed))
            {
                return None;
            }
            self.line(line)?;
        }
        Some(())
    }

    /// One line (without its newline); `None` where it is for tobj.
    fn line(&mut self, line: &[u8]) -> Option<()> {
        // (Outside ASCII, and in it the vertical tab, tobj splits words on
        // more than `Fast` does.)
        if !line.is_ascii() || line.contains(&0x0b) {
            return None;
        }
        let mut words = line.split(|b| b.is_ascii_whitespace()).filter(|w| !w.is_empty());
        let Some(first) = words.next() else { return Some(()) };
        match first {
            b"v" => {
                let p = floats::<3>(&mut words);
                // (A fourth value is a weight, six a colour: tobj's.)
                p.filter(|_| words.next().is_none()).map(|p| self.v.push(Vec3::from(p)))
            }
            b"vn" => {
                let n = floats::<3>(&mut words);
                n.filter(|_| words.next().is_none()).map(|n| self.vn.push(Vec3::from(n)))
            }
            // u and v (a third, w, is ignored, as tobj ignores it).
            b"vt" => floats::<2>(&mut words).map(|t| self.vt.push(t)),
            b"f" => self.face(words),
            // A new object after faces is a model of its own in tobj, its
            // pools numbered apart.
            b"o" | b"g" => self.mesh.tris.is_empty().then_some(()),
            // (No material is ever loaded, so none splits the mesh; a
            // name is needed, after a space.)
            b"usemtl" => {
                let name = line.iter().position(|&b| b == b' ').map_or(&[][..], |k| &line[k + 1..]);
                (!name.trim_ascii().is_empty()).then_some(())
            }
            // tobj reads a polyline's corners as a face's.
            b"l" => None,
            _ => Some(()),
        }
    }

    /// A face line's corners (after `f`), as fans of triangles.
    fn face<'a>(&mut self, words: impl Iterator<Item = &'a [u8]>) -> Option<()> {
        let mut first = [0u32; 3];
        let mut last = [0u32; 3];
        let mut n = 0;
        for word in words {
            let mut parts = word.split(|&b| b == b'/');
            let v = index(parts.next()?, self.v.len())?;
            let (vt, vn) = match (parts.next(), parts.next(), parts.next()) {
                (None, _, _) => (None, None),
                (Some(t), None, _) => (Some(index(t, self.vt.len())?), None),
                (Some(b""), Some(nrm), None) => (None, Some(index(nrm, self.vn.len())?)),
                (Some(t), Some(nrm), None) => {
                    (Some(index(t, self.vt.len())?), Some(index(nrm, self.vn.len())?))
                }
                _ => return None,
            };
            let form = (vt.is_some(), vn.is_some());
            if *self.form.get_or_insert(form) != form {
                return None;
            }
            let corner = [
                at(&mut self.v_at, v, &self.v, &mut self.mesh.positions),
                vt.map_or(0, |t| at(&mut self.vt_at, t, &self.vt, &mut self.mesh.uvs)),
                vn.map_or(0, |k| at(&mut self.vn_at, k, &self.vn, &mut self.mesh.normals)),
            ];
            n += 1;
            if n == 1 {
                first = corner;
            } else if n >= 3 {
                let tri = |k: usize| [first[k], last[k], corner[k]];
                self.mesh.tris.push(tri(0));
                if form.0 {
                    self.uv_tris.push(tri(1));
                }
                if form.1 {
                    self.normal_tris.push(tri(2));
                }
            }
            last = corner;
        }
        (n >= 3).then_some(())
    }

    /// The mesh, or `None` where tobj makes something else of the file.
    fn finish(self) -> Option<MeshData> {
        let Fast { vn, vt, form, mut mesh, normal_tris, uv_tris, .. } = self;
        let (uvs, normals) = form?;
        // Pools the faces do not use: tobj gives each corner an entry of
        // them all the same.
        if (!vt.is_empty() && !uvs) || (!vn.is_empty() && !normals) {
            return None;
        }
        mesh.uv_tris = uvs.then_some(uv_tris);
        mesh.normal_tris = normals.then_some(normal_tris);
        Some(mesh)
    }
}

/// `N` finite numbers from `words` (f32, parsed as tobj parses them).
fn floats<'a, const N: usize>(words: &mut impl Iterator<Item = &'a [u8]>) -> Option<[f32; N]> {
    let mut out = [0.0; N];
    for o in &mut out {
        // (ASCII, so UTF-8.)
        let x: f32 = std::str::from_utf8(words.next()?).ok()?.parse().ok()?;
        *o = x.is_finite().then_some(x)?;
    }
    Some(out)
}

/// A corner's index into a pool of `n` entries so far, from 0: 1 to n, or
/// -n to -1 counted back from the last.
fn index(word: &[u8], n: usize) -> Option<usize> {
    let (negative, digits) = match word.split_first()? {
        (b'-', rest) => (true, rest),
        _ => (false, word),
    };
    if digits.is_empty() || digits.len() > 18 || !digits.iter().all(u8::is_ascii_digit) {
        return None;
    }
    let k = digits.iter().fold(0usize, |a, &d| a * 10 + (d - b'0') as usize);
    match (negative, k) {
        (_, 0) => None,
        (false, k) if k <= n => Some(k - 1),
        (true, k) if k <= n => Some(n - k),
        _ => None,
    }
}

/// Pool entry `i`'s number in the mesh, given it (from `pool` into `out`)
/// at its first use.
fn at<T: Copy>(numbers: &mut Vec<u32>, i: usize, pool: &[T], out: &mut Vec<T>) -> u32 {
    if numbers.len() < pool.len() {
        numbers.resize(pool.len(), u32::MAX);
    }
    if numbers[i] == u32::MAX {
        numbers[i] = out.len() as u32;
        out.push(pool[i]);
    }
    numbers[i]
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

#[cfg(test)]
mod tests {
    use super::*;

    /// A mesh's values, bit for bit: pools and triangles, then the
    /// corners' normals and texture coordinates.
    type Bits = (Vec<[u32; 3]>, Vec<[u32; 3]>, Vec<[u32; 2]>, Vec<[u32; 3]>);
    type Corners = Option<Vec<[u32; 3]>>;

    fn bits(m: &MeshData) -> (Bits, Corners, Corners) {
        let v3 = |v: &Vec<Vec3>| v.iter().map(|p| p.to_array().map(f32::to_bits)).collect();
        let uv = m.uvs.iter().map(|t| t.map(f32::to_bits)).collect();
        (
            (v3(&m.positions), v3(&m.normals), uv, m.tris.clone()),
            m.normal_tris.clone(),
            m.uv_tris.clone(),
        )
    }

    /// `Fast` reads `text` and makes tobj's mesh of it.
    fn same(text: &str) {
        let fast = parse_fast(text.as_bytes()).unwrap_or_else(|| panic!("left to tobj:\n{text}"));
        let tobj = parse_with_tobj("t.obj", text.as_bytes()).expect("tobj reads it");
        assert_eq!(bits(&fast), bits(&tobj), "{text}");
    }

    /// `Fast` leaves `text` to tobj, and `parse` gives tobj's answer.
    fn left(text: &str) {
        assert!(parse_fast(text.as_bytes()).is_none(), "read by Fast:\n{text}");
        let ours = parse("t.obj", text.as_bytes()).map(|m| bits(&m));
        assert_eq!(ours, parse_with_tobj("t.obj", text.as_bytes()).map(|m| bits(&m)));
    }

    const QUAD: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n";

    #[test]
    fn fast_reader_makes_tobjs_mesh() {
        same("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
        // Pools numbered by first use; unused entries dropped; fans.
        same(
            "v 9 9 9\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 2 0\nf 5 4 3 2\nf 2 3 6\nf 6 5 4 3 2\n",
        );
        same(&format!("{QUAD}f -4 -3 -2 -1\nv 2 2 2\nf -1 -2 -3\n"));
        same(&format!("{QUAD}vt 0 0\nvt 1 0 0.5\nvt 1 1\nf 1/3 2/2 3/1\nf 1/1 3/3 4/2\n"));
        same(&format!("{QUAD}vn 0 0 1\nvn 0 0 -1\nf 1//2 2//2 3//1 4//1\n"));
        same(&format!("{QUAD}vt 0 0\nvt 1 0\nvn 0 0 1\nf 4/2/1 3/1/1 2/2/1 1/1/1\n"));
        // Comments, blank lines, CRLF, tabs, a byte order mark, names
        // before the faces, materials, smoothing groups.
        same(&format!(
            "\u{feff}# a quad\r\nmtllib x.mtl\r\no quad\r\ng side\r\n\r\n{}usemtl red\r\ns off\r\nf\t1  2 3 4 \r\n",
            QUAD.replace('\n', "\r\n")
        ));
        // Pools given after the faces that use them.
        same("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/1\nvt 1 1\nv 5 5 5\n");
        // No newline at the end; numbers in other notations.
        same("v 1e-3 -0 .5\nv 1.5E2 2 3\nv -7 +8 9\nf 1 2 3");
        // Lines longer than a chunk, and lines across chunks.
        let mut big = String::new();
        for k in 0..60_000 {
            big.push_str(&format!("v {k}.25 {} 1e{}\n", k % 7, k % 30));
        }
        for k in 1..59_998 {
            big.push_str(&format!("f {} {} {}\n", k, k + 1, k + 2));
        }
        big.push_str(&format!("# {}\nf 1 2 3\n", "x".repeat(3 * CHUNK)));
        same(&big);
    }

    /// A xorshift generator for the random files.
    struct Rng(u64);

    impl Rng {
        fn below(&mut self, n: usize) -> usize {
            self.0 ^= self.0 << 13;
            self.0 ^= self.0 >> 7;
            self.0 ^= self.0 << 17;
            (self.0 % n as u64) as usize
        }

        /// One time in `n`.
        fn rarely(&mut self, n: usize) -> bool {
            self.below(n) == 0
        }

        /// A corner's index into a pool of `n` so far: in range from either
        /// end, or (`wrong`, rarely) 0 or past the end.
        fn index(&mut self, n: usize, wrong: bool) -> i64 {
            if n == 0 || (wrong && self.rarely(20)) {
                return [0, n as i64 + 1, -(n as i64) - 1][self.below(3)];
            }
            let k = 1 + self.below(n) as i64;
            if self.rarely(4) { -k } else { k }
        }
    }

    /// A random OBJ file: pools and faces of one corner form, and, when
    /// `wrong`, now and then a line tobj rejects or reads its own way.
    fn random_file(r: &mut Rng, wrong: bool) -> String {
        let good = ["0", "1", "-1", "0.5", "2e1", "-0", ".25", "3.75e-2", "7"];
        let bad = ["nan", "x", "+3", "1e40", "inf", "0x1"];
        let number = |r: &mut Rng| {
            if wrong && r.rarely(40) { bad[r.below(bad.len())] } else { good[r.below(good.len())] }
        };
        let form = r.below(4);
        // Pools the faces can use from the start.
        let (mut v, mut vt, mut vn) = (3, (form % 2 == 1) as usize, (form >= 2) as usize);
        let mut text = String::from("v 0 0 0\nv 1 0 0\nv 0 1 0\n");
        text.push_str(["", "vt 0 1\n", "vn 0 0 1\n", "vt 1 0\nvn 1 0 0\n"][form]);
        for _ in 0..1 + r.below(30) {
            let line = match r.below(12) {
                0..=3 => {
                    v += 1;
                    let n = if wrong && r.rarely(15) { 1 + r.below(6) } else { 3 };
                    let xs: Vec<_> = (0..n).map(|_| number(r)).collect();
                    format!("v {}", xs.join(" "))
                }
                4 if form >= 2 || (wrong && r.rarely(10)) => {
                    vn += 1;
                    format!("vn {} {} {}", number(r), number(r), number(r))
                }
                5 if form % 2 == 1 || (wrong && r.rarely(10)) => {
                    vt += 1;
                    let w = if r.rarely(3) { " 0.5" } else { "" };
                    format!("vt {} {}{w}", number(r), number(r))
                }
                6..=9 => {
                    let corners: Vec<_> = (0..3 + r.below(3) - (wrong && r.rarely(20)) as usize)
                        .map(|_| {
                            let f = if wrong && r.rarely(25) { r.below(4) } else { form };
                            let i = r.index(v, wrong);
                            match f {
                                0 => format!("{i}"),
                                1 => format!("{i}/{}", r.index(vt, wrong)),
                                2 => format!("{i}//{}", r.index(vn, wrong)),
                                _ => format!("{i}/{}/{}", r.index(vt, wrong), r.index(vn, wrong)),
                            }
                        })
                        .collect();
                    format!("f {}", corners.join(if r.rarely(8) { "\t" } else { " " }))
                }
                10 => ["# c", "", "s 1", "mtllib x.mtl", "usemtl m", "  \t"][r.below(6)].into(),
                _ if wrong => ["g a", "o b", "usemtl", "l 1 2", "v 1 2 3 4"][r.below(5)].into(),
                _ => String::new(),
            };
            text.push_str(&line);
            text.push_str(if r.rarely(10) { "\r\n" } else { "\n" });
        }
        text
    }

    /// Random files from OBJ's words: wherever `Fast` reads one, tobj
    /// makes the same mesh of it; and `parse` always gives tobj's answer,
    /// mesh or error.
    #[test]
    fn fast_reader_agrees_with_tobj_on_random_files() {
        let mut r = Rng(0x9e37_79b9_7f4a_7c15);
        let (mut read, mut left) = (0, 0);
        for k in 0..4000 {
            let text = random_file(&mut r, k % 2 == 1);
            let bytes = text.as_bytes();
            let tobj = parse_with_tobj("r.obj", bytes).map(|m| bits(&m));
            match parse_fast(bytes) {
                Some(m) => {
                    read += 1;
                    assert_eq!(Ok(bits(&m)), tobj, "{text:?}");
                }
                None => left += 1,
            }
            assert_eq!(parse("r.obj", bytes).map(|m| bits(&m)), tobj, "{text:?}");
        }
        // Both ways taken often enough for the comparison to mean something.
        assert!(read > 1000 && left > 1000, "read {read}, left {left}");
    }

    #[test]
    fn fast_reader_leaves_tobj_its_quirks_and_errors() {
        left(&format!("{QUAD}v 1 1 1 2\nf 1 2 5\n")); // a weight
        left(&format!("{QUAD}v 1 1 1 0.5 0.5 0.5\nf 1 2 5\n")); // a colour
        left(&format!("{QUAD}f 1 2 3\ng two\nf 1 3 4\n")); // a second model
        left(&format!("{QUAD}usemtl\tred\nf 1 2 3\n")); // no material name
        left(&format!("{QUAD}vt 0 0\nf 1/1 2/1 3/1\nf 1 3 4\n")); // mixed forms
        left(&format!("{QUAD}vn 0 0 1\nf 1 2 3\n")); // normals no face uses
        left(&format!("{QUAD}vt 0 0\nf 1 2 3\n"));
        left(&format!("{QUAD}l 1 2 3\nf 1 2 3\n")); // a polyline
        left(&format!("{QUAD}f +1 2 3\n")); // a signed index
        left(&format!("{QUAD}f 1 2 3\u{b}4\n")); // a vertical tab
        left(&format!("{QUAD}f 1 2 3 # é\n"));
        // Errors, named by tobj's reader.
        left(&format!("{QUAD}v nan 0 0\nf 1 2 3\n"));
        left(&format!("{QUAD}v inf 0 0\nf 1 2 3\n"));
        left(&format!("{QUAD}f 0 1 2\n"));
        left(&format!("{QUAD}f 1 2 5\n"));
        left(&format!("{QUAD}f 1 2 -5\n"));
        left(&format!("{QUAD}f 1 2\n"));
        left(&format!("{QUAD}f 1/1 2/1 3/1\n"));
        left(&format!("{QUAD}f 1/1/1/1 2 3\n"));
        left(&format!("{QUAD}vn 0 0\nf 1 2 3\n"));
        left(QUAD);
        left("");
        let e = parse("t.obj", format!("{QUAD}f 1 2 9\n").as_bytes()).map(|_| ());
        assert_eq!(e, Err("t.obj:5: bad OBJ line \"f 1 2 9\"".to_string()));
    }
}
