//! Files written whole or not at all: [`WholeFile`] writes to a temporary name in the
//! file's own folder and renames it to its name only when complete, so that a reader
//! (render's `--resume`, a viewer, Slurm's check) never sees a cut file under the name.
//! On an error the temporary is removed (its drop); on SIGTERM, SIGINT or SIGHUP a
//! handler removes the one being written and the process then dies of the signal as
//! it would have. A process killed by SIGKILL leaves its temporary (`.NAME.PID-N`
//! beside the file), never a cut file under the name.

use std::ffi::CString;
use std::io::{self, Write};
use std::os::unix::ffi::OsStrExt;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU8, AtomicUsize, Ordering};

/// A file being written; [`WholeFile::commit`] gives it its name.
pub struct WholeFile {
    /// `None` once committed.
    temp: Option<tempfile::NamedTempFile>,
    path: PathBuf,
}

/// `cannot write PATH: why`, so that every failure names the file (once: an error this
/// module named already is passed on as it is).
fn named(path: &Path, e: io::Error) -> io::Error {
    // tempfile's own errors end `(os error 20) at path "…"`, naming the temporary.
    let text = crate::error::io_message(&e);
    let text = text.split(" (os error ").next().unwrap_or_default();
    if text.starts_with("cannot write ") {
        return e;
    }
    io::Error::new(e.kind(), format!("cannot write {}: {text}", path.display()))
}

impl WholeFile {
    /// Starts writing `path`: a temporary in its folder, which is made when missing.
    /// Errors name `path`.
    pub fn create(path: impl AsRef<Path>) -> io::Result<WholeFile> {
        let path = path.as_ref().to_path_buf();
        let dir = match path.parent() {
            Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
            _ => PathBuf::from("."),
        };
        if !dir.exists() {
            std::fs::create_dir_all(&dir).map_err(|e| named(&path, e))?;
        }
        // The temporary's name is chosen here and given to the signal handler before the
        // file exists: a stop signal can reach any thread of the process (zbuf reads its
        // inputs on several), so the handler must know the name from before its creation
        // to after its rename; unlinking a name not (or no longer) there is harmless.
        static COUNT: AtomicUsize = AtomicUsize::new(0);
        let name = path.file_name().unwrap_or_default().to_string_lossy();
        let file = loop {
            let n = COUNT.fetch_add(1, Ordering::Relaxed);
            let temp = dir.join(format!(".{name}.{}-{n}", std::process::id()));
            arm(&temp);
            let opened = std::fs::OpenOptions::new()
                .write(true)
                .create_new(true)
                .open(&temp);
            match opened {
                Ok(file) => match tempfile::TempPath::try_from_path(&temp) {
                    Ok(temp) => break tempfile::NamedTempFile::from_parts(file, temp),
                    Err(e) => {
                        let _ = std::fs::remove_file(&temp);
                        disarm();
                        return Err(named(&path, e));
                    }
                },
                // Left by an earlier process of this number killed by SIGKILL.
                Err(e) if e.kind() == io::ErrorKind::AlreadyExists => continue,
                Err(e) => {
                    disarm();
                    return Err(named(&path, e));
                }
            }
        };
        let temp = file;
        Ok(WholeFile {
            temp: Some(temp),
            path,
        })
    }

    /// The name the file will have.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Flushes the file to its end and renames it to its name. Errors name the file (the
    /// temporary is removed).
    pub fn commit(mut self) -> io::Result<()> {
        let _held = Held::new();
        let Some(mut temp) = self.temp.take() else {
            return Ok(());
        };
        let done = temp
            .as_file_mut()
            .flush()
            .and_then(|()| temp.persist(&self.path).map(drop).map_err(|e| e.error));
        disarm();
        done.map_err(|e| named(&self.path, e))
    }

    /// The temporary's file itself (NamedTempFile's own writes would name the temporary).
    fn file(&mut self) -> io::Result<&mut std::fs::File> {
        self.temp
            .as_mut()
            .map(tempfile::NamedTempFile::as_file_mut)
            .ok_or_else(|| io::Error::other("written after its commit"))
    }
}

impl Drop for WholeFile {
    fn drop(&mut self) {
        // Committed files have moved out of here; one dropped unfinished loses its
        // temporary with the NamedTempFile, and the handler need not know it any more.
        disarm();
    }
}

impl Write for WholeFile {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        let r = self.file().and_then(|f| f.write(buf));
        r.map_err(|e| named(&self.path, e))
    }

    fn flush(&mut self) -> io::Result<()> {
        let r = self.file().and_then(|f| f.flush());
        r.map_err(|e| named(&self.path, e))
    }
}

/// Writes `bytes` to `path` whole or not at all ([`WholeFile`]).
pub fn write_whole(path: impl AsRef<Path>, bytes: &[u8]) -> io::Result<()> {
    let mut f = WholeFile::create(path)?;
    f.write_all(bytes)?;
    f.commit()
}

// --- The signal handler's view: the temporary being written, as a C string. -------------

