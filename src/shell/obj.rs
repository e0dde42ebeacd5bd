//! Reading Wavefront OBJ meshes (with tobj) into `scene::MeshData`. Polygons
//! are triangulated; `vn` normals are kept; `vt`, materials and groups are
//! ignored. A file tobj rejects is scanned again to name the bad line.

use glam::Vec3;

use crate::scene::MeshData;

pub fn load(path: &str) -> Result<MeshData, String> {
    let file = std::fs::File::open(path)
        .map_err(|e| format!("couldn't read \"{path}\": {}", super::io_reason(&e)))?;
    let mut reader = std::io::BufReader::new(file);
    let opts = tobj::LoadOptions {
        triangulate: true,
        single_index: false,
        ignore_points: true,
        ignore_lines: true,
    };
    let loaded = tobj::load_obj_buf(&mut reader, &opts, |_| Err(tobj::LoadError::OpenFileFailed));
    let models = match loaded {
        Ok((models, _materials)) => models,
        Err(e) => {
            return Err(locate_error(path).unwrap_or_else(|| format!("{path}: bad OBJ file: {e}")));
        }
    };
    let mut mesh = MeshData::default();
    let mut normal_tris = Vec::new();
    let mut all_have_normals = true;
    for m in &models {
        let msh = &m.mesh;
        let vbase = mesh.positions.len() as u32;
        let nbase = mesh.normals.len() as u32;
        mesh.positions.extend(msh.positions.chunks_exact(3).map(|c| Vec3::new(c[0], c[1], c[2])));
        mesh.normals.extend(msh.normals.chunks_exact(3).map(|c| Vec3::new(c[0], c[1], c[2])));
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
    }
    if all_have_normals && !mesh.tris.is_empty() {
        mesh.normal_tris = Some(normal_tris);
    }
    if mesh.tris.is_empty() {
        return Err(format!("{path}: the file has no faces"));
    }
    Ok(mesh)
}

/// Finds the first line tobj would reject, for a `file:line:` message.
fn locate_error(path: &str) -> Option<String> {
    let text = super::read_text(path).ok()?;
    let (mut nv, mut nn) = (0i64, 0i64);
    for (k, line) in text.lines().enumerate() {
        let mut words = line.split_whitespace();
        let floats = |w: std::str::SplitWhitespace| {
            w.take(3).filter(|x| x.parse::<f32>().is_ok()).count() == 3
        };
        let bad = match words.next() {
            Some("v") => {
                nv += 1;
                !floats(words)
            }
            Some("vn") => {
                nn += 1;
                !floats(words)
            }
            Some("f") => {
                let corners: Vec<&str> = words.collect();
                corners.len() < 3
                    || corners.iter().any(|c| {
                        let mut f = c.split('/');
                        let ok_index = |s: Option<&str>, n: i64| match s {
                            None | Some("") => true,
                            Some(s) => s
                                .parse::<i64>()
                                .is_ok_and(|i| i != 0 && i.abs() <= n.max(1) && (i > 0 || -i <= n)),
                        };
                        let v = f.next();
                        v.is_none_or(|v| v.is_empty())
                            || !ok_index(v, nv)
                            || !ok_index(f.next(), i64::MAX)
                            || !ok_index(f.next(), nn)
                    })
            }
            _ => false,
        };
        if bad {
            return Some(format!("{path}:{}: bad OBJ line \"{}\"", k + 1, line.trim()));
        }
    }
    None
}
