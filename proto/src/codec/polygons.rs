//! The polygon stream's records in their binary and text forms: the codec of
//! [`crate::polygon`]'s [`Token`]s, which [`crate::codec`]'s reader and writer use.

use crate::codec::{
    expect_zero, head, head_n, write_vertex_attrs, write_vertices, BinaryError, BinaryInput,
    Control, Record, MAX_VERTICES,
};
use crate::header::{Header, Space};
use crate::polygon::{Colour, Polygon, Token, Vertex, OPAQUE};
use crate::text::{is_blank, Lexer, Shown};
use crate::StreamError;
use glam::{DVec3, DVec4};
use std::io::{self, BufRead, Read, Write};

impl Token {
    /// Makes `self` a polygon whose buffers can be refilled: its own if it is one, else
    /// the spare's, else new ones.
    #[inline]
    fn polygon_mut<'a>(&'a mut self, spare: &mut Token) -> &'a mut Polygon {
        if !matches!(self, Token::Polygon(_)) {
            if matches!(spare, Token::Polygon(_)) {
                std::mem::swap(self, spare);
            } else {
                *self = Token::Polygon(Polygon::default());
            }
        }
        match self {
            Token::Polygon(p) => p,
            _ => unreachable!("made a polygon above"),
        }
    }

    /// Sets `self` to a record without a polygon, keeping a polygon's buffers in `spare`.
    #[inline]
    fn set(&mut self, spare: &mut Token, token: Token) {
        let old = std::mem::replace(self, token);
        if matches!(old, Token::Polygon(_)) {
            *spare = old;
        }
    }
}

/// The binary records of the polygon stream (stream version 2; `proto::codec` describes
/// the 8-byte head `tag, colour, n`):
///
/// | tag | record | head | then |
/// |-----|--------|------|------|
/// | 0 | polygon | colour, n = vertex count | n vertices |
/// | 1 | NEXT.FRAME | zeros | – |
/// | 2 | END | zeros | – |
/// | 3 | annotated polygon | colour, n | `flags: u32` (1 = plane, 2 = supports, 4 = shade, 8 = vertex attributes: colours or normals) and a `u32` whose low byte is 255 − opacity (zero: opaque), the rest zero; the plane (one vertex's 32 bytes) if flagged; the three colour planes (96 bytes) if flagged; n vertices; if flagged, n vertex attributes (three `f64`s, 24 bytes each); if flagged, the supports in groups of eight edges: eight bytes 0/1 (edge has one), then the two ends of each that has one |
/// | 4 | `skip N` | zero colour, n = N | – |
///
/// A polygon without annotations, vertex attributes or opacity is tag 0, so the common
/// record is its head and its vertices, which are read and written as one block; a flat
/// stream's records are those of stream version 3.
mod tag {
    pub const POLYGON: u8 = 0;
    pub const NEXT_FRAME: u8 = 1;
    pub const END: u8 = 2;
    pub const ANNOTATED: u8 = 3;
    pub const SKIP: u8 = 4;
}

const FLAG_PLANE: u64 = 1;
const FLAG_SUPPORTS: u64 = 2;
const FLAG_SHADE: u64 = 4;
const FLAG_VERTEX_ATTRS: u64 = 8;
/// The flag word's bits 32–39 hold 255 − opacity, so an opaque polygon's are zero.
const TRANSPARENCY_SHIFT: u32 = 32;
const KNOWN_FLAGS: u64 =
    FLAG_PLANE | FLAG_SUPPORTS | FLAG_SHADE | FLAG_VERTEX_ATTRS | (0xff << TRANSPARENCY_SHIFT);

/// Writes a polygon's binary record (tag 0, or tag 3 when it carries annotations).
#[inline]
pub(crate) fn write_polygon_binary<W: Write>(p: &Polygon, out: &mut W) -> io::Result<()> {
    let n = p.vertices.len();
    if n > MAX_VERTICES {
        return Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            format!("polygon of {n} vertices (at most {MAX_VERTICES})"),
        ));
    }
    if p.plane.is_none()
        && p.supports.is_empty()
        && p.vertex_attrs.is_empty()
        && p.shade.is_none()
        && p.opacity == OPAQUE
    {
        // The common record: a flat polygon with nothing else (tag 0).
        out.write_all(&head(tag::POLYGON, p.colour, n as u32))?;
        return write_vertices(out, &p.vertices);
    }
    write_annotated(p, out)
}

