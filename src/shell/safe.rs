//! `--safe`: running a scene from the internet without letting it run
//! programs or touch files it should not, in the spirit of Tcl's safe
//! interpreters and POV-Ray's I/O restrictions. Scripts may read under
//! the scene's directory and the `--allow-read` directories; they may not
//! write, delete, rename, make directories or change directory; `render`
//! writes its images only inside the output directory. The policy is set
//! once per process, before the session starts (`install`).

use std::path::{Component, Path, PathBuf};
use std::sync::OnceLock;

use crate::interp::{Access, Exception};

/// The directories each kind of access may reach (empty: refused).
#[derive(Debug, Default)]
pub struct Policy {
    pub read: Vec<PathBuf>,
    pub write: Vec<PathBuf>,
    pub modify: Vec<PathBuf>,
    pub images: Vec<PathBuf>,
}

static POLICY: OnceLock<Policy> = OnceLock::new();

/// Turns the fence on for the rest of the process (directories are
/// resolved now, symbolic links included).
pub fn install(mut p: Policy) {
    for dirs in [&mut p.read, &mut p.write, &mut p.modify, &mut p.images] {
        for d in dirs.iter_mut() {
            *d = resolve(d);
        }
    }
    let _ = POLICY.set(p);
}

/// Confines every file access of scripts to one directory (the fuzz
/// targets' scratch directory).
pub fn confine(dir: &Path) {
    let d = vec![dir.to_path_buf()];
    install(Policy { read: d.clone(), write: d.clone(), modify: d.clone(), images: d });
}

pub fn active() -> bool {
    POLICY.get().is_some()
}

/// An absolute path with `.` and `..` folded and every symbolic link of
/// its existing part followed, so `dir/../../etc` and links out of the
/// directory are seen for what they are.
fn resolve(path: &Path) -> PathBuf {
    let abs = if path.is_absolute() {
        path.to_path_buf()
    } else {
        std::env::current_dir().unwrap_or_default().join(path)
    };
    let mut folded = PathBuf::new();
    for c in abs.components() {
        match c {
            Component::ParentDir => {
                folded.pop();
            }
            Component::CurDir => {}
            c => folded.push(c),
        }
    }
    // Follow links in the longest part that exists; keep the rest.
    let mut head = folded.clone();
    let mut tail = Vec::new();
    loop {
        if let Ok(real) = head.canonicalize() {
            let mut out = real;
            for t in tail.iter().rev() {
                out.push(t);
            }
            return out;
        }
        match (head.file_name().map(|n| n.to_owned()), head.parent()) {
            (Some(n), Some(parent)) => {
                tail.push(n);
                head = parent.to_path_buf();
            }
            _ => return folded,
        }
    }
}

/// Whether the policy lets a script do `access` to `path`.
pub fn check(path: &str, access: Access) -> Result<(), String> {
    let Some(p) = POLICY.get() else { return Ok(()) };
    let roots = match access {
        Access::Read => &p.read,
        Access::Write => &p.write,
        Access::Modify => &p.modify,
        Access::Image => &p.images,
        // No directory makes a program safe to run.
        Access::Run => return Err(format!("--safe: a scene may not run programs (\"{path}\")")),
    };
    let what = match access {
        Access::Read => "read",
        Access::Write => "write",
        Access::Modify => "change",
        Access::Image => "write an image to",
        Access::Run => "run",
    };
    if roots.is_empty() {
        return Err(format!("--safe: a scene may not {what} \"{path}\""));
    }
    let real = resolve(Path::new(path));
    if roots.iter().any(|r| real.starts_with(r)) {
        return Ok(());
    }
    let allowed: Vec<String> = roots.iter().map(|r| r.to_string_lossy().into_owned()).collect();
    Err(format!("--safe: a scene may not {what} \"{path}\" (only under {})", allowed.join(", ")))
}

/// `check` for the shell's own file reads (meshes, images, NFF).
pub fn check_read(path: &str) -> Result<(), Exception> {
    check(path, Access::Read).map_err(|m| Exception::error(m).with_error_code("TCL SAFE ACCESS"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paths_resolve_before_they_are_judged() {
        let tmp = std::env::temp_dir().canonicalize().unwrap();
        let r = resolve(&tmp.join("a/../b/./c"));
        assert_eq!(r, tmp.join("b/c"));
        assert!(!resolve(&tmp.join("x/../../etc")).starts_with(&tmp));
    }
}
