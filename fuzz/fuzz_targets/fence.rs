//! The `--safe` fence against random link trees and random paths (issue
//! "untrusted scenes"). Each input builds a tree of directories, files and
//! symbolic links inside the fenced directory (links to `..`, `/`, outside,
//! inside, absolute and relative, dangling), then asks the gate about paths
//! made of the tree's names, `.`, `..` and `/`. The oracle is not the
//! gate's: whatever the gate opens, the kernel says where it is
//! (`/proc/self/fd`); whatever it lets through, `realpath` says where it
//! leads. Nothing outside may ever be opened or let through.
#![no_main]

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use libfuzzer_sys::fuzz_target;
use rayshell::interp::Access;
use rayshell::shell::safe;

struct Dirs {
    inside: PathBuf,
    outside: PathBuf,
}

fn dirs() -> &'static Dirs {
    static DIRS: OnceLock<Dirs> = OnceLock::new();
    DIRS.get_or_init(|| {
        let base = std::env::temp_dir().join(format!("rayshell-fuzz-fence-{}", std::process::id()));
        let (inside, outside) = (base.join("in"), base.join("out"));
        for d in [&inside, &outside, &outside.join("deep")] {
            std::fs::create_dir_all(d).unwrap();
        }
        std::fs::write(outside.join("secret"), "secret").unwrap();
        std::fs::write(outside.join("deep/secret"), "secret").unwrap();
        let inside = inside.canonicalize().unwrap();
        std::env::set_current_dir(&inside).unwrap();
        safe::confine(&inside).expect("the fence goes up");
        Dirs { inside, outside: outside.canonicalize().unwrap() }
    })
}

const NAMES: &[&str] = &["a", "b", "l", "m", "secret", "x.ppm"];

/// A link target from one byte: up, the root, outside, inside, itself.
fn target(b: u8, d: &Dirs) -> String {
    match b % 12 {
        0 => "..".into(),
        1 => "../..".into(),
        2 => "/".into(),
        3 => d.outside.to_string_lossy().into_owned(),
        4 => d.outside.join("secret").to_string_lossy().into_owned(),
        5 => d.inside.to_string_lossy().into_owned(),
        6 => "a".into(),
        7 => "../out".into(),
        8 => "../../out/deep".into(),
        9 => ".".into(),
        10 => "l/..".into(),
        _ => "nowhere".into(),
    }
}

/// A path from bytes: names, `.`, `..`, separators, absolute starts.
fn path_of(bytes: &[u8], d: &Dirs) -> String {
    let mut p = String::new();
    for (k, &b) in bytes.iter().enumerate() {
        match b % 16 {
            0 if k == 0 => p.push_str(&d.inside.to_string_lossy()),
            1 if k == 0 => p.push_str(&d.outside.to_string_lossy()),
            2 => p.push_str(".."),
            3 => p.push('.'),
            4 => p.push('/'),
            n => p.push_str(NAMES[n as usize % NAMES.len()]),
        }
        if b & 0x80 == 0 {
            p.push('/');
        }
    }
    p.trim_end_matches('/').to_string()
}

fn beneath(real: &Path, d: &Dirs) -> bool {
    real.starts_with(&d.inside)
}

fuzz_target!(|data: &[u8]| {
    let d = dirs();
    // A fresh tree inside: the first half of the input builds it.
    for e in std::fs::read_dir(&d.inside).unwrap().flatten() {
        let p = e.path();
        let _ = std::fs::remove_dir_all(&p).or_else(|_| std::fs::remove_file(&p));
    }
    let (tree, paths) = data.split_at(data.len() / 2);
    for op in tree.chunks(3) {
        let [kind, at, what] = op else { break };
        let dir = match at % 4 {
            0 => d.inside.clone(),
            1 => d.inside.join("a"),
            2 => d.inside.join("a/b"),
            _ => d.inside.join("m"),
        };
        // The tree is made inside only: never through a link made before.
        if !std::fs::canonicalize(&dir).is_ok_and(|r| beneath(&r, d)) {
            continue;
        }
        let name = dir.join(NAMES[*what as usize % NAMES.len()]);
        let _ = match kind % 3 {
            0 => std::fs::create_dir(&name),
            1 => std::fs::OpenOptions::new()
                .write(true)
                .create_new(true)
                .open(&name)
                .and_then(|mut f| std::io::Write::write_all(&mut f, b"inside")),
            _ => std::os::unix::fs::symlink(target(*what / 7, d), &name),
        };
    }
    for words in paths.split(|&b| b == 0xff) {
        let path = path_of(words, d);
        // Opened through the gate: the kernel says where the file is.
        if let Ok(f) = safe::open_read(&path) {
            use std::os::fd::AsRawFd;
            let real = std::fs::read_link(format!("/proc/self/fd/{}", f.as_raw_fd())).unwrap();
            assert!(beneath(&real, d), "{path:?} opened {real:?}");
        }
        // Let through: where the path leads, if anywhere, is inside.
        if safe::check(&path, Access::Read).is_ok()
            && let Ok(real) = std::fs::canonicalize(&path)
        {
            assert!(beneath(&real, d), "read {path:?} leads to {real:?}");
        }
        if safe::check(&path, Access::Image).is_ok() {
            let p = Path::new(&path);
            assert!(
                !std::fs::symlink_metadata(p).is_ok_and(|m| m.file_type().is_symlink()),
                "an image through the link {path:?}"
            );
            let parent = match p.parent() {
                Some(x) if !x.as_os_str().is_empty() => x,
                _ => Path::new("."),
            };
            if let Ok(real) = std::fs::canonicalize(parent) {
                assert!(beneath(&real, d), "image {path:?} in {real:?}");
            }
        }
    }
    // Nothing outside changed.
    assert_eq!(std::fs::read(d.outside.join("secret")).unwrap(), b"secret");
});
