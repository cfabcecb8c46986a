//! farm's own files written whole: to a temporary name in the same folder, renamed when
//! complete, so that a file under its name is never a cut one (a frame `--resume` and
//! `--check` can trust, a render.sbatch Slurm can run).

use std::io::Write;
use std::path::Path;

/// Writes `bytes` to `path` whole: a temporary file in `path`'s folder, renamed to `path`
/// once written; on any failure the temporary is removed and `path` left as it was. The
/// message is the one line of the failure, without the path.
pub fn write_whole(path: &Path, bytes: &[u8]) -> Result<(), String> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let mut file = tempfile::Builder::new()
        .prefix(".farm.")
        .tempfile_in(dir)
        .map_err(|e| stagecli::error::io_message(&e))?;
    file.write_all(bytes)
        .and_then(|()| file.flush())
        .map_err(|e| stagecli::error::io_message(&e))?;
    file.persist(path)
        .map_err(|e| stagecli::error::io_message(&e.error))?;
    Ok(())
}

/// Makes `dir` and the folders above it where missing; the message names it.
pub fn make_folder(dir: &Path, what: &str) -> stagecli::Result<()> {
    if dir.as_os_str().is_empty() || dir.is_dir() {
        return Ok(());
    }
    std::fs::create_dir_all(dir).map_err(|e| {
        stagecli::Error::io(format!(
            "cannot make {what} {}: {}",
            dir.display(),
            stagecli::error::io_message(&e)
        ))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_file_is_written_whole_and_nothing_else_is_left() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("f.txt");
        std::fs::write(&path, "old").unwrap();
        write_whole(&path, b"new").unwrap();
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "new");
        let names: Vec<_> = std::fs::read_dir(dir.path()).unwrap().flatten().collect();
        assert_eq!(names.len(), 1);
        // A folder that is not there: an error, nothing written.
        let err = write_whole(&dir.path().join("none/f.txt"), b"x").unwrap_err();
        assert!(err.contains("No such file or directory"), "{err}");
    }
}
