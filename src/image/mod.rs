//! Images: a linear f32 RGB buffer, written as binary PPM (P6, maxval 255)
//! or PNG (8-bit RGB). Writers take `impl Write`; the shell does the files.

use std::io::{self, Write};

use glam::Vec3;

#[derive(Clone, Debug)]
pub struct Image {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<Vec3>,
}

/// How linear values become 8-bit numbers.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Encoding {
    /// Clamp to [0, 1] and scale (the COS 426 convention; the default).
    #[default]
    Linear,
    /// Clamp, then apply the sRGB transfer curve.
    Srgb,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    Ppm,
    Png,
    /// Portable Float Map: linear values unclipped (after `exposure` and
    /// the tone map), for comparing with other renderers and compositing.
    Pfm,
}

impl Format {
    /// From a file name's extension.
    pub fn from_path(path: &str) -> Option<Format> {
        let lower = path.to_ascii_lowercase();
        if lower.ends_with(".ppm") {
            Some(Format::Ppm)
        } else if lower.ends_with(".png") {
            Some(Format::Png)
        } else if lower.ends_with(".pfm") {
            Some(Format::Pfm)
        } else {
            None
        }
    }
}

/// 8-bit linear values re-encoded with the sRGB curve (for display).
pub fn linear_bytes_to_srgb(rgb: &[u8]) -> Vec<u8> {
    let of: [u8; 256] = std::array::from_fn(|b| to_byte(b as f32 / 255.0, Encoding::Srgb));
    rgb.iter().map(|&b| of[b as usize]).collect()
}

/// `to_byte(v, Encoding::Srgb)` without the curve: a value's byte is the
/// number of bytes' lower edges at or below it (the curve rises, so each
/// byte's values are one interval). The edges come from `to_byte` itself,
/// each the least value giving its byte (a search over the values' bit
/// patterns); a table indexed by a value's top 16 bits gives the byte at
/// the low end of the value's bucket, and one comparison with the next
/// edge finishes it, as no bucket holds two edges. The same bytes (unit
/// test `srgb_table_is_to_byte`), without a `powf` each: 6.5–6.8 ns a
/// value went to 0.8 (a 16k-pixel band in cache, 100 passes).
struct Srgb {
    /// `edge[k]`: the least value whose byte is `k` (`edge[256]` infinite).
    edge: [f32; 257],
    /// The byte of the least value of each bucket of `2^16` bit patterns.
    start: Vec<u8>,
}

impl Srgb {
    /// Buckets up to 1.0's bit pattern.
    const BUCKETS: usize = (0x3f80_0000 >> 16) + 1;

    fn table() -> &'static Srgb {
        static TABLE: std::sync::OnceLock<Srgb> = std::sync::OnceLock::new();
        TABLE.get_or_init(|| {
            let byte = |bits: u32| to_byte(f32::from_bits(bits), Encoding::Srgb);
            let mut edge = [f32::INFINITY; 257];
            edge[0] = 0.0;
            for (k, e) in edge.iter_mut().enumerate().take(256).skip(1) {
                // The least pattern in 0..=1.0 whose byte reaches k.
                let (mut lo, mut hi) = (0u32, 0x3f80_0000u32);
                while lo < hi {
                    let mid = lo + (hi - lo) / 2;
                    if byte(mid) as usize >= k { hi = mid } else { lo = mid + 1 }
                }
                *e = f32::from_bits(lo);
            }
            let start = (0..Srgb::BUCKETS).map(|b| byte((b as u32) << 16)).collect();
            Srgb { edge, start }
        })
    }

    #[inline(always)]
    fn byte(&self, v: f32) -> u8 {
        // (A NaN goes to 0, as through the curve and `as u8`; -0 loses its
        // sign bit below.)
        let v = if v >= 0.0 { v.min(1.0) } else { 0.0 };
        let bucket = (v.to_bits() & 0x7fff_ffff) as usize >> 16;
        let b = self.start.get(bucket).copied().unwrap_or(255);
        b + (v >= self.edge[b as usize + 1]) as u8
    }
}

#[inline(always)]
fn to_byte(v: f32, enc: Encoding) -> u8 {
    // No branch for NaN: it stays NaN through the curve, and `as u8` makes
    // it 0.
    let v = v.clamp(0.0, 1.0);
    let v = match enc {
        Encoding::Linear => v,
        Encoding::Srgb => {
            if v <= 0.0031308 {
                12.92 * v
            } else {
                1.055 * v.powf(1.0 / 2.4) - 0.055
            }
        }
    };
    (v * 255.0 + 0.5) as u8
}