/// The rest of [`write_polygon_binary`]: tag 3, or tag 0 for a list of no support.
#[inline(never)]
fn write_annotated<W: Write>(p: &Polygon, out: &mut W) -> io::Result<()> {
    let n = p.vertices.len();
    let supports = p.supports.iter().any(Option::is_some);
    let shaded = !p.vertex_attrs.is_empty();
    if p.plane.is_none() && !supports && !shaded && p.shade.is_none() && p.opacity == OPAQUE {
        out.write_all(&head(tag::POLYGON, p.colour, n as u32))?;
        return write_vertices(out, &p.vertices);
    }
    if supports && p.supports.len() != n {
        return Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            format!("{} edge supports for {n} vertices", p.supports.len()),
        ));
    }
    if shaded && p.vertex_attrs.len() != n {
        return Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            format!("{} vertex colours for {n} vertices", p.vertex_attrs.len()),
        ));
    }
    out.write_all(&head(tag::ANNOTATED, p.colour, n as u32))?;
    let flag = |set: bool, f: u64| if set { f } else { 0 };
    let flags = flag(p.plane.is_some(), FLAG_PLANE)
        | flag(supports, FLAG_SUPPORTS)
        | flag(p.shade.is_some(), FLAG_SHADE)
        | flag(shaded, FLAG_VERTEX_ATTRS)
        | u64::from(OPAQUE - p.opacity) << TRANSPARENCY_SHIFT;
    out.write_all(&flags.to_le_bytes())?;
    if let Some(plane) = p.plane {
        write_vertices(out, &[plane])?;
    }
    if let Some(shade) = &p.shade {
        write_vertices(out, &shade[..])?;
    }
    write_vertices(out, &p.vertices)?;
    if shaded {
        write_vertex_attrs(out, &p.vertex_attrs)?;
    }
    if supports {
        for group in (0..n).step_by(8) {
            let edges = group..(group + 8).min(n);
            let mut present = [0u8; 8];
            for i in edges.clone() {
                present[i - group] = p.support(i).is_some() as u8;
            }
            out.write_all(&present)?;
            for i in edges {
                if let Some(ends) = p.support(i) {
                    write_vertices(out, &ends)?;
                }
            }
        }
    }
    Ok(())
}

/// Reads the rest of a polygon record (tag 0 or 3) whose head is `head` into `p`.
#[inline]
fn read_polygon_binary<R: Read>(
    p: &mut Polygon,
    head: &[u8; 8],
    input: &mut BinaryInput<R>,
) -> Result<(), BinaryError> {
    p.colour = [head[1], head[2], head[3]];
    p.plane = None;
    p.supports.clear();
    p.shade = None;
    p.opacity = OPAQUE;
    if !p.vertex_attrs.is_empty() {
        p.vertex_attrs.clear();
    }
    let n = head_n(head) as usize;
    if n > MAX_VERTICES {
        return Err(BinaryError::TooLarge);
    }
    if head[0] == tag::POLYGON {
        return input.vertices(&mut p.vertices, n);
    }
    let flags = u64::from_le_bytes(input.array()?);
    if flags & !KNOWN_FLAGS != 0 {
        return Err(BinaryError::Invalid(format!(
            "not a valid annotated polygon (flags {flags:#x}); is the stream corrupt?"
        )));
    }
    p.opacity = OPAQUE - (flags >> TRANSPARENCY_SHIFT) as u8;
    if flags & FLAG_PLANE != 0 {
        p.plane = Some(input.vertex()?);
    }
    if flags & FLAG_SHADE != 0 {
        p.shade = Some(Box::new([
            input.vertex()?,
            input.vertex()?,
            input.vertex()?,
        ]));
    }
    input.vertices(&mut p.vertices, n)?;
    if flags & FLAG_VERTEX_ATTRS != 0 {
        input.vertex_attrs(&mut p.vertex_attrs, n)?;
    }
    if flags & FLAG_SUPPORTS != 0 {
        for group in (0..n).step_by(8) {
            let present: [u8; 8] = input.array()?;
            let edges = (n - group).min(8);
            for (k, &flag) in present.iter().enumerate() {
                match (flag, k < edges) {
                    (0, _) if k >= edges => {}
                    (0, _) => p.supports.push(None),
                    (1, true) => p.supports.push(Some([input.vertex()?, input.vertex()?])),
                    _ => {
                        return Err(BinaryError::Invalid(format!(
                            "not a valid annotated polygon (support flag {flag} for edge {}); \
                             is the stream corrupt?",
                            group + k
                        )))
                    }
                }
            }
        }
        if !p.supports.iter().any(Option::is_some) {
            // As the text form reads it: a list of no support is no list.
            p.supports.clear();
        }
    }
    Ok(())
}

