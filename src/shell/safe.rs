//! `--safe`: running a scene from the internet without letting it run
//! programs or touch files it should not, in the spirit of Tcl's safe
//! interpreters and POV-Ray's I/O restrictions. `docs/safe.md` is the
//! threat model: what the fence promises and what it does not.
//!
//! The fence is the kernel's, not string handling: each allowed directory
//! is opened once, when the fence goes up (`install`), and every path a
//! scene names is resolved by `openat2(2)` from one of those descriptors
//! with `RESOLVE_BENEATH | RESOLVE_NO_MAGICLINKS`. The kernel then walks
//! the path itself, symbolic links and `..` included, and refuses
//! (`EXDEV`) any step that leaves the directory: `lnk/../x` means what it
//! means to `open`, the parent of the link's target, and an absolute link
//! or one to `/` is refused outright. Paths are matched to a directory by
//! how the user spelled it on the command line or by its real path; a
//! path that starts with neither is refused without touching the disk, so
//! refusals say nothing about what exists outside.
//!
//! What each access may reach:
//! - reads (`source`, `open` for reading, `file` questions, `glob`,
//!   meshes, NFF, images, `environment`): regular files and directories
//!   beneath the scene's own directory and the `--allow-read` ones; never
//!   a FIFO or a device, which could block or never end;
//! - images (`render`): a new file in the output directory, or a file the
//!   user named as output (the output argument, `--frames`' names), and
//!   never through a symbolic link;
//! - writes and changes (`open` for writing, `file delete`, `mkdir`, ...)
//!   and programs: nothing.
//!
//! Under the fence nothing can add a link or change the tree, so the
//! verdict the kernel gives when a path is checked holds when the caller
//! then opens it; the shell's own readers open through the gate itself
//! (`open_read`).

use std::ffi::OsString;
use std::path::{Path, PathBuf};
use std::sync::{Mutex, OnceLock};

use crate::interp::{Access, Exception};

/// The directories each kind of access may reach (empty: refused).
#[derive(Debug, Default)]
pub struct Policy {
    pub read: Vec<PathBuf>,
    /// Writes and changes (`open` for writing, `file delete`, ...): only
    /// the fuzz targets' scratch directory (`confine`); `--safe` has none.
    pub write: Vec<PathBuf>,
    /// Where `render` may create new pictures.
    pub images: Vec<PathBuf>,
    /// Pictures the user named, which `render` may replace.
    pub outputs: Vec<PathBuf>,
}

/// An allowed directory: its descriptor, and the spellings that lead to it.
struct Root {
    #[cfg(target_os = "linux")]
    fd: std::os::fd::OwnedFd,
    /// As the user wrote it (made absolute, `..` kept) and its real path.
    names: Vec<PathBuf>,
}

struct Fence {
    read: Vec<Root>,
    write: Vec<Root>,
    images: Vec<Root>,
    /// Named outputs by (device, inode of the directory, file name).
    outputs: Mutex<Vec<(u64, u64, OsString)>>,
}

static FENCE: OnceLock<Fence> = OnceLock::new();

/// Turns the fence on for the rest of the process. A directory that does
/// not exist is left out (nothing lies beneath it); one that cannot be
/// opened, or a kernel without `openat2`, is an error: the fence fails
/// closed, never open.
pub fn install(p: Policy) -> Result<(), String> {
    if FENCE.get().is_some() {
        return Ok(());
    }
    let roots = |dirs: &[PathBuf]| -> Result<Vec<Root>, String> {
        dirs.iter().filter(|d| d.is_dir()).map(|d| open_root(d)).collect()
    };
    let fence = Fence {
        read: roots(&p.read)?,
        write: roots(&p.write)?,
        images: roots(&p.images)?,
        outputs: Mutex::new(Vec::new()),
    };
    gate::probe()?;
    let _ = FENCE.set(fence);
    for o in &p.outputs {
        name_output(o);
    }
    Ok(())
}

/// Confines every file access of scripts to one directory (the fuzz
/// targets' scratch directory): reads, writes and images alike.
pub fn confine(dir: &Path) -> Result<(), String> {
    let d = vec![dir.to_path_buf()];
    install(Policy { read: d.clone(), write: d.clone(), images: d, outputs: Vec::new() })
}

pub fn active() -> bool {
    FENCE.get().is_some()
}

