//! The README's examples are run from the README's own text: the opening
//! example must render the picture shown under it, and each step of "Your
//! first scene" (its blocks so far, in order) the picture after it. A
//! mismatch beyond 2/255 fails; `UPDATE_EXPECT=1` rewrites the pictures.

use std::path::Path;

use rayshell::image::{Format, read_rgb8};

use crate::util::{raytrace, root, scratch, text};

fn readme() -> String {
    std::fs::read_to_string(root().join("README.md")).expect("README.md")
}

/// The ```tcl blocks of `text`, each with the image (`![...](path)`) that
/// follows it before the next block, if any.
fn blocks_and_images(text: &str) -> Vec<(String, Option<String>)> {
    let mut out: Vec<(String, Option<String>)> = Vec::new();
    let mut lines = text.lines();
    while let Some(line) = lines.next() {
        if line.trim() == "```tcl" {
            let block: Vec<&str> = lines.by_ref().take_while(|l| l.trim() != "```").collect();
            out.push((block.join("\n") + "\n", None));
        } else if let (Some(rest), Some(last)) = (line.strip_prefix("!["), out.last_mut())
            && last.1.is_none()
            && let Some((_, path)) = rest.split_once("](")
        {
            last.1 = Some(path.trim_end_matches(')').to_string());
        }
    }
    out
}

/// Compares the picture in `got` with the file `want` (relative to the
/// repository), or rewrites it under UPDATE_EXPECT=1.
fn check_picture(got: &Path, want: &str) {
    let want_path = root().join(want);
    if std::env::var_os("UPDATE_EXPECT").is_some() {
        std::fs::copy(got, &want_path).expect("update the picture");
        return;
    }
    let a = read_rgb8(&std::fs::read(got).unwrap()).unwrap();
    let b = read_rgb8(
        &std::fs::read(&want_path)
            .unwrap_or_else(|_| panic!("missing {want} (UPDATE_EXPECT=1 makes it)")),
    )
    .unwrap();
    assert_eq!((a.width, a.height), (b.width, b.height), "{want}: size");
    let worst = a.rgb.iter().zip(&b.rgb).map(|(x, y)| x.abs_diff(*y)).max().unwrap_or(0);
    assert!(worst <= 2, "{want}: differs from the README's text by {worst}/255");
}

pub fn the_opening_example_renders_the_picture_under_it() {
    let doc = readme();
    let intro = &doc[..doc.find("\n## ").unwrap()];
    let blocks = blocks_and_images(intro);
    let (src, image) = blocks.first().expect("an example before the first section");
    let image = image.as_ref().expect("a picture under the example");
    let out = src
        .lines()
        .find_map(|l| l.trim().strip_prefix("render "))
        .expect("the example renders")
        .trim()
        .to_string();
    assert_eq!(Format::from_path(&out), Some(Format::Png), "the example writes a PNG");
    let dir = scratch("readme-intro");
    std::fs::write(dir.join("example.tsd"), src).unwrap();
    let r = raytrace().arg("example.tsd").current_dir(&dir).output().unwrap();
    assert!(r.status.success(), "{}", text(&r.stderr));
    check_picture(&dir.join(&out), image);
}

pub fn first_scene_steps_render_their_pictures() {
    let doc = readme();
    let start = doc.find("\n## Your first scene").expect("the walk-through");
    let section = &doc[start + 1..];
    let section = &section[..section[3..].find("\n## ").map_or(section.len(), |i| i + 3)];
    let steps = blocks_and_images(section);
    assert!(steps.len() >= 4, "camera and sphere, floor, loop, proc");
    let dir = scratch("readme-first");
    let mut so_far = String::new();
    for (k, (block, image)) in steps.iter().enumerate() {
        so_far.push_str(block);
        let Some(image) = image else { continue };
        let out = dir.join(format!("step{k}.png"));
        let script = format!("{so_far}render {{{}}}\n", out.display());
        let r = raytrace().args(["-c", &script]).output().unwrap();
        assert!(r.status.success(), "step {}: {}", k + 1, text(&r.stderr));
        check_picture(&out, image);
    }
}
