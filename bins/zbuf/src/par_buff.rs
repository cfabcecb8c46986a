//! PAR.BUFF (thesis 6.3.3): one frame buffer fed by many scan converters at once.
//!
//! The occam process ALTs over its input channels, taking whichever scan converter is
//! ready, and shows the frame once all of them have sent NEXT.FRAME.PIXEL. Here each input
//! (a file, a named pipe, stdin) has a reader thread that decodes its stream and sends
//! batches of fragments over one bounded channel to the buffer thread: the channel is the
//! ALT, the batches keep the cost of a send off each pixel.
//!
//! A reader that reaches NEXT.FRAME sends what it has, says so, and waits for the buffer
//! thread's go-ahead before it reads on. The buffer thread keeps draining the channel
//! meanwhile, so an input whose scan converter is still busy with this frame is never
//! blocked by one that has finished it: however unevenly the polygons fall between the
//! inputs, nothing deadlocks, and memory stays one frame buffer and a few batches.

use crate::FrameBuffer;
use proto::shade::{Lighting, Shading};
use proto::{Attributes, Colour, DVec4, DepthForm, Fragment, Reader, SpaceKind, Token};
use scan::frame::HiddenSurface;
use scan::precision::QuantumWatch;
use scan::{check_on_screen, RegionBuffer, SpanWalker};
use stagecli::memory::Spare;
use stagecli::{Context, Counted, Error, Result};
use std::io::Read;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::mpsc::{channel, sync_channel, Receiver, Sender, SyncSender};
use std::sync::Arc;

/// Fragments per batch sent from a reader thread to the buffer thread.
pub const BATCH: usize = 4096;

/// Opens an input when its reader thread starts (so a named pipe's open, which blocks
/// until the writer opens it, holds up only that input).
pub type Opener = Box<dyn FnOnce() -> Result<Box<dyn Read + Send>> + Send>;

/// One input: its name for messages, and how to open it.
pub struct Input {
    pub name: String,
    pub open: Opener,
    /// With `zbuf --project`: an eye-space input is projected to this screen, as persp
    /// would, and resolved here ([`ToScreen`]).
    pub to_screen: Option<ToScreen>,
}

/// persp's work done in zbuf's reader (`zbuf --project --zmode MODE --size WxH`): an
/// eye-space input (the clipper's output) is projected polygon by polygon with the same
/// code and to the same numbers as persp ([`proto::perspective::Perspective`]), and then resolved as a
/// screen-space input is. render.sh's depth 0 runs `clipbatch | zbuf --project …` so: a
/// process and a pipe's copy of the stream fewer (docs/performance.md, "Start-up").
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ToScreen {
    pub width: u32,
    pub height: u32,
    pub depth: proto::perspective::DepthMode,
}

/// A polygon stream zbuf resolves itself: its screen, its attributes (a projected stream's
/// as persp would write them), and the projection, for an eye-space one.
struct Resolvable {
    width: u32,
    height: u32,
    attributes: Attributes,
    perspective: Option<proto::perspective::Perspective>,
}

impl Resolvable {
    /// A screen-space stream as it is, or an eye-space one projected to `to_screen`.
    fn of<R: Read>(reader: &Reader<Token, R>, to_screen: Option<ToScreen>) -> Result<Resolvable> {
        let header = reader.header();
        match (header.space, to_screen) {
            (proto::Space::Eye(view), Some(t)) => {
                // A view volume persp cannot map (from the stream's header) is bad input.
                let perspective =
                    proto::perspective::Perspective::new(t.width, t.height, view, t.depth)
                        .map_err(Error::data)?;
                Ok(Resolvable {
                    width: t.width,
                    height: t.height,
                    attributes: perspective.screen_header(header).attributes,
                    perspective: Some(perspective),
                })
            }
            _ => {
                let (width, height) = screen_of(reader, "screen-space")?;
                Ok(Resolvable {
                    width,
                    height,
                    attributes: header.attributes,
                    perspective: None,
                })
            }
        }
    }

    /// The polygon to the screen, as persp refuses or projects it (a no-op for a
    /// screen-space stream).
    fn project<R: Read>(&self, poly: &mut proto::Polygon, reader: &Reader<Token, R>) -> Result<()> {
        let Some(perspective) = &self.perspective else {
            return Ok(());
        };
        stagecli::stream::project_to_screen(perspective, poly)
            .map_err(|m| Error::data(format!("{}: {m}", reader.position())))
    }
}

/// What an input delivered, for `--stats`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct InputStats {
    pub spans: u64,
    /// Runs of finished pixels (from a leaf that resolved its own region).
    pub runs: u64,
    pub pixels: u64,
    /// Bytes read from the input: the load on its link (thesis 6.5).
    pub bytes: u64,
    /// For a screen-space input, resolved in zbuf: what its z-buffer did (all frames).
    pub resolved: Option<Resolved>,
}

/// The counts of a screen-space input that zbuf resolved itself.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Resolved {
    /// Polygons read.
    pub polygons: u64,
    /// Pixels depth-tested, and of those written (the nearer so far).
    pub pixels_tested: u64,
    pub pixels_written: u64,
    /// Depth tests that rounding in a coarse depth form, not the tie rule, decided
    /// ([`scan::precision`]).
    pub rounding_decided: u64,
    /// Frames resolved (counted where a method other than the z-buffer resolved them,
    /// [`one_input`]'s `method`).
    pub frames: u64,
}

