//! Wavefront OBJ models as scenes, read with `tobj`.
//!
//! Faces keep their vertex counts (no triangulation): the pipeline clips and scan
//! converts polygons of any size, and a quad drawn as one polygon has no interior edge.
//! A face takes the diffuse colour (`Kd`) of its material, scaled to 0–255; a face with
//! no material, or whose material library cannot be read, takes [`DEFAULT_COLOUR`].

use crate::shapes::Face;
use glam::DVec3;
use proto::text::Shown;
use stagecli::{Context, Error};
use std::cell::RefCell;
use std::io::BufRead;
use std::path::{Path, PathBuf};

/// The colour of a face without a material.
pub const DEFAULT_COLOUR: proto::Colour = [200, 200, 200];

/// The radius the model's bounding sphere is scaled to by [`fit`]: inside the
/// visible square (half-side 12.5 at the origin) and between hither and yon (the
/// origin is at z_e = 20, yon at 30).
pub const FIT_RADIUS: f64 = 8.0;

/// A loaded model: its faces, and the warnings met on the way (a material library that
/// could not be read, a material that is not in any library).
#[derive(Clone, Debug, PartialEq)]
pub struct Model {
    pub faces: Vec<Face>,
    pub warnings: Vec<String>,
}

/// Reads an OBJ model. `dir` is where its `mtllib` files are looked for (the OBJ file's
/// folder, or the current one for standard input); `name` names it in messages. A file
/// that cannot be read is an I/O error; a vertex that is not finite (`v nan 0 0`), or a
/// file tobj cannot parse, is bad input.
pub fn load<R: BufRead>(input: &mut R, dir: &Path, name: &str) -> stagecli::Result<Model> {
    // Read it whole first: a read that fails is then an I/O error of its own, not a
    // parse error of tobj's, and the vertices can be checked with their line numbers.
    let text = read_lines(input, name)?;
    let text = join_continued_lines(&text);
    check_lines(&text).map_err(|m| Error::data(format!("{name}: {m}")))?;
    let input = &mut std::io::Cursor::new(text);
    let warnings = RefCell::new(Vec::new());
    let bad_material = RefCell::new(None);
    let options = tobj::LoadOptions {
        triangulate: false,
        single_index: true,
        ..Default::default()
    };
    let (models, materials) = tobj::load_obj_buf(input, &options, |mtl: &Path| {
        let path: PathBuf = dir.join(mtl);
        if let Ok(text) = std::fs::read(&path) {
            if let Err(why) = check_material_lines(&join_continued_lines(&text)) {
                bad_material.replace(Some(format!("{}: {why}", path.display())));
                return Ok((Vec::new(), Default::default()));
            }
        }
        match tobj::load_mtl(&path) {
            Ok(m) => Ok(m),
            Err(e) => {
                warnings.borrow_mut().push(format!(
                    "cannot read material library {} ({e}); using default colours",
                    path.display()
                ));
                Ok((Vec::new(), Default::default()))
            }
        }
    })
    .map_err(|e| Error::data(format!("{name}: not a valid OBJ file: {e}")))?;
    if let Some(why) = bad_material.into_inner() {
        return Err(Error::data(why));
    }
    let mut warnings = warnings.into_inner();
    let materials = materials.unwrap_or_default();
    let mut faces = Vec::new();
    for model in &models {
        let mesh = &model.mesh;
        let colour = match mesh.material_id.and_then(|id| materials.get(id)) {
            Some(m) => match m.diffuse {
                Some(kd) => kd.map(|c| (c * 255.0).round().clamp(0.0, 255.0) as u8),
                None => DEFAULT_COLOUR,
            },
            None => DEFAULT_COLOUR,
        };
        let position = |i: u32| {
            let i = i as usize * 3;
            DVec3::new(
                mesh.positions[i],
                mesh.positions[i + 1],
                mesh.positions[i + 2],
            )
        };
        // face_arities is empty when every face is a triangle.
        let arities: Vec<usize> = if mesh.face_arities.is_empty() {
            vec![3; mesh.indices.len() / 3]
        } else {
            mesh.face_arities.iter().map(|&a| a as usize).collect()
        };
        let mut start = 0;
        for arity in arities {
            let Some(indices) = mesh.indices.get(start..start + arity) else {
                return Err(Error::data(format!(
                    "{name}: object `{}` has a face past its index list",
                    model.name
                )));
            };
            let mut face = Face::new(colour, indices.iter().map(|&i| position(i)).collect());
            // Its `vn` normals, where the file gives each of its vertices a usable one
            // (tobj's single index puts them beside the positions).
            if mesh.normals.len() == mesh.positions.len() {
                let normals: Vec<DVec3> = indices
                    .iter()
                    .map(|&i| {
                        let i = i as usize * 3;
                        DVec3::new(mesh.normals[i], mesh.normals[i + 1], mesh.normals[i + 2])
                            .normalize_or_zero()
                    })
                    .collect();
                if normals.iter().all(|n| *n != DVec3::ZERO) {
                    face.normals = normals;
                }
            }
            faces.push(face);
            start += arity;
        }
    }
    if faces.is_empty() {
        warnings.push(format!("{name} has no faces"));
    }
    Ok(Model { faces, warnings })
}