/// The keywords of the text form (Appendix 1's special values).
pub const NEXT_POLYGON: &str = "NEXT.POLYGON";
pub const NEXT_FRAME: &str = "NEXT.FRAME";
pub const END: &str = "END";
pub const COLOUR: &str = "colour";
/// The optional plane line after `colour`.
pub const PLANE: &str = "plane";
/// The optional colour planes line (three planes, four numbers each) after `plane`.
pub const SHADE: &str = "shade";
/// Starts a vertex's support (the original edge from it to the next vertex lies on).
pub const ON: &str = "on";
/// `skip N`, standing for N polygons of which the stream carries nothing.
pub const SKIP: &str = "skip";

/// What starts an item of a frame in the text form.
pub(crate) enum Start {
    /// `colour R G B`: a polygon (or a fragment polygon) follows.
    Colour(Colour),
    /// `skip N`.
    Skip(u32),
    NextFrame,
    End,
}

/// The words that may start an item of a frame.
enum Head {
    NextFrame,
    End,
    NextPolygon,
    Colour,
    Skip,
    Other,
}

fn head_word(w: &str) -> Head {
    match w {
        NEXT_FRAME => Head::NextFrame,
        END => Head::End,
        NEXT_POLYGON => Head::NextPolygon,
        COLOUR | "color" => Head::Colour,
        SKIP => Head::Skip,
        _ => Head::Other,
    }
}

/// Reads what starts a polygon or a fragment polygon (`colour R G B`, or `skip N` in its
/// place), NEXT.POLYGON first unless it starts the frame; or NEXT.FRAME or END.
#[inline]
pub(crate) fn read_polygon_start<R: BufRead>(
    lex: &mut Lexer<R>,
    first_in_frame: bool,
) -> Result<Start, StreamError> {
    // Between two polygons (nearly every time): NEXT.POLYGON, peeked past the last
    // vertex, and a plain `colour R G B` line, taken whole.
    if !first_in_frame {
        if let Some(colour) = lex.line_after(NEXT_POLYGON, colour_line) {
            return Ok(Start::Colour(colour));
        }
    }
    let Some(word) = lex.peek()? else {
        return Err(
            lex.error_at_end("expected a polygon, NEXT.FRAME or END, found the end of the input")
        );
    };
    let mut kind = head_word(word);
    match kind {
        Head::NextFrame => {
            lex.skip_word();
            return Ok(Start::NextFrame);
        }
        Head::End => {
            lex.skip_word();
            return Ok(Start::End);
        }
        Head::NextPolygon if !first_in_frame => {
            lex.skip_word();
            let Some(w) = lex.peek()? else {
                return Err(lex.error_at_end(
                    "expected `colour` after NEXT.POLYGON, found the end of the input",
                ));
            };
            kind = head_word(w);
            if !matches!(kind, Head::Colour | Head::Skip) {
                let msg = format!("expected `colour` after NEXT.POLYGON, found `{}`", Shown(w));
                return Err(lex.error(msg));
            }
        }
        Head::NextPolygon => {
            return Err(
                lex.error("NEXT.POLYGON before the frame's first polygon (expected `colour`)")
            )
        }
        Head::Colour | Head::Skip if first_in_frame => {}
        Head::Colour | Head::Skip => {
            let msg = format!(
                "expected NEXT.POLYGON between polygons, found `{}`",
                Shown(word)
            );
            return Err(lex.error(msg));
        }
        Head::Other if first_in_frame => {
            let msg = format!(
                "expected `colour`, NEXT.FRAME or END, found `{}`",
                Shown(word)
            );
            return Err(lex.error(msg));
        }
        Head::Other => {
            let msg = format!(
                "expected a vertex, NEXT.POLYGON, NEXT.FRAME or END, found `{}`",
                Shown(word)
            );
            return Err(lex.error(msg));
        }
    }
    lex.skip_word();
    if let Head::Skip = kind {
        let n = lex.integer("the number of polygons skipped", u32::MAX as u64)? as u32;
        if n == 0 {
            return Err(lex.error("`skip 0`: a skip stands for at least one polygon"));
        }
        return Ok(Start::Skip(n));
    }
    let mut colour = [0u8; 3];
    for (c, name) in colour.iter_mut().zip(["red", "green", "blue"]) {
        *c = lex.integer(format_args!("the {name} component of the colour"), 255)? as u8;
    }
    Ok(Start::Colour(colour))
}