/// From a reader thread to the buffer thread.
enum Message {
    /// The input's screen size, sent before anything else.
    Header {
        input: usize,
        width: u32,
        height: u32,
        depth: Option<DepthForm>,
        /// The lighting of a Phong-shaded input (its header says `vertex-normals`).
        lighting: Option<Arc<Lighting>>,
    },
    /// Fragments in stream order (polygon records, spans, pixels; no control records).
    Batch {
        input: usize,
        fragments: Vec<Fragment>,
    },
    /// The input reached NEXT.FRAME (`end == false`, and now waits) or END; a
    /// screen-space input resolved here says what it has done so far, and at END hands
    /// over its last frame's region, to be placed once every input has finished it.
    Boundary {
        input: usize,
        end: bool,
        resolved: Option<Resolved>,
        region: Option<Box<RegionBuffer>>,
    },
    /// The input failed; the error says where.
    Failed { input: usize, error: Error },
}

/// Where an input is in the current frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum At {
    Reading,
    NextFrame,
    End,
}

/// The buffer thread's view of one input.
struct InputState {
    name: String,
    go_ahead: Sender<()>,
    at: At,
    /// Polygon records seen in this frame: the current polygon is `polygons − 1`.
    polygons: u32,
    colour: Colour,
    /// The current polygon's colour planes, when its `shade` records have come (a
    /// Gouraud-shaded polygon, docs/DESIGN.md, "Shading").
    shading: Option<Shading>,
    /// The input's lighting, when it is Phong-shaded: its `shade` records are then a
    /// normal's planes, lit per pixel.
    lighting: Option<Arc<Lighting>>,
    stats: InputStats,
    /// Bytes its reader thread has read.
    bytes: Arc<AtomicU64>,
    /// A screen-space input resolved here: its last frame's region, until the frame is
    /// complete.
    region: Option<Box<RegionBuffer>>,
}

/// Runs PAR.BUFF over `inputs`: `on_frame(k, buffer)` is called as soon as frame k is
/// complete on every input. Returns each input's counts once every input has reached END.
/// An error names the input it came from; frames completed before it have been handed to
/// `on_frame`. `list_runs`: the frames are passed on as their runs (`zbuf --runs`,
/// [`FrameBuffer::runs`]), so the region of an input resolved here is placed run by run.
pub fn par_buff(
    inputs: Vec<Input>,
    background: Colour,
    list_runs: bool,
    mut on_frame: impl FnMut(u64, &FrameBuffer) -> Result<()>,
) -> Result<Vec<InputStats>> {
    if inputs.is_empty() {
        return Err(Error::usage("no inputs"));
    }
    let n = inputs.len();
    let (to_buffer, from_readers) = sync_channel::<Message>(2 * n + 2);
    // The batches go back to the readers once applied (`Spare`).
    let spare = Arc::new(Spare::<Fragment>::default());
    let mut states = Vec::with_capacity(n);
    for (id, input) in inputs.into_iter().enumerate() {
        let (go_ahead, wait) = channel();
        let tx = to_buffer.clone();
        let bytes = Arc::new(AtomicU64::new(0));
        let counter = Arc::clone(&bytes);
        let spare = Arc::clone(&spare);
        std::thread::Builder::new()
            .name(format!("zbuf-in-{id}"))
            .spawn(move || {
                let to = ToBuffer { tx, spare };
                read_input(id, input.open, input.to_screen, counter, to, wait)
            })
            .map_err(|e| Error::io(format!("cannot start a reader thread: {e}")))?;
        states.push(InputState {
            name: input.name,
            go_ahead,
            at: At::Reading,
            polygons: 0,
            colour: [0; 3],
            shading: None,
            lighting: None,
            stats: InputStats::default(),
            bytes,
            region: None,
        });
    }
    drop(to_buffer);

    let mut fb: Option<FrameBuffer> = None;
    let mut first_header: Option<usize> = None;
    // Fragments whose depths rounding, not the tie rule, ordered (the first header's depth
    // form decides; arrival order stands in for stream order, which it is for one input).
    let mut watch: Option<QuantumWatch> = None;
    let mut frame = 0u64;
    let mut at_boundary = 0usize;
    loop {
        let message = from_readers
            .recv()
            .map_err(|_| Error::data("every input stopped before END"))?;
        match message {
            Message::Header {
                input,
                width,
                height,
                depth,
                lighting,
            } => {
                states[input].lighting = lighting;
                match (&fb, first_header) {
                    (Some(b), Some(first)) if (b.width(), b.height()) != (width, height) => {
                        return Err(Error::data(format!(
                        "{}: header: screen {width}x{height}, but {} is {}x{} (all inputs must have the same screen size)",
                        states[input].name,
                        states[first].name,
                        b.width(),
                        b.height()
                    )));
                    }
                    (Some(_), _) => {}
                    (None, _) => {
                        // The first header decides the screen; one too large for this
                        // machine is refused (status 3; the message says how much it needs).
                        let name = &states[input].name;
                        crate::check_memory(width, height).map_err(|e| e.context(name))?;
                        let mut buffer = FrameBuffer::new(width, height, background)
                            .map_err(|m| Error::io(format!("{name}: {m}")))?;
                        buffer.list_runs(list_runs);
                        fb = Some(buffer);
                        first_header = Some(input);
                        watch = QuantumWatch::for_form(depth, width, height);
                    }
                }
            }
            Message::Batch { input, fragments } => {
                let fb = fb
                    .as_mut()
                    .ok_or_else(|| Error::data("fragments before a header"))?;
                let s = &mut states[input];
                apply(fb, s, &fragments, watch.as_mut())
                    .with_context(|| format!("{}: frame {frame}", s.name))?;
                spare.give(fragments);
            }
            Message::Boundary {
                input,
                end,
                resolved,
                region,
            } => {
                states[input].at = if end { At::End } else { At::NextFrame };
                if resolved.is_some() {
                    states[input].stats.resolved = resolved;
                }
                states[input].region = region;
                at_boundary += 1;
                if at_boundary < n {
                    continue;
                }
                // Every input has finished the frame: show it (the thesis sends the
                // F-buffer to the screen), then let the inputs go on.
                let fb = fb
                    .as_mut()
                    .ok_or_else(|| Error::data("a frame before a header"))?;
                // The regions resolved here, placed as their runs would have been: they
                // are final, whatever else came for their pixels.
                for s in &mut states {
                    if let Some(mut region) = s.region.take() {
                        fb.place(&mut region, list_runs);
                    }
                }
                warn_rounding(&mut watch, frame);
                on_frame(frame, fb)?;
                let ended = states.iter().filter(|s| s.at == At::End).count();
                if ended == n {
                    return Ok(states
                        .iter()
                        .map(|s| InputStats {
                            bytes: s.bytes.load(Ordering::Relaxed),
                            ..s.stats
                        })
                        .collect());
                }
                if ended > 0 {
                    let short = states.iter().find(|s| s.at == At::End).map(|s| &s.name);
                    let long = states
                        .iter()
                        .find(|s| s.at == At::NextFrame)
                        .map(|s| &s.name);
                    return Err(Error::data(format!(
                        "{}: frame {frame}: END here, but {} goes on to frame {} (all inputs must have the same number of frames)",
                        short.map_or("?", |s| s),
                        long.map_or("?", |s| s),
                        frame + 1
                    )));
                }
                fb.clear();
                frame += 1;
                at_boundary = 0;
                for s in &mut states {
                    s.at = At::Reading;
                    s.polygons = 0;
                    // A reader gone (its input failed) reports that through the channel.
                    let _ = s.go_ahead.send(());
                }
            }
            Message::Failed { input, error } => {
                return Err(error.context(states[input].name.clone()));
            }
        }
    }
}

