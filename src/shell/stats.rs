//! What the shell remembers between commands (whether to print statistics,
//! the last render's figures) and the `--stats` / `stats` report.

use std::time::Instant;

use super::feedback::{Feedback, ProgressMode};
use crate::render::RayStats;
use crate::scene::Scene;

pub struct ShellState {
    pub print_stats: bool,
    /// When the script started, or the last render finished: the time
    /// since is reported as "parse" (running the script up to the render).
    pub since_last: Instant,
    pub last: Option<RenderReport>,
    /// Progress, preview, crop and pass order for renders.
    pub feedback: Feedback,
    /// `raybench -threads N`'s thread pools, kept for the session.
    pub pools: Vec<(usize, std::sync::Arc<rayon::ThreadPool>)>,
    /// The last picture traced, so rendering an unchanged scene again
    /// writes it without tracing.
    pub last_picture: Option<Picture>,
    /// The bytes of the last picture written, the next one's buffer
    /// (`Image::to_rgb8_into`).
    pub bytes: Vec<u8>,
    /// How many times this session traced its scene (`render`,
    /// `raybench`): none means a script built a scene and never looked.
    pub renders: usize,
    /// The last render's BVH, for the next render of the same geometry
    /// from the same eye.
    pub tree: Option<Tree>,
}

/// A BVH kept between renders, and what it was built from.
pub struct Tree {
    /// `Builder::geometry` when it was built.
    pub geometry: u64,
    /// The eye (`Builder::from`), bit for bit: the tree is built around it.
    pub from: [u64; 3],
    pub bvh: std::sync::Arc<crate::geometry::Bvh>,
}

/// A traced picture and what it was traced from.
pub struct Picture {
    /// The scene's `Builder::generation` when it was traced.
    pub generation: u64,
    pub heatmap: bool,
    pub image: crate::image::Image,
}

impl Default for ShellState {
    fn default() -> Self {
        ShellState {
            print_stats: false,
            since_last: Instant::now(),
            last: None,
            feedback: Feedback::new(ProgressMode::Auto),
            pools: Vec::new(),
            last_picture: None,
            bytes: Vec::new(),
            renders: 0,
            tree: None,
        }
    }
}

#[derive(Clone, Debug)]
pub struct RenderReport {
    pub parse_seconds: f64,
    pub build_seconds: f64,
    /// The BVH was the last render's (nothing it is built from changed).
    pub reused: bool,
    pub nodes: usize,
    /// How many children a node has (8 with AVX2, else 4).
    pub node_width: u32,
    pub depth: usize,
    pub primitives: usize,
    pub triangles: usize,
    pub geometry_bytes: usize,
    pub render_seconds: f64,
    pub width: u32,
    pub height: u32,
    pub rays: RayStats,
    pub peak_rss: Option<u64>,
}

/// Peak resident memory of this process, from /proc (Linux).
pub fn peak_rss() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

impl RenderReport {
    pub fn new(
        scene: &Scene,
        parse_seconds: f64,
        render_seconds: f64,
        rays: RayStats,
    ) -> RenderReport {
        let st = scene.bvh.stats();
        RenderReport {
            parse_seconds,
            build_seconds: scene.build_seconds,
            reused: scene.reused,
            nodes: st.nodes,
            node_width: st.width.lanes(),
            depth: st.depth,
            primitives: scene.bvh.len(),
            triangles: scene.bvh.triangles(),
            geometry_bytes: st.bytes + scene.normals.len() * 12,
            render_seconds,
            width: scene.camera.width,
            height: scene.camera.height,
            rays,
            peak_rss: peak_rss(),
        }
    }

    pub fn bytes_per_triangle(&self) -> f64 {
        if self.triangles == 0 { 0.0 } else { self.geometry_bytes as f64 / self.triangles as f64 }
    }
}

impl std::fmt::Display for RenderReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let mib = |b: u64| b as f64 / (1 << 20) as f64;
        writeln!(f, "parse      {:.3} s", self.parse_seconds)?;
        let speed = if self.reused {
            "the last render's tree, reused".to_string()
        } else {
            let rate = self.primitives as f64 / self.build_seconds.max(1e-9) / 1e6;
            format!("{rate:.2} M primitives/s")
        };
        writeln!(
            f,
            "bvh build  {:.3} s  ({} primitives, {} {}-wide nodes, depth {}; {speed})",
            self.build_seconds, self.primitives, self.nodes, self.node_width, self.depth
        )?;
        writeln!(f, "render     {:.3} s  ({}x{})", self.render_seconds, self.width, self.height)?;
        let r = &self.rays;
        writeln!(
            f,
            "rays       {} primary, {} shadow, {} reflected, {} refracted ({:.1} BVH steps per ray)",
            r.primary,
            r.shadow,
            r.reflected,
            r.refracted,
            r.bvh_steps as f64 / (r.primary + r.reflected + r.refracted).max(1) as f64
        )?;
        writeln!(
            f,
            "samples    {:.2} camera rays per pixel",
            r.primary as f64 / (self.width as f64 * self.height as f64).max(1.0)
        )?;
        writeln!(
            f,
            "speed      {:.2} Mrays/s",
            r.total() as f64 / self.render_seconds.max(1e-9) / 1e6
        )?;
        write!(f, "memory     geometry + BVH {:.1} MiB", mib(self.geometry_bytes as u64))?;
        // (Per triangle only where triangles are most of the scene: the
        // SPD tree's one ground quad among 1,022 cones and spheres made
        // it read 79,216.)
        if self.triangles > 0 && 2 * self.triangles >= self.primitives {
            write!(f, " = {:.0} bytes/triangle", self.bytes_per_triangle())?;
        }
        if let Some(p) = self.peak_rss {
            write!(f, "; peak RSS {:.1} MiB", mib(p))?;
        }
        Ok(())
    }
}
