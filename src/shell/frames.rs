//! Animation batches for render farms (`--frames`, `--step`, `--shard`,
//! `--skip-existing`) and `--merge`, which puts cropped regions of one
//! picture back together.
//!
//! Each frame runs the script in a fresh interpreter and scene with
//! `$frame` set, then renders the final scene into the frame's file (unless
//! the script rendered by itself and no output pattern was given), so a
//! frame's picture never depends on which other frames ran before it: any
//! sharding gives the same bytes. An unchanged scene is never traced twice.

use std::path::{Path, PathBuf};
use std::time::Instant;

use super::feedback::FrameInfo;
use super::{Cli, EXIT_IO, EXIT_SCRIPT, EXIT_USAGE};
use crate::image::{Format, read_rgb8};
use crate::interp::Value;

/// The frame numbers this run renders, in order.
pub fn frames_of(first: i64, last: i64, step: u32, shard: Option<(usize, usize)>) -> Vec<i64> {
    let all = (first..=last).step_by(step as usize);
    match shard {
        Some((i, n)) => all.enumerate().filter(|(k, _)| k % n == i).map(|(_, f)| f).collect(),
        None => all.collect(),
    }
}

/// The file for frame `f`: the pattern's `%0Nd` is replaced as printf
/// would (at least N digits), or its last run of `#` by the number
/// zero-padded to at least `width` digits; a pattern with neither gets
/// `-NNNN` before its extension.
pub fn frame_name(pattern: &str, f: i64, width: usize) -> String {
    if let Some(start) = pattern.find('%') {
        let rest = &pattern[start + 1..];
        let digits = rest.bytes().take_while(|b| b.is_ascii_digit()).count();
        if rest[digits..].starts_with('d') {
            // As printf does: `%03d` pads to three digits, `%d` not at all.
            // No name holds more than 255 bytes: wider is refused later.
            let w = match digits {
                0 => 0,
                _ => rest[..digits].parse::<usize>().unwrap_or(256).min(256),
            };
            return format!("{}{f:0w$}{}", &pattern[..start], &rest[digits + 1..]);
        }
    }
    if let Some(end) = pattern.rfind('#') {
        let start = pattern[..end].trim_end_matches('#').len();
        let w = (end + 1 - start).max(width).min(256);
        return format!("{}{f:0w$}{}", &pattern[..start], &pattern[end + 1..]);
    }
    let p = Path::new(pattern);
    match (p.file_stem(), p.extension()) {
        (Some(stem), Some(ext)) => {
            let name = format!("{}-{f:0width$}.{}", stem.to_string_lossy(), ext.to_string_lossy());
            p.with_file_name(name).to_string_lossy().into_owned()
        }
        _ => format!("{pattern}-{f:0width$}"),
    }
}

/// Runs a `--frames` batch; returns the exit status. It stops at the
/// first failing frame (the frames before it are kept, so a rerun with
/// `--skip-existing` goes on from there).
pub fn run_batch(cli: &Cli) -> i32 {
    let Some(script) = &cli.script else {
        say!("raytrace: --frames needs a script file");
        return EXIT_USAGE;
    };
    let script_name = script.to_string_lossy().into_owned();
    let (first, last) = cli.frames.expect("batch mode has --frames");
    let frames = frames_of(first, last, cli.step, cli.shard);
    let pattern = match &cli.output {
        Some(p) => p.to_string_lossy().into_owned(),
        None => {
            let stem = script.file_stem().map(|s| s.to_string_lossy().into_owned());
            format!("{}-####.png", stem.unwrap_or_else(|| "frame".into()))
        }
    };
    let width = first.unsigned_abs().max(last.unsigned_abs()).to_string().len().max(4);
    if Format::from_path(&frame_name(&pattern, first, width)).is_none() {
        say!("raytrace: frame file names must end in .ppm or .png, got \"{pattern}\"");
        return EXIT_USAGE;
    }
    // A name that cannot be written is a usage error now, not a failed
    // frame (which a farm would retry) after the script ran.
    for f in [first, last] {
        if let Err(msg) = super::check_output_name(Path::new(&frame_name(&pattern, f, width))) {
            say!("raytrace: {msg}");
            return EXIT_USAGE;
        }
    }
    let src = match super::read_text(&script_name) {
        Ok(s) => s,
        Err(e) => {
            say!("raytrace: couldn't read file \"{script_name}\": {}", super::io_reason(&e));
            return EXIT_SCRIPT;
        }
    };
    // The batch's feedback (bars, lines) lives across the frames' sessions.
    let mut fb = match super::new_session(cli) {
        Ok(s) => std::mem::replace(
            &mut s.state.borrow_mut().feedback,
            super::feedback::Feedback::new(super::ProgressMode::None),
        ),
        Err(msg) => {
            say!("raytrace: {msg}");
            return EXIT_USAGE;
        }
    };
    let start = Instant::now();
    let (mut rendered, mut skipped) = (0, 0);
    fb.start_batch(frames.len());
    for (k, &f) in frames.iter().enumerate() {
        let out = frame_name(&pattern, f, width);
        super::safe::name_output(std::path::Path::new(&out));
        fb.frame = Some(FrameInfo { frame: f, index: k + 1, count: frames.len() });
        if cli.skip_existing && Path::new(&out).exists() {
            fb.skipped(&out);
            skipped += 1;
            continue;
        }
        if let Some(dir) = Path::new(&out).parent().filter(|d| !d.as_os_str().is_empty())
            && let Err(e) = std::fs::create_dir_all(dir)
        {
            say!("raytrace: couldn't create \"{}\": {}", dir.display(), super::io_reason(&e));
            return EXIT_IO;
        }
        let session = super::new_session(cli).expect("the options were checked above");
        std::mem::swap(&mut session.state.borrow_mut().feedback, &mut fb);
        let mut interp = session.interp;
        super::set_argv(&mut interp, &script_name, &cli.args);
        let _ = interp.set_var("frame", Value::from_int(f));
        session.scene.borrow_mut().sampling.frame = f;
        let mut r = interp.eval_source(&src, Some(&script_name));
        // A script that renders its frames itself, with no output pattern
        // given, has written what it wanted: no second picture.
        let rendered_itself = session.state.borrow().renders > 0;
        if r.is_ok() && (cli.output.is_some() || !rendered_itself) {
            r = interp
                .invoke(&[Value::from("render"), Value::from(out.as_str())])
                .map_err(|e| super::at_end_of(e, &script_name, super::last_line(src.as_bytes())));
        }
        std::mem::swap(&mut session.state.borrow_mut().feedback, &mut fb);
        let code = super::finish(&mut interp, r);
        if code != 0 {
            fb.end_batch(rendered, skipped, start.elapsed().as_secs_f64());
            say!("raytrace: frame {f} failed; {rendered} frame(s) rendered before it");
            return code;
        }
        rendered += 1;
    }
    fb.end_batch(rendered, skipped, start.elapsed().as_secs_f64());
    if super::feedback::INTERRUPTED.load(std::sync::atomic::Ordering::Relaxed) {
        return super::exit_code_of(&super::interrupted());
    }
    0
}