/// BUFFER's inner loop: a batch of one input's fragments into the frame buffer.
fn apply(
    fb: &mut FrameBuffer,
    s: &mut InputState,
    fragments: &[Fragment],
    mut watch: Option<&mut QuantumWatch>,
) -> Result<()> {
    // The current polygon's index in the frame; set by its colour record.
    let mut polygon = s.polygons.wrapping_sub(1);
    for f in fragments {
        match *f {
            Fragment::Polygon(colour) => {
                polygon = s.polygons;
                s.polygons = s
                    .polygons
                    .checked_add(1)
                    .filter(|p| *p != u32::MAX)
                    .ok_or_else(|| Error::data("more than 4294967294 polygons in one frame"))?;
                s.colour = colour;
                s.shading = None;
            }
            Fragment::Span { y, x0, x1, z, dz } => {
                s.stats.spans += 1;
                s.stats.pixels += (x1 - x0) as u64;
                match &s.shading {
                    None => fb.span(y, x0..x1, z, dz, polygon, s.colour),
                    Some(shading) => fb.shaded_span(y, x0..x1, (z, dz), polygon, shading.row(y)),
                }
                if let Some(w) = watch.as_deref_mut() {
                    w.row(y, x0, x1, z, dz);
                }
            }
            Fragment::Pixel { x, y, z } => {
                s.stats.pixels += 1;
                let colour = match &s.shading {
                    None => s.colour,
                    Some(shading) => shading.at(x, y),
                };
                fb.pixel(x, y, z, polygon, colour);
                if let Some(w) = watch.as_deref_mut() {
                    w.pixel(x, y, z);
                }
            }
            Fragment::Shade { channel, plane } => {
                // The channels come red, green, blue; one not sent keeps the colour
                // record's value.
                let mut planes = match &s.shading {
                    Some(shading) => *shading.planes(),
                    None => s.colour.map(|c| DVec4::new(0.0, 0.0, 1.0, -f64::from(c))),
                };
                let [a, b, d] = plane;
                planes[usize::from(channel.min(2))] = DVec4::new(a, b, 1.0, d);
                s.shading = Some(Shading::new(planes).lit(s.lighting.as_ref(), s.colour));
            }
            Fragment::Skip(n) => {
                s.polygons = s
                    .polygons
                    .checked_add(n)
                    .filter(|p| *p != u32::MAX)
                    .ok_or_else(|| Error::data("more than 4294967294 polygons in one frame"))?;
                polygon = s.polygons.wrapping_sub(1);
            }
            Fragment::Run { y, x0, x1, colour } => {
                s.stats.runs += 1;
                s.stats.pixels += (x1 - x0) as u64;
                fb.paint(y, x0..x1, colour);
            }
            Fragment::NextFrame | Fragment::End => {}
        }
    }
    Ok(())
}