/// Lets `render` replace `path`, a picture the user named (the output
/// argument, or a frame's name from `--frames`). A no-op without the fence.
pub fn name_output(path: &Path) {
    let Some(f) = FENCE.get() else { return };
    if let Some(id) = gate::parent_id(path) {
        f.outputs.lock().unwrap_or_else(|e| e.into_inner()).push(id);
    }
}

fn open_root(dir: &Path) -> Result<Root, String> {
    let fd = gate::open_dir(dir)
        .map_err(|e| format!("--safe: can't open \"{}\": {e}", dir.display()))?;
    let mut names = vec![absolute(dir)];
    if let Ok(real) = dir.canonicalize()
        && !names.contains(&real)
    {
        names.push(real);
    }
    Ok(Root {
        #[cfg(target_os = "linux")]
        fd,
        names,
    })
}

/// `path` made absolute against the current directory, with nothing
/// folded: `..` and links are the kernel's to resolve.
fn absolute(path: &Path) -> PathBuf {
    if path.is_absolute() {
        path.to_path_buf()
    } else {
        std::env::current_dir().unwrap_or_default().join(path)
    }
}

/// The roots whose spelling `path` starts with, each with the rest of the
/// path ("." for the root itself).
fn candidates<'a>(roots: &'a [Root], path: &Path) -> Vec<(&'a Root, PathBuf)> {
    let abs = absolute(path);
    let mut out = Vec::new();
    for r in roots {
        if let Some(rest) = r.names.iter().find_map(|n| abs.strip_prefix(n).ok()) {
            let rest = if rest.as_os_str().is_empty() { PathBuf::from(".") } else { rest.into() };
            out.push((r, rest));
        }
    }
    out
}

/// Why the gate said no, or what the file system said once inside.
#[derive(Debug)]
pub enum Denied {
    /// Outside every allowed directory (or through a link out of one).
    Outside,
    /// Inside, but not a kind of file a scene may read (FIFO, device).
    Kind,
    /// Inside, and the final name is a symbolic link: not written through.
    Link,
    /// Inside, and the file exists but is not a named output.
    Exists,
    /// Inside: what the kernel said (no such file, permission denied).
    Io(std::io::Error),
}

fn what(access: Access) -> &'static str {
    match access {
        Access::Read => "read",
        Access::Write => "write",
        Access::Modify => "change",
        Access::Image => "write an image to",
        Access::Run => "run",
    }
}

fn refusal(path: &str, access: Access, d: &Denied) -> String {
    let w = what(access);
    match d {
        Denied::Outside | Denied::Io(_) => {
            let roots = FENCE.get().map(|f| match access {
                Access::Read => &f.read,
                Access::Image => &f.images,
                _ => &f.write,
            });
            match roots.filter(|r| !r.is_empty()) {
                Some(r) => {
                    let names: Vec<String> = r
                        .iter()
                        .map(|r| r.names[r.names.len() - 1].to_string_lossy().into_owned())
                        .collect();
                    format!(
                        "--safe: a scene may not {w} \"{path}\" (only under {})",
                        names.join(", ")
                    )
                }
                None => format!("--safe: a scene may not {w} \"{path}\""),
            }
        }
        Denied::Kind => {
            format!("--safe: a scene may not {w} \"{path}\": only regular files and directories")
        }
        Denied::Link => {
            format!("--safe: a scene may not {w} \"{path}\": it is a symbolic link")
        }
        Denied::Exists => format!(
            "--safe: a scene may not {w} \"{path}\": it exists, and only the outputs named on \
             the command line may be replaced"
        ),
    }
}

/// Whether the fence lets a script do `access` to `path` (always, with no
/// fence). A file that does not exist inside the fence passes: the caller
/// reports it as it would without the fence.
pub fn check(path: &str, access: Access) -> Result<(), String> {
    let Some(f) = FENCE.get() else { return Ok(()) };
    if path.contains('\0') {
        return Err(format!("--safe: a scene may not {} \"{path}\"", what(access)));
    }
    let p = Path::new(path);
    let r = match access {
        Access::Run => return Err(format!("--safe: a scene may not run programs (\"{path}\")")),
        Access::Read => gate::open_beneath(&f.read, p, gate::Open::Look).map(drop),
        Access::Write | Access::Modify => gate::may_write(f, &f.write, p, false),
        Access::Image => gate::may_write(f, &f.images, p, true),
    };
    match r {
        Ok(()) | Err(Denied::Io(_)) => Ok(()),
        Err(d) => Err(refusal(path, access, &d)),
    }
}

