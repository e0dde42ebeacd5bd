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

/// The README's table of scene commands, as `help` would write it: usage
/// from each command's registration, meaning and default from
/// `shell::docs` (one source for both).
fn command_table() -> String {
    let session = rayshell::shell::Session::new(Box::new(rayshell::shell::CaptureHost::default()));
    let mut rows =
        vec!["| command | meaning | default |".to_string(), "| --- | --- | --- |".into()];
    for doc in rayshell::shell::docs::SCENE {
        let (usage, _) = session.interp.help(doc.name).expect("a registered scene command");
        let usage = format!("{} {usage}", doc.name).trim().replace('|', "\\|");
        let default =
            if doc.default.is_empty() { String::new() } else { format!("`{}`", doc.default) };
        rows.push(format!("| `{usage}` | {} | {default} |", doc.meaning.replace('|', "\\|")));
    }
    rows.join("\n")
}

pub fn the_command_table_is_the_help_text() {
    let doc = readme();
    let start = doc.find("| command | meaning | default |").expect("the scene command table");
    let end = start + doc[start..].find("\n\n").expect("the table's end");
    let want = command_table();
    if std::env::var_os("UPDATE_EXPECT").is_some() {
        let updated = format!("{}{want}{}", &doc[..start], &doc[end..]);
        std::fs::write(root().join("README.md"), updated).unwrap();
        return;
    }
    let got = &doc[start..end];
    if got != want {
        let first = got.lines().zip(want.lines()).find(|(a, b)| a != b);
        panic!(
            "the README's command table differs from `help` (UPDATE_EXPECT=1 rewrites it); first difference:\n{first:?}"
        );
    }
}

pub fn help_shows_a_whole_entry() {
    let mut session =
        rayshell::shell::Session::new(Box::new(rayshell::shell::CaptureHost::default()));
    let text = session.interp.eval_str("help material").unwrap();
    let text = text.as_str();
    assert!(text.starts_with("material r g b Ka Kd Ks n_s T index_of_refraction\n"), "{text}");
    assert!(text.contains("Phong exponent"), "{text}");
    assert!(text.contains("default: 1 1 1  0.2 0.8 0 1 0 1"), "{text}");
    assert!(text.contains("example: material "), "{text}");
    // Every scene command documented is a command.
    for doc in rayshell::shell::docs::SCENE {
        assert!(session.interp.has_command(doc.name), "{}", doc.name);
    }
}
