//! Where this machine's calibration is kept, and whether it is this machine's: the file
//! `${XDG_CACHE_HOME:-$HOME/.cache}/polypipe/model.toml`, the model's constants with the
//! machine they were fitted on ([`Machine`]: CPU model, cores, the binaries' version and
//! build). A file made on another CPU or core count is foreign, one made with other
//! binaries stale: `chart` and `chart calibrate` fit it again; `--depth auto` plans with
//! a stale one (this machine's, if not these binaries') and with the repository's
//! `bench/model.toml` where there is none or a foreign one.

use crate::error::{Context, Error, Result};
use crate::model::{Constants, Machine};
use std::path::{Path, PathBuf};

/// The folder of polypipe's cache: `$XDG_CACHE_HOME/polypipe` (an absolute
/// XDG_CACHE_HOME, as the XDG base directory specification requires), else
/// `$HOME/.cache/polypipe`; `None` with neither.
pub fn dir() -> Option<PathBuf> {
    let xdg = std::env::var_os("XDG_CACHE_HOME")
        .map(PathBuf::from)
        .filter(|p| p.is_absolute());
    let base = xdg.or_else(|| {
        std::env::var_os("HOME")
            .filter(|h| !h.is_empty())
            .map(|h| PathBuf::from(h).join(".cache"))
    })?;
    Some(base.join("polypipe"))
}

/// The calibration file.
pub fn path() -> Option<PathBuf> {
    dir().map(|d| d.join("model.toml"))
}

/// The stage binaries whose build the calibration measured.
pub const MEASURED: [&str; 7] = [
    "viewxf",
    "clipbatch",
    "splitter",
    "persp",
    "scanconv",
    "zbuf",
    "scene",
];

/// This machine and the binaries in `bin`.
pub fn this_machine(bin: &Path) -> Machine {
    Machine {
        cpu: cpu_model(),
        cores: machine_cores(),
        version: env!("CARGO_PKG_VERSION").to_string(),
        binaries: fingerprint(bin),
    }
}

/// The machine's cores (what the standard library sees as available).
pub fn cores() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// The machine's cores, online, whatever this process's affinity: what tells one
/// machine from another for its calibration (a stage costs the same CPU seconds on one
/// core of it as on two, so a render under `taskset -c 0` plans with the machine's
/// calibration, for one core), and what the load average is spread over.
pub fn machine_cores() -> usize {
    // SAFETY: sysconf reads a system value and has no other effect.
    let online = unsafe { libc::sysconf(libc::_SC_NPROCESSORS_ONLN) };
    usize::try_from(online)
        .ok()
        .filter(|&n| n > 0)
        .unwrap_or_else(cores)
        .max(cores())
}

/// The CPU model, from /proc/cpuinfo (`model name`, else the first of `Hardware`,
/// `cpu model`, `Processor` some architectures use).
pub fn cpu_model() -> String {
    let text = std::fs::read_to_string("/proc/cpuinfo").unwrap_or_default();
    for key in ["model name", "Hardware", "cpu model", "Processor"] {
        if let Some(v) = text
            .lines()
            .filter(|l| l.starts_with(key))
            .find_map(|l| l.split_once(':').map(|(_, v)| v.trim().to_string()))
        {
            if !v.is_empty() {
                return v;
            }
        }
    }
    "an unknown CPU".into()
}

/// The measured binaries' sizes and modification times, hashed (FNV-1a, 64 bits): a
/// rebuild changes it.
pub fn fingerprint(bin: &Path) -> String {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for name in MEASURED {
        let meta = std::fs::metadata(bin.join(name)).ok();
        let size = meta.as_ref().map_or(0, |m| m.len());
        let mtime = meta
            .and_then(|m| m.modified().ok())
            .and_then(|t| t.duration_since(std::time::UNIX_EPOCH).ok())
            .map_or(0, |d| d.as_nanos() as u64);
        for b in name
            .bytes()
            .chain(size.to_le_bytes())
            .chain(mtime.to_le_bytes())
        {
            h ^= b as u64;
            h = h.wrapping_mul(0x100_0000_01b3);
        }
    }
    format!("{h:016x}")
}

/// What the cache holds for this machine.
#[derive(Clone, Debug, PartialEq)]
pub enum State {
    /// A calibration of this machine and these binaries.
    Current(Constants),
    /// This machine's, but of other binaries (rebuilt since): why.
    Stale(Constants, String),
    /// Another machine's (another CPU or core count; copied, or a home shared between
    /// machines), or a file that cannot be read as one: why.
    Foreign(String),
    /// No calibration yet.
    Missing,
}

impl State {
    /// The constants to plan with: this machine's, stale or not; else `None`.
    pub fn constants(&self) -> Option<&Constants> {
        match self {
            State::Current(k) | State::Stale(k, _) => Some(k),
            _ => None,
        }
    }

    /// Whether `chart` should fit the constants again before using them.
    pub fn needs_fitting(&self) -> bool {
        !matches!(self, State::Current(_))
    }