/// Pixels `px` into bytes `out` (three to a pixel), as `Image::to_rgb8`
/// makes them: a band of a picture at a time, while it is in cache, for
/// the renderer.
pub fn rgb8_of(px: &[Vec3], enc: Encoding, out: &mut [u8]) {
    // One loop per encoding (the encoding was looked up for each value).
    match enc {
        Encoding::Linear => linear_bytes(out, px),
        Encoding::Srgb => {
            let t = Srgb::table();
            bytes(out, px, |v| t.byte(v))
        }
    }
}

/// `bytes` for the linear encoding, sixteen values at a time in SIMD
/// lanes where the CPU has AVX2: `to_byte`'s clamp (a NaN made 0 by the
/// lanes' max, as `as u8` makes it), then a truncating conversion and
/// saturating packs of values known to be in 0.5..=255.5. Value by value
/// the conversion took a nanosecond a value, 2 ms of each 1024² picture
/// on two threads. The same bytes (unit test).
fn linear_bytes(out: &mut [u8], px: &[Vec3]) {
    let values: &[f32] = bytemuck::cast_slice(px);
    let done = match () {
        #[cfg(target_arch = "x86_64")]
        () if let Some(v3) = pulp::x86::V3::try_new() => sixteen(v3, out, values),
        () => 0,
    };
    bytes(&mut out[done..], &px[done / 3..], |v| to_byte(v, Encoding::Linear));
}

/// The leading values of `values` into `out`, sixteen at a time, by the
/// lanes' arithmetic of `linear_bytes`; returns how many, a multiple of 3
/// (whole pixels).
#[cfg(target_arch = "x86_64")]
fn sixteen(v3: pulp::x86::V3, out: &mut [u8], values: &[f32]) -> usize {
    use std::arch::x86_64::__m128;
    let n = values.len() / 48 * 48;
    let (sse, sse2) = (v3.sse, v3.sse2);
    let (zero, one, scale, half) =
        (sse._mm_set1_ps(0.0), sse._mm_set1_ps(1.0), sse._mm_set1_ps(255.0), sse._mm_set1_ps(0.5));
    for (o, v) in out[..n].chunks_exact_mut(16).zip(values[..n].chunks_exact(16)) {
        let lane = |k: usize| {
            let x: __m128 =
                pulp::cast(<[f32; 4]>::try_from(&v[4 * k..4 * k + 4]).unwrap_or_default());
            // max(x, 0) is 0 for a NaN x (the second operand).
            let x = sse._mm_min_ps(sse._mm_max_ps(x, zero), one);
            sse2._mm_cvttps_epi32(sse._mm_add_ps(sse._mm_mul_ps(x, scale), half))
        };
        let (a, b) =
            (sse2._mm_packs_epi32(lane(0), lane(1)), sse2._mm_packs_epi32(lane(2), lane(3)));
        let bytes: [u8; 16] = pulp::cast(sse2._mm_packus_epi16(a, b));
        o.copy_from_slice(&bytes);
    }
    n
}

/// `px` into bytes `o`, each value by `byte`.
#[inline(always)]
fn bytes(o: &mut [u8], px: &[Vec3], byte: impl Fn(f32) -> u8) {
    for (o, p) in o.chunks_exact_mut(3).zip(px) {
        o.copy_from_slice(&[byte(p.x), byte(p.y), byte(p.z)]);
    }
}

/// `n` copies of `value`, written on all threads: a new buffer that a
/// picture's bands then fill. (`vec!` writes them on one thread, and the
/// first touch of fresh memory is slow: the first 1024² render spent
/// 2.4–2.7 ms there before its bands could start; on two threads,
/// 1.6–2.0 ms.)
pub(crate) fn filled<T: Copy + Send + Sync>(n: usize, value: T) -> Vec<T> {
    use rayon::iter::ParallelExtend;
    let mut v = Vec::new();
    v.par_extend(rayon::iter::repeat_n(value, n));
    v
}

/// Makes `out` `len` bytes long, keeping what it holds (a new buffer
/// `filled`).
pub(crate) fn resize_bytes(out: &mut Vec<u8>, len: usize) {
    if out.is_empty() {
        *out = filled(len, 0);
    } else {
        out.resize(len, 0);
    }
}

