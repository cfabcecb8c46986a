//! The loop of a one-in, one-out polygon stage (viewxf, clipplane, persp): the stream
//! read by one reader ([`filter_records`]), or, for a text stream written on as binary,
//! in pieces on several threads ([`crate::pieces`]).

use crate::pieces;
use crate::stream::{filter_records, read_stdin, write_stdout};
use crate::Result;
use proto::{Form, Header, Polygon, SpaceKind, Token};

/// The loop of a one-in, one-out polygon stage (viewxf, clipplane, persp): reads the
/// polygon stream on stdin, which must be in space `expect`; `setup` turns its header
/// into the output's header and the stage's transformation of a polygon. Writes that
/// header and then every record to stdout in `form`, each polygon transformed. A polygon
/// the transformation refuses, or leaves with a number that is not finite, ends the stage
/// with a data error naming the polygon's place in the input (`frame 0, polygon 3: …`);
/// `doing` says what the stage did to it (`the viewing transformation`).
///
/// A text stream written on as binary is read in pieces on several threads where there
/// are cores for them ([`crate::pieces`]), with the same output and messages.
pub fn filter_polygons<F>(
    expect: SpaceKind,
    form: Form,
    doing: &str,
    setup: impl FnOnce(&Header) -> Result<(Header, F)>,
) -> Result<()>
where
    F: FnMut(&mut Polygon) -> std::result::Result<(), String> + Clone + Send,
{
    let reader = read_stdin::<Token>(expect)?;
    let in_header = *reader.header();
    let (header, mut transform) = setup(reader.header())?;
    let mut writer = write_stdout(header, form)?;
    let mut reader = match (form, pieces::piece_workers()) {
        (Form::Binary, Some(workers)) => match reader.into_text_rest() {
            Ok(rest) => {
                pieces::filter_text_in_pieces(
                    rest,
                    in_header,
                    header,
                    &mut writer,
                    transform,
                    doing,
                    (workers, pieces::PIECE_BYTES),
                    stdin_ready,
                )?;
                writer.flush()?;
                return Ok(());
            }
            Err(reader) => reader,
        },
        _ => reader,
    };
    filter_records(&mut reader, &mut writer, &mut transform, doing)?;
    writer.flush()?;
    Ok(())
}

/// Whether standard input can be read at once, without waiting: more input there, or
/// its end.
fn stdin_ready() -> bool {
    let mut fd = libc::pollfd {
        fd: 0,
        events: libc::POLLIN,
        revents: 0,
    };
    // SAFETY: poll reads and writes the one pollfd it is given, and waits not at all.
    unsafe { libc::poll(&mut fd, 1, 0) > 0 }
}