/// A line that is exactly `colour R G B` (single spaces or tabs between, blanks after;
/// each channel one to three digits, at most 255): the colour, and where B starts.
/// Anything else is `None`, read again word by word.
fn colour_line(line: &[u8]) -> Option<(Colour, usize)> {
    if !line.starts_with(COLOUR.as_bytes()) {
        return None;
    }
    let mut i = COLOUR.len();
    let mut colour = [0u8; 3];
    let mut at = 0;
    for c in &mut colour {
        let blanks = i;
        while i < line.len() && is_blank(line[i]) {
            i += 1;
        }
        if i == blanks {
            return None;
        }
        at = i;
        let mut value = 0u32;
        while i < line.len() && line[i].is_ascii_digit() && i - at < 3 {
            value = value * 10 + u32::from(line[i] - b'0');
            i += 1;
        }
        if i == at || line.get(i).is_some_and(u8::is_ascii_digit) {
            return None; // no digit, or more than three
        }
        *c = u8::try_from(value).ok()?;
    }
    line[i..]
        .iter()
        .all(|&b| is_blank(b))
        .then_some((colour, at))
}

/// Writes `skip N`, after NEXT.POLYGON unless it starts the frame.
pub(crate) fn write_skip<W: Write>(out: &mut W, n: u32, first_in_frame: bool) -> io::Result<()> {
    if !first_in_frame {
        writeln!(out, "{NEXT_POLYGON}")?;
    }
    writeln!(out, "{SKIP} {n}")
}

/// Writes `colour R G B`, after NEXT.POLYGON unless it starts the frame.
pub(crate) fn write_polygon_start<W: Write>(
    out: &mut W,
    colour: Colour,
    first_in_frame: bool,
) -> io::Result<()> {
    if !first_in_frame {
        writeln!(out, "{NEXT_POLYGON}")?;
    }
    writeln!(out, "{COLOUR} {} {} {}", colour[0], colour[1], colour[2])
}

/// The names of a vertex's numbers in a space, for messages.
fn coordinate_name(space: &Space, k: usize) -> &'static str {
    match (space, k) {
        (Space::Eye(_), 3) => "w",
        (Space::Screen { .. }, 2) => "depth",
        (_, k) => ["x", "y", "z", "w"][k],
    }
}

/// The annotations are defined for eye and screen space (the splitter makes them, persp
/// takes them to the screen); in a world-space stream viewxf would pass them on
/// untransformed, and the picture would be wrong.
fn annotations_allowed(space: &Space) -> bool {
    matches!(space, Space::Eye(_) | Space::Screen { .. })
}

const NO_WORLD_ANNOTATIONS: &str =
    "annotations (`plane`, `shade`, `on`) are defined for eye and screen space only";

/// Refuses `what` (an annotation, as the message names it) where the stream's space has
/// no annotations ([`annotations_allowed`]), at the lexer's place.
fn allow_annotation<R: BufRead>(
    lex: &Lexer<R>,
    space: &Space,
    what: &str,
) -> Result<(), StreamError> {
    if annotations_allowed(space) {
        return Ok(());
    }
    Err(lex.error(format!(
        "{what} in a {}-space stream: {NO_WORLD_ANNOTATIONS}",
        space.name()
    )))
}