impl Image {
    pub fn new(width: u32, height: u32) -> Image {
        Image { width, height, pixels: vec![Vec3::ZERO; width as usize * height as usize] }
    }

    pub fn get(&self, x: u32, y: u32) -> Vec3 {
        self.pixels[y as usize * self.width as usize + x as usize]
    }

    /// The picture in bytes, rows in parallel.
    pub fn to_rgb8(&self, enc: Encoding) -> Vec<u8> {
        let mut out = Vec::new();
        self.to_rgb8_into(enc, &mut out);
        out
    }

    /// `to_rgb8` into `out`, whose memory is reused: a buffer of the
    /// right size is overwritten, not cleared (a fresh one is faulted in
    /// and zeroed page by page: 800 faults for a 1024x1024 picture).
    pub fn to_rgb8_into(&self, enc: Encoding, out: &mut Vec<u8>) {
        use rayon::prelude::*;
        resize_bytes(out, self.pixels.len() * 3);
        let w = (self.width as usize).max(1);
        // Bands of rows of about 64k pixels each.
        let rows = (65536 / w).max(1);
        out.par_chunks_mut(3 * w * rows)
            .zip(self.pixels.par_chunks(w * rows))
            .for_each(|(o, px)| rgb8_of(px, enc, o));
    }

    pub fn write(&self, w: impl Write, format: Format, enc: Encoding) -> io::Result<()> {
        self.write_placed(w, format, enc, None, &|| false, &mut Vec::new())
    }

    /// Writes the image, recording where it sits in a larger picture (a
    /// `--crop` region) so `merge` can put it back. `stop` is asked between
    /// bands of rows: when it says yes the write fails ("interrupted"), so
    /// a long PNG encode gives way to Ctrl-C. The bytes are made in `rgb`
    /// (`to_rgb8_into`).
    pub fn write_placed(
        &self,
        w: impl Write,
        format: Format,
        enc: Encoding,
        at: Option<Placement>,
        stop: &dyn Fn() -> bool,
        rgb: &mut Vec<u8>,
    ) -> io::Result<()> {
        if format != Format::Pfm {
            self.to_rgb8_into(enc, rgb);
        }
        self.write_bytes_placed(w, format, enc, at, stop, rgb)
    }

    /// `write_placed` with the picture's bytes made already (`rgb`, as
    /// `to_rgb8_into` makes them in `enc`; unused for a PFM).
    pub fn write_bytes_placed(
        &self,
        w: impl Write,
        format: Format,
        enc: Encoding,
        at: Option<Placement>,
        stop: &dyn Fn() -> bool,
        rgb: &[u8],
    ) -> io::Result<()> {
        match format {
            Format::Pfm => self.write_pfm(w),
            Format::Ppm => write_ppm_placed(w, self.width, self.height, rgb, at),
            Format::Png => write_png_placed(w, self.width, self.height, rgb, enc, at, stop),
        }
    }

    /// The image as a little-endian colour PFM (rows from the bottom up;
    /// NaNs written as 0).
    pub fn write_pfm(&self, mut w: impl Write) -> io::Result<()> {
        write!(w, "PF\n{} {}\n-1.0\n", self.width, self.height)?;
        let mut row = Vec::with_capacity(self.width as usize * 12);
        for y in (0..self.height).rev() {
            row.clear();
            for x in 0..self.width {
                let p = self.get(x, y);
                for v in [p.x, p.y, p.z] {
                    row.extend((if v.is_nan() { 0.0 } else { v }).to_le_bytes());
                }
            }
            w.write_all(&row)?;
        }
        w.flush()
    }
}

/// Where a cropped image sits: its top-left corner in the full picture,
/// and the full picture's size. Stored in the file as the text
/// `rayshell-crop X0 Y0 WIDTH HEIGHT` (a PPM comment, a PNG tEXt chunk).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Placement {
    pub x0: u32,
    pub y0: u32,
    pub full_width: u32,
    pub full_height: u32,
}

const PLACEMENT_KEY: &str = "rayshell-crop";

impl Placement {
    fn text(&self) -> String {
        format!("{} {} {} {}", self.x0, self.y0, self.full_width, self.full_height)
    }

    fn parse(text: &str) -> Option<Placement> {
        let v: Vec<u32> = text.split_whitespace().map(|w| w.parse().ok()).collect::<Option<_>>()?;
        match v[..] {
            [x0, y0, full_width, full_height] => {
                Some(Placement { x0, y0, full_width, full_height })
            }
            _ => None,
        }
    }
}

