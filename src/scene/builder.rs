//! `Builder`: geometry pools (vertices, normals), triangles and spheres,
//! added by the scene commands. Indices are checked when a primitive is
//! added, so a frozen scene never holds a dangling index.

use glam::Vec3;

#[derive(Debug, Clone, PartialEq)]
pub enum SceneError {
    IndexOutOfRange { pool: &'static str, index: i64, size: usize },
    NotFinite,
    Capacity { what: &'static str },
}

impl std::fmt::Display for SceneError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            SceneError::IndexOutOfRange { pool, index, size } => {
                write!(f, "{pool} index {index} out of range: the {pool} pool has {size} entries")
            }
            SceneError::NotFinite => write!(f, "numbers must be finite (not NaN or infinite)"),
            SceneError::Capacity { what } => write!(f, "too many {what}: the limit is 2^32"),
        }
    }
}

#[derive(Default)]
pub struct Builder {
    pub vertices: Vec<Vec3>,
    pub normals: Vec<Vec3>,
    /// Triangles as (vertex, normal) index triples; normal `u32::MAX` = flat.
    pub triangles: Vec<[(u32, u32); 3]>,
}

const FLAT: u32 = u32::MAX;

impl Builder {
    pub fn new() -> Builder {
        Builder::default()
    }

    fn check_finite(v: Vec3) -> Result<(), SceneError> {
        if v.is_finite() { Ok(()) } else { Err(SceneError::NotFinite) }
    }

    /// Adds a vertex; returns its index.
    pub fn vertex(&mut self, p: Vec3) -> Result<usize, SceneError> {
        Builder::check_finite(p)?;
        if self.vertices.len() >= FLAT as usize {
            return Err(SceneError::Capacity { what: "vertices" });
        }
        self.vertices.push(p);
        Ok(self.vertices.len() - 1)
    }

    /// Adds a normal; returns its index.
    pub fn normal(&mut self, n: Vec3) -> Result<usize, SceneError> {
        Builder::check_finite(n)?;
        if self.normals.len() >= FLAT as usize {
            return Err(SceneError::Capacity { what: "normals" });
        }
        self.normals.push(n);
        Ok(self.normals.len() - 1)
    }

    fn vertex_index(&self, i: i64) -> Result<u32, SceneError> {
        if i < 0 || i as usize >= self.vertices.len() {
            return Err(SceneError::IndexOutOfRange {
                pool: "vertex",
                index: i,
                size: self.vertices.len(),
            });
        }
        Ok(i as u32)
    }

    fn normal_index(&self, i: i64) -> Result<u32, SceneError> {
        if i < 0 || i as usize >= self.normals.len() {
            return Err(SceneError::IndexOutOfRange {
                pool: "normal",
                index: i,
                size: self.normals.len(),
            });
        }
        Ok(i as u32)
    }

    /// A flat triangle from three vertex indices (counter-clockwise).
    pub fn tri(&mut self, v: [i64; 3]) -> Result<(), SceneError> {
        let t = [
            (self.vertex_index(v[0])?, FLAT),
            (self.vertex_index(v[1])?, FLAT),
            (self.vertex_index(v[2])?, FLAT),
        ];
        self.triangles.push(t);
        Ok(())
    }

    /// A smooth triangle: (vertex, normal) index pairs.
    pub fn ntri(&mut self, vn: [(i64, i64); 3]) -> Result<(), SceneError> {
        let mut t = [(0, 0); 3];
        for (slot, (v, n)) in t.iter_mut().zip(vn) {
            *slot = (self.vertex_index(v)?, self.normal_index(n)?);
        }
        self.triangles.push(t);
        Ok(())
    }

    /// Back to the initial state.
    pub fn clear(&mut self) {
        *self = Builder::default();
    }
}