/// Reads a polygon's text after its `colour R G B` into `p`, reusing its buffers: the
/// opacity `A` where the header declares `opacity`, and each vertex's colour `r g b` after
/// its coordinates where it declares `vertex-colours`.
#[inline]
fn read_polygon_text<R: BufRead>(
    p: &mut Polygon,
    colour: Colour,
    lex: &mut Lexer<R>,
    header: &Header,
) -> Result<(), StreamError> {
    let space = &header.space;
    p.colour = colour;
    p.plane = None;
    p.shade = None;
    p.opacity = OPAQUE;
    p.vertices.clear();
    p.supports.clear();
    p.vertex_attrs.clear();
    let arity = space.vertex_arity();
    if arity == 0 {
        // A fragments stream has no vertices: a polygon's vertices there would have no
        // numbers, and reading them would take nothing from the input (found by the
        // decode_text fuzz target). Stages check the space first; this keeps the
        // reader itself from looping.
        return Err(lex.error(format!(
            "a polygon in a {}-space stream, which holds no vertices",
            space.name()
        )));
    }
    if header.attributes.opacity {
        p.opacity = lex.integer(
            "the opacity of the colour (colour R G B A: the header says `opacity`)",
            255,
        )? as u8;
    }
    let coloured = header.attributes.shaded();
    // Vertex lines right after the colour line, taken straight from the input: then there
    // is no `plane` or `shade` line (they come before the vertices), and the look for
    // them, a peek, would have copied the first vertex line and read it word by word.
    let mut first_taken = if coloured {
        0
    } else {
        take_vertex_lines(p, lex, arity)
    };
    if first_taken == 0 && lex.peek()? == Some(PLANE) {
        allow_annotation(lex, space, "a `plane` line")?;
        lex.skip_word();
        let mut n = [0.0; 4];
        for (c, name) in n.iter_mut().zip(["a", "b", "c", "d"]) {
            *c = lex.number(format_args!(
                "{name} of the polygon's plane (plane a b c d)"
            ))?;
        }
        p.plane = Some(DVec4::from_array(n));
    }
    if first_taken == 0 && lex.peek()? == Some(SHADE) {
        allow_annotation(lex, space, "a `shade` line")?;
        lex.skip_word();
        let mut planes = [DVec4::ZERO; 3];
        for (plane, channel) in planes.iter_mut().zip(["red", "green", "blue"]) {
            let mut n = [0.0; 4];
            for (c, name) in n.iter_mut().zip(["a", "b", "c", "d"]) {
                *c = lex.number(format_args!(
                    "{name} of the {channel} colour plane (shade, four numbers a channel)"
                ))?;
            }
            *plane = DVec4::from_array(n);
        }
        p.shade = Some(Box::new(planes));
    }
    loop {
        // Lines of just a vertex's coordinates (nearly every line of a scene), taken
        // straight from the input; any other line, and a vertex past the most a polygon
        // may have, is read below, word by word, with its messages.
        let taken = if coloured {
            0
        } else if first_taken > 0 {
            std::mem::take(&mut first_taken)
        } else {
            take_vertex_lines(p, lex, arity)
        };
        if taken == 0 {
            if !lex.next_is_number()? {
                break;
            }
            read_vertex_words(p, lex, header)?;
        } else if lex.next_line_is(NEXT_POLYGON) {
            // The polygon ends, and the next starts: no `on` line to look for, and the
            // NEXT.POLYGON line is taken with the next `colour` line (`Lexer::line_after`).
            break;
        }
        if lex.peek()? == Some(ON) {
            read_support(p, lex, space)?;
        }
    }
    if !p.supports.is_empty() {
        p.supports.resize(p.vertices.len(), None);
    }
    Ok(())
}

/// Takes the lines of just a vertex's `arity` coordinates that come next, straight from
/// the input ([`Lexer::number_lines`]), as vertices of `p`, up to the most a polygon may
/// have; the lines taken.
#[inline]
fn take_vertex_lines<R: BufRead>(p: &mut Polygon, lex: &mut Lexer<R>, arity: usize) -> usize {
    lex.number_lines(arity, |c| {
        let room = p.vertices.len() < MAX_VERTICES;
        if room {
            let w = if arity == 4 { c[3] } else { 1.0 };
            p.vertices.push(DVec4::new(c[0], c[1], c[2], w));
        }
        room
    })
}

/// Reads one vertex line word by word (the first word peeked, and a number), and pushes
/// the vertex and its colour or normal.
fn read_vertex_words<R: BufRead>(
    p: &mut Polygon,
    lex: &mut Lexer<R>,
    header: &Header,
) -> Result<(), StreamError> {
    let space = &header.space;
    let arity = space.vertex_arity();
    let space_name = space.name();
    let coloured = header.attributes.shaded();
    let normals = header.attributes.vertex_normals;
    let values = if normals { &NORMALS } else { &COLOURS };
    // The numbers of a vertex line: its coordinates, then its colour or normal if
    // declared.
    let numbers = arity + if coloured { 3 } else { 0 };
    if p.vertices.len() == MAX_VERTICES {
        lex.peek()?;
        return Err(lex.error(format!("polygon has more than {MAX_VERTICES} vertices")));
    }
    let mut v = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0];
    let i = p.vertices.len();
    // A line of just the vertex's numbers is read whole; anything else, word by word,
    // with its messages.
    let whole_line = lex.numbers_to_line_end(&mut v[..numbers]);
    if !whole_line {
        for (k, c) in v.iter_mut().take(arity).enumerate() {
            *c = lex.number(format_args!(
                "{} of vertex {i} ({numbers} numbers a vertex in {space_name} space{})",
                coordinate_name(space, k),
                if coloured { values.with } else { "" }
            ))?;
        }
        for (k, name) in values
            .names
            .into_iter()
            .enumerate()
            .take(if coloured { 3 } else { 0 })
        {
            v[arity + k] = lex.number(format_args!(
                "the {name} of vertex {i}'s {} (the header says `{}`: {} after the \
                 coordinates)",
                values.what, values.word, values.order
            ))?;
        }
    }
    if coloured {
        let c = DVec3::new(v[arity], v[arity + 1], v[arity + 2]);
        if !normals && !is_colour(c) {
            return Err(lex.error(format!(
                "vertex {i}'s colour {} {} {}: a vertex colour's channels are numbers from \
                 0 to 255",
                c.x, c.y, c.z
            )));
        }
        p.vertex_attrs.push(c);
        v[arity..].fill(0.0);
        if arity == 3 {
            v[3] = 1.0;
        }
    }
    p.vertices.push(DVec4::new(v[0], v[1], v[2], v[3]));
    Ok(())
}