    /// In words, for `plan status` and the notes.
    pub fn describe(&self) -> String {
        match self {
            State::Current(k) => format!("calibrated: {}", k.measured_on),
            State::Stale(_, why) => format!("stale calibration ({why})"),
            State::Foreign(why) => format!("not calibrated on this machine ({why})"),
            State::Missing => "not calibrated on this machine".into(),
        }
    }
}

/// Compares a calibration file's text with this machine.
pub fn judge(text: &str, here: &Machine) -> State {
    let k = match Constants::parse(text) {
        Ok(k) => k,
        Err(e) => return State::Foreign(format!("unreadable: {}", first_line(&e.to_string()))),
    };
    let m = &k.machine;
    if m.cpu != here.cpu || m.cores != here.cores {
        return State::Foreign(format!(
            "made on {}, {} cores; this is {}, {} cores",
            m.cpu, m.cores, here.cpu, here.cores
        ));
    }
    if m.version != here.version || m.binaries != here.binaries {
        let why = if m.version != here.version {
            format!("binaries {} then, {} now", m.version, here.version)
        } else {
            "the binaries were rebuilt since".to_string()
        };
        return State::Stale(k, why);
    }
    State::Current(k)
}

fn first_line(s: &str) -> &str {
    s.lines().next().unwrap_or("")
}

/// The cache's calibration, judged against this machine and the binaries in `bin`.
pub fn load(bin: &Path) -> State {
    let Some(path) = path() else {
        return State::Missing;
    };
    match std::fs::read_to_string(&path) {
        Ok(text) => judge(&text, &this_machine(bin)),
        Err(_) => State::Missing,
    }
}

/// Writes a calibration to the cache (a temporary file renamed over the old, so that a
/// reader never sees half of one). Returns the path.
pub fn store(k: &Constants, header: &str) -> Result<PathBuf> {
    let path = path().ok_or_else(|| {
        Error::Io(
            "no cache folder for the calibration: neither XDG_CACHE_HOME nor HOME is set".into(),
        )
    })?;
    let dir = path.parent().unwrap_or(Path::new("."));
    std::fs::create_dir_all(dir).with_context(|| format!("cannot make {}", dir.display()))?;
    let tmp = dir.join(format!("model.toml.{}", std::process::id()));
    std::fs::write(&tmp, format!("{header}{}", k.to_toml()?))
        .with_context(|| format!("cannot write {}", tmp.display()))?;
    std::fs::rename(&tmp, &path).with_context(|| format!("cannot write {}", path.display()))?;
    Ok(path)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn machine() -> Machine {
        Machine {
            cpu: "Some CPU".into(),
            cores: 2,
            version: "0.1.0".into(),
            binaries: "abc".into(),
        }
    }

    #[test]
    fn a_file_is_current_stale_or_foreign_by_its_machine() {
        let k = Constants {
            machine: machine(),
            measured_on: "here".into(),
            ..Default::default()
        };
        let text = k.to_toml().unwrap();
        assert_eq!(judge(&text, &machine()), State::Current(k.clone()));
        let rebuilt = Machine {
            binaries: "abd".into(),
            ..machine()
        };
        assert!(matches!(judge(&text, &rebuilt), State::Stale(_, ref w) if w.contains("rebuilt")));
        let bigger = Machine {
            cores: 16,
            ..machine()
        };
        match judge(&text, &bigger) {
            State::Foreign(why) => {
                assert_eq!(why, "made on Some CPU, 2 cores; this is Some CPU, 16 cores")
            }
            other => panic!("{other:?}"),
        }
        assert!(matches!(judge("[[[", &machine()), State::Foreign(_)));
        // The repository's file is another machine's: never this one's calibration.
        assert!(matches!(
            judge(crate::model::COMMITTED, &machine()),
            State::Foreign(_)
        ));
    }

    #[test]
    fn the_cache_folder_follows_xdg_then_home() {
        // One test changes the environment, so that no other test sees it half-changed.
        let old = (std::env::var_os("XDG_CACHE_HOME"), std::env::var_os("HOME"));
        std::env::set_var("XDG_CACHE_HOME", "/x/cache");
        assert_eq!(path(), Some(PathBuf::from("/x/cache/polypipe/model.toml")));
        std::env::set_var("XDG_CACHE_HOME", "relative");
        std::env::set_var("HOME", "/home/u");
        assert_eq!(
            path(),
            Some(PathBuf::from("/home/u/.cache/polypipe/model.toml"))
        );
        std::env::remove_var("XDG_CACHE_HOME");
        assert_eq!(dir(), Some(PathBuf::from("/home/u/.cache/polypipe")));
        match old.0 {
            Some(v) => std::env::set_var("XDG_CACHE_HOME", v),
            None => std::env::remove_var("XDG_CACHE_HOME"),
        }
        match old.1 {
            Some(v) => std::env::set_var("HOME", v),
            None => std::env::remove_var("HOME"),
        }
    }
}
