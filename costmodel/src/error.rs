//! The cost model's errors: one type for the library, whose kind is the exit status a
//! command gives it (the stages' policy, `stagecli`: 1 bad data, 2 usage, 3 I/O or the
//! machine's limits, 0 when the reader of the output went away). The kind is decided
//! where the error is made, as in the stages, and context added on the way up
//! ([`Context`]) keeps it; a main turns it into a [`stagecli::Error`] by `From`, printed
//! once as `plan: message`. The type is `stagecli::kinded_error`'s, as every library's;
//! this module adds the conversions from TOML's errors.

stagecli::kinded_error!();

/// A constants file that is not the model's TOML is data.
impl From<toml::de::Error> for Error {
    fn from(e: toml::de::Error) -> Self {
        Error::Data(e.to_string().trim_end().replace('\n', " "))
    }
}

/// Constants that cannot be written as TOML (a non-finite number) are data.
impl From<toml::ser::Error> for Error {
    fn from(e: toml::ser::Error) -> Self {
        Error::Data(e.to_string())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_kind_is_its_exit_status_through_context() {
        let missing = std::fs::read("/nonexistent/polypipe/model.toml")
            .context("cannot read /nonexistent/polypipe/model.toml")
            .unwrap_err();
        assert_eq!(
            (missing.status(), missing.message()),
            (
                3,
                "cannot read /nonexistent/polypipe/model.toml: No such file or directory"
            )
        );
        let bad = crate::model::Constants::parse("overheads = 3")
            .context("reading m.toml")
            .unwrap_err();
        assert_eq!(bad.status(), 1, "{bad}");
        assert!(bad.message().starts_with("reading m.toml: "), "{bad}");
        let usage = Error::from(stagecli::Error::usage("--size 0x0")).context("camera");
        assert_eq!(
            (usage.status(), usage.to_string().as_str()),
            (2, "camera: --size 0x0")
        );
        let gone = Error::from(std::io::Error::from(std::io::ErrorKind::BrokenPipe));
        assert_eq!(gone.status(), 0);
        // A main's error, printed once: the kind and the whole message kept.
        let s = stagecli::Error::from(missing);
        assert_eq!(s.kind(), stagecli::Kind::Io);
        assert_eq!(
            s.message(),
            "cannot read /nonexistent/polypipe/model.toml: No such file or directory"
        );
    }
}