/// The text with each line that ends in `\` joined to the next (the OBJ and MTL
/// formats' continuation, which tobj does not read), the backslash and line break
/// becoming a space; an empty line is left after the joined line for each break taken
/// out, so that the lines after it keep their numbers in messages.
fn join_continued_lines(text: &[u8]) -> Vec<u8> {
    let mut out = Vec::with_capacity(text.len());
    let mut owed = 0; // line breaks taken out of the current line
    let mut i = 0;
    while i < text.len() {
        let b = text[i];
        let continued = b == b'\\'
            && (text.get(i + 1) == Some(&b'\n')
                || (text.get(i + 1) == Some(&b'\r') && text.get(i + 2) == Some(&b'\n')));
        if continued {
            out.push(b' ');
            i += if text[i + 1] == b'\r' { 3 } else { 2 };
            owed += 1;
            continue;
        }
        out.push(b);
        if b == b'\n' {
            out.extend(std::iter::repeat_n(b'\n', owed));
            owed = 0;
        }
        i += 1;
    }
    out.extend(std::iter::repeat_n(b'\n', owed));
    out
}

/// Finds, with its line, what in a material library would give a face a colour it does
/// not have: a diffuse colour (`Kd r g b`) whose numbers are not three from 0 to 1
/// (`Kd 2 -1 nan` became 255 0 0 without a word).
fn check_material_lines(text: &[u8]) -> Result<(), String> {
    for (k, line) in text.split(|&b| b == b'\n').enumerate() {
        let line = String::from_utf8_lossy(line);
        let mut words = line.split_whitespace();
        if words.next() != Some("Kd") {
            continue;
        }
        let values: Vec<&str> = words.collect();
        let at = |why: String| format!("line {}: `{}`: {why}", k + 1, Shown(line.trim()));
        if values.len() != 3 {
            return Err(at("a diffuse colour is three numbers from 0 to 1".into()));
        }
        for word in values {
            let word_shown = Shown(word);
            match word.parse::<f64>() {
                Ok(x) if (0.0..=1.0).contains(&x) => {}
                Ok(_) => {
                    return Err(at(format!(
                        "`{word_shown}` is not from 0 to 1 (a diffuse colour is three numbers \
                         from 0 to 1)"
                    )))
                }
                Err(_) => return Err(at(format!("`{word_shown}` is not a number"))),
            }
        }
    }
    Ok(())
}

