//! The stream header: magic, version and coordinate space (docs/DESIGN.md, "Header and spaces").
//!
//! Every stream starts with one. The binary form starts with [`BINARY_MAGIC`], eight
//! bytes whose first is not ASCII, so a reader tells the two forms apart from the first
//! byte alone; the text form starts with the word `polypipe`.

use crate::shade::Lighting;
use serde::{Deserialize, Serialize};
use std::fmt;

/// First bytes of a binary stream. The high-bit first byte and the CR LF pair catch a
/// stream that went through a text-mode channel, as PNG's signature does.
pub const BINARY_MAGIC: [u8; 8] = *b"\x89PPIPE\r\n";

/// The first word of a text stream.
pub const TEXT_MAGIC: &str = "polypipe";

/// The stream format version this code reads and writes, in the binary header.
///
/// Version 2 replaced version 1's bincode records by fixed-layout little-endian records
/// read and written in place (`proto::codec`, "The binary records"); the header itself is
/// still bincode. Version 3 made a fragment's depth an f64 (it was 64-bit fixed point), a
/// span's depth its row's depth at column 0, and screen depth reciprocal by default
/// ([`crate::depth`]). Version 4 added the header's [`Attributes`] (what a screen or
/// fragment stream's depths are: [`DepthForm`]), version 5 the vertex normals and lighting
/// of Phong shading ([`Attributes::lighting`]). A binary reader accepts version 5 only:
/// every stage of one build writes it.
pub const VERSION: u32 = 5;

/// The version the text form's header spells, `polypipe N SPACE`. The polygon streams'
/// text (world, eye, screen) has not changed since version 1, and people's scene files
/// say `polypipe 1`; the fragment stream's text changed with the binary version 3 (its
/// depths are decimal f64s, a span's depth is at column 0), so it says
/// `polypipe 2 fragments W H`, and a version 1 fragment text (fixed-point depths) is
/// refused. A [`Header`] read from either form carries [`VERSION`]: it is the format this
/// code speaks, whichever form carried it.
pub fn text_version(space: &Space) -> u32 {
    match space {
        Space::Fragments { .. } => 2,
        _ => 1,
    }
}

/// The view volume that eye coordinates were computed for: the clipping pyramid
/// −a·w ≤ x_e ≤ a·w, −w ≤ y_e ≤ w, K1 ≤ z_e ≤ K2 (docs/DESIGN.md, "The clipping pyramid").
///
/// `viewxf` records it in the eye-space header so that the clipper chain and `persp`
/// agree on the aspect ratio and the hither/yon distances without repeating options.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct View {
    /// a = W/H, the screen's aspect ratio.
    pub aspect: f64,
    /// K1: the hither plane z_e = K1.
    pub hither: f64,
    /// K2: the yon plane z_e = K2.
    pub yon: f64,
}

impl Default for View {
    /// The thesis's volume: a square screen, K1 = 1, K2 = 30 (Appendix 4's constants).
    fn default() -> Self {
        View {
            aspect: 1.0,
            hither: 1.0,
            yon: 30.0,
        }
    }
}

/// The coordinate space a stream's numbers are in.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub enum Space {
    /// Right-handed world coordinates; a vertex is `x y z`.
    World,
    /// Left-handed eye coordinates with w = z_e·s/d; a vertex is `x y z w`.
    Eye(View),
    /// Device coordinates of a `width`×`height` screen; a vertex is `X Y depth`.
    Screen { width: u32, height: u32 },
    /// The scan converter's output: pixels and spans of a `width`×`height` screen.
    Fragments { width: u32, height: u32 },
}

impl Space {
    /// How many numbers a vertex has in this space's text form.
    pub fn vertex_arity(&self) -> usize {
        match self {
            Space::World | Space::Screen { .. } => 3,
            Space::Eye(_) => 4,
            Space::Fragments { .. } => 0,
        }
    }

