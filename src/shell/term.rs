//! Pictures in the terminal (`show`, `preview term`): viuer picks the
//! kitty, iTerm2 or sixel graphics protocol when the terminal answers for
//! it, and otherwise draws Unicode half-blocks in 24-bit colour (two pixels
//! a character cell), sized to the terminal. Values are shown through the
//! sRGB curve, as a colour-managed viewer shows the linear files.

use std::io::IsTerminal;

/// How to draw.
#[derive(Clone, Copy, Debug, Default)]
pub struct ShowOptions {
    /// Half-blocks even where a graphics protocol is available (and
    /// always when standard output is not a terminal).
    pub blocks: bool,
    /// Width in character cells (default: fit the terminal).
    pub width: Option<u32>,
}

/// Draws an 8-bit sRGB picture (`rgb`, `width`×`height`) on standard output.
pub fn show(rgb: &[u8], width: u32, height: u32, opts: ShowOptions) -> Result<(), String> {
    let img = image::RgbImage::from_raw(width, height, rgb.to_vec())
        .ok_or("the picture's size does not match its pixels")?;
    let blocks = opts.blocks || !std::io::stdout().is_terminal();
    let config = viuer::Config {
        // At the cursor, as the next lines of the session.
        absolute_offset: false,
        x: 0,
        y: 0,
        width: opts.width,
        use_kitty: !blocks,
        use_iterm: !blocks,
        use_sixel: !blocks,
        ..Default::default()
    };
    viuer::print(&image::DynamicImage::ImageRgb8(img), &config)
        .map(|_| ())
        .map_err(|e| format!("couldn't show the picture: {e}"))
}

/// The size to render a preview at so it fills the terminal's width as
/// half-blocks (two pixels a cell), keeping the camera's aspect.
pub fn preview_size(aspect: f64) -> (u32, u32) {
    let (cols, rows) = viuer::terminal_size();
    let w = (cols as u32).clamp(8, 200);
    let h = ((w as f64 / aspect).round() as u32).clamp(2, 2 * rows.max(4) as u32);
    (w, h.max(2))
}