/// Assembles cropped renders into the full picture `out`. Every pixel
/// must be covered; overlapping parts must agree.
pub fn merge(out: &Path, parts: &[PathBuf]) -> Result<(), (i32, String)> {
    let fail = |msg: String| (EXIT_SCRIPT, msg);
    let out_name = out.to_string_lossy().into_owned();
    let format = Format::from_path(&out_name).filter(|f| *f != Format::Pfm).ok_or_else(|| {
        fail(format!("unknown image format for \"{out_name}\": the name must end in .ppm or .png"))
    })?;
    let mut full: Option<(u32, u32, Vec<u8>, Vec<bool>)> = None;
    let mut encoding = None;
    for part in parts {
        let name = part.to_string_lossy();
        let bytes = std::fs::read(part)
            .map_err(|e| fail(format!("couldn't read \"{name}\": {}", super::io_reason(&e))))?;
        let img = read_rgb8(&bytes).map_err(|e| fail(format!("\"{name}\": {e}")))?;
        encoding = encoding.or(img.encoding);
        let p = img.placement.ok_or_else(|| {
            fail(format!("\"{name}\" is not a cropped render (it has no rayshell-crop placement)"))
        })?;
        if full.is_none() {
            // The full size is the part's claim: checked before it is made.
            crate::image::check_size(p.full_width, p.full_height, 4)
                .map_err(|e| fail(format!("\"{name}\": {e}")))?;
        }
        let (w, h, rgb, covered) = full.get_or_insert_with(|| {
            let n = p.full_width as usize * p.full_height as usize;
            (p.full_width, p.full_height, vec![0; n * 3], vec![false; n])
        });
        if (p.full_width, p.full_height) != (*w, *h)
            || p.x0 + img.width > *w
            || p.y0 + img.height > *h
        {
            return Err(fail(format!(
                "\"{name}\" is a region of a {}x{} picture, not of the {w}x{h} one of the first part",
                p.full_width, p.full_height
            )));
        }
        for y in 0..img.height {
            for x in 0..img.width {
                let src = (y * img.width + x) as usize;
                let dst = ((p.y0 + y) * *w + p.x0 + x) as usize;
                let px = &img.rgb[src * 3..src * 3 + 3];
                if covered[dst] && &rgb[dst * 3..dst * 3 + 3] != px {
                    return Err(fail(format!(
                        "\"{name}\" disagrees with an earlier part at pixel {} {}",
                        p.x0 + x,
                        p.y0 + y
                    )));
                }
                rgb[dst * 3..dst * 3 + 3].copy_from_slice(px);
                covered[dst] = true;
            }
        }
    }
    let (w, h, rgb, covered) = full.ok_or_else(|| fail("no parts to merge".into()))?;
    if let Some(i) = covered.iter().position(|c| !c) {
        let missing = covered.iter().filter(|c| !**c).count();
        return Err(fail(format!(
            "the parts leave {missing} of {} pixels uncovered (the first at {} {})",
            covered.len(),
            i as u32 % w,
            i as u32 / w
        )));
    }
    let io = |e: std::io::Error| {
        (EXIT_IO, format!("couldn't write \"{out_name}\": {}", super::io_reason(&e)))
    };
    let mut file = super::AtomicFile::create(&out_name).map_err(io)?;
    match format {
        // (A .pfm name is refused above: parts are 8-bit.)
        Format::Ppm | Format::Pfm => crate::image::write_ppm(file.writer(), w, h, &rgb),
        Format::Png => crate::image::write_png(
            file.writer(),
            w,
            h,
            &rgb,
            encoding.unwrap_or(crate::image::Encoding::Linear),
        ),
    }
    .map_err(io)?;
    file.commit().map_err(io)
}