pub fn write_ppm(w: impl Write, width: u32, height: u32, rgb: &[u8]) -> io::Result<()> {
    write_ppm_placed(w, width, height, rgb, None)
}

fn write_ppm_placed(
    mut w: impl Write,
    width: u32,
    height: u32,
    rgb: &[u8],
    at: Option<Placement>,
) -> io::Result<()> {
    match at {
        Some(p) => write!(w, "P6\n# {PLACEMENT_KEY} {}\n{width} {height}\n255\n", p.text())?,
        None => write!(w, "P6\n{width} {height}\n255\n")?,
    }
    w.write_all(rgb)?;
    w.flush()
}

pub fn write_png(
    w: impl Write,
    width: u32,
    height: u32,
    rgb: &[u8],
    enc: Encoding,
) -> io::Result<()> {
    write_png_placed(w, width, height, rgb, enc, None, &|| false)
}

/// Says in a PNG how its values are encoded, so viewers show it right:
/// the sRGB chunk (and the gAMA it implies) for sRGB output, gAMA 1.0
/// for linear values.
pub fn tag_png<W: Write>(enc: &mut png::Encoder<'_, W>, encoding: Encoding) {
    match encoding {
        Encoding::Srgb => {
            enc.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
            // The gAMA an sRGB chunk implies, for decoders that know only it.
            enc.set_source_gamma(png::ScaledFloat::from_scaled(45455));
        }
        Encoding::Linear => enc.set_source_gamma(png::ScaledFloat::new(1.0)),
    }
}

fn write_png_placed(
    w: impl Write,
    width: u32,
    height: u32,
    rgb: &[u8],
    encoding: Encoding,
    at: Option<Placement>,
    stop: &dyn Fn() -> bool,
) -> io::Result<()> {
    let mut enc = png::Encoder::new(w, width, height);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    tag_png(&mut enc, encoding);
    if let Some(p) = at {
        enc.add_text_chunk(PLACEMENT_KEY.into(), p.text()).map_err(io::Error::other)?;
    }
    let mut writer = enc.write_header().map_err(io::Error::other)?;
    // Fed in bands of rows, asking `stop` between them.
    let mut stream = writer.stream_writer().map_err(io::Error::other)?;
    for band in rgb.chunks((width as usize * 3 * 64).max(1)) {
        if stop() {
            return Err(io::Error::other("interrupted"));
        }
        stream.write_all(band)?;
    }
    stream.finish().map_err(io::Error::other)
}

/// An 8-bit RGB picture read back from a file, with its placement if it
/// is a crop.
pub struct Rgb8 {
    pub width: u32,
    pub height: u32,
    pub rgb: Vec<u8>,
    pub placement: Option<Placement>,
    /// How a PNG says its values are encoded (an sRGB chunk, or gAMA
    /// 1.0); `None` for a PPM or an untagged PNG.
    pub encoding: Option<Encoding>,
}

/// The most pixels a picture read from a file may have: 2^28, 16,384
/// squared (a header is only a claim: a 69-byte PNG can say a million by
/// a million).
pub const MAX_PIXELS: u64 = 1 << 28;

/// Checks a picture's size, as its header gives it, before any buffer is
/// made for it: at most `MAX_PIXELS`, and `bytes_per_pixel` for each of
/// them within the memory budget.
pub fn check_size(width: u32, height: u32, bytes_per_pixel: usize) -> Result<(), String> {
    let n = width as u64 * height as u64;
    if n > MAX_PIXELS {
        return Err(format!(
            "{width}x{height} is more than the {MAX_PIXELS} pixels a picture read from a file may have"
        ));
    }
    crate::mem::reserve_n(n as usize, bytes_per_pixel).map_err(|e| e.to_string())
}