/// Reads the edge support (`on A B`, peeked) of the polygon's last vertex.
fn read_support<R: BufRead>(
    p: &mut Polygon,
    lex: &mut Lexer<R>,
    space: &Space,
) -> Result<(), StreamError> {
    let arity = space.vertex_arity();
    allow_annotation(lex, space, "an edge support (`on`)")?;
    lex.skip_word();
    let i = p.vertices.len() - 1;
    let mut ends = [DVec4::new(0.0, 0.0, 0.0, 1.0); 2];
    for (end, name) in ends.iter_mut().zip(["A", "B"]) {
        let mut c = [0.0, 0.0, 0.0, 1.0];
        for (k, slot) in c.iter_mut().take(arity).enumerate() {
            *slot = lex.number(format_args!(
                "coordinate {k} of support end {name} of edge {i} ({arity} numbers a point)"
            ))?;
        }
        *end = DVec4::from_array(c);
    }
    p.supports.resize(i, None);
    p.supports.push(Some(ends));
    Ok(())
}

/// Writes a polygon's text form (colour, plane, vertices and supports), with the opacity
/// and the vertex colours where the header declares them.
pub(crate) fn write_polygon_text<W: Write>(
    p: &Polygon,
    out: &mut W,
    header: &Header,
    first_in_frame: bool,
) -> io::Result<()> {
    let space = &header.space;
    if header.attributes.opacity {
        if !first_in_frame {
            writeln!(out, "{NEXT_POLYGON}")?;
        }
        let [r, g, b] = p.colour;
        writeln!(out, "{COLOUR} {r} {g} {b} {}", p.opacity)?;
    } else {
        write_polygon_start(out, p.colour, first_in_frame)?;
    }
    if let Some(n) = p.plane {
        writeln!(out, "{PLANE} {} {} {} {}", n.x, n.y, n.z, n.w)?;
    }
    if let Some(&[r, g, b]) = p.shade.as_deref() {
        writeln!(
            out,
            "{SHADE} {} {} {} {}  {} {} {} {}  {} {} {} {}",
            r.x, r.y, r.z, r.w, g.x, g.y, g.z, g.w, b.x, b.y, b.z, b.w
        )?;
    }
    let point = |out: &mut W, v: &Vertex| match space.vertex_arity() {
        4 => write!(out, "{} {} {} {}", v.x, v.y, v.z, v.w),
        _ => write!(out, "{} {} {}", v.x, v.y, v.z),
    };
    let coloured = header.attributes.shaded();
    for (i, v) in p.vertices.iter().enumerate() {
        point(out, v)?;
        if coloured {
            // A polygon of a declared stream has one colour a vertex (the writer's
            // caller validated it); a missing one is written black rather than dropped.
            let c = p.vertex_attrs.get(i).copied().unwrap_or_default();
            write!(out, " {} {} {}", c.x, c.y, c.z)?;
        }
        if let Some([a, b]) = p.support(i) {
            write!(out, " {ON} ")?;
            point(out, &a)?;
            write!(out, " ")?;
            point(out, &b)?;
        }
        writeln!(out)?;
    }
    Ok(())
}

/// Whether every channel of a vertex colour is a number from 0 to 255.
fn is_colour(c: DVec3) -> bool {
    c.cmpge(DVec3::ZERO).all() && c.cmple(DVec3::splat(255.0)).all()
}

