//! render.sh's private folder, kept by one process (`plan folder DIR`).
//!
//! A render needs a folder of its own for its named pipes and its stages' stderr files.
//! Made with `mkdir`, filled with `mkfifo` and removed with `rm -r`, that was three
//! processes a render, on its critical path: about 4 ms of a two-polygon render's 19 on
//! the 2-core machine this was measured on, where forking bash alone costs 0.4 ms and a
//! small program's start another 0.6 (docs/performance.md, "Start-up"). One process
//! started once does all three:
//!
//! 1. it makes DIR (mode 700; refused if anything is there) and in it the named pipe
//!    `requests`, leaves its parent (which exits at once) and says `ready PID` on stdout,
//!    PID its own;
//! 2. each line written to `requests` is a request: names (one path component each,
//!    separated by spaces) of named pipes to make in DIR, mode 600; it makes them and
//!    says `made` (or `error: …`, and stops);
//! 3. it removes DIR and everything in it, and exits, when it is told to (SIGUSR1), or
//!    when no one is left to read what it says (the script is gone, however that ended:
//!    SIGKILL too). SIGINT, SIGTERM and SIGHUP, which a terminal, `timeout` or a hung-up
//!    ssh send the whole process group, it ignores: the script's clean-up needs the
//!    folder until it has stopped every stage (it lists its jobs into a file there, and
//!    a stage it missed would wait for ever in the open of a named pipe), and then asks.
//!
//! It is not the script's child: a child that outlives the stages would hold up bash's
//! `wait -n`, which waits for any child once it has no job left to report, and render.sh
//! watches its stages with it. The script knows the folder is gone when the keeper's
//! stdout ends.

use std::ffi::CString;
use std::io::{BufRead, Write};
use std::os::unix::ffi::OsStrExt;
use std::os::unix::fs::DirBuilderExt;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

/// The named pipe in the folder that requests come through.
pub const REQUESTS: &str = "requests";

/// Why a folder could not be kept.
#[derive(Debug, thiserror::Error)]
pub enum FolderError {
    #[error("cannot make {path}: {source}")]
    Make {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("{0}: not a name for a named pipe in the folder")]
    Name(String),
}

/// Makes named pipe `name` (one path component) in `dir`, mode 600.
pub fn make_fifo(dir: &Path, name: &str) -> Result<(), FolderError> {
    if name.is_empty() || name == "." || name == ".." || name.contains(['/', '\0']) {
        return Err(FolderError::Name(name.to_string()));
    }
    let path = dir.join(name);
    let c =
        CString::new(path.as_os_str().as_bytes()).map_err(|_| FolderError::Name(name.into()))?;
    // SAFETY: `c` is a NUL-terminated path; mkfifo reads it and touches no other memory.
    if unsafe { libc::mkfifo(c.as_ptr(), 0o600) } != 0 {
        return Err(FolderError::Make {
            path,
            source: std::io::Error::last_os_error(),
        });
    }
    Ok(())
}

/// Makes `dir` (mode 700, refused if it exists) and its [`REQUESTS`] pipe.
pub fn make_folder(dir: &Path) -> Result<(), FolderError> {
    std::fs::DirBuilder::new()
        .mode(0o700)
        .create(dir)
        .map_err(|source| FolderError::Make {
            path: dir.to_path_buf(),
            source,
        })?;
    make_fifo(dir, REQUESTS)
}

/// A request's names, separated by spaces, made in `dir`.
pub fn make_requested(dir: &Path, request: &str) -> Result<(), FolderError> {
    request
        .split_ascii_whitespace()
        .try_for_each(|name| make_fifo(dir, name))
}

/// Removes the folder and ends the process, with the folder's lock held so that no
/// request is half done in it.
fn remove_and_exit(dir: &Path, lock: &Mutex<()>) -> ! {
    let _held = lock.lock();
    let _ = std::fs::remove_dir_all(dir);
    std::process::exit(0)
}