/// Reads a PPM (P6, maxval 255) or an 8-bit RGB PNG, as written here.
pub fn read_rgb8(data: &[u8]) -> Result<Rgb8, String> {
    if data.starts_with(b"P6") {
        let (width, height, rgb) = read_ppm(data).ok_or("not a P6 PPM with maxval 255")?;
        // The placement comment, if any, is in the header's first lines.
        let head = String::from_utf8_lossy(&data[..data.len().min(200)]);
        let placement = head
            .lines()
            .take(3)
            .find_map(|l| l.strip_prefix("# ")?.strip_prefix(PLACEMENT_KEY))
            .and_then(Placement::parse);
        return Ok(Rgb8 { width, height, rgb, placement, encoding: None });
    }
    let mut decoder = png::Decoder::new(io::Cursor::new(data));
    decoder.set_transformations(png::Transformations::EXPAND);
    let mut reader = decoder.read_info().map_err(|e| format!("not a PNG or PPM: {e}"))?;
    let placement = reader
        .info()
        .uncompressed_latin1_text
        .iter()
        .find(|t| t.keyword == PLACEMENT_KEY)
        .and_then(|t| Placement::parse(&t.text));
    let (width, height) = (reader.info().width, reader.info().height);
    check_size(width, height, 3)?;
    let encoding = match (reader.info().srgb, reader.info().gama_chunk) {
        (Some(_), _) => Some(Encoding::Srgb),
        (None, Some(g)) if g == png::ScaledFloat::new(1.0) => Some(Encoding::Linear),
        _ => None,
    };
    let mut buf = vec![0; reader.output_buffer_size().ok_or("PNG too large")?];
    let frame = reader.next_frame(&mut buf).map_err(|e| format!("bad PNG: {e}"))?;
    if frame.color_type != png::ColorType::Rgb || frame.bit_depth != png::BitDepth::Eight {
        return Err("not an 8-bit RGB PNG".into());
    }
    buf.truncate(frame.buffer_size());
    Ok(Rgb8 { width, height, rgb: buf, placement, encoding })
}

/// Reads a texture: a PNG of any 8- or 16-bit colour type (grey, grey and
/// alpha, RGB, RGBA; alpha is ignored) or a binary PPM, as linear values:
/// a PNG is decoded from sRGB unless it says it is linear (gAMA 1.0); a
/// PPM is linear (the pictures this program writes are).
pub fn read_texture(data: &[u8]) -> Result<(u32, u32, Vec<glam::Vec3>), String> {
    if data.starts_with(b"PF\n") {
        // Its body must hold every pixel: no claim is believed unread.
        return read_pfm(data).ok_or_else(|| "not a readable RGB PFM".into());
    }
    if data.starts_with(b"#?") {
        return read_hdr(data);
    }
    if data.starts_with(b"P6") {
        let (w, h, rgb) = read_ppm(data).ok_or("not a P6 PPM with maxval 255")?;
        check_size(w, h, 12)?;
        let px =
            rgb.chunks(3).map(|c| glam::Vec3::new(c[0] as f32, c[1] as f32, c[2] as f32) / 255.0);
        return Ok((w, h, px.collect()));
    }
    let mut decoder = png::Decoder::new(io::Cursor::new(data));
    decoder.set_transformations(png::Transformations::EXPAND | png::Transformations::STRIP_16);
    let mut reader = decoder.read_info().map_err(|e| format!("not a PNG or PPM: {e}"))?;
    let linear = reader.info().srgb.is_none()
        && reader.info().gama_chunk.is_some_and(|g| g == png::ScaledFloat::new(1.0));
    // The decoded bytes (up to 4 a pixel) and the linear values (12).
    check_size(reader.info().width, reader.info().height, 4 + 12)?;
    let mut buf = vec![0; reader.output_buffer_size().ok_or("PNG too large")?];
    let frame = reader.next_frame(&mut buf).map_err(|e| format!("bad PNG: {e}"))?;
    let channels = match frame.color_type {
        png::ColorType::Grayscale => 1,
        png::ColorType::GrayscaleAlpha => 2,
        png::ColorType::Rgb => 3,
        png::ColorType::Rgba => 4,
        png::ColorType::Indexed => return Err("an indexed PNG that did not expand".into()),
    };
    let decode = |b: u8| {
        let v = b as f32 / 255.0;
        if linear {
            v
        } else if v <= 0.04045 {
            v / 12.92
        } else {
            ((v + 0.055) / 1.055).powf(2.4)
        }
    };
    let px = buf[..frame.buffer_size()]
        .chunks(channels)
        .map(|c| {
            if channels < 3 {
                glam::Vec3::splat(decode(c[0]))
            } else {
                glam::Vec3::new(decode(c[0]), decode(c[1]), decode(c[2]))
            }
        })
        .collect();
    Ok((frame.width, frame.height, px))
}