/// A reader thread: decodes one input and sends it on in batches, waiting at each
/// NEXT.FRAME for the frame to be shown. Ends quietly if the buffer thread has gone.
fn read_input(
    input: usize,
    open: Opener,
    to_screen: Option<ToScreen>,
    bytes: Arc<AtomicU64>,
    to: ToBuffer,
    wait: Receiver<()>,
) {
    let result = (|| -> Result<()> {
        let counted = Counted {
            inner: open()?,
            bytes,
        };
        let mut reader = Reader::<Fragment, _>::new(counted)?;
        match SpaceKind::of(&reader.header().space) {
            SpaceKind::Fragments => {}
            SpaceKind::Screen => return resolve_input(input, reader.into_kind(), None, &to, &wait),
            SpaceKind::Eye if to_screen.is_some() => {
                return resolve_input(input, reader.into_kind(), to_screen, &to, &wait)
            }
            other => {
                let first = if other == SpaceKind::Eye {
                    "persp"
                } else {
                    "viewxf, the clipper and persp"
                };
                return Err(Error::data(format!(
                    "input is {}-space, expected fragments (scanconv's) or screen-space \
                     polygons (persp's); put {first} first",
                    other.name()
                )));
            }
        }
        let attributes = reader.header().attributes;
        if !send_header(&to.tx, input, screen_of(&reader, "fragment")?, &attributes) {
            return Ok(());
        }
        let send = |m| to.tx.send(m).is_ok();
        let mut batch = Vec::with_capacity(BATCH);
        let mut frame = 0u64;
        let mut in_polygon = false;
        loop {
            // A leaf's runs, as many as are buffered, without a call per record.
            let room = BATCH - batch.len();
            reader.runs_into(&mut batch, room);
            if batch.len() == BATCH {
                if !to.send_batch(input, &mut batch) {
                    return Ok(());
                }
                continue;
            }
            let Some(record) = reader.next_record()? else {
                break;
            };
            match record {
                Fragment::Polygon(_) => {
                    in_polygon = true;
                    batch.push(record);
                }
                Fragment::Skip(_) => {
                    in_polygon = false;
                    batch.push(record);
                }
                Fragment::Run { .. } => batch.push(record),
                Fragment::Span { .. } | Fragment::Pixel { .. } | Fragment::Shade { .. } => {
                    if !in_polygon {
                        return Err(Error::data(format!(
                            "frame {frame}, {}: pixels outside a polygon (before the frame's \
                             first colour record, or after a skip)",
                            reader.position()
                        )));
                    }
                    batch.push(record);
                }
                Fragment::NextFrame | Fragment::End => {
                    let end = record == Fragment::End;
                    if !batch.is_empty() && !to.send_batch(input, &mut batch) {
                        return Ok(());
                    }
                    if !send(Message::Boundary {
                        input,
                        end,
                        resolved: None,
                        region: None,
                    }) || end
                    {
                        return Ok(());
                    }
                    // Hold here until every input has finished the frame and it is out.
                    if wait.recv().is_err() {
                        return Ok(());
                    }
                    frame += 1;
                    in_polygon = false;
                    continue;
                }
            }
            if batch.len() == BATCH && !to.send_batch(input, &mut batch) {
                return Ok(());
            }
        }
        Ok(())
    })();
    if let Err(error) = result {
        let _ = to.tx.send(Message::Failed { input, error });
    }
}

/// The screen size a stream's header gives; `what` names the header in the message.
fn screen_of<T: proto::Record, R: Read>(reader: &Reader<T, R>, what: &str) -> Result<(u32, u32)> {
    reader
        .header()
        .space
        .screen_size()
        .ok_or_else(|| Error::data(format!("{what} header without a screen size")))
}

/// A reader thread's first message: its input's screen size. `false` when the buffer
/// thread has stopped (on another input's error): then there is nothing left to do.
fn send_header(
    tx: &SyncSender<Message>,
    input: usize,
    (width, height): (u32, u32),
    attributes: &Attributes,
) -> bool {
    tx.send(Message::Header {
        input,
        width,
        height,
        depth: attributes.depth,
        lighting: attributes.phong(),
    })
    .is_ok()
}

/// A reader thread's way to the buffer thread: the channel, and the batches the buffer
/// thread has applied and given back.
struct ToBuffer {
    tx: SyncSender<Message>,
    spare: Arc<Spare<Fragment>>,
}

impl ToBuffer {
    /// Sends the fragments gathered so far (`batch`) and starts a new batch in its place,
    /// one given back if there is one; `false` as [`send_header`]. A batch is a few
    /// hundred kilobytes, which the allocator handed back to the kernel and took again as
    /// fresh pages each time: on the fill-heavy scene's runs from two leaves, a third of
    /// the merger's time was its reader threads zeroing pages.
    fn send_batch(&self, input: usize, batch: &mut Vec<Fragment>) -> bool {
        let mut next = self.spare.take();
        next.reserve(BATCH);
        let fragments = std::mem::replace(batch, next);
        self.tx.send(Message::Batch { input, fragments }).is_ok()
    }
}

/// What a screen-space input resolved here needs beside its region buffer (which goes
/// round between threads on its own): the span walker, the depth form's watch and the
/// lighting of a Phong-shaded stream.
struct LeafScan {
    walker: SpanWalker,
    watch: Option<QuantumWatch>,
    lighting: Option<Arc<Lighting>>,
}

