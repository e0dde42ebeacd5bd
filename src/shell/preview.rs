//! The live preview window (`preview on`, `--preview`): shows the picture
//! as it is traced, coarse passes filled in as blocks. Built only with the
//! `preview` cargo feature (minifb); otherwise, and on a machine without a
//! display, asking for it gives a clear message instead.

use glam::Vec3;

/// Why there is no window, for the message.
pub fn unavailable() -> Option<String> {
    if !cfg!(feature = "preview") {
        return Some(
            "this build has no preview window: rebuild with `cargo build --release --features preview`"
                .into(),
        );
    }
    if std::env::var_os("DISPLAY").is_none() && std::env::var_os("WAYLAND_DISPLAY").is_none() {
        return Some("no display to open a preview window on (DISPLAY is not set)".into());
    }
    None
}

#[cfg_attr(not(feature = "preview"), allow(dead_code))]
/// The colours to show: untraced pixels take the value of the traced pixel
/// that anchors their block in the last finished pass (stride `pass`).
fn to_rgb32(pixels: &[Vec3], width: u32, height: u32, pass: u32, progressive: bool) -> Vec<u32> {
    let pack = |c: Vec3| {
        let c = (c.clamp(Vec3::ZERO, Vec3::ONE) * 255.0).round();
        ((c.x as u32) << 16) | ((c.y as u32) << 8) | c.z as u32
    };
    let s = if progressive && pass > 1 { pass } else { 1 };
    let mut out = Vec::with_capacity(pixels.len());
    for y in 0..height {
        for x in 0..width {
            let (ax, ay) = (x - x % s, y - y % s);
            out.push(pack(pixels[(ay * width + ax) as usize]));
        }
    }
    out
}

/// The largest window the preview opens (a common laptop screen, less its
/// frame): larger pictures are shown shrunk by a whole factor.
const MAX_WINDOW: (u32, u32) = (1280, 760);

#[cfg_attr(not(feature = "preview"), allow(dead_code))]
fn shrink_factor(width: u32, height: u32) -> u32 {
    width.div_ceil(MAX_WINDOW.0).max(height.div_ceil(MAX_WINDOW.1)).max(1)
}

/// Every `k`th pixel of every `k`th row.
#[cfg_attr(not(feature = "preview"), allow(dead_code))]
fn shrink(rgb: &[u32], width: u32, height: u32, k: u32) -> Vec<u32> {
    if k == 1 {
        return rgb.to_vec();
    }
    (0..height)
        .step_by(k as usize)
        .flat_map(|y| (0..width).step_by(k as usize).map(move |x| rgb[(y * width + x) as usize]))
        .collect()
}

#[cfg(feature = "preview")]
pub struct Preview {
    window: Option<minifb::Window>,
    size: (u32, u32),
}

#[cfg(feature = "preview")]
impl Preview {
    /// Opens the window now, so an unreachable display is an error here
    /// (`DISPLAY=:99` with no server there), not a window that never shows.
    pub fn open() -> Result<Preview, String> {
        if let Some(why) = unavailable() {
            return Err(why);
        }
        let window = minifb::Window::new("rayshell", 320, 240, minifb::WindowOptions::default())
            .map_err(|e| {
                let display = std::env::var("DISPLAY").unwrap_or_default();
                format!("couldn't open a preview window on display \"{display}\": {e}")
            })?;
        Ok(Preview { window: Some(window), size: (320, 240) })
    }

    pub fn show(&mut self, pixels: &[Vec3], width: u32, height: u32, pass: u32, progressive: bool) {
        // A picture larger than the screen is shown scaled down to fit.
        let k = shrink_factor(width, height);
        let (w, h) = (width.div_ceil(k), height.div_ceil(k));
        if self.size != (w, h) || !self.window.as_ref().is_some_and(|w| w.is_open()) {
            let opts = minifb::WindowOptions {
                scale: if w.max(h) < 400 { minifb::Scale::X2 } else { minifb::Scale::X1 },
                ..minifb::WindowOptions::default()
            };
            self.window = minifb::Window::new("rayshell", w as usize, h as usize, opts).ok();
            self.size = (w, h);
        }
        if let Some(win) = &mut self.window {
            let full = to_rgb32(pixels, width, height, pass, progressive);
            let buf = shrink(&full, width, height, k);
            let _ = win.update_with_buffer(&buf, w as usize, h as usize);
        }
    }
}

#[cfg(not(feature = "preview"))]
pub struct Preview;

#[cfg(not(feature = "preview"))]
impl Preview {
    pub fn open() -> Result<Preview, String> {
        Err(unavailable().unwrap_or_default())
    }

    pub fn show(&mut self, _: &[Vec3], _: u32, _: u32, _: u32, _: bool) {}
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn coarse_passes_fill_blocks_from_their_anchor() {
        let mut px = vec![Vec3::ZERO; 16];
        px[0] = Vec3::ONE; // (0, 0), traced in the first pass
        let out = to_rgb32(&px, 4, 4, 2, true);
        assert_eq!(&out[..2], &[0xffffff, 0xffffff]);
        assert_eq!(out[4], 0xffffff); // (0, 1) shows (0, 0)
        assert_eq!(out[2], 0); // (2, 0) anchors its own block
        assert_eq!(to_rgb32(&px, 4, 4, 1, false)[1], 0);
    }

    #[test]
    fn pictures_larger_than_the_screen_shrink_to_fit() {
        assert_eq!(shrink_factor(640, 480), 1);
        assert_eq!(shrink_factor(3000, 2000), 3);
        let rgb: Vec<u32> = (0..25).collect();
        assert_eq!(shrink(&rgb, 5, 5, 2), vec![0, 2, 4, 10, 12, 14, 20, 22, 24]);
        assert_eq!(shrink(&rgb, 5, 5, 1).len(), 25);
    }
}