/// `plan folder DIR`: keeps DIR for the process that started this one, as the module
/// says, until told to remove it. Returns only on a failure to make it (nothing is left
/// then); every other way out removes it and exits.
pub fn keep(dir: &Path) -> Result<(), FolderError> {
    // Files made with exactly the modes asked (700, 600), whatever the caller's umask.
    // SAFETY: umask and signal only change this process's mask and dispositions.
    unsafe {
        libc::umask(0o077);
        for ignored in [libc::SIGINT, libc::SIGTERM, libc::SIGHUP] {
            libc::signal(ignored, libc::SIG_IGN);
        }
    }
    make_folder(dir)?;
    // Away from the parent: it exits now, and this process goes on as its own.
    // SAFETY: no thread has been started yet, so the child is a whole copy of this one.
    match unsafe { libc::fork() } {
        0 => {}
        -1 => {
            let source = std::io::Error::last_os_error();
            let _ = std::fs::remove_dir_all(dir);
            return Err(FolderError::Make {
                path: dir.to_path_buf(),
                source,
            });
        }
        _ => std::process::exit(0),
    }
    let lock = Arc::new(Mutex::new(()));
    // USR1 is taken by a thread of its own with sigwait: blocked here, before the thread
    // starts, so that every thread inherits the mask and it stays pending until taken.
    // SAFETY: the set is initialised by sigemptyset before use; pthread_sigmask changes
    // only this thread's mask.
    let set = unsafe {
        let mut set: libc::sigset_t = std::mem::zeroed();
        libc::sigemptyset(&mut set);
        libc::sigaddset(&mut set, libc::SIGUSR1);
        libc::pthread_sigmask(libc::SIG_BLOCK, &set, std::ptr::null_mut());
        set
    };
    {
        let (dir, lock) = (dir.to_path_buf(), Arc::clone(&lock));
        std::thread::spawn(move || {
            let mut signal = 0;
            // SAFETY: `set` is an initialised signal set and `signal` a place for the one
            // taken; sigwait returns when one of the set is pending.
            unsafe { libc::sigwait(&set, &mut signal) };
            remove_and_exit(&dir, &lock)
        });
    }
    {
        // No reader left on stdout (the script and whatever it handed the pipe to):
        // poll says so with POLLERR, which needs no events asked.
        let (dir, lock) = (dir.to_path_buf(), Arc::clone(&lock));
        std::thread::spawn(move || loop {
            let mut out = libc::pollfd {
                fd: 1,
                events: 0,
                revents: 0,
            };
            // SAFETY: one valid pollfd; poll writes only its revents.
            let n = unsafe { libc::poll(&mut out, 1, -1) };
            if n > 0 && out.revents & (libc::POLLERR | libc::POLLHUP | libc::POLLNVAL) != 0 {
                remove_and_exit(&dir, &lock);
            }
        });
    }
    // Opened for reading and writing: the open does not wait for a writer, and the pipe
    // keeps what a request wrote even when the writer has closed its end before this
    // reads it.
    let requests = dir.join(REQUESTS);
    let Ok(pipe) = std::fs::OpenOptions::new()
        .read(true)
        .write(true)
        .open(&requests)
    else {
        remove_and_exit(dir, &lock);
    };
    let mut requests = std::io::BufReader::new(pipe);
    let mut out = std::io::stdout().lock();
    let mut say = |words: &str| {
        if out
            .write_all(words.as_bytes())
            .and_then(|_| out.flush())
            .is_err()
        {
            remove_and_exit(dir, &lock); // the script stopped listening
        }
    };
    say(&format!("ready {}\n", std::process::id()));
    let mut request = String::new();
    loop {
        request.clear();
        if !matches!(requests.read_line(&mut request), Ok(n) if n > 0) {
            remove_and_exit(dir, &lock);
        }
        let made = {
            let _held = lock.lock();
            make_requested(dir, &request)
        };
        match made {
            Ok(()) => say("made\n"),
            Err(e) => {
                say(&format!("error: {e}\n"));
                remove_and_exit(dir, &lock);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::os::unix::fs::{FileTypeExt, PermissionsExt};

    #[test]
    fn a_folder_is_made_with_its_requests_pipe_and_refused_twice() {
        let base = tempfile::tempdir().unwrap();
        let dir = base.path().join("render.1");
        make_folder(&dir).unwrap();
        let meta = std::fs::metadata(&dir).unwrap();
        assert_eq!(meta.permissions().mode() & 0o777, 0o700 & !current_umask());
        let pipe = std::fs::metadata(dir.join(REQUESTS)).unwrap();
        assert!(pipe.file_type().is_fifo());
        let again = make_folder(&dir).unwrap_err().to_string();
        assert!(again.starts_with("cannot make "), "{again}");
        assert!(again.contains("exists"), "{again}");
    }

    #[test]
    fn requested_names_become_pipes_and_bad_names_are_refused() {
        let base = tempfile::tempdir().unwrap();
        make_requested(base.path(), "view clipped  leaf-0\n").unwrap();
        for name in ["view", "clipped", "leaf-0"] {
            let m = std::fs::metadata(base.path().join(name)).unwrap();
            assert!(m.file_type().is_fifo(), "{name}");
        }
        for bad in ["../x", "a/b", ".", ".."] {
            let e = make_requested(base.path(), bad).unwrap_err().to_string();
            assert_eq!(
                e,
                format!("{bad}: not a name for a named pipe in the folder")
            );
        }
        // A name already there is refused, as mkfifo refuses it.
        let e = make_requested(base.path(), "view").unwrap_err().to_string();
        assert!(e.contains("exists"), "{e}");
    }

    fn current_umask() -> u32 {
        // SAFETY: umask only reads and sets this process's mask; it is set back at once.
        unsafe {
            let m = libc::umask(0o022);
            libc::umask(m);
            m as u32
        }
    }
}
