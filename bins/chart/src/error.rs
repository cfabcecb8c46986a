//! chart's errors: one type for the library, whose kind is the exit status chart gives it
//! (the stages' policy, `stagecli`: 1 bad data, 2 usage, 3 I/O or the machine's limits, 0
//! when the reader of the output went away). The kind is decided where the error is made,
//! as in the stages and the cost model (`costmodel::Error`: both are `stagecli::kinded_error`'s type): a bad
//! scene argument is usage, a scene that cannot be read I/O, a broken pipe the reader
//! gone, a run that failed data; context added on the way up ([`Context`]) keeps it.
//! chart's main turns it into a [`stagecli::Error`] by `From`, printed once as
//! `chart: message`.

stagecli::kinded_error!();

/// The cost model's errors keep their kind (a scene that cannot be opened is I/O, a bad
/// camera option usage).
impl From<costmodel::Error> for Error {
    fn from(e: costmodel::Error) -> Self {
        Error::new(e.kind(), e.message())
    }
}

/// A CSV file's reading or writing is I/O; its contents that are not the rows', data.
impl From<csv::Error> for Error {
    fn from(e: csv::Error) -> Self {
        let text = e.to_string();
        match e.into_kind() {
            csv::ErrorKind::Io(io) => io.into(),
            _ => Error::Data(text),
        }
    }
}

/// A picture that cannot be written is I/O; one that cannot be encoded, data.
impl From<image::ImageError> for Error {
    fn from(e: image::ImageError) -> Self {
        match e {
            image::ImageError::IoError(io) => io.into(),
            other => Error::Data(other.to_string()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proto::StreamError;
    use std::io;

    /// Each kind, made where the error is, gives its status through the context added
    /// above it, and reaches a main's [`stagecli::Error`] with its kind and whole message.
    #[test]
    fn each_kind_is_its_exit_status_through_context() {
        let cases: [(Error, u8, &str); 4] = [
            (
                Error::Data("no overall row".into()),
                1,
                "zspec compare: no overall row",
            ),
            (
                stagecli::Error::usage("bad size").into(),
                2,
                "zspec compare: bad size",
            ),
            (
                io::Error::from_raw_os_error(28).into(),
                3,
                "zspec compare: No space left on device",
            ),
            (
                io::Error::from(io::ErrorKind::BrokenPipe).into(),
                0,
                "zspec compare: broken pipe",
            ),
        ];
        for (e, status, message) in cases {
            let e = Err::<(), _>(e)
                .context("zspec compare")
                .context("outer")
                .unwrap_err();
            assert_eq!(e.status(), status, "{e}");
            assert_eq!(e.message(), format!("outer: {message}"));
            let s = stagecli::Error::from(e.clone());
            assert_eq!((s.kind(), s.message()), (e.kind(), e.message()));
        }
    }

    #[test]
    fn os_errors_are_io_said_once() {
        let e = Err::<(), _>(StreamError::Io(io::Error::from_raw_os_error(21)))
            .context("reading /tmp")
            .unwrap_err();
        assert_eq!(e, Error::Io("reading /tmp: Is a directory".into()));
        let e = std::fs::read("/nonexistent/polypipe/s.txt")
            .with_context(|| "cannot open /nonexistent/polypipe/s.txt")
            .unwrap_err();
        assert_eq!(
            e,
            Error::Io("cannot open /nonexistent/polypipe/s.txt: No such file or directory".into())
        );
    }

    #[test]
    fn the_libraries_errors_keep_their_kind() {
        let e = Error::from(costmodel::Error::Usage("--size 0x0".into())).context("camera");
        assert_eq!((e.status(), e.message()), (2, "camera: --size 0x0"));
        // A CSV file that cannot be read is I/O, one whose rows are not the chart's data.
        let missing = csv::Reader::from_path("/nonexistent/polypipe/results.csv")
            .map(|_| ())
            .context("cannot read /nonexistent/polypipe/results.csv")
            .unwrap_err();
        assert_eq!(
            missing,
            Error::Io(
                "cannot read /nonexistent/polypipe/results.csv: No such file or directory".into()
            )
        );
        let rows: std::result::Result<Vec<(u32,)>, _> = csv::Reader::from_reader(&b"n\nx\n"[..])
            .deserialize()
            .collect();
        let bad = Error::from(rows.unwrap_err());
        assert_eq!(bad.status(), 1, "{bad}");
        let stream = Error::from(StreamError::Text {
            line: 2,
            column: 1,
            msg: "no".into(),
        });
        assert_eq!(stream.status(), 1, "{stream}");
    }
}