    /// The space's name as the header spells it.
    pub fn name(&self) -> &'static str {
        match self {
            Space::World => "world",
            Space::Eye(_) => "eye",
            Space::Screen { .. } => "screen",
            Space::Fragments { .. } => "fragments",
        }
    }

    /// The screen size, for the spaces that have one.
    pub fn screen_size(&self) -> Option<(u32, u32)> {
        match *self {
            Space::Screen { width, height } | Space::Fragments { width, height } => {
                Some((width, height))
            }
            _ => None,
        }
    }
}

impl fmt::Display for Space {
    /// The text header's spelling after the version, e.g. `screen 500 500`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Space::World => write!(f, "world"),
            Space::Eye(v) => write!(
                f,
                "eye aspect {} hither {} yon {}",
                v.aspect, v.hither, v.yon
            ),
            Space::Screen { width, height } => write!(f, "screen {width} {height}"),
            Space::Fragments { width, height } => write!(f, "fragments {width} {height}"),
        }
    }
}

/// What the third number of a screen vertex, and a fragment's depth, is: the form persp
/// wrote (`persp --zmode`), with the view volume's planes it was computed from. Smaller is
/// nearer in every form. A stage that knows the form can tell how finely its f64 depths
/// order eye-space depth ([`DepthForm::quantum`]); one that does not (a hand-written
/// screen stream says nothing) treats depths as numbers.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub enum DepthForm {
    /// D = −K1/z_e ([`crate::camera::Device::reciprocal_depth`]), K1 the hither distance.
    Reciprocal { hither: f64 },
    /// z_s = (1 − K1/z_e)·K2/(K2 − K1) ([`crate::camera::Device::projective_depth`]).
    Projective { hither: f64, yon: f64 },
    /// z_e itself (the thesis's occam code).
    EyeZ,
}

impl DepthForm {
    /// The eye-space depth z_e (K1 ≤ z_e ≤ K2, smaller nearer) of the depth `d` in this
    /// form: −K1/D for reciprocal depth, K1/(1 − z_s·(K2 − K1)/K2) for projective depth.
    pub fn eye_depth(&self, d: f64) -> f64 {
        match *self {
            DepthForm::Reciprocal { hither } => -hither / d,
            DepthForm::Projective { hither, yon } => hither / (1.0 - d * ((yon - hither) / yon)),
            DepthForm::EyeZ => d,
        }
    }

    /// The relative width in eye space, |Δz_e|/z_e, of one f64 ulp of the depth `d` in this
    /// form: how far apart in eye space two polygons can be and still get the same depth.
    /// About 2⁻⁵² for reciprocal depth and eye-z at any distance; for projective depth
    /// ulp(z_s)·z_e·(K2 − K1)/(K1·K2), which grows with the distance (its derivative
    /// dz_s/dz_e = K1·K2/((K2 − K1)·z_e²) vanishes far from the eye).
    pub fn quantum(&self, d: f64) -> f64 {
        let ulp = d.abs() * f64::EPSILON;
        match *self {
            DepthForm::Reciprocal { .. } | DepthForm::EyeZ => f64::EPSILON,
            DepthForm::Projective { hither, yon } => {
                ulp * self.eye_depth(d) * (yon - hither) / (hither * yon)
            }
        }
    }

    /// The relative width in eye space of the tie rule's 2⁻³⁰·|d| ([`crate::depth::TIE`])
    /// when a z-buffer applies it to depths of this form, as every stage does: exactly
    /// 2⁻³⁰ for reciprocal depth and eye-z (the rule is relative, and so are they), but
    /// 2⁻³⁰·(z_e − K1)/K1 for projective depth, since z_s = k·(1 − K1/z_e) moves by only
    /// k·K1/z_e for a relative step of z_e. Projective depth ties two polygons that the
    /// rule orders wherever z_e > 2·K1.
    pub fn rule_width(&self, d: f64) -> f64 {
        match *self {
            DepthForm::Reciprocal { .. } | DepthForm::EyeZ => crate::depth::TIE,
            DepthForm::Projective { hither, .. } => {
                crate::depth::TIE * (self.eye_depth(d) - hither) / hither
            }
        }
    }

