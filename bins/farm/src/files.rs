//! farm's folders, made where missing before its files are written (its files are
//! written whole by `stagecli::whole`, as every binary's are).

use std::path::Path;

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
    fn folders_are_made_and_a_file_in_the_way_is_named() {
        let dir = tempfile::tempdir().unwrap();
        let deep = dir.path().join("a/b");
        make_folder(&deep, "-o's folder").unwrap();
        assert!(deep.is_dir());
        let file = dir.path().join("f");
        std::fs::write(&file, "").unwrap();
        let err = make_folder(&file.join("c"), "-o's folder").unwrap_err();
        assert_eq!(
            err.message(),
            format!(
                "cannot make -o's folder {}: Not a directory",
                file.join("c").display()
            )
        );
    }
}