/// Writes the pictures `frames` (same size) as one animated PNG (APNG,
/// looping) at `fps` frames a second: the movie format that needs nothing
/// but this program (`scripts/movie` prefers ffmpeg's MP4 when it is there).
pub fn movie(out: &Path, frames: &[PathBuf], fps: u16) -> Result<(), (i32, String)> {
    let fail = |msg: String| (EXIT_SCRIPT, msg);
    let out_name = out.to_string_lossy().into_owned();
    if Format::from_path(&out_name) != Some(Format::Png) {
        return Err(fail(format!("a movie is an animated PNG: \"{out_name}\" must end in .png")));
    }
    let mut pictures = Vec::with_capacity(frames.len());
    for f in frames {
        let name = f.to_string_lossy();
        let bytes = std::fs::read(f)
            .map_err(|e| fail(format!("couldn't read \"{name}\": {}", super::io_reason(&e))))?;
        let img = read_rgb8(&bytes).map_err(|e| fail(format!("\"{name}\": {e}")))?;
        if let Some(first) = pictures.first().map(|p: &crate::image::Rgb8| (p.width, p.height))
            && first != (img.width, img.height)
        {
            return Err(fail(format!(
                "\"{name}\" is {}x{}, the first frame {}x{}",
                img.width, img.height, first.0, first.1
            )));
        }
        pictures.push(img);
    }
    let (w, h) = match pictures.first() {
        Some(p) => (p.width, p.height),
        None => return Err(fail("no frames".into())),
    };
    let io = |e: std::io::Error| {
        (EXIT_IO, format!("couldn't write \"{out_name}\": {}", super::io_reason(&e)))
    };
    let mut file = super::AtomicFile::create(&out_name).map_err(io)?;
    let mut enc = png::Encoder::new(file.writer(), w, h);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    let encoding = pictures[0].encoding.unwrap_or(crate::image::Encoding::Linear);
    crate::image::tag_png(&mut enc, encoding);
    let png_err = |e: png::EncodingError| io(std::io::Error::other(e));
    enc.set_animated(pictures.len() as u32, 0).map_err(png_err)?;
    enc.set_frame_delay(1, fps.max(1)).map_err(png_err)?;
    let mut writer = enc.write_header().map_err(png_err)?;
    for p in &pictures {
        writer.write_image_data(&p.rgb).map_err(png_err)?;
    }
    writer.finish().map_err(png_err)?;
    file.commit().map_err(io)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_names() {
        assert_eq!(frame_name("out/f####.png", 7, 4), "out/f0007.png");
        assert_eq!(frame_name("f##.ppm", 7, 4), "f0007.ppm");
        assert_eq!(frame_name("f######.png", 12, 4), "f000012.png");
        assert_eq!(frame_name("f%03d.png", 7, 4), "f007.png");
        assert_eq!(frame_name("f%03d.png", 1234, 4), "f1234.png");
        assert_eq!(frame_name("f%d.png", 7, 4), "f7.png");
        assert_eq!(frame_name("f%06d.png", 7, 4), "f000007.png");
        assert_eq!(frame_name("dir/anim.png", 7, 4), "dir/anim-0007.png");
        assert_eq!(frame_name("f####.png", 12345, 5), "f12345.png");
        assert_eq!(frame_name("f####.png", -3, 4), "f-003.png");
        // Wider than a name can be: capped (the name is refused later).
        assert_eq!(frame_name("f%065536d.png", 7, 4).len(), 1 + 256 + 4);
        assert_eq!(frame_name(&format!("f{}.png", "#".repeat(70_000)), 7, 4).len(), 1 + 256 + 4);
    }

    #[test]
    fn shards_cover_every_frame_once() {
        let all = frames_of(0, 239, 1, None);
        assert_eq!(all.len(), 240);
        for n in 1..=7 {
            let mut seen: Vec<i64> =
                (0..n).flat_map(|i| frames_of(0, 239, 1, Some((i, n)))).collect();
            seen.sort();
            assert_eq!(seen, all, "{n} shards");
        }
        assert_eq!(frames_of(0, 10, 3, None), vec![0, 3, 6, 9]);
        assert_eq!(frames_of(0, 10, 3, Some((1, 2))), vec![3, 9]);
    }
}