impl LeafScan {
    /// For a screen-space input whose header has `attributes`, on a `width`×`height` screen.
    fn new(attributes: &Attributes, width: u32, height: u32) -> Self {
        LeafScan {
            walker: SpanWalker::new(),
            watch: QuantumWatch::for_form(attributes.depth, width, height),
            lighting: attributes.phong(),
        }
    }

    /// A leaf's z-buffer at work: one polygon checked against the screen's guard band, as
    /// scanconv checks it, and its spans depth-tested into `region`.
    fn resolve<R: Read>(
        &mut self,
        region: &mut RegionBuffer,
        polygon: &proto::Polygon,
        reader: &Reader<Token, R>,
    ) -> Result<()> {
        let (width, height) = region.size();
        check_on_screen(polygon, width, height)
            .map_err(|m| Error::data(format!("{}: {m}", reader.position())))?;
        stagecli::refuse_transparent("zbuf", polygon, || reader.position())?;
        region.draw_polygon(
            &mut self.walker,
            polygon,
            self.lighting.as_ref(),
            self.watch.as_mut(),
        );
        Ok(())
    }
}

/// At a frame's end, the warning of [`scan::precision`] on stderr when rounding in the
/// stream's depth form decided some of the frame's depth tests; their count.
fn warn_rounding(watch: &mut Option<QuantumWatch>, frame: u64) -> u64 {
    let Some(watch) = watch else { return 0 };
    let (lost, warning) = watch.finish_frame(frame);
    if let Some(warning) = warning {
        eprintln!("zbuf: {warning}");
    }
    lost
}

/// The reader thread's side of two buffers going round between it and the thread that
/// paints and writes the frames ([`one_input`]'s region buffers, [`by_method`]'s runs):
/// a filled one handed over, an empty one taken back, the spare first.
struct HandOver<T> {
    spare: Option<T>,
    to_paint: SyncSender<T>,
    reusable: Receiver<T>,
}

impl<T> HandOver<T> {
    /// `filled` to the painter, an empty buffer in its place; false when the painter has
    /// stopped (it says why).
    fn hand_over(&mut self, filled: &mut T) -> bool {
        let next = match self.spare.take() {
            Some(r) => r,
            None => match self.reusable.recv() {
                Ok(r) => r,
                Err(_) => return false,
            },
        };
        self.to_paint.send(std::mem::replace(filled, next)).is_ok()
    }
}

/// The two threads of a polygon input resolved here ([`one_input`], [`by_method`]): `read`
/// runs on a reader thread, filling a frame's buffer and handing it over ([`HandOver`],
/// `spare` the second buffer), while this thread gives each filled one to `paint` with
/// its frame's number, to paint into the frame buffer and write, and sends it back: frame
/// k is written while frame k + 1 is read. A read error comes first, named `name`: the
/// painter stops for it too, with nothing of its own. Only the reader's errors are the
/// input's; the painter's are on_frame's, writing the output (`stdout: …`, `cannot
/// write a.png: …`), which on_frame labels itself.
fn read_and_paint<T: Send, C: Send>(
    name: &str,
    spare: T,
    read: impl FnOnce(&mut HandOver<T>) -> Result<C> + Send,
    mut paint: impl FnMut(u64, &mut T) -> Result<()>,
) -> Result<C> {
    let (to_paint, painting) = sync_channel::<T>(1);
    let (to_reuse, reusable) = sync_channel::<T>(2);
    std::thread::scope(|scope| {
        let reader_thread = scope.spawn(move || {
            let mut hand = HandOver {
                spare: Some(spare),
                to_paint,
                reusable,
            };
            read(&mut hand)
        });
        let painted = (|| -> Result<()> {
            for (frame, mut filled) in (0u64..).zip(painting.iter()) {
                paint(frame, &mut filled)?;
                let _ = to_reuse.send(filled);
            }
            Ok(())
        })();
        drop(painting);
        drop(to_reuse);
        let read = reader_thread
            .join()
            .unwrap_or_else(|_| Err(Error::data("the reader thread panicked")));
        let counts = read.map_err(|e| e.context(name))?;
        painted?;
        Ok(counts)
    })
}