    /// The widest relative eye-space width, over the view volume, within which a z-buffer
    /// holding this form cannot order two polygons: the rule's width or `ulps` ulps,
    /// whichever is wider, at yon for projective depth. Above 2⁻³⁰, the form can tie
    /// polygons that the rule orders.
    pub fn widest(&self, ulps: f64) -> f64 {
        match *self {
            DepthForm::Reciprocal { .. } | DepthForm::EyeZ => {
                crate::depth::TIE.max(ulps * f64::EPSILON)
            }
            DepthForm::Projective { hither, yon } => {
                let at_yon = (yon - hither) / hither;
                (crate::depth::TIE * at_yon).max(ulps * f64::EPSILON * at_yon)
            }
        }
    }

    /// The form's name, as `persp --zmode` and the header spell it.
    pub fn name(&self) -> &'static str {
        match self {
            DepthForm::Reciprocal { .. } => "reciprocal",
            DepthForm::Projective { .. } => "projective",
            DepthForm::EyeZ => "eye-z",
        }
    }

    /// The header's words for it, after `depth`: `reciprocal K1`, `projective K1 K2`, `eye-z`.
    fn words(&self) -> String {
        match *self {
            DepthForm::Reciprocal { hither } => format!("reciprocal {hither}"),
            DepthForm::Projective { hither, yon } => format!("projective {hither} {yon}"),
            DepthForm::EyeZ => self.name().to_string(),
        }
    }
}

/// What a stream's header says about its records beyond the space: written after the
/// space's words in the text form (`polypipe 1 screen 500 500 depth reciprocal 1`), and in
/// the binary form's header. Every stage passes on the attributes of its input that still
/// hold for its output.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Attributes {
    /// The form of the depths (screen and fragment streams): `depth FORM …`. `None` where
    /// the writer did not say (a hand-written stream, a stage that has no depths).
    pub depth: Option<DepthForm>,
    /// `vertex-colours` (polygon streams): every vertex carries a colour, `r g b` after its
    /// coordinates, numbers from 0 to 255 ([`crate::shade`]: Gouraud shading).
    pub vertex_colours: bool,
    /// `vertex-normals` (polygon and fragment streams): every vertex carries a normal,
    /// `nx ny nz` after its coordinates, in world coordinates, and the stream is
    /// Phong-shaded: the normals are interpolated across the screen as vertex colours are,
    /// and each pixel is lit by [`Attributes::lighting`] from the polygon's colour
    /// ([`crate::shade`]). A fragment stream says it when its `shade` records are a
    /// normal's planes.
    pub vertex_normals: bool,
    /// The lighting of a `vertex-normals` stream: the header's `ambient A`,
    /// `light X Y Z I` (repeatable), `specular KS N` and `viewer X Y Z` words. Written and
    /// read only with `vertex-normals`; the default otherwise. In the binary header, one
    /// byte where it is the default ([`default_is_absent`]).
    #[serde(with = "default_is_absent")]
    pub lighting: Lighting,
    /// `opacity` (polygon streams): every colour record is `colour R G B A`, A the opacity
    /// from 0 (clear) to 255 (opaque).
    pub opacity: bool,
}

/// Serializes a [`Lighting`] as an `Option`: `None` (one byte in bincode) for the
/// default, which every stream but a Phong-shaded one has, so that the lighting's few
/// hundred bytes are in no other header.
mod default_is_absent {
    use super::Lighting;
    use serde::{Deserialize, Deserializer, Serialize, Serializer};

    pub fn serialize<S: Serializer>(l: &Lighting, s: S) -> Result<S::Ok, S::Error> {
        (*l != Lighting::default()).then_some(l).serialize(s)
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Lighting, D::Error> {
        Ok(Option::<Lighting>::deserialize(d)?.unwrap_or_default())
    }
}

impl Attributes {
    /// What a fragment stream scan-converted from a stream with these attributes says:
    /// the depth form. Vertex colours and opacity belong to polygon records (a shaded
    /// polygon's fragments carry its colour planes in `shade` records instead).
    pub fn for_fragments(&self) -> Attributes {
        Attributes {
            depth: self.depth,
            vertex_normals: self.vertex_normals,
            lighting: self.lighting,
            ..Attributes::default()
        }
    }

    /// Whether polygons carry per-vertex values (colours or normals): the stream is
    /// smooth-shaded, Gouraud or Phong.
    pub fn shaded(&self) -> bool {
        self.vertex_colours || self.vertex_normals
    }