const MAX_PATH: usize = 4096;
/// The temporary's path, NUL-terminated; valid while `ARMED` is its length (0: none).
static PATH: [AtomicU8; MAX_PATH] = [const { AtomicU8::new(0) }; MAX_PATH];
static ARMED: AtomicUsize = AtomicUsize::new(0);
const SIGNALS: [libc::c_int; 3] = [libc::SIGTERM, libc::SIGINT, libc::SIGHUP];

/// The stop signals held (blocked) in this thread while it lives, so that the handler
/// never sees a path half set.
struct Held(libc::sigset_t);

impl Held {
    fn new() -> Held {
        // SAFETY: sigemptyset/sigaddset fill the set given; pthread_sigmask changes this
        // thread's mask and writes the old one into `old`.
        unsafe {
            let mut set = std::mem::zeroed::<libc::sigset_t>();
            let mut old = std::mem::zeroed::<libc::sigset_t>();
            libc::sigemptyset(&mut set);
            for s in SIGNALS {
                libc::sigaddset(&mut set, s);
            }
            libc::pthread_sigmask(libc::SIG_BLOCK, &set, &mut old);
            Held(old)
        }
    }
}

impl Drop for Held {
    fn drop(&mut self) {
        // SAFETY: restores the mask saved by `new`.
        unsafe { libc::pthread_sigmask(libc::SIG_SETMASK, &self.0, std::ptr::null_mut()) };
    }
}

/// Tells the handler (installed the first time) which temporary to remove.
fn arm(temp: &Path) {
    static INSTALL: std::sync::Once = std::sync::Once::new();
    INSTALL.call_once(install);
    let Ok(c) = CString::new(temp.as_os_str().as_bytes()) else {
        return;
    };
    let bytes = c.as_bytes_with_nul();
    if bytes.len() > MAX_PATH {
        return;
    }
    ARMED.store(0, Ordering::SeqCst);
    for (slot, &b) in PATH.iter().zip(bytes) {
        slot.store(b, Ordering::Relaxed);
    }
    ARMED.store(bytes.len(), Ordering::SeqCst);
}

fn disarm() {
    ARMED.store(0, Ordering::SeqCst);
}

/// The handler for SIGTERM, SIGINT and SIGHUP, where their action is the default
/// (a process that ignores one, as `nohup` makes it, keeps ignoring it).
fn install() {
    for s in SIGNALS {
        // SAFETY: sigaction reads and writes the plain structs given; the handler is an
        // extern "C" function that makes only async-signal-safe calls.
        unsafe {
            let mut old = std::mem::zeroed::<libc::sigaction>();
            if libc::sigaction(s, std::ptr::null(), &mut old) != 0
                || old.sa_sigaction != libc::SIG_DFL
            {
                continue;
            }
            let mut act = std::mem::zeroed::<libc::sigaction>();
            act.sa_sigaction = on_stop as extern "C" fn(libc::c_int) as libc::sighandler_t;
            libc::sigemptyset(&mut act.sa_mask);
            act.sa_flags = libc::SA_RESETHAND;
            libc::sigaction(s, &act, std::ptr::null_mut());
        }
    }
}

/// Removes the temporary being written, then dies of `sig` (its action is the default
/// again: SA_RESETHAND).
extern "C" fn on_stop(sig: libc::c_int) {
    let n = ARMED.swap(0, Ordering::SeqCst);
    if n > 0 {
        let mut buf = [0u8; MAX_PATH];
        for (b, slot) in buf.iter_mut().zip(&PATH[..n]) {
            *b = slot.load(Ordering::Relaxed);
        }
        // SAFETY: unlink takes a NUL-terminated path, which `buf` holds (its last byte
        // of `n` is the NUL `arm` stored).
        unsafe { libc::unlink(buf.as_ptr().cast()) };
    }
    // SAFETY: raise is async-signal-safe; with the default action back, the process ends
    // as the signal ends it.
    unsafe { libc::raise(sig) };
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_file_is_under_its_name_only_when_committed() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("new/folder/f.txt");
        let mut f = WholeFile::create(&path).unwrap();
        f.write_all(b"hello").unwrap();
        assert!(!path.exists());
        f.commit().unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), b"hello");
        let names: Vec<_> = std::fs::read_dir(path.parent().unwrap())
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(names, ["f.txt"]);
    }

    #[test]
    fn a_file_dropped_unfinished_leaves_nothing() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("f.txt");
        std::fs::write(&path, b"old").unwrap();
        let mut f = WholeFile::create(&path).unwrap();
        f.write_all(b"new, cut").unwrap();
        drop(f);
        assert_eq!(std::fs::read(&path).unwrap(), b"old");
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
        write_whole(&path, b"new").unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), b"new");
    }

    #[test]
    fn errors_name_the_file() {
        let dir = tempfile::tempdir().unwrap();
        let blocker = dir.path().join("file");
        std::fs::write(&blocker, b"").unwrap();
        let path = blocker.join("f.txt");
        let e = write_whole(&path, b"x").err().unwrap();
        assert!(
            e.to_string()
                .starts_with(&format!("cannot write {}: ", path.display())),
            "{e}"
        );
    }
}