/// Finds, with its line, what would make the model unusable or tobj refuse it without
/// saying where (its errors name no line: `position parse error`, `face vertex index out
/// of bounds`):
///
/// - a vertex (`v x y z`) without three numbers, or with one that is not finite (`nan`,
///   `inf`, which Rust's and tobj's number parsing accept: such a vertex has no place,
///   and the stages after this one would otherwise take the blame);
/// - a texture coordinate (`vt u v`) or normal (`vn x y z`) without its numbers;
/// - a face or line (`f`, `l`) with a word that is not `v`, `v/vt`, `v//vn` or `v/vt/vn`
///   indices, or whose vertex index is 0 or beyond the file's vertices (tobj counts a
///   negative index back from the vertices read so far, 1-based ones from the start).
///
/// What this does not catch, tobj still refuses, in its own words.
/// Reads an OBJ file whole, each line checked as it comes in: at most
/// [`proto::text::MAX_LINE_BYTES`] long and UTF-8 (which tobj needs, and refuses without
/// saying where), so that input that is not an OBJ file (`/dev/zero`, `/dev/urandom`) is
/// refused at its first line rather than read into memory for ever.
fn read_lines<R: BufRead>(input: &mut R, name: &str) -> stagecli::Result<Vec<u8>> {
    use proto::text::{line_too_long, MAX_LINE_BYTES};
    let mut text = Vec::new();
    let (mut line_start, mut searched, mut line_no) = (0usize, 0usize, 1u64);
    let check = |line: &[u8], line_no: u64| match std::str::from_utf8(line) {
        Ok(_) => Ok(()),
        Err(e) => Err(Error::data(format!(
            "{name}: line {line_no}: not text: byte {} of the line is not UTF-8 (is this an \
             OBJ file?)",
            e.valid_up_to() + 1
        ))),
    };
    loop {
        let buf = match input.fill_buf() {
            Ok(buf) => buf,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
            Err(e) => return Err(e).context(name),
        };
        if buf.is_empty() {
            break;
        }
        let n = buf.len();
        text.extend_from_slice(buf);
        input.consume(n);
        while let Some(i) = text[searched..].iter().position(|&b| b == b'\n') {
            let end = searched + i;
            check(&text[line_start..end], line_no)?;
            (line_start, searched, line_no) = (end + 1, end + 1, line_no + 1);
        }
        searched = text.len();
        if text.len() - line_start > MAX_LINE_BYTES {
            return Err(Error::data(format!(
                "{name}: line {line_no}: {}",
                line_too_long()
            )));
        }
    }
    check(&text[line_start..], line_no)?;
    Ok(text)
}

fn check_lines(text: &[u8]) -> Result<(), String> {
    // tobj reads lines as UTF-8 and refuses others without saying where.
    for (k, line) in text.split(|&b| b == b'\n').enumerate() {
        if let Err(e) = std::str::from_utf8(line) {
            return Err(format!(
                "line {}: not text: byte {} of the line is not UTF-8 (is this an OBJ file?)",
                k + 1,
                e.valid_up_to() + 1
            ));
        }
    }
    let lines = || text.split(|&b| b == b'\n').map(String::from_utf8_lossy);
    let vertices = lines()
        .filter(|l| l.split_whitespace().next() == Some("v"))
        .count();
    let mut seen = 0usize; // vertices before this line
    for (k, line) in lines().enumerate() {
        let at = |what: String| format!("line {}: {what}", k + 1);
        let mut words = line.split_whitespace();
        let (kind, numbers) = match words.next() {
            Some("v") => ("vertex", 3),
            Some("vt") => ("texture coordinate", 2),
            Some("vn") => ("normal", 3),
            Some("f" | "l") => {
                for word in words {
                    check_face_word(word, seen, vertices)
                        .map_err(|why| at(format!("face `{}`: {why}", Shown(line.trim()))))?;
                }
                continue;
            }
            _ => continue,
        };
        let values: Vec<&str> = words.take(numbers).collect();
        if values.len() < numbers {
            return Err(at(format!(
                "{kind} `{}` needs {numbers} numbers",
                Shown(line.trim())
            )));
        }
        for word in values {
            let word_shown = Shown(word);
            match word.parse::<f64>() {
                Err(_) => {
                    return Err(at(format!(
                        "{kind} `{}` has `{word_shown}`, which is not a number",
                        Shown(line.trim())
                    )))
                }
                Ok(x) if kind == "vertex" && !x.is_finite() => {
                    return Err(at(format!(
                        "vertex `{}` has a coordinate `{word_shown}` that is not a finite number",
                        Shown(line.trim())
                    )))
                }
                Ok(_) => {}
            }
        }
        if kind == "vertex" {
            seen += 1;
        }
    }
    Ok(())
}