/// `check` for the shell's own file reads, as a Tcl error.
pub fn check_read(path: &str) -> Result<(), Exception> {
    check(path, Access::Read).map_err(safe_error)
}

fn safe_error(m: String) -> Exception {
    Exception::error(m).with_error_code("TCL SAFE ACCESS")
}

/// Why the shell's reader could not open a file (`Send`, unlike a Tcl
/// error, so reads can wait on a thread of their own).
#[derive(Debug)]
pub enum ReadError {
    Refused(String),
    Io(std::io::Error),
}

impl ReadError {
    /// As Tcl says it: `couldn't read "F": why`, or the fence's refusal.
    pub fn message(&self, path: &str) -> String {
        match self {
            ReadError::Refused(m) => m.clone(),
            ReadError::Io(e) => format!("couldn't read \"{path}\": {}", super::io_reason(e)),
        }
    }

    pub fn into_exception(self, path: &str) -> Exception {
        let e = Exception::error(self.message(path));
        match self {
            ReadError::Refused(_) => e.with_error_code("TCL SAFE ACCESS"),
            ReadError::Io(_) => e,
        }
    }
}

/// Opens a file for the shell's readers (meshes, NFF, images, the sky):
/// through the gate under the fence, so what is judged is what is read;
/// plainly otherwise.
pub fn open_read(path: &str) -> Result<std::fs::File, ReadError> {
    match FENCE.get() {
        None => std::fs::File::open(path).map_err(ReadError::Io),
        Some(f) => match gate::open_beneath(&f.read, Path::new(path), gate::Open::Read) {
            Ok(file) => Ok(file),
            Err(Denied::Io(e)) => Err(ReadError::Io(e)),
            Err(d) => Err(ReadError::Refused(refusal(path, Access::Read, &d))),
        },
    }
}

#[cfg(target_os = "linux")]
mod gate {
    use std::os::fd::{AsFd, OwnedFd};
    use std::path::{Component, Path};

    use rustix::fs::{AtFlags, FileType, Mode, OFlags, ResolveFlags};
    use rustix::io::Errno;

    use super::{Denied, Fence, Root, candidates};

    const RESOLVE: ResolveFlags = ResolveFlags::BENEATH.union(ResolveFlags::NO_MAGICLINKS);

    /// How `open_beneath` opens what it finds.
    #[derive(Clone, Copy, PartialEq)]
    pub enum Open {
        /// A descriptor that only names the file (`O_PATH`): for questions.
        Look,
        /// Open for reading.
        Read,
    }

    /// Fails where the kernel has no `openat2` (before Linux 5.6).
    pub fn probe() -> Result<(), String> {
        match rustix::fs::openat2(
            rustix::fs::CWD,
            "/",
            OFlags::PATH | OFlags::CLOEXEC,
            Mode::empty(),
            ResolveFlags::empty(),
        ) {
            Err(Errno::NOSYS) => Err("--safe needs Linux 5.6 or later (openat2)".into()),
            _ => Ok(()),
        }
    }

    pub fn open_dir(dir: &Path) -> std::io::Result<OwnedFd> {
        let flags = OFlags::PATH | OFlags::DIRECTORY | OFlags::CLOEXEC;
        Ok(rustix::fs::open(dir, flags, Mode::empty())?)
    }

    fn openat2(root: &Root, rest: &Path, flags: OFlags) -> Result<OwnedFd, Errno> {
        // EAGAIN: a rename elsewhere raced the walk; the kernel asks to retry.
        let mut tries = 0;
        loop {
            match rustix::fs::openat2(
                root.fd.as_fd(),
                rest,
                flags | OFlags::CLOEXEC,
                Mode::empty(),
                RESOLVE,
            ) {
                Err(Errno::AGAIN) if tries < 8 => tries += 1,
                r => return r,
            }
        }
    }

    /// Opens `path` beneath the first of `roots` that holds it. Only
    /// regular files and directories are given out; a FIFO is opened
    /// without blocking and refused.
    pub fn open_beneath(roots: &[Root], path: &Path, how: Open) -> Result<std::fs::File, Denied> {
        let flags = match how {
            Open::Look => OFlags::PATH,
            Open::Read => OFlags::RDONLY | OFlags::NONBLOCK | OFlags::NOCTTY,
        };
        let mut inside = None;
        for (root, rest) in candidates(roots, path) {
            match openat2(root, &rest, flags) {
                Ok(fd) => {
                    let st = rustix::fs::fstat(&fd).map_err(|e| Denied::Io(e.into()))?;
                    let kind = FileType::from_raw_mode(st.st_mode);
                    if kind != FileType::RegularFile && kind != FileType::Directory {
                        return Err(Denied::Kind);
                    }
                    if how == Open::Read {
                        rustix::fs::fcntl_setfl(&fd, OFlags::empty())
                            .map_err(|e| Denied::Io(e.into()))?;
                    }
                    return Ok(std::fs::File::from(fd));
                }
                // Left the directory (a `..` too many, or a link out of it).
                Err(Errno::XDEV) | Err(Errno::LOOP) => {}
                Err(e) => inside = Some(e),
            }
        }
        Err(inside.map_or(Denied::Outside, |e| Denied::Io(e.into())))
    }

