//! Reading the files a user names and the files those files name, and checking where a run
//! will write, before anything is read or written.
//!
//! Why one module: a file is hostile input as much as its bytes are. A glTF's `buffers[].uri`
//! or a garment manifest's sidecar name could point anywhere (`../../etc/passwd`, an absolute
//! path, a symbolic link out of the folder); a path could name `/dev/zero` (reads until memory
//! runs out), a FIFO (blocks for ever) or a 3 GB sparse file (read whole before any size check).
//! Every reader in the crate goes through [`read_input`] or [`read_beside`], which refuse all of
//! these before opening the file, and every command that writes checks its outputs with
//! [`check_outputs`] before it runs.

use std::fs::{self, File};
use std::io::Read;
use std::path::{Component, Path, PathBuf};

use crate::error::{Result, TailorError};

/// The largest input file any reader accepts (1 GiB): the biggest real inputs (a scanned body
/// as PLY, a character glTF) are tens of megabytes.
pub const MAX_INPUT_BYTES: u64 = 1 << 30;

fn io_err(path: &Path, reason: impl Into<String>) -> TailorError {
    TailorError::Io { path: path.display().to_string(), reason: reason.into() }
}

/// Reads the file at `path` whole, refusing before it opens it anything that is not a regular
/// file (a folder, a device such as `/dev/zero`, a FIFO, a socket) and any file over `limit`
/// bytes. A symbolic link the user named is followed (they chose it); links *inside* a file's
/// references are [`read_beside`]'s business.
pub fn read_input(path: &Path, limit: u64) -> Result<Vec<u8>> {
    let meta = fs::metadata(path).map_err(|e| TailorError::io(path.display().to_string(), e))?;
    check_regular(path, &meta, limit)?;
    let file = File::open(path).map_err(|e| TailorError::io(path.display().to_string(), e))?;
    // The file may have been swapped between the two calls: look again at what was opened.
    let meta = file.metadata().map_err(|e| TailorError::io(path.display().to_string(), e))?;
    check_regular(path, &meta, limit)?;
    let mut bytes = Vec::with_capacity(meta.len() as usize);
    // `take` bounds the read even if the file grows while it is read.
    file.take(limit + 1).read_to_end(&mut bytes).map_err(|e| TailorError::io(path.display().to_string(), e))?;
    if bytes.len() as u64 > limit {
        return Err(too_large(path, bytes.len() as u64, limit));
    }
    Ok(bytes)
}

/// [`read_input`] as UTF-8 text.
pub fn read_input_text(path: &Path, limit: u64) -> Result<String> {
    String::from_utf8(read_input(path, limit)?)
        .map_err(|e| TailorError::parse(path.display().to_string(), "file", format!("not UTF-8 text: {e}")))
}

fn check_regular(path: &Path, meta: &fs::Metadata, limit: u64) -> Result<()> {
    if meta.is_dir() {
        return Err(io_err(path, "is a folder, not a file"));
    }
    if !meta.is_file() {
        return Err(io_err(path, "is not a regular file (a device, pipe or socket); refusing to read it"));
    }
    if meta.len() > limit {
        return Err(too_large(path, meta.len(), limit));
    }
    Ok(())
}

fn too_large(path: &Path, len: u64, limit: u64) -> TailorError {
    io_err(path, format!("{len} bytes is larger than the {limit}-byte limit for this file"))
}

/// The path of `name`, a file that the file `owner` refers to (a glTF buffer URI, a garment
/// sidecar), confined to `owner`'s folder: `name` must be relative, without `..`, and must not
/// resolve (through symbolic links) outside that folder. `what` names the reference in errors.
/// glTF URIs are percent-encoded; `name` is decoded first, so `%2E%2E/` is `../`.
pub fn resolve_beside(owner: &Path, name: &str, what: &str) -> Result<PathBuf> {
    let file = owner.display().to_string();
    let refuse = |reason: String| TailorError::parse(&file, what, reason);
    let decoded = percent_decode(name).ok_or_else(|| refuse(format!("{name:?} is not a valid URI")))?;
    let rel = Path::new(&decoded);
    if decoded.is_empty() || rel.is_absolute() || decoded.contains('\0') {
        return Err(refuse(format!("{name:?} must be a file name relative to the file's folder")));
    }
    if rel.components().any(|c| !matches!(c, Component::Normal(_) | Component::CurDir)) {
        return Err(refuse(format!("{name:?} must not leave the file's folder ('..' or an absolute path)")));
    }
    let dir = match owner.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let joined = dir.join(rel);
    let real = fs::canonicalize(&joined).map_err(|e| TailorError::io(joined.display().to_string(), e))?;
    let real_dir = fs::canonicalize(&dir).map_err(|e| TailorError::io(dir.display().to_string(), e))?;
    if !real.starts_with(&real_dir) {
        return Err(refuse(format!("{name:?} is a symbolic link out of the file's folder")));
    }
    Ok(real)
}

