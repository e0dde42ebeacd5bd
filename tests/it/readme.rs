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

/// The README's one-line table of scene commands: each command's usage
/// and short description from its registration (what `help` lists),
/// linked to its whole entry in docs/reference.md.
fn summary_table() -> String {
    let session = rayshell::shell::Session::new(Box::new(rayshell::shell::CaptureHost::default()));
    let mut rows = vec!["| command | what it does |".to_string(), "| --- | --- |".into()];
    for doc in rayshell::shell::docs::SCENE {
        let (usage, short) = session.interp.help(doc.name).expect("a registered scene command");
        let usage = format!("{} {usage}", doc.name).trim().replace('|', "\\|");
        rows.push(format!(
            "| [`{usage}`](docs/reference.md#{}) | {} |",
            doc.name,
            short.replace('|', "\\|")
        ));
    }
    rows.join("\n")
}

/// docs/reference.md's entries, as `help NAME` writes them: usage from
/// each command's registration, meaning, default and example from
/// `shell::docs` (one source for both).
fn reference_entries() -> String {
    let session = rayshell::shell::Session::new(Box::new(rayshell::shell::CaptureHost::default()));
    let mut out = Vec::new();
    for doc in rayshell::shell::docs::SCENE {
        let (usage, _) = session.interp.help(doc.name).expect("a registered scene command");
        out.push(format!("### {}\n", doc.name));
        out.push(format!("`{}`\n", format!("{} {usage}", doc.name).trim()));
        out.push(format!("{}\n", doc.meaning));
        if !doc.default.is_empty() {
            out.push(format!("Default: `{}`.\n", doc.default));
        }
        if !doc.example.is_empty() {
            out.push(format!("Example: `{}`\n", doc.example));
        }
    }
    out.join("\n")
}

/// Checks the part of `file` from the line `begin` to the next line
/// `end` (or blank line, for `end` empty) against `want`, or rewrites it
/// under UPDATE_EXPECT=1.
fn check_generated(file: &str, begin: &str, end: &str, want: &str) {
    let path = root().join(file);
    let doc = std::fs::read_to_string(&path).unwrap_or_else(|_| panic!("{file}"));
    let start = doc.find(begin).unwrap_or_else(|| panic!("{file}: no \"{begin}\"")) + begin.len();
    let stop = if end.is_empty() {
        start + doc[start..].find("\n\n").unwrap_or(doc.len() - start)
    } else {
        start + doc[start..].find(end).unwrap_or_else(|| panic!("{file}: no \"{end}\""))
    };
    if std::env::var_os("UPDATE_EXPECT").is_some() {
        std::fs::write(&path, format!("{}{want}{}", &doc[..start], &doc[stop..])).unwrap();
        return;
    }
    let got = &doc[start..stop];
    if got != want {
        let first = got.lines().zip(want.lines()).find(|(a, b)| a != b);
        panic!(
            "{file} differs from `help` (UPDATE_EXPECT=1 rewrites it); first difference:\n{first:?}"
        );
    }
}

pub fn the_command_table_is_the_help_text() {
    let table = summary_table();
    let body = table.split_once("| --- | --- |\n").map_or("", |x| x.1).to_string();
    check_generated("README.md", "| command | what it does |\n| --- | --- |\n", "", &body);
    check_generated(
        "docs/reference.md",
        "UPDATE_EXPECT=1 rewrites it -->\n",
        "<!-- end of generated text -->",
        &(reference_entries() + "\n"),
    );
}

/// Every link in the README and docs/ leads somewhere: a file that exists,
/// and a heading in it for an anchor (GitHub's way of naming headings).
pub fn every_link_resolves() {
    let slug = |h: &str| -> String {
        h.trim()
            .to_lowercase()
            .chars()
            .filter(|c| c.is_alphanumeric() || matches!(c, '-' | '_' | ' '))
            .map(|c| if c == ' ' { '-' } else { c })
            .collect()
    };
    let anchors = |text: &str| -> Vec<String> {
        let mut fenced = false;
        let mut v = Vec::new();
        for l in text.lines() {
            if l.starts_with("```") {
                fenced = !fenced;
            }
            if !fenced && l.starts_with('#') {
                v.push(slug(l.trim_start_matches('#')));
            }
        }
        v
    };
    let mut files = vec![root().join("README.md")];
    for e in std::fs::read_dir(root().join("docs")).unwrap().flatten() {
        if e.path().extension().is_some_and(|x| x == "md") {
            files.push(e.path());
        }
    }
    let mut bad = Vec::new();
    for file in &files {
        let text = std::fs::read_to_string(file).unwrap();
        let mut rest = text.as_str();
        while let Some(i) = rest.find("](") {
            rest = &rest[i + 2..];
            let Some(end) = rest.find(')') else { break };
            let target = &rest[..end];
            if target.contains("://") || target.contains(' ') || target.is_empty() {
                continue;
            }
            let (path, anchor) = target.split_once('#').unwrap_or((target, ""));
            let dest =
                if path.is_empty() { file.clone() } else { file.parent().unwrap().join(path) };
            if !dest.exists() {
                bad.push(format!("{}: {target}: no such file", file.display()));
                continue;
            }
            if !anchor.is_empty() {
                let t = std::fs::read_to_string(&dest).unwrap_or_default();
                if !anchors(&t).iter().any(|a| a == anchor) {
                    bad.push(format!("{}: {target}: no such heading", file.display()));
                }
            }
        }
    }
    assert!(bad.is_empty(), "{} broken links:\n{}", bad.len(), bad.join("\n"));
    // The README is a front page, not the manual.
    let lines = std::fs::read_to_string(root().join("README.md")).unwrap().lines().count();
    assert!(lines <= 600, "README.md has {lines} lines; the reference belongs in docs/");
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