/// Reads a binary PPM (P6, maxval 255): (width, height, rgb bytes).
pub fn read_ppm(data: &[u8]) -> Option<(u32, u32, Vec<u8>)> {
    let mut fields = Vec::new();
    let mut i = 0;
    while fields.len() < 4 {
        while i < data.len() && data[i].is_ascii_whitespace() {
            i += 1;
        }
        if i < data.len() && data[i] == b'#' {
            while i < data.len() && data[i] != b'\n' {
                i += 1;
            }
            continue;
        }
        let start = i;
        while i < data.len() && !data[i].is_ascii_whitespace() {
            i += 1;
        }
        if start == i {
            return None;
        }
        fields.push(std::str::from_utf8(&data[start..i]).ok()?.to_string());
    }
    if fields[0] != "P6" || fields[3] != "255" {
        return None;
    }
    let (w, h): (u32, u32) = (fields[1].parse().ok()?, fields[2].parse().ok()?);
    let body = data.get(i + 1..)?;
    let n = (w as usize).checked_mul(h as usize)?.checked_mul(3)?;
    if body.len() < n {
        return None;
    }
    Some((w, h, body[..n].to_vec()))
}

/// A colour PFM (Portable Float Map: "PF", width and height, a scale whose
/// sign gives the byte order, rows of RGB floats from the bottom up), as
/// linear values row by row from the top.
pub fn read_pfm(data: &[u8]) -> Option<(u32, u32, Vec<glam::Vec3>)> {
    let mut fields = Vec::new();
    let mut pos = 0;
    // Three whitespace-separated header words after "PF", then one byte.
    while fields.len() < 4 {
        while data.get(pos)?.is_ascii_whitespace() {
            pos += 1;
        }
        let start = pos;
        while !data.get(pos)?.is_ascii_whitespace() {
            pos += 1;
        }
        fields.push(std::str::from_utf8(&data[start..pos]).ok()?);
    }
    pos += 1;
    let (w, h): (u32, u32) = (fields[1].parse().ok()?, fields[2].parse().ok()?);
    let little = fields[3].parse::<f32>().ok()? < 0.0;
    let n = (w as usize).checked_mul(h as usize)?;
    let body = data.get(pos..pos.checked_add(n.checked_mul(12)?)?)?;
    if w == 0 || h == 0 {
        return None;
    }
    let f = |b: &[u8]| {
        let b = [b[0], b[1], b[2], b[3]];
        let v = if little { f32::from_le_bytes(b) } else { f32::from_be_bytes(b) };
        if v.is_finite() { v.max(0.0) } else { 0.0 }
    };
    let mut px = Vec::with_capacity(n);
    for y in (0..h as usize).rev() {
        let row = &body[y * w as usize * 12..(y + 1) * w as usize * 12];
        px.extend(
            row.chunks_exact(12).map(|c| glam::Vec3::new(f(&c[0..4]), f(&c[4..8]), f(&c[8..12]))),
        );
    }
    Some((w, h, px))
}