/// Reads the file `name` that `owner` refers to: [`resolve_beside`], then [`read_input`].
pub fn read_beside(owner: &Path, name: &str, what: &str, limit: u64) -> Result<Vec<u8>> {
    read_input(&resolve_beside(owner, name, what)?, limit)
}

/// Decodes `%XX` escapes; `None` for a malformed escape or bytes that are not UTF-8.
fn percent_decode(s: &str) -> Option<String> {
    let b = s.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'%' {
            let hex = std::str::from_utf8(b.get(i + 1..i + 3)?).ok()?;
            out.push(u8::from_str_radix(hex, 16).ok()?);
            i += 3;
        } else {
            out.push(b[i]);
            i += 1;
        }
    }
    String::from_utf8(out).ok()
}

/// Whether `a` and `b` are the same existing file (same device and inode on Unix, the same
/// canonical path elsewhere): a hard link or a different spelling of an input is still it.
fn same_file(a: &Path, b: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        match (fs::metadata(a), fs::metadata(b)) {
            (Ok(x), Ok(y)) => x.dev() == y.dev() && x.ino() == y.ino(),
            _ => false,
        }
    }
    #[cfg(not(unix))]
    {
        matches!((fs::canonicalize(a), fs::canonicalize(b)), (Ok(x), Ok(y)) if x == y)
    }
}

/// Checks, before a run, the files it will write. `inputs` and `outputs` are `(name, path)`
/// pairs, the name being what the user called it (`GARMENT_FILE`, `--report`). Refused:
/// an output that is (the same file as) an input or another output, an output that is a folder
/// or not a regular file, and an output whose folder cannot hold it (its nearest existing
/// ancestor is not a folder, or a file cannot be created there). Missing folders are fine:
/// writers create them.
pub fn check_outputs(inputs: &[(&str, &Path)], outputs: &[(&str, &Path)]) -> Result<()> {
    for (k, &(oname, out)) in outputs.iter().enumerate() {
        let refuse = |reason: String| io_err(out, format!("{oname}: {reason}"));
        if out.as_os_str().is_empty() {
            return Err(refuse("empty path".into()));
        }
        for &(iname, input) in inputs {
            if same_file(out, input) || out == input {
                return Err(refuse(format!("is {iname}, an input of this run; refusing to write over it")));
            }
        }
        for &(other, path) in &outputs[..k] {
            if out == path || same_file(out, path) {
                return Err(refuse(format!("is also {other}; choose two different files")));
            }
        }
        match fs::metadata(out) {
            Ok(m) if m.is_dir() => return Err(refuse("is a folder, not a file".into())),
            Ok(m) if !m.is_file() => return Err(refuse("exists and is not a regular file".into())),
            Ok(_) => {
                // Opened for appending only to learn that it can be written: nothing changes.
                if let Err(e) = fs::OpenOptions::new().append(true).open(out) {
                    return Err(refuse(format!("cannot be written: {e}")));
                }
            }
            Err(_) => {}
        }
        let parent = match out.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => PathBuf::from("."),
        };
        let mut existing = parent.as_path();
        while !existing.exists() {
            match existing.parent() {
                Some(p) if !p.as_os_str().is_empty() => existing = p,
                _ => {
                    existing = Path::new(".");
                    break;
                }
            }
        }
        if !existing.is_dir() {
            return Err(refuse(format!("{} is not a folder", existing.display())));
        }
        if existing == parent.as_path() {
            // Probe: a file that can be created here can be written; read-only folders and
            // full or read-only file systems fail now, not after the run.
            let probe = parent.join(format!(".tailor-write-check-{}", std::process::id()));
            match fs::OpenOptions::new().write(true).create_new(true).open(&probe) {
                Ok(_) => {
                    let _ = fs::remove_file(&probe);
                }
                Err(e) => return Err(refuse(format!("cannot write in {}: {e}", parent.display()))),
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests;