/// [`par_buff`] for one input. When the input is a screen-space polygon stream (the
/// whole screen's one leaf, as render.sh runs `zbuf --project` at depth 0; an eye-space
/// one with [`Input::to_screen`], projected first) its polygons are
/// resolved in this thread and each frame painted straight into the frame buffer
/// ([`RegionBuffer::finish_into`]): no runs, no reader thread, no batches. Any other
/// input goes to [`par_buff`]. The header is recognised from the input's first bytes,
/// which are then read again as the start of the stream.
///
/// With `method` (`zbuf --aa MODE`, render's `--aa` at depth 0),
/// that method resolves each frame of a polygon input instead of the z-buffer
/// ([`by_method`]); a fragment input is then refused.
pub fn one_input(
    input: Input,
    background: Colour,
    method: Option<Leaf<'_>>,
    mut on_frame: impl FnMut(u64, &FrameBuffer) -> Result<()>,
) -> Result<Vec<InputStats>> {
    let name = input.name.clone();
    let bytes = Arc::new(AtomicU64::new(0));
    let mut inner = Counted {
        inner: (input.open)().map_err(|e| e.context(name.clone()))?,
        bytes: Arc::clone(&bytes),
    };
    // The first bytes, read until they hold a whole header (a pipe may deliver it in
    // pieces), or 64 KiB, or the end; then handed on ahead of the rest.
    let mut head = Vec::new();
    let to_screen = input.to_screen;
    // Whether the header says a polygon stream to resolve here; None where no header was
    // read (par_buff says what is wrong with it).
    let screen = loop {
        if let Ok(r) = Reader::<Token, _>::new(&head[..]) {
            break Some(match SpaceKind::of(&r.header().space) {
                SpaceKind::Screen => true,
                SpaceKind::Eye => to_screen.is_some(),
                _ => false,
            });
        }
        if head.len() >= 1 << 16 {
            break None;
        }
        let mut chunk = [0u8; 4096];
        match inner.read(&mut chunk) {
            Ok(0) => break None,
            Ok(n) => head.extend_from_slice(&chunk[..n]),
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
            Err(e) => return Err(Error::io(stagecli::error::io_message(&e)).context(name)),
        }
    };
    let buffered = std::io::Cursor::new(head).chain(inner);
    if screen == Some(false) && method.is_some() {
        return Err(Error::usage(format!(
            "{name}: --aa resolves a polygon stream here (screen space, or eye space with \
             --project), and this is a stream of fragments"
        )));
    }
    if screen != Some(true) {
        let rest = Input {
            name: input.name,
            open: Box::new(move || Ok(Box::new(buffered) as Box<dyn Read + Send>)),
            to_screen,
        };
        return par_buff(vec![rest], background, false, on_frame);
    }
    let mut reader =
        Reader::<Token, _>::new(buffered).map_err(|e| Error::from(e).context(&name))?;
    let stream = Resolvable::of(&reader, to_screen).map_err(|e| e.context(&name))?;
    let (width, height, attributes) = (stream.width, stream.height, stream.attributes);
    // The frame buffer is made as the header is read, as par_buff makes it at the first
    // header: a screen too large to hold is refused at once, with what it needs, rather
    // than after its first frame has been scan-converted (tens of seconds and gigabytes
    // of region buffer for a 65536x65536 screen). Too large is this machine's limit, as
    // there: status 3, naming the input.
    crate::check_memory(width, height).map_err(|e| e.context(&name))?;
    let mut fb = FrameBuffer::new(width, height, background)
        .map_err(|m| Error::io(format!("{name}: {m}")))?;
    if let Some(method) = method {
        let resolved = by_method(&name, reader, &stream, fb, method, on_frame)?;
        return Ok(vec![InputStats {
            bytes: bytes.load(Ordering::Relaxed),
            runs: resolved.1,
            resolved: Some(resolved.0),
            ..Default::default()
        }]);
    }
    // Two region buffers go round between two threads: this one paints frame k from one
    // into the frame buffer and writes it while the reader thread scan-converts frame
    // k + 1 into the other.
    let spare = RegionBuffer::new(width, height);
    let read = |hand: &mut HandOver<RegionBuffer>| -> Result<Resolved> {
        let mut scan = LeafScan::new(&attributes, width, height);
        let mut region = RegionBuffer::new(width, height);
        let mut counts = Resolved::default();
        let mut record = Token::default();
        let mut frame = 0u64;
        while reader.next_into(&mut record)? {
            if let Token::Polygon(p) = &mut record {
                stream.project(p, &reader)?;
            }
            match &record {
                Token::Polygon(p) => {
                    scan.resolve(&mut region, p, &reader)?;
                    counts.polygons += 1;
                }
                Token::Skip(_) => {}
                Token::NextFrame | Token::End => {
                    counts.rounding_decided += warn_rounding(&mut scan.watch, frame);
                    frame += 1;
                    let stats = std::mem::take(&mut region.stats);
                    counts.pixels_tested += stats.pixels_tested;
                    counts.pixels_written += stats.pixels_written;
                    if !hand.hand_over(&mut region) {
                        break; // the painter stopped; it says why
                    }
                }
            }
        }
        Ok(counts)
    };
    let paint = |frame: u64, region: &mut RegionBuffer| {
        // The first frame is painted over the background the frame buffer was made
        // with; each later one over the frame before, every pixel written (its colour, or
        // the background put back), with no pass of its own to clear it first. The frame
        // buffer's depth and polygon buffers are never made here: the region buffer did
        // the depth tests.
        if frame == 0 {
            region.finish_into(fb.raster_mut());
        } else {
            region.finish_over(fb.raster_mut(), background);
        }
        on_frame(frame, &fb)
    };
    let resolved = read_and_paint(&name, spare, read, paint)?;
    Ok(vec![InputStats {
        bytes: bytes.load(Ordering::Relaxed),
        resolved: Some(resolved),
        ..Default::default()
    }])
}

/// An anti-aliasing leaf's method that zbuf runs in the leaf's place (`zbuf --aa`), and
/// the leaf's name, which its messages give as the leaf's would.
pub struct Leaf<'a> {
    pub name: &'static str,
    pub method: &'a mut (dyn HiddenSurface + Send),
}