/// A Radiance HDR (RGBE) picture, flat or run-length encoded scanlines,
/// "-Y h +X w" orientation, as linear values row by row from the top.
pub fn read_hdr(data: &[u8]) -> Result<(u32, u32, Vec<glam::Vec3>), String> {
    let bad = |why: &str| format!("bad Radiance HDR file: {why}");
    // The header ends with an empty line; the next line gives the size.
    let end = data.windows(2).position(|w| w == b"\n\n").ok_or_else(|| bad("no header end"))?;
    let header = String::from_utf8_lossy(&data[..end]);
    if header.lines().any(|l| l.starts_with("FORMAT=") && l != "FORMAT=32-bit_rle_rgbe") {
        return Err(bad("only 32-bit_rle_rgbe is read"));
    }
    let rest = &data[end + 2..];
    let nl = rest.iter().position(|&b| b == b'\n').ok_or_else(|| bad("no size line"))?;
    let size = String::from_utf8_lossy(&rest[..nl]);
    let words: Vec<&str> = size.split_whitespace().collect();
    let (h, w): (u32, u32) = match words[..] {
        ["-Y", h, "+X", w] => {
            (h.parse().map_err(|_| bad("size"))?, w.parse().map_err(|_| bad("size"))?)
        }
        _ => return Err(bad("only the -Y h +X w orientation is read")),
    };
    if w == 0 || h == 0 || (w as u64) * (h as u64) > 1 << 28 {
        return Err(bad("size"));
    }
    // The picture, before its scanlines are read (they may be runs).
    crate::mem::reserve_n(w as usize * h as usize, size_of::<glam::Vec3>())
        .map_err(|e| e.to_string())?;
    let mut src = &rest[nl + 1..];
    let mut px = Vec::with_capacity(w as usize * h as usize);
    let wu = w as usize;
    // One scanline as four planes (r, g, b, exponent).
    let mut planes = vec![0u8; 4 * wu];
    for _ in 0..h {
        let rle = src.len() >= 4
            && src[0] == 2
            && src[1] == 2
            && src[2] & 0x80 == 0
            && (8..0x8000).contains(&w)
            && ((src[2] as u32) << 8 | src[3] as u32) == w;
        if rle {
            src = &src[4..];
            for plane in planes.chunks_exact_mut(wu) {
                let mut x = 0usize;
                while x < wu {
                    let (&n, tail) = src.split_first().ok_or_else(|| bad("truncated"))?;
                    if n > 128 {
                        let run = (n - 128) as usize;
                        let (&v, tail) = tail.split_first().ok_or_else(|| bad("truncated"))?;
                        if x + run > wu {
                            return Err(bad("run past the line"));
                        }
                        plane[x..x + run].fill(v);
                        x += run;
                        src = tail;
                    } else {
                        let n = n as usize;
                        if n == 0 || x + n > wu || tail.len() < n {
                            return Err(bad("bad run"));
                        }
                        plane[x..x + n].copy_from_slice(&tail[..n]);
                        x += n;
                        src = &tail[n..];
                    }
                }
            }
        } else {
            let flat = src.get(..4 * wu).ok_or_else(|| bad("truncated"))?;
            for (x, t) in flat.chunks_exact(4).enumerate() {
                (0..4).for_each(|c| planes[c * wu + x] = t[c]);
            }
            src = &src[4 * wu..];
        }
        px.extend((0..wu).map(|x| {
            let [r, g, b, e] = [0, 1, 2, 3].map(|c| planes[c * wu + x]);
            if e == 0 {
                glam::Vec3::ZERO
            } else {
                let f = 2f32.powi(e as i32 - 136);
                glam::Vec3::new(r as f32 + 0.5, g as f32 + 0.5, b as f32 + 0.5) * f
            }
        }));
    }
    Ok((w, h, px))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A PFM written is read back to the bit, rows in order; a Radiance
    /// HDR decodes flat and run-length scanlines alike.
    #[test]
    fn float_pictures_round_trip() {
        let mut img = Image::new(3, 2);
        img.pixels =
            (0..6).map(|k| Vec3::new(k as f32 * 1.5, 100.0 / (k + 1) as f32, 0.25)).collect();
        let mut buf = Vec::new();
        img.write(&mut buf, Format::Pfm, Encoding::Linear).unwrap();
        let (w, h, px) = read_texture(&buf).unwrap();
        assert_eq!((w, h), (3, 2));
        assert_eq!(px, img.pixels);
        // 8 texels: (m + 0.5)·2^(e − 136) with m = 128, e = 129: 1.00390625.
        let head = b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 2 +X 8\n".to_vec();
        let mut flat = head.clone();
        let mut rle = head;
        for _ in 0..2 {
            flat.extend([128, 128, 128, 129].repeat(8));
            rle.extend([2, 2, 0, 8]);
            for v in [128, 128, 128, 129] {
                rle.extend([128 + 8, v]);
            }
        }
        for data in [flat, rle] {
            let (w, h, px) = read_texture(&data).unwrap();
            assert_eq!((w, h, px.len()), (8, 2, 16));
            assert!(px.iter().all(|p| *p == Vec3::splat(128.5 / 128.0)), "{:?}", px[0]);
        }
        assert!(read_texture(b"#?RADIANCE\n\n-Y 2 +X 8\n\x02\x02").is_err());
    }

    #[test]
    fn ppm_round_trip_and_clamping() {
        let mut img = Image::new(2, 1);
        img.pixels[0] = Vec3::new(1.5, 0.5, -1.0);
        img.pixels[1] = Vec3::new(f32::NAN, 0.0, 1.0);
        let mut buf = Vec::new();
        img.write(&mut buf, Format::Ppm, Encoding::Linear).unwrap();
        assert!(buf.starts_with(b"P6\n2 1\n255\n"));
        let (w, h, rgb) = read_ppm(&buf).unwrap();
        assert_eq!((w, h), (2, 1));
        assert_eq!(rgb, vec![255, 128, 0, 0, 0, 255]);
        assert_eq!(to_byte(0.5, Encoding::Srgb), 188);
        for enc in [Encoding::Linear, Encoding::Srgb] {
            assert_eq!(to_byte(f32::NAN, enc), 0);
            assert_eq!(to_byte(f32::INFINITY, enc), 255);
            assert_eq!(to_byte(f32::NEG_INFINITY, enc), 0);
        }
    }

    /// The sRGB table (`Srgb`) gives the bytes `to_byte` gives: at and
    /// around every byte's edge, at each bucket's ends, across 0..=1 and
    /// for the odd values.
    #[test]
    fn srgb_table_is_to_byte() {
        let t = Srgb::table();
        let bucket = |v: f32| v.to_bits() as usize >> 16;
        // No bucket holds two edges, and every byte has values.
        for k in 1..255 {
            assert!(bucket(t.edge[k]) < bucket(t.edge[k + 1]), "edges {k}, {}", k + 1);
        }
        let same = |bits: u32| {
            let v = f32::from_bits(bits);
            assert_eq!(t.byte(v), to_byte(v, Encoding::Srgb), "{v:e} ({bits:#x})");
        };
        // Around every edge, each pattern; each bucket's ends; a spread of
        // patterns across 0..=1.
        for e in &t.edge[1..256] {
            let b = e.to_bits();
            (b.saturating_sub(4096)..=b + 4096).for_each(same);
        }
        for k in 0..Srgb::BUCKETS as u32 {
            same(k << 16);
            same((k << 16) | 0xffff);
        }
        (0..=0x3f80_0000u32).step_by(61).for_each(same);
        for v in
            [f32::NAN, -f32::NAN, f32::INFINITY, f32::NEG_INFINITY, -0.0, 1.0, 1.5, -1.0, 1e-40]
        {
            assert_eq!(t.byte(v), to_byte(v, Encoding::Srgb), "{v}");
        }
        // Through `rgb8_of`, as a render's bands use it.
        let px: Vec<Vec3> = (0..999).map(|k| Vec3::new(k as f32 / 998.0, 0.003, 2.0)).collect();
        let mut out = vec![0; 3 * px.len()];
        rgb8_of(&px, Encoding::Srgb, &mut out);
        let want: Vec<u8> =
            px.iter().flat_map(|p| p.to_array().map(|v| to_byte(v, Encoding::Srgb))).collect();
        assert_eq!(out, want);
    }

    /// The linear encoding's vectorized loop (`linear_bytes`) makes the
    /// bytes `to_byte` makes, value by value, for odd values and those at
    /// and around every byte's edges, in every position of a four-pixel
    /// group and in the remainder.
    #[test]
    fn linear_bytes_are_to_bytes() {
        // Every value at and around each byte's edges, and the odd ones.
        let mut values = vec![f32::NAN, f32::INFINITY, f32::NEG_INFINITY, -0.0, 0.0, -1.0, 2.0];
        values.extend([f32::MIN_POSITIVE, 1e-30, f32::MAX, f32::MIN, 0.5, 1.0]);
        for k in 0..=256 {
            let edge = (k as f32 - 0.5) / 255.0;
            let mut x = edge;
            for _ in 0..4 {
                x = x.next_down();
            }
            for _ in 0..9 {
                values.push(x);
                x = x.next_up();
            }
        }
        for n in 0..values.len() {
            let px: Vec<Vec3> = values[n..]
                .chunks(3)
                .map(|c| Vec3::new(c[0], c[c.len().min(2) - 1], c[c.len() - 1]))
                .collect();
            let mut out = vec![0u8; px.len() * 3];
            rgb8_of(&px, Encoding::Linear, &mut out);
            let want: Vec<u8> = px
                .iter()
                .flat_map(|p| [p.x, p.y, p.z].map(|v| to_byte(v, Encoding::Linear)))
                .collect();
            assert_eq!(out, want, "from value {n}");
        }
    }

    /// The bytes come out in pixel order across the parallel bands (here
    /// 300 rows: two bands of 218 and 82).
    #[test]
    fn bytes_keep_pixel_order_across_bands() {
        let mut img = Image::new(300, 300);
        for (k, p) in img.pixels.iter_mut().enumerate() {
            *p = Vec3::new((k % 256) as f32 / 255.0, (k / 300) as f32 / 299.0, 0.5);
        }
        let rgb = img.to_rgb8(Encoding::Srgb);
        let want: Vec<u8> = img
            .pixels
            .iter()
            .flat_map(|p| [p.x, p.y, p.z].map(|v| to_byte(v, Encoding::Srgb)))
            .collect();
        assert_eq!(rgb, want);
    }
}
