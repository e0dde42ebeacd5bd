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

#[cfg(feature = "preview")]
pub struct Preview {
    window: Option<minifb::Window>,
    size: (u32, u32),
}

#[cfg(feature = "preview")]
impl Preview {
    pub fn open() -> Result<Preview, String> {
        if let Some(why) = unavailable() {
            return Err(why);
        }
        Ok(Preview { window: None, size: (0, 0) })
    }

    pub fn show(&mut self, pixels: &[Vec3], width: u32, height: u32, pass: u32, progressive: bool) {
        if self.size != (width, height) || !self.window.as_ref().is_some_and(|w| w.is_open()) {
            let opts = minifb::WindowOptions {
                scale: if width.max(height) < 400 { minifb::Scale::X2 } else { minifb::Scale::X1 },
                ..minifb::WindowOptions::default()
            };
            self.window =
                minifb::Window::new("rayshell", width as usize, height as usize, opts).ok();
            self.size = (width, height);
        }
        if let Some(w) = &mut self.window {
            let buf = to_rgb32(pixels, width, height, pass, progressive);
            let _ = w.update_with_buffer(&buf, width as usize, height as usize);
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
}