/// [`one_input`] with a frame-resolving `method` in the leaf's place (the anti-aliasing
/// leaf's method, `supersample`'s or `abuf`'s, when render runs `--aa` at depth 0):
/// the leaf's and the merger's work in one process, as the z-buffer's is at depth 0
/// (docs/performance.md, "Start-up"). A reader thread gathers each frame's polygons,
/// projected and checked as a leaf checks them (`leaf::resolve`: on the screen's guard
/// band, opaque unless the method draws transparency, flat unless it shades), has the
/// method resolve them into runs, and hands the runs to this thread, which paints them
/// over the background and writes the frame while the next one is read and resolved:
/// the pixels `supersample` would have sent as runs, neither encoded, piped nor decoded.
/// Returns the counts and the runs painted; the input's errors name it, `input`.
fn by_method<R: Read + Send>(
    input: &str,
    mut reader: Reader<Token, R>,
    stream: &Resolvable,
    mut fb: FrameBuffer,
    leaf: Leaf<'_>,
    mut on_frame: impl FnMut(u64, &FrameBuffer) -> Result<()>,
) -> Result<(Resolved, u64)> {
    let Leaf { name: leaf, method } = leaf;
    let (width, height) = (stream.width, stream.height);
    if let Some((name, word)) = stream.attributes.smooth_shading() {
        if !method.shades() {
            return Err(Error::usage(format!(
                "{leaf} draws each polygon in one colour, and the stream is {name}-shaded \
                 (its header says `{word}`)"
            ))
            .context(input));
        }
    }
    method.set_lighting(stream.attributes.phong());
    // Two run lists go round between the threads, as the region buffers do in
    // [`one_input`].
    let read = |hand: &mut HandOver<Vec<scan::Run>>| -> Result<Resolved> {
        let mut counts = Resolved::default();
        let mut polygons: Vec<proto::Polygon> = Vec::new();
        let mut runs = Vec::new();
        let mut record = Token::default();
        while reader.next_into(&mut record)? {
            match &mut record {
                Token::Polygon(p) => {
                    stream.project(p, &reader)?;
                    check_on_screen(p, width, height)
                        .map_err(|m| Error::data(format!("{}: {m}", reader.position())))?;
                    if !method.transparency() {
                        stagecli::refuse_transparent(leaf, p, || reader.position())?;
                    }
                    counts.polygons += 1;
                    polygons.push(std::mem::take(p));
                }
                Token::Skip(_) => {}
                Token::NextFrame | Token::End => {
                    method.resolve(&polygons, width, height, &mut runs);
                    polygons.clear();
                    counts.frames += 1;
                    if !hand.hand_over(&mut runs) {
                        break; // the painter stopped; it says why
                    }
                }
            }
        }
        Ok(counts)
    };
    let mut painted = 0u64;
    let paint = |frame: u64, runs: &mut Vec<scan::Run>| {
        // The first frame over the background the frame buffer was made with; each later
        // one over the background put back. The leaf's runs are finished pixels, placed
        // as the merger places any leaf's.
        if frame > 0 {
            fb.clear();
        }
        for r in runs.drain(..) {
            fb.paint(r.y, r.x0..r.x1, r.colour);
            painted += 1;
        }
        on_frame(frame, &fb)
    };
    let counts = read_and_paint(input, Vec::new(), read, paint)?;
    Ok((counts, painted))
}

