//! Output files that appear whole or not at all: every file the program
//! writes goes to a hidden temporary name in the same directory (so the
//! rename stays on one file system) and is renamed over its real name only
//! once complete.

use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

/// `DIR/.NAME.tmp-PID-N` beside `path`: hidden, unique per process and call.
pub fn temp_sibling(path: &Path) -> PathBuf {
    static CALLS: AtomicUsize = AtomicUsize::new(0);
    let call = CALLS.fetch_add(1, Ordering::Relaxed);
    let name = path
        .file_name()
        .map_or_else(|| "output".into(), |n| n.to_string_lossy().into_owned());
    path.with_file_name(format!(".{name}.tmp-{}-{call}", std::process::id()))
}

/// Writes `bytes` to `path` through a temporary sibling and a rename; on
/// failure the temporary file is removed and `path` is untouched.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let tmp = stage(path, bytes)?;
    commit(&[(tmp, path.to_path_buf())]).map_err(|(_, e)| e)
}

/// Writes `bytes` under a temporary sibling of `path` (flushed to disk) and
/// returns its name, for a later [`commit`]; on failure nothing is left.
pub fn stage(path: &Path, bytes: &[u8]) -> std::io::Result<PathBuf> {
    let tmp = temp_sibling(path);
    let written = (|| {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()
    })();
    match written {
        Ok(()) => Ok(tmp),
        Err(e) => {
            let _ = std::fs::remove_file(&tmp);
            Err(e)
        }
    }
}

/// Renames each staged temporary (`from`) onto its final name (`to`), in
/// order. A set of outputs appears together or not at all: when a rename
/// fails, the files this call already renamed and the temporaries not yet
/// renamed are removed, and the error names the file that failed.
pub fn commit(staged: &[(PathBuf, PathBuf)]) -> Result<(), (PathBuf, std::io::Error)> {
    for (i, (from, to)) in staged.iter().enumerate() {
        if let Err(e) = std::fs::rename(from, to) {
            for (_, done) in &staged[..i] {
                let _ = std::fs::remove_file(done);
            }
            for (left, _) in &staged[i..] {
                let _ = std::fs::remove_file(left);
            }
            return Err((to.clone(), e));
        }
    }
    Ok(())
}

/// Checks, before any expensive work, that `path` can be written: its
/// directory exists (or is created, with `create_dir`) and accepts files,
/// and `path` is not a directory. The message names the file.
pub fn check_writable(path: &Path, create_dir: bool) -> Result<(), String> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    if create_dir {
        std::fs::create_dir_all(&dir).map_err(|e| {
            format!(
                "cannot write {}: creating {}: {e}",
                path.display(),
                dir.display()
            )
        })?;
    }
    if !dir.is_dir() {
        return Err(format!(
            "cannot write {}: the directory {} does not exist",
            path.display(),
            dir.display()
        ));
    }
    if path.is_dir() {
        return Err(format!(
            "cannot write {}: it is a directory",
            path.display()
        ));
    }
    let probe = temp_sibling(path);
    std::fs::File::create(&probe).map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    let _ = std::fs::remove_file(&probe);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn writes_whole_files_and_refuses_bad_places() {
        let dir = std::env::temp_dir().join(format!("bezier-subdiv-files-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        let nested = dir.join("a/b/out.txt");
        assert!(check_writable(&nested, false)
            .unwrap_err()
            .contains("does not exist"));
        check_writable(&nested, true).unwrap();
        write_atomic(&nested, b"hello").unwrap();
        assert_eq!(std::fs::read(&nested).unwrap(), b"hello");
        assert!(check_writable(&dir.join("a"), false)
            .unwrap_err()
            .contains("directory"));
        // A failed write leaves neither the file nor a temporary behind.
        let missing = dir.join("missing/out.txt");
        assert!(write_atomic(&missing, b"x").is_err());
        assert_eq!(std::fs::read_dir(dir.join("a/b")).unwrap().count(), 1);
        let _ = std::fs::remove_dir_all(&dir);
    }

    /// A set of outputs whose second rename fails leaves nothing behind:
    /// neither the first file (already renamed) nor any temporary.
    #[test]
    fn failed_commit_leaves_no_file() {
        let dir = std::env::temp_dir().join(format!("bezier-subdiv-commit-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(dir.join("blocked.json/inside")).unwrap();
        let png = dir.join("out.png");
        let json = dir.join("blocked.json");
        let staged = vec![
            (stage(&png, b"png").unwrap(), png.clone()),
            (stage(&json, b"json").unwrap(), json.clone()),
        ];
        let (failed, _) = commit(&staged).unwrap_err();
        assert_eq!(failed, json);
        let mut names: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().into_string().unwrap())
            .collect();
        names.sort();
        assert_eq!(
            names,
            ["blocked.json"],
            "only the directory that blocked is left"
        );
        // The same set commits when nothing is in the way.
        std::fs::remove_dir_all(&json).unwrap();
        let staged = vec![
            (stage(&png, b"png").unwrap(), png.clone()),
            (stage(&json, b"json").unwrap(), json.clone()),
        ];
        commit(&staged).unwrap();
        assert_eq!(std::fs::read(&png).unwrap(), b"png");
        assert_eq!(std::fs::read(&json).unwrap(), b"json");
        let _ = std::fs::remove_dir_all(&dir);
    }
}
