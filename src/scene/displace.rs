//! Displacement mapping: a mesh subdivided (each triangle into four, n
//! times, edges shared) and its vertices moved along their normals by a
//! height, amount·noise(p/size), in the mesh's own coordinates. Real
//! geometry: silhouettes and shadows change.

use std::collections::HashMap;

use glam::Vec3;

use super::builder::MeshData;
use super::texture::{Image, noise};

/// `displace noise amount size`, or `displace image FILE amount` (the
/// image's luminance laid on the mesh's xy-plane, the unit square
/// repeating, as a planar texture).
#[derive(Clone, Debug)]
pub struct Displace {
    pub amount: f32,
    pub size: f32,
    pub image: Option<std::sync::Arc<Image>>,
}

impl Displace {
    /// The height at `p`.
    pub fn height(&self, p: Vec3) -> f32 {
        match &self.image {
            None => self.amount * noise(p / self.size),
            Some(img) => {
                self.amount * luminance(img.sample(p.x - p.x.floor(), p.y - p.y.floor(), 1.0))
            }
        }
    }
}

/// Rec. 709 luminance of a linear colour.
pub fn luminance(c: Vec3) -> f32 {
    c.dot(Vec3::new(0.2126, 0.7152, 0.0722))
}

/// The most subdivisions `mesh -subdivide` accepts (4^8 = 65,536
/// triangles for each one).
pub const MAX_SUBDIVIDE: u32 = 8;

/// `mesh` subdivided `n` times (midpoints shared between neighbours, so
/// the surface stays closed), then displaced along its area-weighted
/// vertex normals if `displace` is given. The file's own normals are
/// dropped (the new surface has its own, computed when it is placed).
pub fn subdivide(mesh: &MeshData, n: u32, displace: Option<&Displace>) -> MeshData {
    let mut positions = mesh.positions.clone();
    let mut tris = mesh.tris.clone();
    // Texture coordinates are split the same way, corner by corner (a seam
    // keeps its two sides).
    let mut uvs = mesh.uvs.clone();
    let mut uv_tris = mesh.uv_tris.clone();
    for _ in 0..n.min(MAX_SUBDIVIDE) {
        tris = split(&tris, &mut positions, |a, b| (a + b) * 0.5);
        if let Some(t) = &uv_tris {
            uv_tris = Some(split(t, &mut uvs, |a, b| [(a[0] + b[0]) * 0.5, (a[1] + b[1]) * 0.5]));
        }
    }
    if let Some(d) = displace {
        let mut normals = vec![Vec3::ZERO; positions.len()];
        for t in &tris {
            let [a, b, c] = t.map(|i| positions[i as usize]);
            let n = (b - a).cross(c - a);
            for &i in t {
                normals[i as usize] += n;
            }
        }
        for (p, n) in positions.iter_mut().zip(&normals) {
            *p += n.normalize_or_zero() * d.height(*p);
        }
    }
    MeshData { positions, normals: Vec::new(), tris, normal_tris: None, uvs, uv_tris }
}

/// Each triangle of `tris` cut in four at its edges' midpoints (made by
/// `mid` and added to `pool`, once for each edge neighbours share).
fn split<T: Copy>(tris: &[[u32; 3]], pool: &mut Vec<T>, mid: impl Fn(T, T) -> T) -> Vec<[u32; 3]> {
    let mut made: HashMap<(u32, u32), u32> = HashMap::new();
    let mut at = |a: u32, b: u32, pool: &mut Vec<T>| {
        *made.entry((a.min(b), a.max(b))).or_insert_with(|| {
            pool.push(mid(pool[a as usize], pool[b as usize]));
            pool.len() as u32 - 1
        })
    };
    let mut next = Vec::with_capacity(tris.len() * 4);
    for &[a, b, c] in tris {
        let (ab, bc, ca) = (at(a, b, pool), at(b, c, pool), at(c, a, pool));
        next.extend([[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]);
    }
    next
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A flat square: every vertex moves straight up by its height, and
    /// subdividing twice makes 32 triangles on 25 shared vertices.
    #[test]
    fn vertices_move_by_height_along_the_normal() {
        let square = MeshData {
            positions: vec![
                Vec3::new(0.0, 0.0, 0.0),
                Vec3::new(1.0, 0.0, 0.0),
                Vec3::new(1.0, 1.0, 0.0),
                Vec3::new(0.0, 1.0, 0.0),
            ],
            normals: Vec::new(),
            tris: vec![[0, 1, 2], [0, 2, 3]],
            normal_tris: None,
            ..MeshData::default()
        };
        let flat = subdivide(&square, 2, None);
        assert_eq!((flat.tris.len(), flat.positions.len()), (32, 25));
        let d = Displace { amount: 0.2, size: 0.3, image: None };
        let moved = subdivide(&square, 2, Some(&d));
        for (p, q) in flat.positions.iter().zip(&moved.positions) {
            assert!((q.x - p.x).abs() < 1e-6 && (q.y - p.y).abs() < 1e-6);
            assert!((q.z - d.height(*p)).abs() < 1e-6, "{p} went to {q}");
        }
        assert!(moved.positions.iter().any(|p| p.z.abs() > 0.01));
    }
}
