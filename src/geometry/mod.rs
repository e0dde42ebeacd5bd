//! Geometry: rays, boxes, spheres, triangles, cones and the BVH over them,
//! and the objects it holds beside them. A leaf:
//! it depends only on glam. Every query takes its own `t_min`/`t_max`;
//! there is no global epsilon.

mod aabb;
mod blob;
mod blocks;
mod bvh;
mod csg;
mod fractal;
mod object;
mod poly;
mod ray;
mod shapes;
mod solid;

pub use aabb::Aabb;
pub use blob::{Blob, Component as BlobComponent};
pub use bvh::{Bvh, BvhStats, Occluder, PACKET, Prefetch, Shadow, TIE, Width};
pub use csg::{
    Csg, Leaf as CsgLeaf, LeafShape as CsgShape, MAX_LEAVES as CSG_MAX_LEAVES, Node as CsgNode,
    Op as CsgOp,
};
pub use fractal::{Flake, MAX_DEPTH as FRACTAL_MAX_DEPTH, Menger};
pub use object::{Kind, Local, Located, Object, Place, ShadowHit};
pub use ray::{Ray, finite};
pub use shapes::{
    Cone, Hit, RayPre, Shape, Triangle, intersect_brute, intersect_cone, intersect_sphere,
    intersect_triangle, intersect_triangle_f64,
};
pub use solid::{Crossing, Crossings, Solid};
