//! Where a program of the workspace finds its siblings and its sources: the built
//! binaries beside its own (target/<profile>), and the repository above them.

use crate::{Error, Result};
use std::path::PathBuf;

/// The built binaries: the folder of the running program.
pub fn bin_dir() -> Result<PathBuf> {
    let exe = std::env::current_exe()
        .map_err(|e| Error::from(e).context("cannot tell where this program is"))?;
    exe.parent()
        .map(|p| p.to_path_buf())
        .ok_or_else(|| Error::io(format!("{} has no folder", exe.display())))
}

/// The repository: `root` when given, else the first folder above the binaries' with
/// scripts/render.sh, else the current folder.
pub fn root_dir(root: Option<PathBuf>) -> Result<PathBuf> {
    if let Some(r) = root {
        return Ok(r);
    }
    let bin = bin_dir()?;
    for up in bin.ancestors() {
        if up.join("scripts/render.sh").is_file() {
            return Ok(up.to_path_buf());
        }
    }
    Ok(std::env::current_dir()?)
}