    /// `path`'s directory opened beneath one of `roots`, and its last name.
    fn parent_beneath<'a>(
        roots: &[Root],
        path: &'a Path,
    ) -> Result<(OwnedFd, &'a std::ffi::OsStr), Denied> {
        let (dir, name) = dir_and_name(path).ok_or(Denied::Outside)?;
        let mut inside = None;
        for (root, rest) in candidates(roots, dir) {
            match openat2(root, &rest, OFlags::PATH | OFlags::DIRECTORY) {
                Ok(fd) => return Ok((fd, name)),
                Err(Errno::XDEV) | Err(Errno::LOOP) => {}
                Err(e) => inside = Some(e),
            }
        }
        Err(inside.map_or(Denied::Outside, |e| Denied::Io(e.into())))
    }

    /// Whether `path` may be written beneath `roots`: its directory is
    /// inside, its name is no symbolic link, and (for images) it is new or
    /// a named output.
    pub fn may_write(f: &Fence, roots: &[Root], path: &Path, image: bool) -> Result<(), Denied> {
        let (dir, name) = parent_beneath(roots, path)?;
        match rustix::fs::statat(&dir, name, AtFlags::SYMLINK_NOFOLLOW) {
            Err(Errno::NOENT) => Ok(()),
            Err(e) => Err(Denied::Io(e.into())),
            Ok(st) => match FileType::from_raw_mode(st.st_mode) {
                FileType::Symlink => Err(Denied::Link),
                _ if !image => Ok(()),
                FileType::RegularFile => {
                    let d = rustix::fs::fstat(&dir).map_err(|e| Denied::Io(e.into()))?;
                    let id = (d.st_dev, d.st_ino, name.to_os_string());
                    let named = f.outputs.lock().unwrap_or_else(|e| e.into_inner());
                    if named.contains(&id) { Ok(()) } else { Err(Denied::Exists) }
                }
                _ => Err(Denied::Kind),
            },
        }
    }

    /// The (device, inode) of `path`'s directory and its last name, as the
    /// kernel finds them now (following links, as the user meant).
    pub fn parent_id(path: &Path) -> Option<(u64, u64, std::ffi::OsString)> {
        let (dir, name) = dir_and_name(path)?;
        let st = rustix::fs::stat(dir).ok()?;
        Some((st.st_dev, st.st_ino, name.to_os_string()))
    }

    /// `path`'s directory ("." for a bare name) and its last name, when
    /// that is a name (not `..`, `.` or `/`).
    fn dir_and_name(path: &Path) -> Option<(&Path, &std::ffi::OsStr)> {
        let Some(Component::Normal(name)) = path.components().next_back() else { return None };
        let dir = path.parent().filter(|d| !d.as_os_str().is_empty()).unwrap_or(Path::new("."));
        Some((dir, name))
    }
}

/// Elsewhere the fence cannot be built on the kernel: `--safe` refuses to
/// start rather than guard by string handling.
#[cfg(not(target_os = "linux"))]
mod gate {
    use std::path::Path;

    use super::{Denied, Fence, Root};

    #[derive(Clone, Copy, PartialEq)]
    pub enum Open {
        Look,
        Read,
    }

    pub fn probe() -> Result<(), String> {
        Err("--safe needs Linux (openat2)".into())
    }
    pub fn open_dir(_: &Path) -> std::io::Result<()> {
        Ok(())
    }
    pub fn open_beneath(_: &[Root], _: &Path, _: Open) -> Result<std::fs::File, Denied> {
        Err(Denied::Outside)
    }
    pub fn may_write(_: &Fence, _: &[Root], _: &Path, _: bool) -> Result<(), Denied> {
        Err(Denied::Outside)
    }
    pub fn parent_id(_: &Path) -> Option<(u64, u64, std::ffi::OsString)> {
        None
    }
}