/// What a vertex's three numbers after its coordinates are, for the text reader's
/// messages: colours (`vertex-colours`) or normals (`vertex-normals`).
struct VertexValues {
    what: &'static str,
    word: &'static str,
    names: [&'static str; 3],
    order: &'static str,
    /// After "N numbers a vertex in SPACE space".
    with: &'static str,
}

const COLOURS: VertexValues = VertexValues {
    what: "colour",
    word: "vertex-colours",
    names: ["red", "green", "blue"],
    order: "r g b",
    with: " with vertex colours",
};

const NORMALS: VertexValues = VertexValues {
    what: "normal",
    word: "vertex-normals",
    names: ["x", "y", "z"],
    order: "nx ny nz",
    with: " with vertex normals",
};

/// Checks a polygon's vertex colours: one a vertex, each channel a number from 0 to 255;
/// or its normals (`normals`): one a vertex, finite.
fn check_vertex_attrs(p: &Polygon, normals: bool) -> Result<(), String> {
    let what = if normals { "normals" } else { "colours" };
    if p.vertex_attrs.len() != p.vertices.len() {
        return Err(format!(
            "{} vertex {what} for {} vertices (one per vertex)",
            p.vertex_attrs.len(),
            p.vertices.len()
        ));
    }
    if normals {
        return match p.vertex_attrs.iter().position(|n| !n.is_finite()) {
            Some(i) => Err(format!(
                "the normal of vertex {i} is {:?}; a normal's numbers must be finite",
                p.vertex_attrs[i].to_array()
            )),
            None => Ok(()),
        };
    }
    match p.vertex_attrs.iter().position(|&c| !is_colour(c)) {
        Some(i) => Err(format!(
            "the colour of vertex {i} is {:?}; a vertex colour's channels are numbers from 0 \
             to 255",
            p.vertex_attrs[i].to_array()
        )),
        None => Ok(()),
    }
}

impl Record for Token {
    #[inline]
    fn control(&self) -> Control {
        match self {
            Token::Polygon(_) => Control::Polygon,
            Token::Skip(n) => Control::Skip(*n),
            Token::NextFrame => Control::NextFrame,
            Token::End => Control::End,
        }
    }

    fn binary_control(head: &[u8; 8]) -> Option<Control> {
        match head[0] {
            tag::POLYGON | tag::ANNOTATED => Some(Control::Polygon),
            tag::NEXT_FRAME => Some(Control::NextFrame),
            tag::END => Some(Control::End),
            tag::SKIP => Some(Control::Skip(head_n(head))),
            _ => None,
        }
    }

    #[inline]
    fn validate(&self, header: &Header) -> Result<(), String> {
        let space = &header.space;
        if let Token::Skip(0) = self {
            return Err("`skip 0`: a skip stands for at least one polygon".into());
        }
        if let Token::Polygon(p) = self {
            if p.vertices.len() > MAX_VERTICES {
                return Err(format!(
                    "polygon of {} vertices (at most {MAX_VERTICES})",
                    p.vertices.len()
                ));
            }
            if let Some(i) = p.vertices.iter().position(|v| !v.is_finite()) {
                return Err(format!(
                    "vertex {i} is {:?}; coordinates must be finite",
                    p.vertices[i].to_array()
                ));
            }
            let shaded = header.attributes.shaded();
            if !p.vertex_attrs.is_empty() || (shaded && !p.vertices.is_empty()) {
                if !shaded {
                    return Err(
                        "a polygon with vertex colours or normals in a stream whose header \
                         declares neither (`vertex-colours`, `vertex-normals`)"
                            .into(),
                    );
                }
                check_vertex_attrs(p, header.attributes.vertex_normals)?;
            }
            if p.opacity != OPAQUE && !header.attributes.opacity {
                return Err(format!(
                    "a polygon of opacity {} in a stream whose header does not declare \
                     `opacity`",
                    p.opacity
                ));
            }
            if p.supports.is_empty() && p.plane.is_none() && p.shade.is_none() {
                return Ok(());
            }
            if !annotations_allowed(space) && p.is_annotated() {
                return Err(format!(
                    "an annotated polygon in a {}-space stream: {NO_WORLD_ANNOTATIONS}",
                    space.name()
                ));
            }
            if !p.supports.is_empty() && p.supports.len() != p.vertices.len() {
                return Err(format!(
                    "{} edge supports for {} vertices (one per edge, or none)",
                    p.supports.len(),
                    p.vertices.len()
                ));
            }
            if let Some(i) = p
                .supports
                .iter()
                .position(|s| s.is_some_and(|[a, b]| !a.is_finite() || !b.is_finite()))
            {
                return Err(format!(
                    "the support of edge {i} is not finite; coordinates must be finite"
                ));
            }
            if p.plane.is_some_and(|n| !n.is_finite()) {
                return Err("the polygon's plane is not finite".into());
            }
            if p.shade
                .as_ref()
                .is_some_and(|s| s.iter().any(|n| !n.is_finite()))
            {
                return Err("the polygon's colour planes (`shade`) are not finite".into());
            }
        }
        Ok(())
    }