/// One vertex of a face, `v`, `v/vt`, `v//vn` or `v/vt/vn`, read as tobj reads it; its
/// vertex index checked against the `vertices` of the file (`seen` of them before the
/// face, for an index counted back from there).
fn check_face_word(word: &str, seen: usize, vertices: usize) -> Result<(), String> {
    let word_shown = Shown(word);
    let parts: Vec<&str> = word.split('/').collect();
    if parts.len() > 3 || parts[0].is_empty() {
        return Err(format!("`{word_shown}` is not a vertex's indices"));
    }
    for part in parts.iter().filter(|p| !p.is_empty()) {
        if part.parse::<isize>().is_err() {
            return Err(format!("`{word_shown}` is not a vertex's indices"));
        }
    }
    let index: isize = parts[0].parse().unwrap_or(0);
    if index == 0 {
        return Err(
            "vertex index 0: OBJ counts vertices from 1 (and back from the last \
                    with -1, -2, …), so 0 names none"
                .into(),
        );
    }
    let place = if index < 0 {
        seen as isize + index
    } else {
        index - 1
    };
    if index == 0 || place < 0 || place >= vertices as isize {
        let count = |n: usize| match n {
            1 => "1 vertex".to_string(),
            n => format!("{n} vertices"),
        };
        let have = if index < 0 {
            format!("{} before it", count(seen))
        } else {
            format!("the file has {}", count(vertices))
        };
        return Err(format!("vertex index {index} is out of bounds ({have})"));
    }
    Ok(())
}

/// Vertex normals for the faces that have none from the file: at each corner, the
/// normals of the faces that meet at that point (the same coordinates) averaged, each
/// weighted by its area (its Newell normal's length), over those within `crease_degrees`
/// of this face's own; a face across a sharper edge keeps its side of the crease. The
/// normals are taken as lines, not arrows (the lighting is two-sided, and an OBJ's faces
/// need not all wind one way): a neighbour facing the other way counts turned round. A
/// face of no area keeps no normals (it is lit by its sphere normal, and covers nothing).
pub fn smooth_normals(faces: &mut [Face], crease_degrees: f64) {
    let key = |p: DVec3| (p.x.to_bits(), p.y.to_bits(), p.z.to_bits());
    let area_normals: Vec<DVec3> = faces
        .iter()
        .map(|f| proto::geometry::newell_normal(&f.points))
        .collect();
    let mut at: std::collections::HashMap<(u64, u64, u64), Vec<usize>> =
        std::collections::HashMap::new();
    for (i, f) in faces.iter().enumerate() {
        for p in &f.points {
            let list = at.entry(key(*p)).or_default();
            if list.last() != Some(&i) {
                list.push(i);
            }
        }
    }
    let cos_crease = crease_degrees.to_radians().cos();
    for i in 0..faces.len() {
        if !faces[i].normals.is_empty() {
            continue;
        }
        let own = area_normals[i].normalize_or_zero();
        if own == DVec3::ZERO {
            continue;
        }
        let normals = faces[i]
            .points
            .iter()
            .map(|p| {
                let mut sum = DVec3::ZERO;
                for &j in &at[&key(*p)] {
                    let n = area_normals[j];
                    let along = n.normalize_or_zero().dot(own);
                    if along.abs() >= cos_crease {
                        sum += n * along.signum();
                    }
                }
                sum.try_normalize().unwrap_or(own)
            })
            .collect();
        faces[i].normals = normals;
    }
}