/// A screen-space input (persp's output) is a leaf's and its merger's work at once: the
/// reader thread scan-converts its polygons into a [`RegionBuffer`], the leaf's z-buffer
/// (docs/DESIGN.md, "Leaves resolve visibility"). A tree's merger resolves leaf 0 so.
///
/// The last frame's region is handed to the buffer thread whole with the frame's END,
/// and placed once every input has finished the frame ([`FrameBuffer::place`]): what
/// `scanconv --resolve` would have sent as runs, neither made into runs nor taken apart
/// again. A frame before it is sent on as runs, as scanconv sends them, which frees the
/// region for the next frame at once: handing it over too would have wanted a second
/// region, and a movie's merger that much more memory.
///
/// Such an input sends nothing until a frame is resolved, so it need not wait for the
/// go-ahead before it reads the next frame's polygons, only before it sends that frame:
/// the next frame is scan-converted while the buffer thread shows this one.
fn resolve_input<R: Read>(
    input: usize,
    mut reader: Reader<Token, R>,
    to_screen: Option<ToScreen>,
    to: &ToBuffer,
    wait: &Receiver<()>,
) -> Result<()> {
    let stream = Resolvable::of(&reader, to_screen)?;
    let (width, height, attributes) = (stream.width, stream.height, stream.attributes);
    if !send_header(&to.tx, input, (width, height), &attributes) {
        return Ok(());
    }
    let send = |m| to.tx.send(m).is_ok();
    let mut scan = LeafScan::new(&attributes, width, height);
    let mut region = RegionBuffer::new(width, height);
    let mut polygons = 0u64;
    let mut record = Token::default();
    let mut batch = Vec::with_capacity(BATCH);
    let mut waiting = false; // for the go-ahead after the last frame sent
    let (mut frame, mut rounding_decided) = (0u64, 0u64);
    while reader.next_into(&mut record)? {
        if let Token::Polygon(p) = &mut record {
            stream.project(p, &reader)?;
        }
        let end = match &record {
            Token::Polygon(p) => {
                scan.resolve(&mut region, p, &reader)?;
                polygons += 1;
                continue;
            }
            // A skip carries nothing a leaf needs: the order of the polygons it gets
            // decides ties.
            Token::Skip(_) => continue,
            Token::NextFrame => false,
            Token::End => true,
        };
        rounding_decided += warn_rounding(&mut scan.watch, frame);
        frame += 1;
        // Nothing of a frame is sent before the buffer thread has shown the frame
        // before it (its go-ahead); the polygons of this frame were resolved meanwhile.
        if waiting && wait.recv().is_err() {
            return Ok(());
        }
        waiting = true;
        let resolved = Some(Resolved {
            polygons,
            pixels_tested: region.stats.pixels_tested,
            pixels_written: region.stats.pixels_written,
            rounding_decided,
            ..Default::default()
        });
        if end {
            let _ = send(Message::Boundary {
                input,
                end,
                resolved,
                region: Some(Box::new(region)),
            });
            return Ok(());
        }
        let sent = region.finish_frame(|run| {
            batch.push(run.into());
            if batch.len() == BATCH && !to.send_batch(input, &mut batch) {
                return Err(());
            }
            Ok(())
        });
        if sent.is_err() || (!batch.is_empty() && !to.send_batch(input, &mut batch)) {
            return Ok(());
        }
        if !send(Message::Boundary {
            input,
            end,
            resolved,
            region: None,
        }) {
            return Ok(());
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// An input that reads a string.
    fn text_input(name: &str, text: String) -> Input {
        Input {
            to_screen: None,
            name: name.into(),
            open: Box::new(
                move || Ok(Box::new(std::io::Cursor::new(text)) as Box<dyn Read + Send>),
            ),
        }
    }

    /// Runs PAR.BUFF and returns every frame's RGB bytes.
    fn frames(inputs: Vec<Input>) -> Result<Vec<Vec<u8>>> {
        let mut out = vec![];
        par_buff(inputs, [0, 0, 0], false, |_, fb| {
            out.push(fb.rgb().to_vec());
            Ok(())
        })?;
        Ok(out)
    }

    /// A span of polygon `polygon`: row, first column, length, depth at column 0, step.
    type Span = (usize, u32, u32, u32, i64, i64);

    /// The fragment text of `frames` frames of `polygons` polygons on an 8x4 screen,
    /// keeping only the spans `keep` accepts (every polygon keeps its colour record).
    fn stream(polygons: usize, frames: &[Vec<Span>], keep: impl Fn(usize) -> bool) -> String {
        let mut s = String::from("polypipe 2 fragments 8 4\n");
        let mut k = 0;
        for (f, spans) in frames.iter().enumerate() {
            if f > 0 {
                s += "NEXT.FRAME\n";
            }
            for p in 0..polygons {
                if p > 0 {
                    s += "NEXT.POLYGON\n";
                }
                s += &format!("colour {} {} {}\n", p * 20, f * 50, 255 - p);
                for &(q, y, x0, len, z0, dz) in spans {
                    if q == p {
                        if keep(k) {
                            let x1 = (x0 + len).min(8);
                            s += &format!("span {y} {x0} {x1} {z0} {dz}\n");
                        }
                        k += 1;
                    }
                }
            }
        }
        s + "END\n"
    }

    proptest! {
        /// However a frame's spans are dealt between inputs, and whatever order the
        /// inputs are named in, the frames are the same: the nearest pixel, the earlier
        /// polygon on a tie (depths are drawn from a few whole values to force exact ties;
        /// whole depths are further apart than the tie width, so the fold is the least
        /// (depth, polygon)).
        #[test]
        fn dealing_spans_between_inputs_changes_nothing(
            spans in prop::collection::vec(
                prop::collection::vec((0usize..5, 0u32..4, 0u32..8, 1u32..6, 0i64..3, -1i64..=1), 0..30),
                1..4,
            ),
            deal in prop::collection::vec(0usize..3, 200),
            inputs in 1usize..4,
        ) {
            let whole = frames(vec![text_input("whole", stream(5, &spans, |_| true))]).unwrap();
            // The reference: each pixel's least (depth, polygon).
            for (f, frame) in spans.iter().enumerate() {
                let mut best: Vec<Option<(f64, usize)>> = vec![None; 32];
                for &(p, y, x0, len, z0, dz) in frame {
                    for x in x0..(x0 + len).min(8) {
                        let z = proto::fragment::span_depth(z0 as f64, dz as f64, x);
                        let slot = &mut best[y as usize * 8 + x as usize];
                        if slot.is_none_or(|b| z < b.0 || (z == b.0 && p < b.1)) {
                            *slot = Some((z, p));
                        }
                    }
                }
                let want: Vec<u8> = best
                    .iter()
                    .flat_map(|b| match b {
                        Some((_, p)) => [(p * 20) as u8, (f * 50) as u8, 255 - *p as u8],
                        None => [0, 0, 0],
                    })
                    .collect();
                prop_assert_eq!(&whole[f], &want);
            }
            let dealt: Vec<Input> = (0..inputs)
                .rev()
                .map(|i| {
                    let deal = deal.clone();
                    text_input(&format!("in{i}"), stream(5, &spans, move |k| deal[k % 200] % inputs == i))
                })
                .collect();
            prop_assert_eq!(frames(dealt).unwrap(), whole);
        }
    }
}