    /// The stream's smooth shading, by name and by the header word that declares it:
    /// `("Gouraud", "vertex-colours")` or `("Phong", "vertex-normals")`; `None` for a
    /// flat stream. For the messages of stages that refuse to draw it.
    pub fn smooth_shading(&self) -> Option<(&'static str, &'static str)> {
        if self.vertex_normals {
            Some(("Phong", "vertex-normals"))
        } else if self.vertex_colours {
            Some(("Gouraud", "vertex-colours"))
        } else {
            None
        }
    }

    /// The lighting that a renderer lights pixels by: `Some` where the stream is
    /// Phong-shaded (`vertex-normals`).
    pub fn phong(&self) -> Option<std::sync::Arc<Lighting>> {
        self.vertex_normals
            .then(|| std::sync::Arc::new(self.lighting))
    }
}

impl fmt::Display for Attributes {
    /// The text header's words, each with a leading space (nothing for the default).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some(form) = &self.depth {
            write!(f, " depth {}", form.words())?;
        }
        if self.vertex_colours {
            write!(f, " vertex-colours")?;
        }
        if self.vertex_normals {
            let l = &self.lighting;
            write!(f, " vertex-normals ambient {}", l.ambient)?;
            for (d, i) in l.lights() {
                write!(f, " light {} {} {} {i}", d.x, d.y, d.z)?;
            }
            let v = l.viewer();
            write!(
                f,
                " specular {} {} viewer {} {} {}",
                l.specular, l.exponent, v.x, v.y, v.z
            )?;
        }
        if self.opacity {
            write!(f, " opacity")?;
        }
        Ok(())
    }
}

/// A stream's header. The magic is implied by the form; the version is checked on read.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Header {
    pub version: u32,
    pub space: Space,
    pub attributes: Attributes,
}

impl Header {
    /// A header of the current version, with no attributes.
    pub fn new(space: Space) -> Self {
        Header {
            version: VERSION,
            space,
            attributes: Attributes::default(),
        }
    }

    /// The same header with `attributes`.
    pub fn with(self, attributes: Attributes) -> Self {
        Header { attributes, ..self }
    }

    /// Checks that the stream is in the space a stage consumes, with a message that tells
    /// the user which stage to put in front (e.g. `input is world-space; put viewxf first`).
    pub fn expect(&self, wanted: SpaceKind) -> Result<(), crate::StreamError> {
        let got = SpaceKind::of(&self.space);
        if got == wanted {
            return Ok(());
        }
        let hint = match (got, wanted) {
            (SpaceKind::World, SpaceKind::Eye) => "; put viewxf first",
            (SpaceKind::World, SpaceKind::Screen) => {
                "; put viewxf, the clipper chain and persp first"
            }
            (SpaceKind::Eye, SpaceKind::Screen) => "; put persp first",
            (SpaceKind::Eye, SpaceKind::World) | (SpaceKind::Screen, SpaceKind::World) => {
                "; this stage takes a scene as the source writes it"
            }
            (_, SpaceKind::Fragments) => "; put scanconv first",
            (SpaceKind::Fragments, _) => "; this is scan converter output, for zbuf",
            _ => "",
        };
        Err(crate::StreamError::WrongSpace(format!(
            "input is {}-space, expected {}-space{hint}",
            got.name(),
            wanted.name()
        )))
    }
}

/// A [`Space`] without its parameters, for stages to say what they consume.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SpaceKind {
    World,
    Eye,
    Screen,
    Fragments,
}

impl SpaceKind {
    pub fn of(space: &Space) -> Self {
        match space {
            Space::World => SpaceKind::World,
            Space::Eye(_) => SpaceKind::Eye,
            Space::Screen { .. } => SpaceKind::Screen,
            Space::Fragments { .. } => SpaceKind::Fragments,
        }
    }

    pub fn name(&self) -> &'static str {
        match self {
            SpaceKind::World => "world",
            SpaceKind::Eye => "eye",
            SpaceKind::Screen => "screen",
            SpaceKind::Fragments => "fragments",
        }
    }
}