/// Moves and scales the faces so that the model's bounding box is centred on the
/// origin and its bounding sphere has radius [`FIT_RADIUS`]: the whole model is then in
/// view of the default camera.
///
/// A model whose coordinates are beyond about 1e150 is measured in units of a power of
/// two its size, so that neither the centre (a sum of two coordinates) nor the radius
/// (a sum of squares) overflows however large the numbers are; a model of ordinary size
/// is measured as it is.
pub fn fit(faces: &mut [Face]) {
    let mut lo = DVec3::splat(f64::INFINITY);
    let mut hi = DVec3::splat(f64::NEG_INFINITY);
    for p in faces.iter().flat_map(|f| &f.points) {
        lo = lo.min(*p);
        hi = hi.max(*p);
    }
    if lo.x > hi.x {
        // No vertices.
        return;
    }
    let extent = lo.abs().max(hi.abs()).max_element();
    let unit = if extent > 1e150 {
        // 2^1023 at most (2^1024 is infinite): the scaled coordinates are below 2.
        2f64.powi((extent.log2().ceil() as i32).min(1023))
    } else {
        1.0
    };
    let centre = (lo / unit + hi / unit) * 0.5;
    let radius = faces
        .iter()
        .flat_map(|f| &f.points)
        .map(|p| (*p / unit - centre).length())
        .fold(0.0, f64::max);
    let scale = if radius > 0.0 {
        FIT_RADIUS / radius
    } else {
        1.0
    };
    for p in faces.iter_mut().flat_map(|f| &mut f.points) {
        *p = (*p / unit - centre) * scale;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Cursor;

    /// Two triangles folded 20° along their shared edge (x from 0 to 1 at y = z = 0):
    /// within a crease of 60° the shared corners take the mean of the two normals, the
    /// others their own face's; below 20°, every corner its own face's.
    #[test]
    fn faces_meeting_within_the_crease_share_their_corners_normals() {
        let fold = 20f64.to_radians();
        let text = format!(
            "v 0 0 0\nv 1 0 0\nv 0.5 1 0\nv 0.5 {} {}\nf 1 2 3\nf 2 1 4\n",
            -fold.cos(),
            fold.sin()
        );
        let mut model = load_str(&text);
        let (a, b) = (DVec3::Z, DVec3::new(0.0, fold.sin(), fold.cos()));
        smooth_normals(&mut model.faces, 60.0);
        let mean = (a + b).normalize();
        let close = |u: DVec3, v: DVec3| (u - v).length() < 1e-12;
        let first = &model.faces[0].normals;
        assert!(close(first[0], mean) && close(first[1], mean), "{first:?}");
        assert!(close(first[2], a), "{first:?}");
        let second = &model.faces[1].normals;
        assert!(close(second[0], mean) && close(second[2], b), "{second:?}");
        let mut model = load_str(&text);
        smooth_normals(&mut model.faces, 10.0);
        assert!(model.faces[0].normals.iter().all(|n| close(*n, a)));
        assert!(model.faces[1].normals.iter().all(|n| close(*n, b)));
    }

    /// A file's own `vn` normals are kept (unit length), and no averaging replaces them.
    #[test]
    fn vn_normals_are_the_vertices_normals() {
        let mut model =
            load_str("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 2\nvn 0 1 0\nvn 1 0 0\nf 1//1 2//2 3//3\n");
        assert_eq!(model.faces[0].normals, vec![DVec3::Z, DVec3::Y, DVec3::X]);
        smooth_normals(&mut model.faces, 60.0);
        assert_eq!(model.faces[0].normals, vec![DVec3::Z, DVec3::Y, DVec3::X]);
    }

    fn load_str(text: &str) -> Model {
        load(
            &mut Cursor::new(text),
            Path::new("/nonexistent"),
            "test.obj",
        )
        .unwrap()
    }

    #[test]
    fn quads_and_ngons_keep_their_vertices() {
        let m = load_str(
            "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 1.5 0\n\
             f 1 2 3 4\nf 1 2 3 5 4\nf 1 2 3\n",
        );
        let counts: Vec<usize> = m.faces.iter().map(|f| f.points.len()).collect();
        assert_eq!(counts, [4, 5, 3]);
        assert_eq!(m.faces[1].points[3], DVec3::new(0.5, 1.5, 0.0));
        assert!(m.faces.iter().all(|f| f.colour == DEFAULT_COLOUR));
        assert!(m.warnings.is_empty());
    }

    #[test]
    fn negative_indices_count_back_from_the_last_vertex() {
        let m = load_str("v 0 0 0\nv 2 0 0\nv 2 2 0\nf -3 -2 -1\nv 9 9 9\nf 1 -1 -2\n");
        assert_eq!(
            m.faces[0].points,
            [
                DVec3::ZERO,
                DVec3::new(2.0, 0.0, 0.0),
                DVec3::new(2.0, 2.0, 0.0)
            ]
        );
        assert_eq!(
            m.faces[1].points,
            [DVec3::ZERO, DVec3::splat(9.0), DVec3::new(2.0, 2.0, 0.0)]
        );
    }

    #[test]
    fn fit_centres_and_scales() {
        let mut faces = vec![Face::new(
            DEFAULT_COLOUR,
            vec![
                DVec3::new(10.0, 10.0, 10.0),
                DVec3::new(12.0, 10.0, 10.0),
                DVec3::new(12.0, 10.0, 12.0),
            ],
        )];
        fit(&mut faces);
        let r = FIT_RADIUS / 2f64.sqrt();
        assert!((faces[0].points[0] - DVec3::new(-r, 0.0, -r)).length() < 1e-12);
        assert!((faces[0].points[2] - DVec3::new(r, 0.0, r)).length() < 1e-12);
    }

    #[test]
    fn fit_takes_the_largest_coordinates() {
        let mut faces = vec![Face::new(
            DEFAULT_COLOUR,
            vec![
                DVec3::new(1e308, 1.7e308, 0.0),
                DVec3::new(1.7e308, 1.7e308, 0.0),
                DVec3::new(1.7e308, 1e308, -1.7e308),
            ],
        )];
        fit(&mut faces);
        let p = &faces[0].points;
        assert!(p.iter().all(|v| v.is_finite()), "{p:?}");
        let radius = p.iter().map(|v| v.length()).fold(0.0, f64::max);
        assert!((radius - FIT_RADIUS).abs() < 1e-9, "{p:?}");
    }

    #[test]
    fn a_vertex_that_is_not_finite_is_refused_by_its_line() {
        for (obj, line, word) in [
            ("v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n", 2, "nan"),
            ("# c\n\nv 0 0 0\nv 1 -inf 0\n", 4, "-inf"),
            ("v 0 0 0\n  v 1 0 Infinity\n", 2, "Infinity"),
        ] {
            let err = load(&mut Cursor::new(obj), Path::new("."), "m.obj").unwrap_err();
            assert_eq!(err.kind(), stagecli::Kind::Data);
            let m = err.to_string();
            assert!(
                m.starts_with(&format!("m.obj: line {line}: vertex `v "))
                    && m.ends_with(&format!(
                        "has a coordinate `{word}` that is not a finite number"
                    )),
                "{m}"
            );
        }
        // Normals and texture coordinates are not positions; a vertex's fourth (weight)
        // number is not a coordinate either.
        assert!(load(
            &mut Cursor::new("vn nan 0 0\nv 0 0 0 nan\n"),
            Path::new("."),
            "m"
        )
        .is_ok());
    }

    #[test]
    fn continued_lines_are_joined_and_later_lines_keep_their_numbers() {
        // A vertex and a face broken over two lines each; line 7's error keeps its number.
        let obj = "v 0 0 0\nv 1 0 \\\n0\nv 0 1 0\nf 1 2 \\\r\n3\nf 1 2 x\n";
        let err = load(&mut Cursor::new(obj), Path::new("."), "m.obj").unwrap_err();
        assert_eq!(
            err.to_string(),
            "m.obj: line 7: face `f 1 2 x`: `x` is not a vertex's indices"
        );
        let obj = "v 0 0 0\nv 1 0 \\\n0\nv 0 1 0\nf 1 2 \\\n3\n";
        let m = load_str(obj);
        assert_eq!(m.faces.len(), 1);
        assert_eq!(m.faces[0].points[1], DVec3::new(1.0, 0.0, 0.0));
        assert_eq!(join_continued_lines(b"a \\\nb\nc\n"), b"a  b\n\nc\n");
    }

    #[test]
    fn bytes_that_are_not_text_are_named_by_line() {
        let err = load(
            &mut Cursor::new(&b"v 0 0 0\nv 1 \xff 0\n"[..]),
            Path::new("."),
            "r.obj",
        )
        .unwrap_err();
        assert_eq!(err.kind(), stagecli::Kind::Data);
        assert_eq!(
            err.to_string(),
            "r.obj: line 2: not text: byte 5 of the line is not UTF-8 (is this an OBJ file?)"
        );
    }

    #[test]
    fn a_diffuse_colour_that_is_not_three_numbers_from_0_to_1_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let obj = "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl red\nf 1 2 3\n";
        let mtl = dir.path().join("m.mtl");
        for (kd, why) in [
            (
                "Kd 2 -1 nan",
                "`2` is not from 0 to 1 (a diffuse colour is three numbers from 0 to 1)",
            ),
            (
                "Kd 1 0 nan",
                "`nan` is not from 0 to 1 (a diffuse colour is three numbers from 0 to 1)",
            ),
            ("Kd 1 0", "a diffuse colour is three numbers from 0 to 1"),
            ("Kd 1 0 q", "`q` is not a number"),
        ] {
            std::fs::write(&mtl, format!("newmtl red\n{kd}\n")).unwrap();
            let err = load(&mut Cursor::new(obj), dir.path(), "m.obj").unwrap_err();
            assert_eq!(err.kind(), stagecli::Kind::Data);
            assert_eq!(
                err.to_string(),
                format!("{}: line 2: `{kd}`: {why}", mtl.display())
            );
        }
        std::fs::write(&mtl, "newmtl red\nKd 1 0 0.5\n").unwrap();
        let m = load(&mut Cursor::new(obj), dir.path(), "m.obj").unwrap();
        assert_eq!(m.faces[0].colour, [255, 0, 128]);
    }

    #[test]
    fn a_bad_index_is_an_error() {
        let err = load(
            &mut Cursor::new("v 0 0 0\nf 1 2 3\n"),
            Path::new("."),
            "bad.obj",
        )
        .unwrap_err();
        assert_eq!(
            err.to_string(),
            "bad.obj: line 2: face `f 1 2 3`: vertex index 2 is out of bounds (the file has 1 vertex)"
        );
    }

    #[test]
    fn a_line_tobj_cannot_read_is_named() {
        for (obj, message) in [
            (
                "v 0 0 0\nv 1 0 x\n",
                "line 2: vertex `v 1 0 x` has `x`, which is not a number",
            ),
            ("v 0 0\n", "line 1: vertex `v 0 0` needs 3 numbers"),
            (
                "vt 0 q\n",
                "line 1: texture coordinate `vt 0 q` has `q`, which is not a number",
            ),
            ("vn 0 0\n", "line 1: normal `vn 0 0` needs 3 numbers"),
            (
                "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 0\n",
                "line 4: face `f 1 2 0`: vertex index 0: OBJ counts vertices from 1 (and back \
                 from the last with -1, -2, …), so 0 names none",
            ),
            (
                "v 0 0 0\nf -1 -2 -3\nv 1 0 0\nv 0 1 0\n",
                "line 2: face `f -1 -2 -3`: vertex index -2 is out of bounds (1 vertex before it)",
            ),
            (
                "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x3\n",
                "line 4: face `f 1 2 x3`: `x3` is not a vertex's indices",
            ),
            (
                "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/1/1/1 2 3\n",
                "line 4: face `f 1/1/1/1 2 3`: `1/1/1/1` is not a vertex's indices",
            ),
        ] {
            let err = load(&mut Cursor::new(obj), Path::new("."), "m.obj").unwrap_err();
            assert_eq!(err.kind(), stagecli::Kind::Data, "{obj}");
            assert_eq!(err.to_string(), format!("m.obj: {message}"), "{obj}");
        }
        // What tobj reads, this lets by: a weight after a vertex, every index form,
        // indices counted back, a face before its vertices (tobj resolves them at the
        // object's end), texture indices in a file without texture coordinates.
        let good = "v 0 0 0 1\nv 1 0 0 2\nf 1/1 2//1 3/1/1\nv 0 1 0\nf -3 -2 -1\nl 1 2\n";
        let model = load(&mut Cursor::new(good), Path::new("."), "m").unwrap();
        assert_eq!(model.faces.len(), 3);
    }
}