    #[inline]
    fn read_binary<R: Read>(
        &mut self,
        spare: &mut Self,
        head: &[u8; 8],
        input: &mut BinaryInput<R>,
    ) -> Result<(), BinaryError> {
        match head[0] {
            tag::POLYGON | tag::ANNOTATED => {
                read_polygon_binary(self.polygon_mut(spare), head, input)
            }
            tag::NEXT_FRAME => {
                expect_zero(head, true, "NEXT.FRAME")?;
                self.set(spare, Token::NextFrame);
                Ok(())
            }
            tag::END => {
                expect_zero(head, true, "END")?;
                self.set(spare, Token::End);
                Ok(())
            }
            tag::SKIP => {
                expect_zero(head, false, "skip")?;
                self.set(spare, Token::Skip(head_n(head)));
                Ok(())
            }
            other => Err(BinaryError::Invalid(format!(
                "not a valid record (unknown polygon-stream tag {other}); is the stream corrupt?"
            ))),
        }
    }

    #[inline]
    fn write_binary<W: Write>(&self, out: &mut W) -> io::Result<()> {
        match self {
            Token::Polygon(p) => write_polygon_binary(p, out),
            Token::NextFrame => out.write_all(&head(tag::NEXT_FRAME, [0; 3], 0)),
            Token::End => out.write_all(&head(tag::END, [0; 3], 0)),
            Token::Skip(n) => out.write_all(&head(tag::SKIP, [0; 3], *n)),
        }
    }

    #[inline]
    fn read_text<R: BufRead>(
        &mut self,
        spare: &mut Self,
        lex: &mut Lexer<R>,
        header: &Header,
        first_in_frame: bool,
    ) -> Result<(), StreamError> {
        match read_polygon_start(lex, first_in_frame)? {
            Start::Colour(c) => read_polygon_text(self.polygon_mut(spare), c, lex, header)?,
            Start::Skip(n) => self.set(spare, Token::Skip(n)),
            Start::NextFrame => self.set(spare, Token::NextFrame),
            Start::End => self.set(spare, Token::End),
        }
        Ok(())
    }

    fn write_text<W: Write>(
        &self,
        out: &mut W,
        header: &Header,
        first_in_frame: bool,
    ) -> io::Result<()> {
        match self {
            Token::Polygon(p) => write_polygon_text(p, out, header, first_in_frame),
            Token::Skip(n) => write_skip(out, *n, first_in_frame),
            Token::NextFrame => writeln!(out, "{NEXT_FRAME}"),
            Token::End => writeln!(out, "{END}"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::colour_line;

    #[test]
    fn a_colour_line_is_taken_whole_only_when_plain() {
        // The colour, and where its last channel starts (for a message's column).
        for (line, want) in [
            ("colour 1 2 3", Some(([1, 2, 3], 11))),
            ("colour 255 0 9  ", Some(([255, 0, 9], 13))),
            ("colour\t1\t2\t3\t", Some(([1, 2, 3], 11))),
            ("colour  12  34  056", Some(([12, 34, 56], 16))),
        ] {
            assert_eq!(colour_line(line.as_bytes()), want, "{line:?}");
        }
        // Everything else goes word by word, with its messages (or, for `color` and a
        // channel of four digits that reads as at most 255, its value).
        for line in [
            "colour 256 0 0",
            "colour 0001 2 3",
            "colour 1 2",
            "colour 1 2 3 4",
            "colour1 2 3",
            "colour 1 2 3#",
            "colour 1 2 3 # c",
            "color 1 2 3",
            "colour 1a 2 3",
            "colour -1 2 3",
            "colour 1 2 3\r",
            " colour 1 2 3",
            "colour",
            "",
        ] {
            assert_eq!(colour_line(line.as_bytes()), None, "{line:?}");
        }
    }
}
